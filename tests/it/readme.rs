//! The README quotes what the runs print: its blocks are what `reproduce` prints on the paper
//! scenario (issue 20, item 20) and what `exact-law` prints, so the README's numbers cannot drift
//! from the code's.

use std::path::Path;

use crate::common::stickslip;

/// The README's block between `<!-- NAME stdout: begin -->` and `<!-- NAME stdout: end -->` is
/// what `stickslip ARGS` prints.
fn block_is_what_it_prints(name: &str, args: &[&str]) {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let begin = format!("<!-- {name} stdout: begin -->\n```text\n");
    let end = format!("\n```\n<!-- {name} stdout: end -->");
    let start = readme.find(&begin).unwrap_or_else(|| panic!("the README has the {name} block")) + begin.len();
    let quoted = &readme[start..start + readme[start..].find(&end).expect("the block ends")];
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(args, tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed = String::from_utf8_lossy(&o.stdout);
    let printed = printed.trim_end_matches('\n');
    if quoted != printed {
        let first = quoted.lines().zip(printed.lines()).position(|(a, b)| a != b);
        panic!("the README's {name} block differs from what it prints (first differing line {first:?}):\n--- README\n{quoted}\n--- printed\n{printed}");
    }
}

#[test]
fn the_readme_block_is_what_reproduce_prints() {
    block_is_what_it_prints("reproduce", &["reproduce", "--out", "paper"]);
}

#[test]
fn the_readme_block_is_what_exact_law_prints() {
    block_is_what_it_prints("exact-law", &["exact-law", "--out", "law"]);
}

/// The README's dataset table lists every column of the one declaration
/// (`stickslip::simulation::schema::COLUMNS`) with its type: the documentation cannot drift from
/// the writer and the reader.
#[test]
fn the_readme_dataset_table_is_the_declared_schema() {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let section = &readme[readme.find("## The dataset").expect("the section")..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
    let rows: Vec<Vec<&str>> = section.lines().filter(|l| l.starts_with("| ")).map(|l| l.split(" | ").map(|c| c.trim_matches(['|', ' '])).collect()).collect();
    for c in stickslip::simulation::schema::COLUMNS {
        let row =
            rows.iter().find(|r| r[0].split(", ").any(|n| n == c.name)).unwrap_or_else(|| panic!("the README's dataset table has no row for `{}`", c.name));
        assert_eq!(row[1].replace("string", "utf8"), c.kind().name(), "`{}`", c.name);
    }
    assert!(rows.len() <= stickslip::simulation::schema::COLUMNS.len() + 2, "a README row for a column the schema does not declare");
}
