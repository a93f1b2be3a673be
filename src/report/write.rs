//! Writing the report: the page and its Markdown twin, refused before either is written when
//! either may not be replaced.

use std::path::{Path, PathBuf};

use super::error::{ReportError, HTML_MARK, MD_MARK};
use super::page::{content, html, markdown};

/// Whether the report `out` (HTML) and its Markdown twin may be written: absent, or the tool's own
/// (checked by `reproduce` before its first stage, and by [`run`] before it writes).
pub fn check_replaceable(out: &Path) -> Result<(), ReportError> {
    let contains = |mark: &'static str| move |head: &[u8]| String::from_utf8_lossy(head).contains(mark);
    crate::outdir::check_file_replaceable(out, &contains(HTML_MARK), "--out")?;
    crate::outdir::check_file_replaceable(&out.with_extension("md"), &contains(MD_MARK), "--out")?;
    Ok(())
}

/// Write `out` (HTML, a name ending in `.html`) and its Markdown twin (same path, `.md`);
/// returns both paths. Neither may lie inside an input, nor replace a file the tool did not write.
/// `exact` (if given) is an `exact-law` output directory: its Table 1 goes beside ours.
pub fn run(dataset: &Path, adir: &Path, figdir: &Path, exact: Option<&Path>, out: &Path) -> Result<[PathBuf; 2], ReportError> {
    use crate::outdir::{check_separate, write_file, OutDirError};
    if out.extension().is_none_or(|x| x != "html") {
        return Err(OutDirError { path: out.to_owned(), message: "--out must name an .html file (its Markdown twin gets .md)".into(), refused: true }.into());
    }
    let md_path = out.with_extension("md");
    for p in [out, md_path.as_path()] {
        check_separate(p, "--out", &[dataset, adir, figdir].into_iter().chain(exact).collect::<Vec<_>>())?;
    }
    let contains = |mark: &'static str| move |head: &[u8]| String::from_utf8_lossy(head).contains(mark);
    // the page and its Markdown twin are both refused before either is written
    check_replaceable(out)?;
    let c = content(dataset, adir, figdir, exact)?;
    let (h, m) = (html(&c, figdir)?, markdown(&c, figdir));
    let created = match out.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(dir) => crate::outdir::Created::dir_all(dir)?,
        None => crate::outdir::Created::default(),
    };
    write_file(out, h.as_bytes(), contains(HTML_MARK), "--out")?;
    write_file(&md_path, m.as_bytes(), contains(MD_MARK), "--out")?;
    created.keep();
    Ok([out.to_owned(), md_path])
}
