//! The `report` stage: one self-contained HTML page (figures inlined as SVG) and a Markdown twin.
//!
//! Contents: provenance of the run, our Table 1 beside the paper's with standard errors and each
//! mean / variance cell marked, S_T and S_L, the growth regressions and renewal check, the
//! independence tests, and every figure. A mean or variance is marked ✓ when it is within three
//! of our standard errors plus half a unit of the paper's last printed decimal (the paper gives no
//! errors and rounds to 2–3 decimals), ✗ otherwise, with the relative difference.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::analysis::frame::Table;
use crate::analysis::input;
use crate::analysis::paper;

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("reading {}: {message}", path.display())]
    Read { path: PathBuf, message: String },
    #[error("writing {}: {source}", path.display())]
    Write { path: PathBuf, source: std::io::Error },
    #[error(transparent)]
    Dataset(#[from] input::InputError),
}

/// One cell of the comparison: ours ± se against the paper's printed value.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub ours: Option<f64>,
    pub se: Option<f64>,
    pub paper: Option<f64>,
}

impl Cell {
    /// Half a unit of the last printed decimal of the paper's value.
    fn rounding(p: f64) -> f64 {
        let text = format!("{p}");
        let decimals = text.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
        0.5 * 10f64.powi(-decimals)
    }

    /// `Some(true)` if consistent (see the module docs), `None` without the numbers to judge.
    pub fn consistent(&self) -> Option<bool> {
        let (o, se, p) = (self.ours?, self.se?, self.paper?);
        Some((o - p).abs() <= 3.0 * se + Self::rounding(p))
    }

    fn text(&self, digits: usize) -> String {
        let f = |v: Option<f64>| v.map_or("–".into(), |x| format!("{x:.digits$}"));
        match (self.ours, self.se) {
            (Some(_), Some(_)) => format!("{} ± {}", f(self.ours), f(self.se)),
            _ => f(self.ours),
        }
    }

    /// `ours ± se [paper] mark`, as both renderings show a mean, variance or mode cell.
    fn shown(&self, digits: usize) -> String {
        let paper = self.paper.map_or(String::new(), |p| format!(" [{p}]"));
        format!("{}{paper} {}", self.text(digits), self.mark())
    }

    fn mark(&self) -> String {
        match (self.consistent(), self.ours, self.paper) {
            (Some(true), _, _) => "✓".into(),
            (Some(false), Some(o), Some(p)) => format!("✗ {:+.1} %", 100.0 * (o / p - 1.0)),
            _ => String::new(),
        }
    }
}

/// A row of Table 1: series label and (mean, variance, mode, skewness, kurtosis) cells.
#[derive(Debug, Clone)]
pub struct Row {
    pub label: String,
    pub n: i64,
    pub cells: [Cell; 5],
}

impl Row {
    /// `skewness [paper] / kurtosis [paper]`.
    fn shape(&self) -> String {
        let paper = |c: &Cell| c.paper.map_or("–".into(), |p| p.to_string());
        format!("{} [{}] / {} [{}]", self.cells[3].text(2), paper(&self.cells[3]), self.cells[4].text(2), paper(&self.cells[4]))
    }
}

/// Table 1 from the analysis' `moments.parquet`.
pub fn table1(moments: &Table) -> Vec<Row> {
    let (vars, idx) = (moments.strings("variable").unwrap_or_default(), moments.ints("index").unwrap_or_default());
    let n = moments.ints("n").unwrap_or_default();
    let col = |c: &str| moments.floats(c).unwrap_or_default();
    let (mean, var, mode, skew, kurt, mse, vse) =
        (col("mean"), col("variance"), col("mode"), col("skewness"), col("kurtosis"), col("mean_se"), col("variance_se"));
    let mut rows = Vec::new();
    let wanted = paper::TABLE1.iter().map(|(v, k, p)| (*v, Some(*k), Some(*p))).chain(
        paper::COUNTS.iter().map(|(v, m, s2)| (*v, None, Some([*m, *s2, f64::NAN, f64::NAN, f64::NAN]))),
    );
    for (v, k, p) in wanted {
        let Some(r) = (0..vars.len()).find(|&r| vars[r] == v.name() && idx[r] == k.map(i64::from)) else { continue };
        let pv = |i: usize| p.map(|p| p[i]).filter(|x| x.is_finite());
        let cell = |ours: Option<f64>, se: Option<f64>, i: usize| Cell { ours, se, paper: pv(i) };
        rows.push(Row {
            label: k.map_or(v.name().to_string(), |k| format!("{}_{k}", v.name())),
            n: n[r].unwrap_or(0),
            cells: [
                cell(mean[r], mse[r], 0),
                cell(var[r], vse[r], 1),
                cell(mode[r], None, 2),
                cell(skew[r], None, 3),
                cell(kurt[r], None, 4),
            ],
        });
    }
    rows
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn num(v: &Value) -> String {
    v.as_f64().map_or("–".into(), |x| if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) { format!("{x:.3e}") } else { format!("{x:.4}") })
}

/// The report's sections as (heading, markdown-ish rows) — rendered to HTML and Markdown alike.
struct Content {
    provenance: Vec<(String, String)>,
    scenario: String,
    table1: Vec<Row>,
    growth: Vec<[String; 5]>,
    renewal: Vec<[String; 3]>,
    tests: Vec<[String; 8]>,
    figures: Vec<(String, PathBuf)>,
}

fn content(dataset: &Path, adir: &Path, figdir: &Path) -> Result<Content, ReportError> {
    let data = input::open(dataset)?;
    let read_err = |path: &Path, e: &dyn std::fmt::Display| ReportError::Read { path: path.to_owned(), message: e.to_string() };
    let summary_path = adir.join("summary.json");
    let text = std::fs::read_to_string(&summary_path).map_err(|e| read_err(&summary_path, &e))?;
    let summary: Value = serde_json::from_str(&text).map_err(|e| read_err(&summary_path, &e))?;
    let moments_path = adir.join("moments.parquet");
    let moments = Table::read_parquet(&moments_path).map_err(|e| read_err(&moments_path, &e))?;
    let sc = &data.scenario;
    let provenance = vec![
        ("dataset".into(), format!("{} ({} part file(s))", dataset.display(), data.files.len())),
        ("realizations".into(), data.rows.to_string()),
        ("seed".into(), sc.seed.to_string()),
        ("solver".into(), sc.solver.clone()),
        ("generator".into(), crate::rng::GENERATOR.into()),
        ("stickslip".into(), summary["stickslip_version"].as_str().unwrap_or("?").into()),
        ("analysis".into(), adir.display().to_string()),
        ("truncated intervals".into(), summary["policies"]["truncated_intervals"].as_str().unwrap_or("").into()),
        ("mode".into(), summary["policies"]["mode"].as_str().unwrap_or("").into()),
    ];
    let growth = summary["growth"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|g| {
            [
                format!("{} of {}_k", g["statistic"].as_str().unwrap_or(""), g["variable"].as_str().unwrap_or("")),
                num(&g["slope"]),
                num(&g["slope_se"]),
                num(&g["intercept"]),
                num(&g["r2"]),
            ]
        })
        .collect();
    let r = &summary["renewal_check"];
    let renewal = vec![
        ["E[S_T]".to_string(), num(&r["predicted_mean_S_T"]), num(&r["measured_mean_S_T"])],
        ["Var[S_T]".to_string(), num(&r["predicted_variance_S_T"]), num(&r["measured_variance_S_T"])],
    ];
    let tests = summary["independence"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|t| {
            [
                format!("({}, {})", t["x"].as_str().unwrap_or(""), t["y"].as_str().unwrap_or("")),
                t["n"].to_string(),
                format!("{} on {}", num(&t["chi2"]), t["df"]),
                num(&t["chi2_p_value"]),
                num(&t["g_p_value"]),
                num(&t["mutual_information"]),
                num(&t["mi_p_value"]),
                t["verdict"].as_str().unwrap_or("").to_string(),
            ]
        })
        .collect();
    let mut figures: Vec<(String, PathBuf)> = std::fs::read_dir(figdir)
        .map_err(|e| read_err(figdir, &e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .map(|p| (p.file_stem().unwrap_or_default().to_string_lossy().into_owned(), p))
        .collect();
    figures.sort();
    Ok(Content { provenance, scenario: sc.to_toml(), table1: table1(&moments), growth, renewal, tests, figures })
}

const TABLE1_HEAD: [&str; 6] = ["variable", "n", "mean", "variance", "mode", "skewness / kurtosis"];

fn html(c: &Content, figdir: &Path) -> Result<String, ReportError> {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>stickslip report</title>\n<style>\n\
         body {{ font-family: sans-serif; max-width: 1300px; margin: 2em auto; color: #222; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; }}\n\
         td, th {{ border: 1px solid #ccc; padding: 3px 8px; text-align: right; }}\n\
         th {{ background: #f3f3f3; }} td.l {{ text-align: left; }}\n\
         .ok {{ color: #1a7f37; }} .off {{ color: #b3261e; font-weight: bold; }}\n\
         figure {{ margin: 2em 0; }} figure svg {{ max-width: 100%; height: auto; }}\n\
         pre {{ background: #f6f6f6; padding: 1em; }}\n</style>\n</head>\n<body>\n\
         <h1>Stick-slip oscillator on a random bang-bang belt</h1>\n\
         <p>Reproduction of Lima &amp; Sampaio, <em>Analysis of a dry-friction oscillator driven by a stochastic base motion</em>, with the exact event-driven solver of stickslip.</p>\n\
         <h2>Provenance</h2>\n<table>\n"
    );
    for (k, v) in &c.provenance {
        let _ = writeln!(h, "<tr><th>{}</th><td class=\"l\">{}</td></tr>", escape(k), escape(v));
    }
    let _ = write!(h, "</table>\n<details><summary>resolved scenario</summary>\n<pre>{}</pre>\n</details>\n", escape(&c.scenario));
    let _ = write!(
        h,
        "<h2>Table 1: ours beside the paper's</h2>\n<p>Ours ± one standard error; paper value in brackets. ✓: within 3 standard errors plus the paper's rounding; ✗: beyond, with the relative difference.</p>\n<table>\n<tr>{}</tr>\n",
        TABLE1_HEAD.iter().map(|x| format!("<th>{x}</th>")).collect::<String>()
    );
    for r in &c.table1 {
        let cell = |i: usize, digits: usize| {
            let x = &r.cells[i];
            let class = match x.consistent() {
                Some(true) => " class=\"ok\"",
                Some(false) => " class=\"off\"",
                None => "",
            };
            format!("<td{class}>{}</td>", x.shown(digits))
        };
        let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td>{}</td>{}{}{}<td>{}</td></tr>", r.label, r.n, cell(0, 3), cell(1, 3), cell(2, 3), r.shape());
    }
    h += "</table>\n<h2>Growth with the index (Fig. 7) and the renewal check</h2>\n<table>\n<tr><th>fit</th><th>slope</th><th>slope se</th><th>intercept</th><th>R²</th></tr>\n";
    for g in &c.growth {
        let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>", g[0], g[1], g[2], g[3], g[4]);
    }
    h += "</table>\n<table>\n<tr><th></th><th>renewal prediction</th><th>measured</th></tr>\n";
    for r in &c.renewal {
        let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td></tr>", r[0], r[1], r[2]);
    }
    h += "</table>\n<h2>Independence tests (Figs 11 and 13)</h2>\n<table>\n<tr><th>pair</th><th>n</th><th>χ² on df</th><th>χ² p</th><th>G p</th><th>mutual information [nats]</th><th>permutation p</th><th>verdict (5 %)</th></tr>\n";
    for t in &c.tests {
        let _ = writeln!(h, "<tr>{}</tr>", t.iter().map(|x| format!("<td>{}</td>", escape(x))).collect::<String>());
    }
    h += "</table>\n<h2>Figures</h2>\n";
    for (name, path) in &c.figures {
        let svg = std::fs::read_to_string(path).map_err(|e| ReportError::Read { path: path.clone(), message: e.to_string() })?;
        let body = svg.find("<svg").map_or(svg.as_str(), |i| &svg[i..]);
        let _ = write!(h, "<figure id=\"{name}\">\n{body}\n<figcaption>{name} (PNG: {})</figcaption>\n</figure>\n", escape(&figdir.join(format!("{name}.png")).display().to_string()));
    }
    h += "</body>\n</html>\n";
    Ok(h)
}

fn markdown(c: &Content, figdir: &Path) -> String {
    let mut m = String::from("# Stick-slip oscillator on a random bang-bang belt\n\n## Provenance\n\n");
    for (k, v) in &c.provenance {
        let _ = writeln!(m, "- **{k}**: {v}");
    }
    let _ = write!(m, "\n```toml\n{}```\n\n## Table 1: ours beside the paper's\n\nOurs ± se [paper]; ✓ within 3 se + the paper's rounding, ✗ beyond.\n\n| {} |\n|{}\n", c.scenario, TABLE1_HEAD.join(" | "), "---|".repeat(TABLE1_HEAD.len()));
    for r in &c.table1 {
        let _ = writeln!(m, "| {} | {} | {} | {} | {} | {} |", r.label, r.n, r.cells[0].shown(3), r.cells[1].shown(3), r.cells[2].shown(3), r.shape());
    }
    m += "\n## Growth and renewal check\n\n| fit | slope | slope se | intercept | R² |\n|---|---|---|---|---|\n";
    for g in &c.growth {
        let _ = writeln!(m, "| {} |", g.join(" | "));
    }
    m += "\n| | renewal prediction | measured |\n|---|---|---|\n";
    for r in &c.renewal {
        let _ = writeln!(m, "| {} |", r.join(" | "));
    }
    m += "\n## Independence tests\n\n| pair | n | χ² on df | χ² p | G p | MI [nats] | permutation p | verdict |\n|---|---|---|---|---|---|---|---|\n";
    for t in &c.tests {
        let _ = writeln!(m, "| {} |", t.join(" | "));
    }
    m += "\n## Figures\n\n";
    for (name, _) in &c.figures {
        let _ = writeln!(m, "![{name}]({})\n", figdir.join(format!("{name}.png")).display());
    }
    m
}

/// Write `out` (HTML) and its Markdown twin (same path, `.md`); returns both paths.
pub fn run(dataset: &Path, adir: &Path, figdir: &Path, out: &Path) -> Result<[PathBuf; 2], ReportError> {
    let c = content(dataset, adir, figdir)?;
    let md_path = out.with_extension("md");
    let write = |path: &Path, text: String| -> Result<(), ReportError> {
        let tmp = path.with_file_name(format!(".{}.tmp", path.file_name().unwrap_or_default().to_string_lossy()));
        if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| ReportError::Write { path: path.to_owned(), source })?;
        }
        std::fs::write(&tmp, text)
            .and_then(|()| std::fs::rename(&tmp, path))
            .map_err(|source| {
                let _ = std::fs::remove_file(&tmp);
                ReportError::Write { path: path.to_owned(), source }
            })
    };
    let (h, m) = (html(&c, figdir)?, markdown(&c, figdir));
    write(out, h)?;
    write(&md_path, m)?;
    Ok([out.to_owned(), md_path])
}
