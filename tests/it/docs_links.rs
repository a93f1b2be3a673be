//! The README and the book hold together: every relative link and anchor resolves (a book page
//! links only inside the book, which is all mdBook publishes), every page is in `SUMMARY.md`, and
//! the code layout page names every source file. Anchors are computed as mdBook 0.5 makes heading
//! ids (`id_from_content` in mdbook-html: trimmed, lowercased, alphanumerics, `_` and `-` kept,
//! whitespace to `-`, the rest dropped; a repeated id gets `-1`, `-2`, …).

use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};

use crate::common::files_below;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn book() -> PathBuf {
    root().join("docs/src")
}

/// Every Markdown page of the book, sorted.
fn pages() -> Vec<PathBuf> {
    files_below(&book()).into_iter().filter(|p| p.extension().is_some_and(|e| e == "md")).collect()
}

/// The text a reader sees as prose: fenced code blocks and inline code spans blanked out.
fn prose(text: &str) -> String {
    let mut out = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            out.push('\n');
            continue;
        }
        if !fenced {
            let mut in_code = false;
            out.extend(line.chars().map(|c| {
                if c == '`' {
                    in_code = !in_code;
                    ' '
                } else if in_code {
                    ' '
                } else {
                    c
                }
            }));
        }
        out.push('\n');
    }
    out
}

/// The targets of the inline links `[text](target)` in `text`'s prose.
fn links(text: &str) -> Vec<String> {
    let prose = prose(text);
    let mut out = Vec::new();
    let mut rest = prose.as_str();
    while let Some(at) = rest.find("](") {
        let after = &rest[at + 2..];
        let end = after.find(')').expect("a link's target ends");
        out.push(after[..end].trim().to_string());
        rest = &after[end..];
    }
    out
}

/// mdBook's heading id of a heading's text (its inline Markdown reduced to the words shown).
fn heading_id(heading: &str) -> String {
    let mut shown = String::new();
    let mut rest = heading;
    // a link [text](target) shows its text
    while let Some(open) = rest.find('[') {
        shown += &rest[..open];
        let after = &rest[open + 1..];
        match (after.find("]("), after.find(')')) {
            (Some(close), Some(end)) if close < end => {
                shown += &after[..close];
                rest = &after[end + 1..];
            }
            _ => {
                shown.push('[');
                rest = after;
            }
        }
    }
    shown += rest;
    let shown = shown.replace(['`', '*'], "");
    shown
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// Every heading id of a page, with mdBook's suffixes for repeats.
fn anchors(text: &str) -> HashSet<String> {
    let mut used = HashSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let level = line.chars().take_while(|&c| c == '#').count();
        if fenced || level == 0 || level > 6 || !line[level..].starts_with(' ') {
            continue;
        }
        let id = heading_id(&line[level + 1..]);
        if !used.insert(id.clone()) {
            let mut n = 1;
            while !used.insert(format!("{id}-{n}")) {
                n += 1;
            }
        }
    }
    used
}

/// `path` with `.` and `..` folded away (the files need not exist).
fn normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// What is wrong with each relative link of `file`; `within`: the folder its links must stay in.
fn broken(file: &Path, within: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap();
    let mut out = Vec::new();
    for target in links(&text) {
        if target.starts_with("http://") || target.starts_with("https://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = target.split_once('#').map_or((target.as_str(), None), |(p, a)| (p, Some(a)));
        let resolved = if path.is_empty() { file.to_path_buf() } else { normal(&file.parent().unwrap().join(path)) };
        let name = file.strip_prefix(root()).unwrap().display().to_string();
        if !resolved.starts_with(within) {
            out.push(format!("{name}: {target} leads outside {}", within.strip_prefix(root()).unwrap_or(within).display()));
        } else if !resolved.exists() {
            out.push(format!("{name}: {target}: no such file"));
        } else if let Some(anchor) = anchor {
            let page = std::fs::read_to_string(&resolved).unwrap_or_default();
            if resolved.extension().is_none_or(|e| e != "md") || !anchors(&page).contains(anchor) {
                out.push(format!("{name}: {target}: no heading with that anchor"));
            }
        }
    }
    out
}

#[test]
fn every_relative_link_and_anchor_resolves() {
    let mut bad = broken(&root().join("README.md"), &root());
    for page in pages() {
        bad.extend(broken(&page, &book()));
    }
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}

#[test]
fn the_anchor_rule_is_mdbooks() {
    // the ids mdBook 0.5.4 gave these headings in the built book
    assert_eq!(heading_id("Why results differ from the paper by about 1 %"), "why-results-differ-from-the-paper-by-about-1-");
    assert_eq!(heading_id("How `simulate` is fast"), "how-simulate-is-fast");
    assert_eq!(heading_id("The accurate end: dop853 against compiled and interpreted peers"), "the-accurate-end-dop853-against-compiled-and-interpreted-peers");
    assert_eq!(heading_id("A sweep's cells"), "a-sweeps-cells");
    let ids = anchors("# A\n\n## Tests\n\n```\n# not a heading\n```\n\n## Tests\n");
    assert!(ids.contains("tests") && ids.contains("tests-1") && !ids.contains("not-a-heading"));
    assert_eq!(links("[a](x.md) `[b](y.md)` [c](z.md#q)\n```\n[d](w.md)\n```\n"), ["x.md", "z.md#q"]);
}

#[test]
fn every_book_page_is_in_the_summary() {
    let summary = std::fs::read_to_string(book().join("SUMMARY.md")).unwrap();
    let listed: HashSet<PathBuf> = links(&summary).iter().map(|l| book().join(l)).collect();
    for page in pages() {
        if page.file_name().is_some_and(|n| n == "SUMMARY.md") {
            continue;
        }
        assert!(listed.contains(&page), "{} is not in docs/src/SUMMARY.md", page.display());
    }
}

/// The layout page names every source file: a top-level `src/NAME.rs` by its path, a file in a
/// folder by its path within the folder, in the bullet that names the folder (`src/law/` …
/// `flow.rs`, `src/simulation/` … `belt/markov.rs`).
#[test]
fn the_layout_page_names_every_source_file() {
    let layout = std::fs::read_to_string(book().join("contributing/layout.md")).unwrap();
    let bullets: Vec<&str> = layout.split("\n- ").collect();
    let mut missing = Vec::new();
    let src = root().join("src");
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            let folder = format!("`src/{name}/`");
            let bullet = bullets.iter().find(|b| b.contains(&folder));
            let files = files_below(&path).into_iter().map(|p| p.strip_prefix(&path).unwrap().to_string_lossy().to_string());
            for file in files {
                if file == "mod.rs" {
                    continue;
                }
                if !bullet.is_some_and(|b| b.contains(&format!("`{file}`")) || b.contains(&format!("`{}`", file.trim_end_matches(".rs")))) {
                    missing.push(format!("src/{name}/{file}"));
                }
            }
        } else if name != "lib.rs" && name != "main.rs" && !layout.contains(&format!("`src/{name}`")) {
            missing.push(format!("src/{name}"));
        }
    }
    assert!(missing.is_empty(), "docs/src/contributing/layout.md does not name: {}", missing.join(", "));
}

/// One version: Cargo.toml's `[workspace.package]` (both crates inherit it, `--version` and the
/// provenance read it), which pyproject.toml takes from maturin, CITATION.cff states, and
/// CHANGELOG.md has a section for.
#[test]
fn the_release_has_one_version() {
    let version = env!("CARGO_PKG_VERSION");
    let read = |f: &str| std::fs::read_to_string(root().join(f)).unwrap();
    let cff = read("CITATION.cff");
    assert!(cff.lines().any(|l| l == format!("version: \"{version}\"")), "CITATION.cff's version is not {version}");
    let pyproject = read("pyproject.toml");
    assert!(pyproject.contains("dynamic = [\"version\"]") && !pyproject.lines().any(|l| l.starts_with("version")), "pyproject.toml sets its own version");
    assert!(read("python/Cargo.toml").contains("version.workspace = true"), "the extension's crate sets its own version");
    assert!(read("CHANGELOG.md").contains(&format!("## [{version}]")), "CHANGELOG.md has no section for {version}");
}
