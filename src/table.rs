//! The small tidy tables the stages exchange (analysis tables, `tradeoff.parquet`,
//! `sobol.parquet`) and read back (figures, report), column by column, with their Parquet I/O
//! through polars (its Rust API changes between minor versions; polars is pinned).

use std::fs::File;
use std::path::Path;

use polars::prelude::*;

/// The columns of the stages' tables that hold counts, variances, standard errors or densities:
/// never negative.
const NON_NEGATIVE: [&str; 12] = [
    "n",
    "count",
    "density",
    "variance",
    "mean_se",
    "variance_se",
    "reached",
    "reached_fraction",
    "n_truncated_excluded",
    "futures",
    "error",
    "variance_error",
];

/// The type of a column in a table's definition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type {
    /// text
    Str,
    /// 64-bit integers (null allowed)
    Int,
    /// 64-bit floats (null allowed; never NaN or ±∞)
    Float,
}

impl Type {
    /// The Arrow type of its columns.
    pub fn arrow(self) -> arrow_schema::DataType {
        match self {
            Type::Str => arrow_schema::DataType::Utf8,
            Type::Int => arrow_schema::DataType::Int64,
            Type::Float => arrow_schema::DataType::Float64,
        }
    }
}

/// One column of a table's definition: its name, type and meaning (unit included).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Column {
    /// the column's name
    pub name: &'static str,
    /// its type
    pub ty: Type,
    /// one line of meaning, with the unit
    pub meaning: &'static str,
}

/// A table's one definition: the file it is written as and its columns in order. The writer is
/// checked against it before writing ([`Def::check`]), every reader reads through it
/// ([`Def::read`]), and the documentation is generated from it.
#[derive(Debug, Clone, Copy)]
pub struct Def {
    /// the file's name in its directory (`moments.parquet`)
    pub file: &'static str,
    /// one line of meaning
    pub meaning: &'static str,
    /// the columns, in order
    pub columns: &'static [Column],
}

impl Def {
    /// The table's name (its file without `.parquet`).
    pub fn name(&self) -> &'static str {
        self.file.trim_end_matches(".parquet")
    }

    /// Whether `t` has exactly these columns, in order, of these types; else the first
    /// difference.
    pub fn check(&self, t: &Table) -> Result<(), String> {
        let ty = Col::ty;
        let names: Vec<&str> = t.columns.iter().map(|(n, _)| n.as_str()).collect();
        for (i, c) in self.columns.iter().enumerate() {
            match t.columns.get(i) {
                Some((n, col)) if n == c.name && ty(col) == c.ty => {}
                Some((n, col)) if n == c.name => return Err(format!("{}: column `{n}` is {:?}, its definition says {:?}", self.file, ty(col), c.ty)),
                _ if names.contains(&c.name) => return Err(format!("{}: column `{}` is out of its place ({})", self.file, c.name, names.join(", "))),
                _ => return Err(format!("{}: column `{}` is missing", self.file, c.name)),
            }
        }
        match names.get(self.columns.len()) {
            Some(extra) => Err(format!("{}: column `{extra}` is not in its definition", self.file)),
            None => Ok(()),
        }
    }

    /// Read `dir`'s file of this table and check it against the definition: a table of another
    /// shape (an older stickslip's, or an edited file) is refused with the difference named.
    pub fn read(&self, dir: &Path) -> Result<Table, String> {
        self.read_at(&dir.join(self.file))
    }

    /// [`Def::read`] of the file at `path` (a copy of the table under another name).
    pub fn read_at(&self, path: &Path) -> Result<Table, String> {
        let t = Table::read_parquet(path).map_err(|e| e.to_string())?;
        self.check(&t)
            .map_err(|e| format!("{e}: not the table this version of stickslip writes (written by another version, or edited); run the stage again"))?;
        Ok(t)
    }

    /// [`Def::check`], and every value one this tool's tables hold (no NaN or ±∞; counts,
    /// variances, standard errors and densities not negative): the guard a table passes before
    /// it is written or handed over in memory.
    pub fn check_all(&self, t: &Table) -> Result<(), String> {
        self.check(t)?;
        t.first_impossible().map_or(Ok(()), |problem| Err(format!("{}: {problem}", self.file)))
    }

    /// Whether `t` has these columns in order, of these types, after some leading columns and
    /// before some trailing ones (a table whose first and last columns depend on the run, as a
    /// sweep's keys and tails); the number of leading columns, else the first difference.
    pub fn check_span(&self, t: &Table) -> Result<usize, String> {
        let first = self.columns.first().map_or("", |c| c.name);
        let start = t.columns.iter().position(|(n, _)| n == first).ok_or_else(|| format!("{}: column `{first}` is missing", self.file))?;
        let span = Table { columns: t.columns[start..(start + self.columns.len()).min(t.columns.len())].to_vec() };
        self.check(&span)?;
        Ok(start)
    }

    /// The columns as an Arrow schema, none nullable (a table written with arrow directly, as
    /// the trajectories are).
    pub fn arrow_schema(&self) -> arrow_schema::Schema {
        arrow_schema::Schema::new(self.columns.iter().map(|c| arrow_schema::Field::new(c.name, c.ty.arrow(), false)).collect::<Vec<_>>())
    }

    /// The column named `name` (tests and generated documentation).
    pub fn column(&self, name: &str) -> Option<&'static Column> {
        self.columns.iter().find(|c| c.name == name)
    }
}

/// Define a table: a module holding one constant per column and `DEF`, the definition.
macro_rules! table {
    ($(#[$doc:meta])* $module:ident = $file:literal, $meaning:literal { $($konst:ident: $name:literal, $ty:ident, $m:literal;)* }) => {
        $(#[$doc])*
        pub mod $module {
            use crate::table::{Column, Def, Type};
            $(
                #[doc = $m]
                pub const $konst: Column = Column { name: $name, ty: Type::$ty, meaning: $m };
            )*
            /// The table's definition.
            pub const DEF: Def = Def { file: $file, meaning: $meaning, columns: &[$($konst),*] };
        }
    };
}
pub(crate) use table;

/// A small tidy table, column by column.
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// (name, values) of each column, in order
    pub columns: Vec<(String, Col)>,
}

/// The values of one column.
#[derive(Debug, Clone)]
pub enum Col {
    /// strings (a null read back as the empty string)
    Str(Vec<String>),
    /// integers, None for null
    Int(Vec<Option<i64>>),
    /// floats, None for null
    Float(Vec<Option<f64>>),
}

impl Col {
    /// Its type in a table's definition.
    pub fn ty(&self) -> Type {
        match self {
            Col::Str(_) => Type::Str,
            Col::Int(_) => Type::Int,
            Col::Float(_) => Type::Float,
        }
    }
}

impl Table {
    /// Read a table written by [`Table::write_parquet`] (string, integer and float columns).
    pub fn read_parquet(path: &Path) -> PolarsResult<Table> {
        let file = File::open(path).map_err(|e| polars_err!(ComputeError: "{}: {e}", path.display()))?;
        let df = ParquetReader::new(file).finish()?;
        let mut t = Table::default();
        for c in df.columns() {
            let name = c.name().to_string();
            let col = match c.dtype() {
                DataType::String => Col::Str(c.str()?.iter().map(|v| v.unwrap_or_default().to_string()).collect()),
                DataType::Int64 | DataType::Int32 => Col::Int(c.cast(&DataType::Int64)?.i64()?.iter().collect()),
                DataType::Float64 => Col::Float(c.f64()?.iter().collect()),
                other => polars_bail!(SchemaMismatch: "{}: column `{name}` has unsupported type {other}", path.display()),
            };
            t.columns.push((name, col));
        }
        if let Some(problem) = t.first_impossible() {
            polars_bail!(ComputeError: "{problem}; it is not a table this tool wrote (or it was edited since)");
        }
        Ok(t)
    }

    /// The first value that no table of this tool holds — NaN or ±∞ in any float column, or a
    /// negative value in a column of counts, variances, standard errors or densities
    /// ([`NON_NEGATIVE`]) — as a message naming the column and the row (0-based).
    pub(crate) fn first_impossible(&self) -> Option<String> {
        for (name, col) in &self.columns {
            let Col::Float(values) = col else { continue };
            let non_negative = NON_NEGATIVE.contains(&name.as_str());
            for (row, x) in values.iter().enumerate() {
                let Some(x) = *x else { continue };
                if !x.is_finite() {
                    return Some(format!("column `{name}` row {row}: {x} is not a finite number"));
                }
                if non_negative && x < 0.0 {
                    return Some(format!("column `{name}` row {row}: {} is negative (a count, variance, standard error or density)", crate::shown::short(x)));
                }
            }
        }
        for (name, col) in &self.columns {
            if let (true, Col::Int(values)) = (NON_NEGATIVE.contains(&name.as_str()), col) {
                if let Some((row, Some(x))) = values.iter().enumerate().find(|(_, x)| x.is_some_and(|x| x < 0)) {
                    return Some(format!("column `{name}` row {row}: {x} is negative (a count)"));
                }
            }
        }
        None
    }

    /// Read a table and check that it has `columns`, each of the kind given ('s' string,
    /// 'i' integer, 'f' float): a broken or foreign table is an error naming the column.
    pub fn read_checked(path: &Path, columns: &[(&str, char)]) -> PolarsResult<Table> {
        let t = Table::read_parquet(path)?;
        for &(name, kind) in columns {
            let got = match t.col(name) {
                None => polars_bail!(ColumnNotFound: "{}: column `{name}` is missing", path.display()),
                Some(Col::Str(_)) => 's',
                Some(Col::Int(_)) => 'i',
                Some(Col::Float(_)) => 'f',
            };
            if got != kind {
                let word = |k: char| match k {
                    's' => "string",
                    'i' => "integer",
                    _ => "float",
                };
                polars_bail!(SchemaMismatch: "{}: column `{name}` is {}, expected {}", path.display(), word(got), word(kind));
            }
        }
        Ok(t)
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.columns.first().map_or(0, |(_, c)| match c {
            Col::Str(v) => v.len(),
            Col::Int(v) => v.len(),
            Col::Float(v) => v.len(),
        })
    }

    fn col(&self, name: &str) -> Option<&Col> {
        self.columns.iter().find(|(n, _)| n == name).map(|(_, c)| c)
    }

    /// The string column `name` (None if absent or of another kind).
    pub fn strings(&self, name: &str) -> Option<&[String]> {
        match self.col(name)? {
            Col::Str(v) => Some(v),
            _ => None,
        }
    }

    /// The integer column `name` (None if absent or of another kind).
    pub fn ints(&self, name: &str) -> Option<&[Option<i64>]> {
        match self.col(name)? {
            Col::Int(v) => Some(v),
            _ => None,
        }
    }

    /// The float column `name` (None if absent or of another kind).
    pub fn floats(&self, name: &str) -> Option<&[Option<f64>]> {
        match self.col(name)? {
            Col::Float(v) => Some(v),
            _ => None,
        }
    }

    /// The values of a string column of the table's definition (empty if absent: a table read
    /// through [`Def::read`] has every column).
    pub fn str(&self, c: &Column) -> &[String] {
        self.strings(c.name).unwrap_or_default()
    }

    /// The values of an integer column of the table's definition (empty if absent).
    pub fn int(&self, c: &Column) -> &[Option<i64>] {
        self.ints(c.name).unwrap_or_default()
    }

    /// The values of a float column of the table's definition (empty if absent).
    pub fn float(&self, c: &Column) -> &[Option<f64>] {
        self.floats(c.name).unwrap_or_default()
    }

    /// Append the column `c` of the table's definition.
    pub fn put(&mut self, c: &Column, col: Col) -> &mut Self {
        self.push(c.name, col)
    }

    /// Append the column `name`.
    pub fn push(&mut self, name: &str, col: Col) -> &mut Self {
        self.columns.push((name.to_string(), col));
        self
    }

    /// The table as an Arrow record batch (strings as Utf8, integers Int64, floats Float64; how
    /// the Python package hands a table over without writing it).
    pub fn to_arrow(&self) -> arrow_array::RecordBatch {
        use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, RecordBatchOptions, StringArray};
        use arrow_schema::{Field, Schema};
        let (fields, arrays): (Vec<Field>, Vec<ArrayRef>) = self
            .columns
            .iter()
            .map(|(name, c)| {
                let array: ArrayRef = match c {
                    Col::Str(v) => std::sync::Arc::new(StringArray::from_iter_values(v)),
                    Col::Int(v) => std::sync::Arc::new(Int64Array::from(v.clone())),
                    Col::Float(v) => std::sync::Arc::new(Float64Array::from(v.clone())),
                };
                (Field::new(name, c.ty().arrow(), true), array)
            })
            .unzip();
        let options = RecordBatchOptions::new().with_row_count(Some(self.height()));
        RecordBatch::try_new_with_options(std::sync::Arc::new(Schema::new(fields)), arrays, &options).expect("columns of the table's height")
    }

    /// Write as Parquet (zstd) to `path`; a table holding NaN, ±∞ or a negative count, variance,
    /// standard error or density is refused before anything is written (the last guard of
    /// every stage's tables).
    pub fn write_parquet(&self, path: &Path) -> PolarsResult<()> {
        if let Some(problem) = self.first_impossible() {
            polars_bail!(ComputeError: "{}: refused to write {problem}", path.display());
        }
        let columns: Vec<polars::prelude::Column> = self
            .columns
            .iter()
            .map(|(name, c)| match c {
                Col::Str(v) => polars::prelude::Column::new(name.as_str().into(), v),
                Col::Int(v) => polars::prelude::Column::new(name.as_str().into(), v),
                Col::Float(v) => polars::prelude::Column::new(name.as_str().into(), v),
            })
            .collect();
        let mut df = DataFrame::new_infer_height(columns)?;
        let file = File::create(path).map_err(|e| polars_err!(ComputeError: "{}: {e}", path.display()))?;
        ParquetWriter::new(file).with_compression(ParquetCompression::Zstd(None)).finish(&mut df)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    table! {
        /// a table with run-dependent columns around its own
        spanned = "spanned.parquet", "test" {
            A: "a", Int, "a";
            B: "b", Float, "b";
        }
    }

    fn of(columns: &[(&str, Col)]) -> Table {
        Table { columns: columns.iter().map(|(n, c)| (n.to_string(), c.clone())).collect() }
    }

    #[test]
    fn a_span_is_found_after_leading_columns_and_checked() {
        let (int, float) = (Col::Int(vec![Some(1)]), Col::Float(vec![Some(1.0)]));
        let t = of(&[("key1", float.clone()), ("key2", float.clone()), ("a", int.clone()), ("b", float.clone()), ("tail", float.clone())]);
        assert_eq!(spanned::DEF.check_span(&t), Ok(2));
        assert_eq!(spanned::DEF.check_span(&of(&[("a", int.clone()), ("b", float.clone())])), Ok(0));
        let missing = spanned::DEF.check_span(&of(&[("key", float.clone()), ("b", float.clone())])).unwrap_err();
        assert!(missing.contains("column `a` is missing"), "{missing}");
        let typed = spanned::DEF.check_span(&of(&[("a", int.clone()), ("b", int.clone())])).unwrap_err();
        assert!(typed.contains("column `b` is Int"), "{typed}");
        let cut = spanned::DEF.check_span(&of(&[("a", int), ("x", float)])).unwrap_err();
        assert!(cut.contains("column `b` is missing"), "{cut}");
    }
}
