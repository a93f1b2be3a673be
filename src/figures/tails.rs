//! The tails' figure: the survival curves of stick and slip durations on a log axis (product
//! limit with its band, naive, conditional), the law of the longest stick and the severity's
//! exceedance, from `survival.parquet`, `tails.parquet` and the histograms.

use super::chart::{Figure, Panel, Series};
use super::format;
use super::inputs::Inputs;
use crate::analysis::tables::{survival, tails};
use crate::observables::{Observable, Statistic};

/// The tails: P(D > t) and P(H > t) pooled over every stick (slip) on a log axis — product limit
/// with its 95 % band, the naive curve that drops the censored intervals, and for sticks the
/// conditional estimator — and the laws of the longest stick and of the severity.
pub fn tails_figure(inp: &Inputs) -> Option<Figure> {
    let s = inp.survival.as_ref()?;
    let (vars, idx, method) = (s.str(&survival::VARIABLE), s.int(&survival::INDEX), s.str(&survival::METHOD));
    let (t, surv, lo, hi) = (s.float(&survival::T), s.float(&survival::SURVIVAL), s.float(&survival::LO), s.float(&survival::HI));
    let curve = |var: &str, m: &str, col: &[Option<f64>]| -> Vec<(f64, f64)> {
        (0..s.height())
            .filter(|&r| vars[r] == var && idx[r].is_none() && method[r] == m)
            .filter_map(|r| Some((t[r]?, col[r]?)))
            .filter(|&(_, p)| p > 0.0)
            .collect()
    };
    let survival_panel = |var: &str, what: &str| {
        let mut lines = vec![
            Series { label: "Kaplan–Meier (censored kept)".into(), color: 0, points: curve(var, "kaplan_meier", surv), ..Default::default() },
            Series { label: "95 % band".into(), color: 4, points: curve(var, "kaplan_meier", lo), ..Default::default() },
            Series { label: String::new(), color: 4, points: curve(var, "kaplan_meier", hi), ..Default::default() },
            Series { label: "naive (censored dropped)".into(), color: 3, points: curve(var, "naive", surv), ..Default::default() },
        ];
        let conditional = curve(var, "conditional", surv);
        if !conditional.is_empty() {
            lines.push(Series { label: "conditional (exact in t)".into(), color: 1, points: conditional, ..Default::default() });
        }
        Panel { title: format!("P({var} > t), {what}"), x_label: "t [s]".into(), y_label: format!("P({var} > t)"), lines, y_log: true, ..Default::default() }
    };
    let law = |var: &str, title: String, x_label: &'static str| {
        let bars = inp.histogram(var, None);
        (!bars.is_empty()).then(|| Panel { title, x_label: x_label.into(), y_label: "density".into(), bars, ..Default::default() })
    };
    let exceed = |stat: &str| -> Option<String> {
        let e = inp.tails.as_ref()?;
        let (names, value, lo, hi) = (e.str(&tails::STATISTIC), e.float(&tails::VALUE), e.float(&tails::LO), e.float(&tails::HI));
        let r = (0..e.height()).find(|&r| names[r] == stat)?;
        let band = lo[r].zip(hi[r]).map_or(String::new(), |(a, b)| format!(" [{} – {}]", format::significant(a, 3), format::significant(b, 3)));
        Some(format!("{}{band}", format::significant(value[r]?, 3)))
    };
    let breakaway = exceed(Statistic::BreakawayFraction.name()).map_or(String::new(), |b| format!("; sticks ending by breakaway: {b}"));
    let mut panels = vec![survival_panel("D", "every stick"), survival_panel("H", "every slip")];
    panels.extend(law(Observable::LongestStick.variable(), "law of the longest stick of a realization".into(), "longest stick [s]"));
    // the severity's exceedance P(S > s) from its histogram (mostly a point mass at 1: a mass
    // that follows the belt), with the thresholds of `tails.parquet` as markers
    let bars = inp.histogram(Observable::Severity.variable(), None);
    if !bars.is_empty() {
        let mut above = 1.0;
        let line: Vec<(f64, f64)> = bars
            .iter()
            .map(|&(lo, hi, d)| {
                above -= d * (hi - lo);
                (hi, above.max(0.0))
            })
            .filter(|p| p.1 > 1e-12)
            .collect();
        let marks: Vec<(f64, f64)> = inp
            .tails
            .as_ref()
            .map(|e| {
                let (names, threshold, value) = (e.str(&tails::STATISTIC), e.float(&tails::THRESHOLD), e.float(&tails::VALUE));
                (0..e.height())
                    .filter(|&r| names[r] == Observable::Severity.variable())
                    .filter_map(|r| Some((threshold[r]?, value[r]?)))
                    .filter(|p| p.1 > 0.0)
                    .collect()
            })
            .unwrap_or_default();
        panels.push(Panel {
            title: "P(severity > s), severity = (max ẋ − min ẋ)/(2 v0)".into(),
            x_label: "s".into(),
            y_label: "P(severity > s)".into(),
            lines: vec![Series { label: "from the histogram".into(), color: 0, points: line, ..Default::default() }],
            points: vec![Series { label: "asked thresholds (tails.parquet)".into(), color: 1, points: marks, ..Default::default() }],
            y_log: true,
            ..Default::default()
        });
    }
    (!panels[0].lines[0].points.is_empty()).then(|| Figure {
        name: "tails".into(),
        title: format!("Tails: survival of stick and slip durations (log axis), longest stick, severity{breakaway}"),
        rows: 2,
        cols: 2,
        size: (1200, 900),
        panels,
    })
}
