//! The page: the report's sections gathered from the dataset, the analysis and the figures
//! ([`content`]), rendered as HTML with the figures inlined ([`html`]) and as Markdown
//! ([`markdown`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::error::{ReportError, HTML_MARK, MD_MARK};
use super::exact::{
    density_rows, exact_rows, exact_tail_rows, same_scene_as_law, EXACT_DENSITIES_HEAD, EXACT_DENSITIES_LEGEND, EXACT_HEAD, EXACT_LEGEND, EXACT_TAILS_HEAD,
    EXACT_TAILS_LEGEND,
};
use super::tails::tails_rows;
use crate::analysis::input;
use crate::analysis::paper::{table1, Row};
use crate::analysis::summary::Summary;

/// Whether an SVG is inert, so that inlining it runs nothing (ours are): no script, no
/// `javascript:` link, no foreign HTML, no event-handler attribute (` onload=`, ` onclick =` …).
fn is_inert(svg: &str) -> bool {
    let lower = svg.to_ascii_lowercase();
    let handler = lower.match_indices(" on").any(|(i, _)| {
        let rest = &lower[i + 3..];
        let name = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_alphabetic()).len();
        name > 1 && rest[name..].trim_start().starts_with('=')
    });
    !handler && !["<script", "javascript:", "<foreignobject"].iter().any(|p| lower.contains(p))
}

/// Text made safe for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&#39;")
}

/// A number of `summary.json`: an integer-valued one of 1 or more as an integer (`81`, not
/// `81.0000`), else 4 decimals (exponent notation far from 1); `–` without one.
fn num(v: Option<f64>) -> String {
    // degrees of freedom and counts are integers even when written as 81.0
    if let Some(i) = v.filter(|x| x.abs() >= 1.0).and_then(crate::figures::format::integer) {
        return i;
    }
    v.map_or("–".into(), |x| if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) { format!("{x:.3e}") } else { format!("{x:.4}") })
}

/// A p-value of `summary.json`, as the figures print it ([`crate::figures::format::p_value`]).
fn p_value(v: Option<f64>) -> String {
    crate::figures::format::p_value(v.unwrap_or(f64::NAN))
}

/// The report's sections as (heading, markdown-ish rows) — rendered to HTML and Markdown alike.
pub(super) struct Content {
    provenance: Vec<(String, String)>,
    scenario: String,
    /// the paper's scene: Table 1 is compared with the paper's
    paper: bool,
    table1: Vec<Row>,
    growth: Vec<[String; 5]>,
    renewal: Vec<[String; 3]>,
    tests: Vec<[String; 8]>,
    /// (quantity, estimate [95 %], from how many) of the tails, empty without them
    tails: Vec<[String; 3]>,
    /// Table 1's means and variances without sampling (`exact-law`'s `moments.parquet`) beside
    /// ours: (variable, exact mean ± error, ours [95 %], inside?, the same for the variance);
    /// empty without `--exact`
    exact: Vec<[String; 7]>,
    /// D_k's law without sampling (`exact-law`'s `survival.parquet`) beside our product-limit
    /// curve of D_k at the times both have: (P(D_k > t), exact ± error, ours [95 %], inside?);
    /// empty without `--exact`, or when either lacks the curves
    exact_tails: Vec<[String; 4]>,
    /// the densities of T_k, L_k, H_k without sampling against our histograms: (variable, bins,
    /// how many meet, ✓); empty without `--exact` or its `--densities`
    exact_densities: Vec<[String; 4]>,
    figures: Vec<(String, PathBuf)>,
}

pub(super) fn content(dataset: &Path, adir: &Path, figdir: &Path, exact: Option<&Path>) -> Result<Content, ReportError> {
    let data = input::open_partial(dataset, true)?;
    let read_err = |path: &Path, e: &dyn std::fmt::Display| ReportError::Read { path: path.to_owned(), message: e.to_string() };
    let summary_path = adir.join("summary.json");
    let summary = Summary::read(&summary_path).map_err(|e| read_err(&summary_path, &e))?;
    let moments_def = &crate::analysis::tables::moments::DEF;
    let moments = moments_def.read(adir).map_err(|e| read_err(&adir.join(moments_def.file), &e))?;
    let sc = &data.scenario;
    if let Some(law) = exact {
        same_scene_as_law(law, sc)?;
    }
    // the analysis must be of this dataset: same scenario, same realizations
    let recorded = &summary.dataset;
    if recorded.scenario != sc.to_toml() || recorded.realizations != data.rows {
        return Err(ReportError::Mismatch {
            path: adir.to_owned(),
            message: format!(
                "is the analysis of another dataset than {} (its summary.json records {} realizations of a different scenario or size; this dataset has {}); run analyze on this dataset first",
                dataset.display(),
                recorded.realizations,
                data.rows
            ),
        });
    }
    let provenance = vec![
        ("dataset".into(), format!("{} ({} part file(s))", dataset.display(), data.files.len())),
        (
            "realizations".into(),
            if data.missing.is_empty() {
                data.rows.to_string()
            } else {
                let gaps: Vec<String> = data.missing.iter().map(|r| format!("{}..{}", r.start, r.end)).collect();
                format!("{} of the run's {} — PARTIAL (--allow-partial): missing {}", data.rows, data.expected_rows, gaps.join(", "))
            },
        ),
        ("seed".into(), sc.run.seed.to_string()),
        ("solver".into(), solver_settings(sc)),
        ("generator".into(), crate::simulation::rng::GENERATOR.into()),
        ("stickslip".into(), summary.stickslip_version.clone()),
        ("analysis".into(), adir.display().to_string()),
        ("truncated intervals".into(), summary.policies.truncated_intervals.clone()),
        ("mode".into(), summary.policies.mode.clone()),
    ];
    // a value with its 95 % interval `[lo, hi]`, when the analysis has one
    let with_interval = |v: Option<f64>, iv: Option<[Option<f64>; 2]>| match iv {
        Some([lo, hi]) => format!("{} [{} – {}]", num(v), num(lo), num(hi)),
        None => num(v),
    };
    let growth = summary
        .growth
        .iter()
        .map(|g| [format!("{} of {}_k", g.statistic, g.variable), with_interval(g.slope, g.slope_95), num(g.slope_se), num(g.intercept), num(g.r2)])
        .collect();
    // (without a renewal check, the rows read "–")
    let r = summary.renewal_check.as_ref();
    let renewal = vec![
        ["E[S_T]".to_string(), with_interval(r.and_then(|r| r.predicted_mean), r.and_then(|r| r.predicted_mean_95)), num(r.and_then(|r| r.measured_mean))],
        [
            "Var[S_T]".to_string(),
            with_interval(r.and_then(|r| r.predicted_variance), r.and_then(|r| r.predicted_variance_95)),
            num(r.and_then(|r| r.measured_variance)),
        ],
    ];
    let tests = summary
        .independence
        .iter()
        .map(|t| {
            [
                format!("({}, {})", t.x, t.y),
                t.n.to_string(),
                format!("{} on {}", num(t.chi2), num(Some(t.df))),
                p_value(t.chi2_p_value),
                p_value(t.g_p_value),
                num(t.mutual_information),
                p_value(t.mi_p_value),
                t.verdict.clone(),
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
    let paper = sc.is_paper_scene();
    let table1 = table1(&moments, paper);
    Ok(Content {
        provenance,
        scenario: sc.to_toml(),
        paper,
        exact: exact.map_or(Ok(Vec::new()), |law| exact_rows(law, &table1))?,
        exact_tails: exact.map_or(Ok(Vec::new()), |law| exact_tail_rows(law, adir))?,
        exact_densities: exact.map_or(Ok(Vec::new()), |law| density_rows(law, adir))?,
        table1,
        growth,
        renewal,
        tests,
        tails: tails_rows(adir, &moments, sc.run.duration)?,
        figures,
    })
}

/// The solver actually run and, for a numerical one, the `[numerics]` settings it used.
fn solver_settings(sc: &crate::scenario::Scenario) -> String {
    use crate::scenario::short;
    use crate::solver::SolverKind;
    let (kind, n) = (sc.solver(), &sc.numerics);
    let guard = if n.peak_guard { "on" } else { "off" };
    let settings = match kind {
        SolverKind::Exact | SolverKind::Auto => return kind.name().to_string(),
        SolverKind::Rk45 | SolverKind::Dop853 => {
            format!("rtol = {}, atol = {}, max_step = {} s, peak guard {guard}", short(n.rtol), short(n.atol), short(n.max_step))
        }
        SolverKind::Rk4 => format!("step = {} s, peak guard {guard}", short(n.step)),
        SolverKind::Moreau => format!("step = {} s", short(n.step)),
        SolverKind::Smooth => format!(
            "epsilon = {} m/s, stick_velocity = {} m/s, rtol = {}, atol = {}, max_step = {} s",
            short(n.epsilon),
            short(n.stick_velocity),
            short(n.rtol),
            short(n.atol),
            short(n.max_step)
        ),
    };
    format!("{} ({settings})", kind.name())
}

const TABLE1_HEAD: [&str; 7] = ["variable", "n", "mean", "variance", "mode", "skewness", "kurtosis"];

/// The report's first sentence (HTML): a reproduction of the paper, or a scene built on it.
fn intro(paper: bool) -> &'static str {
    if paper {
        "Reproduction of Lima &amp; Sampaio, <em>Analysis of a dry-friction oscillator driven by a stochastic base motion</em>, with the exact event-driven solver of stickslip."
    } else {
        "A scene built on the oscillator of Lima &amp; Sampaio, <em>Analysis of a dry-friction oscillator driven by a stochastic base motion</em>, but not the paper's own (see the resolved scenario), so its statistics are not compared with the paper's."
    }
}

fn table1_heading(paper: bool) -> &'static str {
    if paper {
        "Table 1: ours beside the paper's"
    } else {
        "Table 1 statistics of this scene"
    }
}

fn table1_legend(paper: bool) -> &'static str {
    if paper {
        "Ours with its 95 % interval (delete-a-group jackknife) in brackets, the paper's value in parentheses. ✓: the paper's value lies inside our interval (widened by the paper's rounding); ✗: outside, with the relative difference. boundary: our mode lies at the boundary of the support (0, where the density peaks), where a relative difference means nothing. ≈: an approximate interval (the skewness of a heavy-tailed variable, and below 18,000 realizations its kurtosis: measured to cover less than 0.93), shown, not judged."
    } else {
        "Ours with its 95 % interval (delete-a-group jackknife) in brackets."
    }
}

pub(super) fn html(c: &Content, figdir: &Path) -> Result<String, ReportError> {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n{HTML_MARK}\n<title>stickslip report</title>\n<style>\n\
         body {{ font-family: sans-serif; max-width: 1200px; margin: 2em auto; padding: 0 2em; color: #222; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; }}\n\
         td, th {{ border: 1px solid #ccc; padding: 3px 8px; text-align: right; }}\n\
         th {{ background: #f3f3f3; }} td.l {{ text-align: left; }}\n\
         .ok {{ color: #1a7f37; }} .off {{ color: #b3261e; font-weight: bold; }}\n\
         figure {{ margin: 2em 0; }} figure svg {{ max-width: 100%; height: auto; }}\n\
         pre {{ background: #f6f6f6; padding: 1em; }}\n</style>\n</head>\n<body>\n\
         <h1>Stick-slip oscillator on a random bang-bang belt</h1>\n\
         <p>{}</p>\n\
         <h2>Provenance</h2>\n<table>\n",
        intro(c.paper)
    );
    for (k, v) in &c.provenance {
        let _ = writeln!(h, "<tr><th>{}</th><td class=\"l\">{}</td></tr>", escape(k), escape(v));
    }
    let _ = write!(h, "</table>\n<details><summary>resolved scenario</summary>\n<pre>{}</pre>\n</details>\n", escape(&c.scenario));
    let _ = write!(
        h,
        "<h2>{}</h2>\n<p>{}</p>\n<table>\n<tr>{}</tr>\n",
        table1_heading(c.paper),
        table1_legend(c.paper),
        TABLE1_HEAD.iter().map(|x| format!("<th>{x}</th>")).collect::<String>()
    );
    for r in &c.table1 {
        let cell = |i: usize, digits: usize| {
            let (text, consistent) = r.shown(i, digits);
            let class = match consistent {
                Some(true) => " class=\"ok\"",
                Some(false) => " class=\"off\"",
                None => "",
            };
            format!("<td{class}>{}</td>", escape(&text))
        };
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td>{}{}{}{}{}</tr>",
            escape(&r.label),
            r.n,
            cell(0, 3),
            cell(1, 3),
            cell(2, 3),
            cell(3, 2),
            cell(4, 2)
        );
    }
    h += "</table>\n";
    if !c.exact.is_empty() {
        let _ = write!(
            h,
            "<h2>Table 1 without sampling</h2>\n<p>{EXACT_LEGEND}</p>\n<table>\n<tr>{}</tr>\n",
            EXACT_HEAD.iter().map(|x| format!("<th>{x}</th>")).collect::<String>()
        );
        let td = |x: &String| match x.as_str() {
            "✓" => "<td class=\"ok\">✓</td>".to_string(),
            "✗" => "<td class=\"off\">✗</td>".to_string(),
            _ => format!("<td>{}</td>", escape(x)),
        };
        for r in &c.exact {
            let _ = writeln!(h, "<tr><td class=\"l\">{}</td>{}</tr>", escape(&r[0]), r[1..].iter().map(td).collect::<String>());
        }
        h += "</table>\n";
        for (legend, head, rows) in [(EXACT_TAILS_LEGEND, EXACT_TAILS_HEAD, &c.exact_tails), (EXACT_DENSITIES_LEGEND, EXACT_DENSITIES_HEAD, &c.exact_densities)]
        {
            if rows.is_empty() {
                continue;
            }
            let _ = write!(h, "<p>{legend}</p>\n<table>\n<tr>{}</tr>\n", head.iter().map(|x| format!("<th>{x}</th>")).collect::<String>());
            for r in rows {
                let _ = writeln!(h, "<tr><td class=\"l\">{}</td>{}</tr>", escape(&r[0]), r[1..].iter().map(td).collect::<String>());
            }
            h += "</table>\n";
        }
    }
    h += "<h2>Growth with the index (Fig. 7) and the renewal check</h2>\n<table>\n<tr><th>fit</th><th>slope [95 %]</th><th>slope se</th><th>intercept</th><th>R²</th></tr>\n";
    for g in &c.growth {
        let [a, b, c2, d, e] = g.clone().map(|x| escape(&x));
        let _ = writeln!(h, "<tr><td class=\"l\">{a}</td><td>{b}</td><td>{c2}</td><td>{d}</td><td>{e}</td></tr>");
    }
    h += "</table>\n<table>\n<tr><th></th><th>renewal prediction [95 %]</th><th>measured</th></tr>\n";
    for r in &c.renewal {
        let [a, b, c2] = r.clone().map(|x| escape(&x));
        let _ = writeln!(h, "<tr><td class=\"l\">{a}</td><td>{b}</td><td>{c2}</td></tr>");
    }
    h += "</table>\n<h2>Independence tests (Figs 11 and 13)</h2>\n<table>\n<tr><th>pair</th><th>n</th><th>χ² on df</th><th>χ² p</th><th>G p</th><th>mutual information [nats]</th><th>permutation p</th><th>verdict (5 %)</th></tr>\n";
    for t in &c.tests {
        let _ = writeln!(h, "<tr>{}</tr>", t.iter().map(|x| format!("<td>{}</td>", escape(x))).collect::<String>());
    }
    h += "</table>\n";
    if !c.tails.is_empty() {
        h += "<h2>Tails (figure <a href=\"#tails\">tails</a>)</h2>\n<p>P(D &gt; t) by the product limit (the stick cut at t_a censored), the naive estimate (cut sticks dropped: biased low) and the conditional estimator (exact in t); the breakaway fraction and the exceedances of the longest stick and the severity. 95 % intervals by the delete-a-group jackknife.</p>\n<table>\n<tr><th>quantity</th><th>estimate [95 %]</th><th>from</th></tr>\n";
        for r in &c.tails {
            let _ = writeln!(h, "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td></tr>", escape(&r[0]), escape(&r[1]), escape(&r[2]));
        }
        h += "</table>\n";
    }
    h += "<h2>Figures</h2>\n";
    for (name, path) in &c.figures {
        let svg = std::fs::read_to_string(path).map_err(|e| ReportError::Read { path: path.clone(), message: e.to_string() })?;
        let body = svg.find("<svg").map_or(svg.as_str(), |i| &svg[i..]);
        let body = if is_inert(body) { body } else { "<p>(not inlined: the SVG holds active content)</p>" };
        let name = escape(name);
        let _ = write!(
            h,
            "<figure id=\"{name}\">\n{body}\n<figcaption>{name} (PNG: {})</figcaption>\n</figure>\n",
            escape(&figdir.join(format!("{name}.png")).display().to_string())
        );
    }
    h += "</body>\n</html>\n";
    Ok(h)
}

pub(super) fn markdown(c: &Content, figdir: &Path) -> String {
    let mut m = format!("{MD_MARK}\n# Stick-slip oscillator on a random bang-bang belt\n\n## Provenance\n\n");
    for (k, v) in &c.provenance {
        let _ = writeln!(m, "- **{k}**: {v}");
    }
    let _ = write!(
        m,
        "\n```toml\n{}```\n\n## {}\n\n{}\n\n| {} |\n|{}\n",
        c.scenario,
        table1_heading(c.paper),
        table1_legend(c.paper),
        TABLE1_HEAD.join(" | "),
        "---|".repeat(TABLE1_HEAD.len())
    );
    for r in &c.table1 {
        let c = |i: usize, digits: usize| r.shown(i, digits).0;
        let _ = writeln!(m, "| {} | {} | {} | {} | {} | {} | {} |", r.label, r.n, c(0, 3), c(1, 3), c(2, 3), c(3, 2), c(4, 2));
    }
    if !c.exact.is_empty() {
        let _ = write!(m, "\n## Table 1 without sampling\n\n{EXACT_LEGEND}\n\n| {} |\n|{}\n", EXACT_HEAD.join(" | "), "---|".repeat(EXACT_HEAD.len()));
        for r in &c.exact {
            let _ = writeln!(m, "| {} |", r.join(" | "));
        }
        for (legend, head, rows) in [(EXACT_TAILS_LEGEND, EXACT_TAILS_HEAD, &c.exact_tails), (EXACT_DENSITIES_LEGEND, EXACT_DENSITIES_HEAD, &c.exact_densities)]
        {
            if rows.is_empty() {
                continue;
            }
            let _ = write!(m, "\n{legend}\n\n| {} |\n|{}\n", head.join(" | "), "---|".repeat(head.len()));
            for r in rows {
                let _ = writeln!(m, "| {} |", r.join(" | "));
            }
        }
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
    if !c.tails.is_empty() {
        m += "\n## Tails\n\nP(D > t) by the product limit (the stick cut at t_a censored), the naive estimate (cut sticks dropped: biased low) and the conditional estimator (exact in t); the breakaway fraction and the exceedances. 95 % intervals by the delete-a-group jackknife.\n\n| quantity | estimate [95 %] | from |\n|---|---|---|\n";
        for r in &c.tails {
            let _ = writeln!(m, "| {} |", r.join(" | "));
        }
    }
    m += "\n## Figures\n\n";
    for (name, _) in &c.figures {
        let _ = writeln!(m, "![{name}]({})\n", figdir.join(format!("{name}.png")).display());
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::{Col, Table};

    fn floats(v: &[f64]) -> Col {
        Col::Float(v.iter().map(|&x| Some(x)).collect())
    }

    /// Table 1 rows for T_1 (its KDE mode at the boundary 0) and S_T (a count whose jackknife
    /// interval of the mode is not integral), compared with the paper's.
    fn rows() -> Vec<Row> {
        let mut m = Table::default();
        m.push("variable", Col::Str(vec!["T".into(), "S_T".into()]))
            .push("index", Col::Int(vec![Some(1), None]))
            .push("n", Col::Int(vec![Some(100), Some(100)]))
            .push("mean", floats(&[0.36, 16.5]))
            .push("mean_lo", floats(&[0.35, 16.4]))
            .push("mean_hi", floats(&[0.37, 16.6]))
            .push("variance", floats(&[0.13, 7.6]))
            .push("mode", floats(&[0.0, 16.0]))
            .push("mode_lo", floats(&[0.0, 13.0]))
            .push("mode_hi", floats(&[0.0, 19.0]))
            .push("skewness", floats(&[2.1, 0.15]))
            .push("kurtosis", floats(&[9.7, 3.1]));
        table1(&m, true)
    }

    #[test]
    fn a_boundary_mode_shows_no_relative_difference() {
        let rows = rows();
        let t1 = rows.iter().find(|r| r.label == "T_1").unwrap();
        // the paper's T_1 mode is 0.16, ours the boundary 0: shown, not "−100 %"
        assert!(t1.cells[2].at_boundary());
        let (text, judged) = t1.shown(2, 3);
        assert!(!text.contains('%') && !text.contains('✗') && text.contains("boundary"), "{text}");
        assert_eq!(judged, None, "not marked in red");
        // other cells keep their marks
        assert!(t1.shown(0, 3).0.ends_with('✓'), "{}", t1.shown(0, 3).0);
    }

    #[test]
    fn a_counts_mode_and_its_interval_are_integers() {
        let rows = rows();
        let st = rows.iter().find(|r| r.label == "S_T").unwrap();
        assert!(st.count);
        // 16 and its (integer, see `SeriesStats::mode_interval`) interval without decimals
        assert_eq!(st.shown(2, 3).0, "16 [13 – 19]");
        // the mean of a count is not an integer and keeps its decimals
        assert!(st.shown(0, 3).0.starts_with("16.500 ["), "{}", st.shown(0, 3).0);
    }

    #[test]
    fn summary_numbers_print_integers_as_integers_and_p_values_by_the_rule() {
        assert_eq!(num(Some(81.0)), "81");
        assert_eq!(num(Some(18000.0)), "18000");
        assert_eq!(num(Some(0.2624)), "0.2624");
        assert_eq!(num(None), "–");
        assert_eq!(p_value(Some(0.0)), "< 1e-300");
        assert_eq!(p_value(Some(0.0004)), "< 0.001");
        assert_eq!(p_value(Some(0.54812)), "0.548");
        assert_eq!(p_value(None), "–");
    }
}
