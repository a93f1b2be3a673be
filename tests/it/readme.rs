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
