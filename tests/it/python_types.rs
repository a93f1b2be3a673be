//! The Python package's typed summary (`python/stickslip/_summary.py`) is generated from the Rust
//! `Summary` (`src/analysis/summary.rs`): this test generates it again and fails when the
//! committed file differs. `STICKSLIP_BLESS=1 cargo test --release python_summary` rewrites it.

use std::path::Path;

/// A Rust field type as a Python annotation.
fn python_type(rust: &str) -> String {
    let rust = rust.trim();
    let inner = |prefix: &str| rust.strip_prefix(prefix).and_then(|r| r.strip_suffix('>'));
    if let Some(t) = inner("Option<") {
        return format!("Optional[{}]", python_type(t));
    }
    if let Some(t) = inner("Vec<") {
        return format!("List[{}]", python_type(t));
    }
    if let Some(t) = inner("BTreeMap<String,") {
        return format!("Dict[str, {}]", python_type(t));
    }
    if let Some((t, n)) = rust.strip_prefix('[').and_then(|r| r.strip_suffix(']')).and_then(|r| r.split_once(';')) {
        let n: usize = n.trim().parse().expect("an array length");
        return format!("Tuple[{}]", vec![python_type(t); n].join(", "));
    }
    match rust {
        "String" => "str".into(),
        "u64" | "u32" | "usize" | "i64" => "int".into(),
        "f64" => "float".into(),
        "bool" => "bool".into(),
        // (the module has `from __future__ import annotations`: a later class is no error)
        name => name.to_string(),
    }
}

/// The Python module for the Rust source of the summary.
fn generate(source: &str) -> String {
    let mut out = String::from(
        "\"\"\"The typed summary of an analysis (``summary.json``), generated from the Rust ``Summary``\n\
         (``src/analysis/summary.rs``) by ``STICKSLIP_BLESS=1 cargo test --release python_summary``;\n\
         do not edit: a test regenerates it and fails when it differs. A number that is not finite\n\
         is ``None``.\"\"\"\n\n\
         from __future__ import annotations\n\n\
         from dataclasses import dataclass\n\
         from typing import Dict, List, Optional, Tuple, Union\n",
    );
    let (mut docs, mut rename, mut untagged): (Vec<String>, Option<String>, bool) = (Vec::new(), None, false);
    let mut open: Option<(String, bool)> = None; // (name, is an untagged enum)
    let mut variants: Vec<String> = Vec::new();
    for line in source.lines().map(str::trim) {
        if let Some(doc) = line.strip_prefix("///") {
            docs.push(doc.trim().to_string());
        } else if line.starts_with("#[serde(untagged)]") {
            untagged = true;
        } else if let Some(r) = line.strip_prefix("#[serde(rename = \"") {
            rename = Some(r.trim_end_matches("\")]").to_string());
        } else if let Some(name) = line.strip_prefix("pub struct ").and_then(|l| l.strip_suffix(" {")) {
            out += &format!("\n\n@dataclass(frozen=True)\nclass {name}:\n    \"\"\"{}\"\"\"\n\n", docs.join(" "));
            open = Some((name.to_string(), false));
            docs.clear();
        } else if let Some(name) = line.strip_prefix("pub enum ").and_then(|l| l.strip_suffix(" {")) {
            assert!(untagged, "only untagged enums (a value of one of the variants' types) are mapped");
            out += &format!("\n\n#: {}\n", docs.join(" "));
            open = Some((name.to_string(), true));
            docs.clear();
        } else if line == "}" {
            if let Some((name, true)) = open.take() {
                out += &format!("{name} = Union[{}]\n", variants.join(", "));
                variants.clear();
                untagged = false;
            }
        } else if let (Some((_, false)), Some(field)) = (&open, line.strip_prefix("pub ")) {
            let (name, ty) = field.trim_end_matches(',').split_once(':').expect("pub name: Type");
            for d in docs.drain(..) {
                out += &format!("    #: {d}\n");
            }
            out += &format!("    {}: {}\n", rename.take().unwrap_or_else(|| name.trim().to_string()), python_type(ty));
        } else if let (Some((_, true)), Some((_, ty))) = (&open, line.split_once('(')) {
            variants.push(python_type(ty.trim_end_matches("),")));
            docs.clear(); // (a variant's own doc)
        }
    }
    out
}

#[test]
fn python_summary_is_generated_from_the_rust_summary() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let source = std::fs::read_to_string(root.join("src/analysis/summary.rs")).unwrap();
    let source = &source[..source.find("\nimpl ").expect("the types come first")];
    let generated = generate(source);
    let path = root.join("python/stickslip/_summary.py");
    if std::env::var_os("STICKSLIP_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{} is not what src/analysis/summary.rs generates: run STICKSLIP_BLESS=1 cargo test --release python_summary",
        path.display()
    );
    // every struct of the source became a class, every field an annotation
    let structs = source.matches("pub struct ").count();
    assert_eq!(generated.matches("@dataclass(frozen=True)").count(), structs);
    assert_eq!(
        generated.matches("\n    ").count() - generated.matches("    #: ").count() - generated.matches("    \"\"\"").count(),
        source.matches("    pub ").count()
    );
}

#[test]
fn rust_types_map_to_python_annotations() {
    assert_eq!(python_type("Option<[Option<f64>; 2]>"), "Optional[Tuple[Optional[float], Optional[float]]]");
    assert_eq!(python_type("BTreeMap<String, CountSummary>"), "Dict[str, CountSummary]");
    assert_eq!(python_type("Vec<String>"), "List[str]");
}
