//! The analysis of the paper scenario pinned before the analysis stage is rebuilt (issue 21):
//! every table equals `tests/fixtures/paper-analysis/` within 1e-12 relative (reassociation
//! only), histogram counts, strings and integers exactly. See that folder's README.

use std::path::Path;

use stickslip::table::{Col, Table};

use crate::common::stickslip;

const TABLES: [&str; 8] = ["moments", "histograms", "joint_histograms", "independence", "growth", "convergence", "survival", "tails"];

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

fn same_json(a: &serde_json::Value, b: &serde_json::Value, at: &str) -> Result<(), String> {
    use serde_json::Value as V;
    match (a, b) {
        (V::Number(x), V::Number(y)) if close(x.as_f64().unwrap(), y.as_f64().unwrap()) => Ok(()),
        (V::Object(x), V::Object(y)) => {
            let (kx, ky): (Vec<&String>, Vec<&String>) = (x.keys().collect(), y.keys().collect());
            if kx != ky {
                return Err(format!("{at}: keys {kx:?} vs {ky:?}"));
            }
            // the dataset's file paths depend on where it was written
            x.iter()
                .filter(|(k, _)| !(at == "dataset" && *k == "files"))
                .try_for_each(|(k, v)| same_json(v, &y[k], &if at.is_empty() { k.clone() } else { format!("{at}.{k}") }))
        }
        (V::Array(x), V::Array(y)) if x.len() == y.len() => x.iter().zip(y).enumerate().try_for_each(|(i, (p, q))| same_json(p, q, &format!("{at}[{i}]"))),
        _ if a == b => Ok(()),
        _ => Err(format!("{at}: {a} vs {b}")),
    }
}

#[test]
fn the_paper_analysis_equals_the_pinned_tables() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["reproduce", "--out", "p", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let pinned = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/paper-analysis");
    let now = tmp.path().join("p/analysis");
    for name in TABLES {
        let file = format!("{name}.parquet");
        let (a, b) = (Table::read_parquet(&now.join(&file)).unwrap(), Table::read_parquet(&pinned.join(&file)).unwrap());
        let names = |t: &Table| t.columns.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        assert_eq!(names(&a), names(&b), "{file}: columns");
        for ((col, x), (_, y)) in a.columns.iter().zip(&b.columns) {
            match (x, y) {
                (Col::Float(x), Col::Float(y)) => {
                    assert_eq!(x.len(), y.len(), "{file}.{col}: rows");
                    for (r, (p, q)) in x.iter().zip(y).enumerate() {
                        let same = match (p, q) {
                            (Some(p), Some(q)) => close(*p, *q),
                            (None, None) => true,
                            _ => false,
                        };
                        assert!(same, "{file}.{col} row {r}: {p:?}, pinned {q:?}");
                    }
                }
                (Col::Int(x), Col::Int(y)) => assert_eq!(x, y, "{file}.{col}"),
                (Col::Str(x), Col::Str(y)) => assert_eq!(x, y, "{file}.{col}"),
                _ => panic!("{file}.{col}: the column's type changed"),
            }
        }
    }
    let json = |dir: &Path| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap() };
    same_json(&json(&now), &json(&pinned), "").unwrap_or_else(|e| panic!("summary.json: {e}"));
    assert_eq!(std::fs::read_to_string(now.join("table1.md")).unwrap(), std::fs::read_to_string(pinned.join("table1.md")).unwrap(), "table1.md");
}
