//! The README quotes what the run prints: its block is what `reproduce` prints on the paper
//! scenario (issue 20, item 20), so the README's numbers cannot drift from the code's.

use std::path::Path;

use crate::common::stickslip;

#[test]
fn the_readme_block_is_what_reproduce_prints() {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let begin = "<!-- reproduce stdout: begin -->\n```text\n";
    let end = "\n```\n<!-- reproduce stdout: end -->";
    let start = readme.find(begin).expect("the README has the reproduce block") + begin.len();
    let quoted = &readme[start..start + readme[start..].find(end).expect("the block ends")];
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["reproduce", "--out", "paper"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed = String::from_utf8_lossy(&o.stdout);
    let printed = printed.trim_end_matches('\n');
    if quoted != printed {
        let first = quoted.lines().zip(printed.lines()).position(|(a, b)| a != b);
        panic!("the README's block differs from what reproduce prints (first differing line {first:?}):\n--- README\n{quoted}\n--- printed\n{printed}");
    }
}
