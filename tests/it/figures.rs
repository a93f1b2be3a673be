//! Figures and report: the data path from analysis tables, valid files, a well-formed report.

use std::path::Path;

use stickslip::figures::{self, Inputs};
use stickslip::scenario::PAPER_TOML;
use stickslip::table::{Col, Table};

use crate::common::stickslip;

/// `t` written as the table of `def`: the columns it lacks added as nulls, in the definition's
/// order (the figures read every table through its definition).
fn write_as(mut t: Table, def: &stickslip::table::Def, dir: &Path) {
    let height = t.height();
    let mut full = Table::default();
    for c in def.columns {
        let col = match t.columns.iter().position(|(n, _)| n == c.name) {
            Some(i) => t.columns.remove(i).1,
            None => match c.ty {
                stickslip::table::Type::Str => Col::Str(vec![String::new(); height]),
                stickslip::table::Type::Int => Col::Int(vec![None; height]),
                stickslip::table::Type::Float => Col::Float(vec![None; height]),
            },
        };
        full.push(c.name, col);
    }
    assert!(t.columns.is_empty(), "columns outside {}: {:?}", def.file, t.columns.iter().map(|c| &c.0).collect::<Vec<_>>());
    full.write_parquet(&dir.join(def.file)).unwrap();
}

fn float(v: &[f64]) -> Col {
    Col::Float(v.iter().map(|&x| Some(x)).collect())
}

fn strs(v: &[&str]) -> Col {
    Col::Str(v.iter().map(|s| s.to_string()).collect())
}

/// A tiny analysis directory written by hand: known histograms, variances, a joint table.
fn hand_made(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    let mut m = Table::default();
    m.push("variable", strs(&["T", "T", "T", "S_T", "S_L"]))
        .push("index", Col::Int(vec![Some(1), Some(2), Some(3), None, None]))
        .push("mean", float(&[0.4, 1.0, 1.6, 16.0, 15.5]))
        .push("variance", float(&[0.1, 0.3, 0.5, 7.0, 6.9]));
    write_as(m, &stickslip::analysis::tables::moments::DEF, dir);
    let mut h = Table::default();
    h.push("variable", strs(&["T", "T", "Q", "Q"]))
        .push("index", Col::Int(vec![Some(1), Some(1), None, None]))
        .push("lo", float(&[0.0, 0.5, 49.5, 50.5]))
        .push("hi", float(&[0.5, 1.0, 50.5, 51.5]))
        .push("density", float(&[1.2, 0.8, 0.6, 0.4]));
    write_as(h, &stickslip::analysis::tables::histograms::DEF, dir);
    let mut j = Table::default();
    // two pairs whose densities differ 20-fold (as (T_1, T_2) and (D_1, D_2) do about 7-fold)
    j.push("x", strs(&["T_1", "T_1", "D_1", "D_1"]))
        .push("y", strs(&["T_2", "T_2", "D_2", "D_2"]))
        .push("x_lo", float(&[0.0, 0.5, 0.0, 0.1]))
        .push("x_hi", float(&[0.5, 1.0, 0.1, 0.2]))
        .push("y_lo", float(&[1.0, 1.0, 0.0, 0.0]))
        .push("y_hi", float(&[2.0, 2.0, 0.1, 0.1]))
        .push("density", float(&[1.5, 0.5, 30.0, 20.0]))
        .push("product_density", float(&[1.0, 1.0, 25.0, 25.0]));
    write_as(j, &stickslip::analysis::tables::joint_histograms::DEF, dir);
    let mut i = Table::default();
    i.push("x", strs(&["T_1"]))
        .push("y", strs(&["T_2"]))
        .push("chi2_p_value", float(&[0.01]))
        .push("g_p_value", float(&[0.0]))
        .push("mi_p_value", float(&[0.0004]))
        .push("verdict", strs(&["dependent"]));
    write_as(i, &stickslip::analysis::tables::independence::DEF, dir);
    let mut g = Table::default();
    g.push("variable", strs(&["T"]))
        .push("statistic", strs(&["variance"]))
        .push("slope", float(&[0.2]))
        .push("intercept", float(&[-0.1]))
        .push("r2", float(&[1.0]));
    write_as(g, &stickslip::analysis::tables::growth::DEF, dir);
    let summary = serde_json::json!({"dataset": {"scenario": PAPER_TOML}});
    std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
}

#[test]
fn figures_draw_exactly_the_analysis_tables() {
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let inp = Inputs::load(tmp.path()).unwrap();
    let t = figures::indexed_histograms(&inp, "T", "fig09_t", "T").unwrap();
    assert_eq!(t.panels[0].bars, [(0.0, 0.5, 1.2), (0.5, 1.0, 0.8)]);
    assert!(t.panels[1..].iter().all(|p| p.bars.is_empty()));
    let g = figures::growth_figure(&inp).unwrap();
    assert_eq!(g.panels[0].points[0].points, [(1.0, 0.1), (2.0, 0.3), (3.0, 0.5)]);
    let line = &g.panels[0].lines[0].points;
    assert!(line.len() == 2 && (line[0].1 - 0.1).abs() < 1e-15 && (line[1].1 - 0.5).abs() < 1e-15, "{line:?}");
    let j = figures::joint_figure(&inp, "T_1", "T_2", "fig11_t1_t2").unwrap();
    assert_eq!(j.panels[0].heat, [[0.0, 0.5, 1.0, 2.0, 1.5], [0.5, 1.0, 1.0, 2.0, 0.5]]);
    assert_eq!(j.panels[1].heat.len(), 2);
    assert!(!j.panels[0].heat_label.is_empty(), "a heat map has a labelled colour bar");
    assert!(j.title.contains("dependent"), "{}", j.title);
    // p-values: 3 significant digits, or a bound below 0.001 and below 1e-300 (never "0.000")
    assert!(j.title.contains("χ² p = 0.0100") && j.title.contains("G p < 1e-300") && j.title.contains("MI permutation p < 0.001"), "{}", j.title);
    let q = figures::q_figure(&inp).unwrap();
    // a PMF is drawn as stems at the integers, not as bars or a line
    assert!(q.panels[0].bars.is_empty() && q.panels[0].lines.is_empty());
    assert_eq!(q.panels[0].stems[0].points, [(50.0, 0.6), (51.0, 0.4)]);
    // Poisson(λ t_a = 50) at 50 and 51: 50^q e^-50 / q!
    let pmf50 = (50.0f64.ln() * 50.0 - 50.0 - (1..=50).map(|k| (k as f64).ln()).sum::<f64>()).exp();
    assert!((q.panels[0].points[0].points[0].1 - pmf50).abs() < 1e-12);
    // each plotted PMF spans 0..mean + 4√mean + 4: all but < 1e-4 of its mass
    let p = figures::poisson_figure(&inp);
    assert!(p.panels[0].lines.is_empty());
    for stems in &p.panels[0].stems {
        let total: f64 = stems.points.iter().map(|pt| pt.1).sum();
        assert!(total <= 1.0 + 1e-12 && total > 1.0 - 1e-4, "{}: {total}", stems.label);
        assert!(stems.points.iter().all(|pt| pt.0.fract() == 0.0), "stems stand on the integers");
    }
    assert!(figures::trajectory_figure(&inp).is_none() && figures::indexed_histograms(&inp, "Y", "fig06_y", "Y").is_none());
}

/// Balanced tags (void elements and self-closing tags aside); returns the first problem.
fn check_tags(html: &str) -> Result<(), String> {
    const VOID: [&str; 6] = ["meta", "br", "hr", "img", "link", "input"];
    let mut stack: Vec<String> = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find('<') {
        rest = &rest[i + 1..];
        let end = rest.find('>').ok_or("unterminated tag")?;
        let tag = &rest[..end];
        rest = &rest[end + 1..];
        if tag.starts_with('!') || tag.starts_with('?') || tag.ends_with('/') {
            continue;
        }
        let name: String = tag.trim_start_matches('/').chars().take_while(|c| c.is_alphanumeric()).collect::<String>().to_lowercase();
        if VOID.contains(&name.as_str()) {
            continue;
        }
        if tag.starts_with('/') {
            match stack.pop() {
                Some(open) if open == name => {}
                other => return Err(format!("</{name}> closes {other:?}")),
            }
        } else {
            stack.push(name);
        }
    }
    if stack.is_empty() {
        Ok(())
    } else {
        Err(format!("unclosed {stack:?}"))
    }
}

#[test]
fn the_whole_pipeline_produces_every_figure_and_a_self_contained_report() {
    let tmp = tempfile::tempdir().unwrap();
    let args = ["reproduce", "--out", "run", "--realizations", "600", "--set", "output.switch_times=true", "--set", "output.trajectories=2", "--quiet"];
    let o = stickslip(&args, tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // the layout: the dataset directory holds only its parts (and its hidden marker); the
    // trajectory tables, analysis, figures and report sit beside it
    let mut dataset: Vec<String> =
        std::fs::read_dir(tmp.path().join("run/dataset")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    dataset.sort();
    assert_eq!(dataset, [".stickslip-dataset", "part-00000-of-00001.parquet"]);
    for beside in [
        "dataset.trajectories/samples.parquet",
        "dataset.trajectories/events.parquet",
        "analysis/moments.parquet",
        "analysis/summary.json",
        "figures",
        "report.html",
        "report.md",
    ] {
        assert!(tmp.path().join("run").join(beside).exists(), "run/{beside}");
    }
    let figs = tmp.path().join("run/figures");
    let names = [
        "fig02_poisson_pmf",
        "fig04_trajectories",
        "fig05_q",
        "fig06_y",
        "fig07_variance_growth",
        "fig08_counts",
        "fig09_t",
        "fig10_l",
        "fig11_t1_t2",
        "fig12_d",
        "fig13_d1_d2",
        "fig14_h",
        "tails",
    ];
    for name in names {
        let png = std::fs::read(figs.join(format!("{name}.png"))).unwrap_or_else(|e| panic!("{name}.png: {e}"));
        let ink = ink(&png).unwrap_or_else(|e| panic!("{name}.png: {e}"));
        assert!(ink > 0.01, "{name}.png: {:.2} % of its pixels drawn", 100.0 * ink);
        let svg = std::fs::read_to_string(figs.join(format!("{name}.svg"))).unwrap();
        assert!(svg.contains("<svg") && svg.trim_end().ends_with("</svg>") && svg.len() > 5_000, "{name}.svg");
        check_tags(&svg).unwrap_or_else(|e| panic!("{name}.svg: {e}"));
    }
    let html = std::fs::read_to_string(tmp.path().join("run/report.html")).unwrap();
    check_tags(&html).unwrap();
    for name in names {
        assert!(html.contains(&format!("<figure id=\"{name}\">")), "{name} missing from the report");
    }
    for external in ["<img", "<link", "<script", "src=\"http", "href=\"http"] {
        assert!(!html.contains(external), "the report loads {external}");
    }
    assert!(html.contains("T_1") && html.contains("16.71") && html.contains("renewal"));
    let md = std::fs::read_to_string(tmp.path().join("run/report.md")).unwrap();
    assert!(md.contains("| T_1 |") && md.contains("fig13_d1_d2.png"));
    // the tails section (issue 22, item 7): sticks per second is E[S_T]/t_a of moments.parquet
    assert!(md.contains("## Tails") && md.contains("| breakaway fraction |") && md.contains("P(severity > 1.25)"), "{md}");
    let m = stickslip::table::Table::read_parquet(&tmp.path().join("run/analysis/moments.parquet")).unwrap();
    let vars = m.strings("variable").unwrap();
    let st = m.floats("mean").unwrap()[vars.iter().position(|v| v == "S_T").unwrap()].unwrap();
    let line = md.lines().find(|l| l.starts_with("| sticks per second")).expect("a sticks-per-second row");
    let shown: f64 = line.split('|').nth(2).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    assert!((shown - st / 10.0).abs() <= 5e-4 * st / 10.0, "{line} against E[S_T] = {st}");
}

#[test]
fn only_the_papers_scene_is_compared_with_the_papers_table() {
    // the paper's values (T_1 mean 0.36, S_T mean 16.71) and the ✓/✗ marks belong to the paper's
    // scene; a Stribeck scene, or a damped one, shows its own statistics alone
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let stribeck = ["--set", "model.friction_law=\"stribeck\"", "--set", "model.stribeck_velocity=0.1", "--set", "model.static_friction_coefficient=0.6"];
    for (name, sets, paper) in [
        ("paper", &["--seed", "7", "--set", "run.solver=\"exact\"", "--set", "model.damping=0", "--set", "model.friction_law=\"coulomb\""][..], true),
        ("stribeck", &stribeck[..], false),
        ("damped", &["--set", "model.damping=0.5"], false),
    ] {
        let mut args = vec!["reproduce", "--out", name, "--realizations", "300", "-q"];
        args.extend(sets);
        let o = stickslip(&args, t);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let table = std::fs::read_to_string(t.join(name).join("analysis/table1.md")).unwrap();
        let html = std::fs::read_to_string(t.join(name).join("report.html")).unwrap();
        let md = std::fs::read_to_string(t.join(name).join("report.md")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(t.join(name).join("analysis/summary.json")).unwrap()).unwrap();
        for (what, text) in [("table1.md", &table), ("report.html", &html), ("report.md", &md)] {
            let marked = text.contains('✓') || text.contains('✗') || text.contains("(0.36)") || text.contains("(16.71)");
            assert_eq!(marked, paper, "{name}: {what} compared with the paper: {marked}");
        }
        assert_eq!(summary["counts"]["S_T"]["paper_mean"].as_f64(), paper.then_some(16.71), "{name}: summary.json");
        assert_eq!(html.contains("Reproduction of Lima"), paper, "{name}: the report's first sentence");
        // the solver actually run, and for a numerical one the settings it ran at
        let solver =
            if name == "stribeck" { "rk45 (rtol = 0.000000001, atol = 0.000000001, max_step = 0.0001 s, peak guard on)" } else { "<td class=\"l\">exact</td>" };
        assert!(html.contains(solver), "{name}: provenance names {solver}");
    }
}

#[test]
fn the_report_escapes_what_it_interpolates() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    for args in [&["simulate", "--out", "d", "--realizations", "300", "-q"][..], &["analyze", "d", "--out", "a", "-q"], &["figures", "a", "--out", "f", "-q"]] {
        let o = stickslip(args, t);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    // a label in the analysis and a figure name carrying markup, and a figure with a script
    let path = t.join("a/summary.json");
    let mut summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    summary["growth"][0]["variable"] = "<script>alert(1)</script>".into();
    std::fs::write(&path, summary.to_string()).unwrap();
    std::fs::write(t.join("f/x<b>\".svg"), "<svg xmlns=\"http://www.w3.org/2000/svg\"><script>alert(2)</script></svg>").unwrap();
    std::fs::write(t.join("f/y.svg"), "<svg xmlns=\"http://www.w3.org/2000/svg\"><rect onload=\"alert(3)\"/></svg>").unwrap();
    let o = stickslip(&["report", "d", "a", "f", "--out", "r.html", "-q"], t);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(t.join("r.html")).unwrap();
    assert!(!html.contains("<script") && !html.contains("alert(2)") && !html.contains("onload"), "unescaped markup in the report");
    assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;"), "the label is shown, escaped");
    assert!(html.contains("id=\"x&lt;b&gt;&quot;\""), "the figure id is escaped");
    check_tags(&html).unwrap();
}

#[test]
fn sweep_maps_have_error_bars_log_axes_and_heat_maps_for_two_keys() {
    let mut one = Table::default();
    one.push("switch_rate", float(&[1.0, 5.0, 20.0]))
        .push("realizations", Col::Int(vec![Some(100); 3]))
        .push("mean_S_T", float(&[5.0, 10.0, 20.0]))
        .push("mean_S_T_se", float(&[0.1, 0.2, 0.4]));
    let f = figures::sweep_figure(&one).unwrap();
    let p = &f.panels[0];
    assert!(p.x_log, "1..20 spans 20x: log axis");
    assert_eq!(p.lines[0].points, [(1.0, 5.0), (5.0, 10.0), (20.0, 20.0)]);
    let want = [0.196, 0.392, 0.784];
    assert!(p.lines[0].errors.iter().zip(want).all(|(e, w)| (e - w).abs() < 1e-12), "{:?}", p.lines[0].errors);
    let mut two = Table::default();
    two.push("switch_rate", float(&[1.0, 1.0, 2.0, 2.0]))
        .push("friction_coefficient", float(&[0.3, 1.0, 0.3, 1.0]))
        .push("realizations", Col::Int(vec![Some(100); 4]))
        .push("mean_S_T", float(&[5.0, 6.0, 7.0, 8.0]));
    let f = figures::sweep_figure(&two).unwrap();
    let p = &f.panels[0];
    assert!(!p.x_log && !p.y_log, "spans under 10x stay linear");
    assert_eq!(p.heat.len(), 4);
    // cells around the grid values, meeting at the midpoints
    let want = [0.5, 1.5, -0.05, 0.65];
    assert!(p.heat[0][..4].iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{:?}", p.heat[0]);
    assert!(!p.heat_label.is_empty());
    // ticks at the grid values, as typed, and the keys with their units
    let labels = |t: &[(f64, String)]| t.iter().map(|(v, l)| (*v, l.clone())).collect::<Vec<_>>();
    assert_eq!(labels(&p.x_ticks), [(1.0, "1".to_string()), (2.0, "2".to_string())]);
    assert_eq!(labels(&p.y_ticks), [(0.3, "0.3".to_string()), (1.0, "1".to_string())]);
    assert_eq!(p.x_label, "belt.switch_rate [1/s]");
    assert_eq!(p.y_label, "model.friction_coefficient (dimensionless)");
}

#[test]
fn swept_keys_are_labelled_with_their_units() {
    for (column, label) in [
        ("mass", "model.mass [kg]"),
        ("stiffness", "model.stiffness [N/m]"),
        ("damping", "model.damping [N·s/m]"),
        ("normal_force", "model.normal_force [N]"),
        ("static_friction_coefficient", "model.static_friction_coefficient (dimensionless)"),
        ("speed", "belt.speed [m/s]"),
        ("switch_rate", "belt.switch_rate [1/s]"),
        ("duration", "run.duration [s]"),
    ] {
        assert_eq!(figures::key_axis_label(column), label);
    }
}

#[test]
fn the_trajectory_figure_draws_the_belt_at_its_own_two_speeds() {
    // an asymmetric belt: +1 m/s, then −0.5 m/s after the switch at 0.3 s, +1 again at 0.6 s
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let mut inp = Inputs::load(tmp.path()).unwrap();
    let samples = (0..10)
        .map(|i| {
            let t = i as f64 * 0.1;
            let v = if (0.3..0.6).contains(&t) { -0.5 } else { 1.0 };
            [t, v, v]
        })
        .collect();
    inp.trajectory = Some(figures::Trajectory { samples, belt_switches: vec![(0.3, -0.5), (0.6, 1.0)], ..Default::default() });
    let f = figures::trajectory_figure(&inp).unwrap();
    let belt = &f.panels[0].lines[1].points;
    // on to the end of the window, t_a (the samples stop at 0.9 s)
    let t_a = inp.scenario.run.duration;
    assert_eq!(belt, &[(0.0, 1.0), (0.3, 1.0), (0.3, -0.5), (0.6, -0.5), (0.6, 1.0), (t_a, 1.0)]);
}

#[test]
fn each_joint_figure_has_its_own_colour_scale() {
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let inp = Inputs::load(tmp.path()).unwrap();
    // with 4 non-empty cells the 99.5th percentile is the largest cell: each figure's top is its
    // own largest density (1.5 and 30), in both of its panels
    for (x, y, name, largest) in [("T_1", "T_2", "fig11_t1_t2", 1.5), ("D_1", "D_2", "fig13_d1_d2", 30.0)] {
        let f = figures::joint_figure(&inp, x, y, name).unwrap();
        for p in &f.panels {
            assert_eq!(p.heat_max, Some(largest), "{name}: {}", p.title);
            assert!(!p.heat_label.contains("above"), "{name}: nothing saturates, so the bar says nothing does: {}", p.heat_label);
        }
    }
}

#[test]
fn a_clipped_colour_scale_says_how_many_cells_it_saturates() {
    // 1000 cells at 1 and 3 spikes at 100: the top is at the 99.5th percentile (1), and the bar
    // says that the 3 spikes of the 1003 non-empty cells (0.3 %) lie above it
    let mut cells: Vec<[f64; 5]> = (0..1000).map(|i| [i as f64, i as f64 + 1.0, 0.0, 1.0, 1.0]).collect();
    cells.extend((0..3).map(|i| [-(i as f64) - 1.0, -(i as f64), 0.0, 1.0, 100.0]));
    let empty = [[0.0, 1.0, 1.0, 2.0, 0.0]];
    let (top, above) = figures::colour_top(&[&cells, &empty]);
    assert_eq!(top, 1.0);
    assert!((above - 3.0 / 1003.0).abs() < 1e-15, "{above}");
}

#[test]
fn the_trajectory_figure_draws_a_belt_of_three_levels_at_the_recorded_velocities() {
    // a belt that stops: +1, 0 at 0.3 s, −1 at 0.6 s, +1 at 0.8 s (with the velocities the events
    // record; alternating two levels would draw +1 where the belt runs at −1)
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let mut inp = Inputs::load(tmp.path()).unwrap();
    let samples = (0..10).map(|i| [i as f64 * 0.1, 0.0, 1.0]).collect();
    inp.trajectory = Some(figures::Trajectory { samples, belt_switches: vec![(0.3, 0.0), (0.6, -1.0), (0.8, 1.0)], ..Default::default() });
    let f = figures::trajectory_figure(&inp).unwrap();
    let t_a = inp.scenario.run.duration;
    let want = [(0.0, 1.0), (0.3, 1.0), (0.3, 0.0), (0.6, 0.0), (0.6, -1.0), (0.8, -1.0), (0.8, 1.0), (t_a, 1.0)];
    assert_eq!(f.panels[0].lines[1].points, want);
}

#[test]
fn the_belt_trace_reaches_the_end_of_each_window() {
    // flips at 0.3, 0.6, 1.8 and 2.2 s: the first-2-s panel must carry the belt on from its last
    // flip (1.8) to 2 s, and the whole-window panel to t_a, though the samples stop at 2.9 s
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let mut inp = Inputs::load(tmp.path()).unwrap();
    let t_a = inp.scenario.run.duration;
    assert!(t_a > 3.0, "the paper's scene runs for {t_a} s");
    let level = |t: f64| if (0.3..0.6).contains(&t) || (1.8..2.2).contains(&t) { -0.5 } else { 1.0 };
    let samples = (0..30).map(|i| i as f64 * 0.1).map(|t| [t, 0.0, level(t)]).collect();
    inp.trajectory = Some(figures::Trajectory { samples, belt_switches: [0.3, 0.6, 1.8, 2.2].map(|t| (t, level(t))).to_vec(), ..Default::default() });
    let f = figures::trajectory_figure(&inp).unwrap();
    let (whole, first) = (&f.panels[0], &f.panels[1]);
    assert_eq!(first.lines[1].points.last(), Some(&(2.0, -0.5)), "{:?}", first.lines[1].points);
    assert_eq!(first.x_range, Some((0.0, 2.0)));
    assert_eq!(whole.lines[1].points.last(), Some(&(t_a, 1.0)), "{:?}", whole.lines[1].points);
    assert_eq!(whole.x_range, Some((0.0, t_a)));
}

#[test]
fn a_panel_with_its_own_ticks_is_drawn_with_their_labels() {
    // categories (as the Sobol plot's parameters) at 0, 1, 2: each name is written once, as a tick
    let tmp = tempfile::tempdir().unwrap();
    let names = ["friction_coefficient", "switch_rate", "intrinsic"];
    let panel = figures::Panel {
        x_label: "input".into(),
        y_label: "Sobol index".into(),
        points: vec![figures::Series { label: "first order".into(), points: vec![(0.0, 0.2), (1.0, 0.5), (2.0, 0.1)], ..Default::default() }],
        x_ticks: names.iter().enumerate().map(|(i, n)| (i as f64, n.to_string())).collect(),
        x_range: Some((-0.5, 2.5)),
        ..Default::default()
    };
    let f = figures::Figure { name: "ticks".into(), title: String::new(), rows: 1, cols: 1, size: (700, 400), panels: vec![panel] };
    let [_, svg] = figures::render::save(&f, tmp.path()).unwrap();
    let svg = std::fs::read_to_string(svg).unwrap();
    for n in names {
        assert_eq!(svg.lines().filter(|l| l.trim() == n).count(), 1, "{n}");
    }
}

/// A table of another shape than its definition (an older analysis, an edited file) is refused
/// with its file and the column named, not drawn from defaults.
#[test]
fn a_table_of_another_shape_is_refused_naming_the_column() {
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let path = tmp.path().join("moments.parquet");
    let mut t = Table::read_parquet(&path).unwrap();
    t.columns.retain(|(n, _)| n != "reached");
    t.write_parquet(&path).unwrap();
    let e = Inputs::load(tmp.path()).unwrap_err().to_string();
    assert!(e.contains("moments.parquet") && e.contains("`reached` is missing") && e.contains("run the stage again"), "{e}");
}

#[test]
fn an_older_analysis_without_the_belt_velocity_of_its_events_is_refused_naming_the_column() {
    let tmp = tempfile::tempdir().unwrap();
    hand_made(tmp.path());
    let mut samples = Table::default();
    samples
        .push("realization", Col::Int(vec![Some(0)]))
        .push("t", Col::Float(vec![Some(0.0)]))
        .push("x", Col::Float(vec![Some(0.0)]))
        .push("xdot", Col::Float(vec![Some(0.0)]))
        .push("belt_velocity", Col::Float(vec![Some(1.0)]));
    samples.write_parquet(&tmp.path().join("trajectory_samples.parquet")).unwrap();
    // the events as an older simulate wrote them: no belt velocity
    let mut events = Table::default();
    events.push("realization", Col::Int(vec![Some(0)])).push("event", Col::Str(vec!["belt_switch".into()])).push("t", Col::Float(vec![Some(0.5)]));
    events.write_parquet(&tmp.path().join("trajectory_events.parquet")).unwrap();
    let err = Inputs::load(tmp.path()).unwrap_err().to_string();
    assert!(err.contains("trajectory_events.parquet") && err.contains("`belt_velocity` is missing") && err.contains("run the stage again"), "{err}");
}

/// The fraction of a PNG's pixels that are not white: a figure with its axes, labels and data
/// draws on several per cent of them, an empty or blank one on none.
fn ink(png: &[u8]) -> Result<f64, String> {
    let mut reader = png::Decoder::new(std::io::Cursor::new(png)).read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    if info.color_type != png::ColorType::Rgb || info.bit_depth != png::BitDepth::Eight {
        return Err(format!("{:?} {:?}, not 8-bit RGB", info.color_type, info.bit_depth));
    }
    let pixels = &buf[..info.buffer_size()];
    let drawn = pixels.chunks_exact(3).filter(|p| *p != [255, 255, 255]).count();
    Ok(drawn as f64 / (pixels.len() / 3) as f64)
}
