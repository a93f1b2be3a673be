//! What the figures are drawn from: the analysis tables, each read through its definition, the
//! recorded scenario and realization 0's trajectory.

use std::path::Path;

use super::error::FigureError;
use super::trajectory::Trajectory;
use crate::analysis::tables::{histograms, moments};
use crate::scenario::Scenario;
use crate::table::{Column, Def, Table};

/// The analysis tables the figures are drawn from.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// `moments.parquet`
    pub moments: Table,
    /// `histograms.parquet`
    pub histograms: Table,
    /// `joint_histograms.parquet`
    pub joints: Table,
    /// `independence.parquet`
    pub independence: Table,
    /// `growth.parquet`
    pub growth: Table,
    /// the scenario recorded in `summary.json`
    pub scenario: Scenario,
    /// realization 0's sampled trajectory, if the analysis has the trajectory tables
    pub trajectory: Option<Trajectory>,
    /// `convergence.parquet`, if the analysis has one (older analyses do not)
    pub convergence: Option<Table>,
    /// `survival.parquet` and `tails.parquet`, if the analysis has the tails (not with
    /// `--no-tails`, nor before them)
    pub survival: Option<Table>,
    /// `tails.parquet` (see `survival`)
    pub tails: Option<Table>,
}

impl Inputs {
    /// Read the tables of an analysis directory, each through its definition
    /// ([`crate::analysis::tables`]): a table of another shape is refused, naming the column.
    pub fn load(adir: &Path) -> Result<Inputs, FigureError> {
        use crate::analysis::tables as t;
        let read = |def: &Def| def.read(adir).map_err(|message| FigureError::Read { path: adir.join(def.file), message });
        // (the convergence table and the tails came later: an analysis without them is read)
        let optional = |def: &Def| if adir.join(def.file).exists() { read(def).map(Some) } else { Ok(None) };
        let summary_path = adir.join("summary.json");
        let bad = |message: String| FigureError::Read { path: summary_path.clone(), message };
        let toml = crate::analysis::summary::Summary::read_scenario(&summary_path).map_err(bad)?;
        let scenario = Scenario::recorded(&toml, &summary_path).map_err(|e| bad(e.to_string()))?;
        Ok(Inputs {
            moments: read(&t::moments::DEF)?,
            histograms: read(&t::histograms::DEF)?,
            joints: read(&t::joint_histograms::DEF)?,
            independence: read(&t::independence::DEF)?,
            growth: read(&t::growth::DEF)?,
            scenario,
            trajectory: Trajectory::load(adir)?,
            convergence: optional(&t::convergence::DEF)?,
            survival: optional(&t::survival::DEF)?,
            tails: optional(&t::tails::DEF)?,
        })
    }

    /// Rows of `table` whose `variable` / `index` columns match.
    fn rows<'a>(table: &'a Table, var: &'a str, index: Option<i64>) -> impl Iterator<Item = usize> + 'a {
        // (moments and histograms share the keys' columns)
        let (vars, idx) = (table.str(&moments::VARIABLE), table.int(&moments::INDEX));
        (0..table.height()).filter(move |&r| vars.get(r).map(String::as_str) == Some(var) && idx.get(r).copied().flatten() == index)
    }

    /// (lo, hi, density) bins of one series' histogram.
    pub fn histogram(&self, var: &str, index: Option<i64>) -> Vec<(f64, f64, f64)> {
        let h = &self.histograms;
        let (lo, hi, d) = (h.float(&histograms::LO), h.float(&histograms::HI), h.float(&histograms::DENSITY));
        Self::rows(h, var, index).filter_map(|r| Some((lo[r]?, hi[r]?, d[r]?))).collect()
    }

    pub(super) fn moment(&self, var: &str, index: Option<i64>, column: &Column) -> Option<f64> {
        let col = self.moments.float(column);
        Self::rows(&self.moments, var, index).next().and_then(|r| col.get(r).copied().flatten())
    }
}
