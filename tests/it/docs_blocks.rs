//! The book quotes what the runs print: its blocks are what `reproduce` prints on the paper
//! scenario (the tutorial "Reproduce the paper") and what `exact-law` prints (the how-to "The law
//! without sampling"), so the book's numbers cannot drift from the code's.

use std::path::Path;

use crate::common::stickslip;

/// The text block between `<!-- MARK: begin -->` and `<!-- MARK: end -->` in `text`.
fn quoted<'a>(text: &'a str, mark: &str) -> Option<&'a str> {
    let begin = format!("<!-- {mark}: begin -->\n```text\n");
    let start = text.find(&begin)? + begin.len();
    Some(&text[start..start + text[start..].find(&format!("\n```\n<!-- {mark}: end -->"))?])
}

/// The block of the book's `page` between `<!-- NAME stdout: begin -->` and `<!-- NAME stdout:
/// end -->` is what `stickslip ARGS` prints.
fn block_is_what_it_prints(page: &str, name: &str, args: &[&str]) {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src").join(page)).unwrap();
    let quoted = quoted(&readme, &format!("{name} stdout")).unwrap_or_else(|| panic!("{page} has the {name} block"));
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(args, tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed = String::from_utf8_lossy(&o.stdout);
    let printed = printed.trim_end_matches('\n');
    if quoted != printed {
        let first = quoted.lines().zip(printed.lines()).position(|(a, b)| a != b);
        panic!("{page}'s {name} block differs from what it prints (first differing line {first:?}):\n--- {page}\n{quoted}\n--- printed\n{printed}");
    }
}

#[test]
fn the_tutorial_block_is_what_reproduce_prints() {
    block_is_what_it_prints("tutorials/reproduce.md", "reproduce", &["reproduce", "--out", "paper"]);
}

#[test]
fn the_how_to_block_is_what_exact_law_prints() {
    block_is_what_it_prints("how-to/exact-law.md", "exact-law", &["exact-law", "--out", "law"]);
}

/// The README's command-line example: the `simulate` command it shows prints the line it quotes
/// (on standard error, beside the run's timing, which is not quoted).
#[test]
fn the_readme_cli_example_prints_what_the_readme_says() {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let command = readme.lines().find(|l| l.starts_with("cargo run --release -- simulate")).expect("the README's simulate example");
    let args: Vec<&str> = command.trim_start_matches("cargo run --release -- ").split_whitespace().collect();
    let quoted = quoted(&readme, "readme cli stderr").expect("the README's quoted output");
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&args, tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let printed = String::from_utf8_lossy(&o.stderr);
    for line in quoted.lines() {
        assert!(printed.lines().any(|l| l == line), "the README quotes {line:?}; the command printed:\n{printed}");
    }
}
