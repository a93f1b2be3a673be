//! Drawing every figure of an analysis directory (every cell of a sweep's) into the figures
//! directory, replaced when complete.

use std::path::{Path, PathBuf};

use super::error::FigureError;
use super::inputs::Inputs;
use super::paper::{all, sweep_figure};
use super::render;
use crate::outdir::{Kind, StagedDir};
use crate::table::Table;

/// Render every figure of the analysis in `adir` into `out` (replaced when complete). For a sweep
/// (`adir/sweep.parquet`), the sweep maps and every cell's figures under `out/key=value/…`.
pub fn run(adir: &Path, out: &Path) -> Result<Vec<String>, FigureError> {
    let staged = StagedDir::new(out, Kind::Figures, "--out", &[adir])?;
    let mut names = Vec::new();
    let sweep_path = adir.join(crate::analysis::sweep::sweep::DEF.file);
    if sweep_path.is_file() {
        let read = Table::read_parquet(&sweep_path).map_err(|e| e.to_string());
        let sweep = read
            .and_then(|t| crate::analysis::sweep::sweep::DEF.check_span(&t).map(|_| t))
            .map_err(|message| FigureError::Read { path: sweep_path.clone(), message })?;
        if let Some(f) = sweep_figure(&sweep) {
            render::save(&f, staged.path()).map_err(|message| FigureError::Draw { name: f.name.clone(), message })?;
            names.push(f.name);
        }
        let mut cells = Vec::new();
        find_cells(adir, adir, &mut cells);
        cells.sort_by(|a, b| crate::analysis::sweep::cell_order(&a.to_string_lossy(), &b.to_string_lossy()));
        for cell in cells {
            let dir = staged.path().join(&cell);
            std::fs::create_dir_all(&dir).map_err(|e| FigureError::Draw { name: cell.display().to_string(), message: e.to_string() })?;
            names.extend(draw_all(&adir.join(&cell), &dir)?.into_iter().map(|n| format!("{}/{n}", cell.display())));
        }
    } else {
        names = draw_all(adir, staged.path())?;
    }
    staged.commit()?;
    Ok(names)
}

/// Directories below `root` that hold an analysis (a `summary.json`), relative to `root`.
fn find_cells(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut subdirs: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_dir()).collect();
    subdirs.sort();
    for d in subdirs {
        if d.join("summary.json").is_file() {
            out.push(d.strip_prefix(root).unwrap_or(&d).to_owned());
        }
        find_cells(root, &d, out);
    }
}

/// Draw every figure of one analysis directory into `dir`.
fn draw_all(adir: &Path, dir: &Path) -> Result<Vec<String>, FigureError> {
    let inputs = Inputs::load(adir)?;
    let figures = all(&inputs);
    for f in &figures {
        render::save(f, dir).map_err(|message| FigureError::Draw { name: f.name.clone(), message })?;
    }
    Ok(figures.into_iter().map(|f| f.name).collect())
}
