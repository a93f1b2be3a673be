//! Command line: flags are parsed and checked here, then handed to the stages as typed requests.
//!
//! Files: `args.rs` the clap types; this one the commands (each checks its flags and runs its
//! stage); `exit.rs` the one-line message and the exit code of a failure; `print.rs` what the
//! analysis prints.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Parser;

use crate::analysis;
use crate::outdir::{check_separate, DatasetDir};
use crate::scenario::{Overrides, Scenario};
use crate::simulation::simulate::{self, Shard};

mod args;
mod exit;
mod print;

pub use args::*;
use exit::usage;
pub use exit::{exit_code, message, Usage};
use print::print_analysis;

/// Parse the process arguments and run.
pub fn main() -> anyhow::Result<()> {
    main_from(std::env::args_os())
}

/// Parse `args` (the program name first) and run: the command line of the binary and of the
/// Python package's `stickslip` script alike. `--help`, `--version` and usage errors print and
/// exit the process, as clap does.
pub fn main_from<I: IntoIterator<Item = T>, T: Into<std::ffi::OsString> + Clone>(args: I) -> anyhow::Result<()> {
    let cli = Cli::parse_from(args);
    let quiet = cli.quiet;
    match cli.command {
        Command::Simulate(args) => simulate_command(args, quiet),
        Command::Analyze(args) => analyze_command(args, quiet),
        Command::Figures(args) => figures_command(&args.analysis, &args.out, quiet),
        Command::Report(args) => report_command(&args, quiet),
        Command::Reproduce(args) => reproduce_command(args, quiet),
        Command::Tradeoff(args) => tradeoff_command(args, quiet),
        Command::Sensitivity(args) => sensitivity_command(args, quiet),
        Command::ExactLaw(args) => exact_law_command(args, quiet),
        Command::Predict(args) => predict_command(args, quiet),
        Command::Scenes(args) => scenes_command(&args),
        Command::Completions { shell } => {
            clap_complete::generate(shell, &mut <Cli as clap::CommandFactory>::command(), "stickslip", &mut std::io::stdout());
            Ok(())
        }
    }
}

fn scenes_command(args: &ScenesArgs) -> anyhow::Result<()> {
    use crate::scenes::{find, SHIPPED};
    let Some(name) = &args.name else {
        for s in &SHIPPED {
            println!("{:<20} {}", s.name, s.summary());
        }
        println!(
            "\n`stickslip scenes NAME` prints one; `stickslip scenes NAME --out FILE` writes it to edit; run it with `stickslip simulate FILE --out DIR`."
        );
        return Ok(());
    };
    let names: Vec<&str> = SHIPPED.iter().map(|s| s.name).collect();
    let scene = find(name).ok_or_else(|| usage(format!("no scene {name:?}; the scenes are {}", names.join(", "))))?;
    match &args.out {
        None => {
            print!("{}", scene.text);
            for (file, _) in scene.companions {
                eprintln!("note: this scene reads {file} beside it: `stickslip scenes {name} --out FILE` writes both");
            }
        }
        Some(path) => {
            // the files it reads first, beside it (each refused if something is there already)
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            for (file, text) in scene.companions {
                crate::outdir::write_new_file(&dir.join(file), text.as_bytes(), "--out")?;
            }
            crate::outdir::write_new_file(path, scene.text.as_bytes(), "--out")?;
        }
    }
    Ok(())
}

fn figures_command(adir: &Path, out: &Path, quiet: bool) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let names = crate::figures::run(adir, out).context("figures")?;
    if !quiet {
        eprintln!("drew {} figures (PNG + SVG) in {:.2} s -> {}", names.len(), start.elapsed().as_secs_f64(), out.display());
    }
    Ok(())
}

fn report_command(args: &ReportArgs, quiet: bool) -> anyhow::Result<()> {
    let [html, md] = crate::report::run(&args.dataset, &args.analysis, &args.figures, args.exact.as_deref(), &args.out).context("report")?;
    if !quiet {
        eprintln!("wrote {} and {}", html.display(), md.display());
    }
    Ok(())
}

/// The scenario file, as an input an output must stay apart from.
fn scenario_inputs(input: &ScenarioArgs) -> Vec<&Path> {
    input.scenario.iter().map(PathBuf::as_path).collect()
}

fn tradeoff_command(args: TradeoffArgs, quiet: bool) -> anyhow::Result<()> {
    if args.realizations == 0 {
        return Err(usage("--realizations must be at least 1"));
    }
    if !(args.bias_fraction > 0.0 && args.bias_fraction.is_finite()) {
        return Err(usage(format!("--bias-fraction {}: must be a positive number", args.bias_fraction)));
    }
    check_separate(&args.out, "--out", &scenario_inputs(&args.input))?;
    let scenario = Scenario::resolve(args.input.scenario.as_deref(), &args.input.sets)?;
    scenario.refuse_sweep("tradeoff")?;
    let rows = crate::tradeoff::run(&scenario, args.realizations, args.bias_fraction, &args.out).context("tradeoff")?;
    if !quiet {
        println!("| solver | setting | evaluations/realization | CPU s/realization | RMS error [s] | max error [s] | missed | spurious | bias E[S_T] | bias E[H] | max bias/SE |\n|---|---|---|---|---|---|---|---|---|---|---|");
        let score = |r: &crate::tradeoff::Row| r.max_bias_over_se.map_or("–".into(), |b| format!("{b:.3}"));
        for r in &rows {
            println!(
                "| {} | {} | {:.0} | {:.2e} | {:.1e} | {:.1e} | {} | {} | {:+.3} | {:+.4} | {} |",
                r.solver,
                r.setting,
                r.evaluations_per_realization,
                r.seconds_per_realization,
                r.error_rms,
                r.error_max,
                r.missed_sticks,
                r.spurious_sticks,
                r.bias_st,
                r.bias_h,
                score(r)
            );
        }
        let n = scenario.run.realizations;
        match rows.iter().find(|r| r.recommended) {
            Some(r) => println!(
                "\nrecommended at run.realizations = {n}: {} {} ({:.0} right-hand-side evaluations and {:.2e} CPU s per realization; every Table 1 bias below {} of its standard error, worst {})",
                r.solver, r.setting, r.evaluations_per_realization, r.seconds_per_realization, args.bias_fraction, score(r)
            ),
            None if args.realizations < crate::tradeoff::MIN_REALIZATIONS => println!(
                "\n{} realizations are too few to estimate a standard error (at least {}): no recommendation; run with --realizations 200 or more",
                args.realizations,
                crate::tradeoff::MIN_REALIZATIONS
            ),
            None => println!("\nno setting keeps every Table 1 bias below {} of its standard error at run.realizations = {n}", args.bias_fraction),
        }
    }
    Ok(())
}

fn sensitivity_command(args: SensitivityArgs, quiet: bool) -> anyhow::Result<()> {
    if args.realizations < 2 || args.realizations > 100_000_000 {
        return Err(usage(format!("--realizations {}: must be between 2 and 100000000", args.realizations)));
    }
    check_separate(&args.out, "--out", &scenario_inputs(&args.input))?;
    let mut scenario = Scenario::resolve(args.input.scenario.as_deref(), &args.input.sets)?;
    Overrides { realizations: None, seed: args.seed }.apply(&mut scenario);
    scenario.check()?;
    scenario.refuse_sweep("sensitivity")?;
    let rows = crate::sensitivity::run(&scenario, args.realizations, &args.out).context("sensitivity")?;
    if !quiet {
        print!("{}", crate::sensitivity::markdown(&rows, args.realizations));
    }
    Ok(())
}

fn exact_law_command(args: ExactLawArgs, quiet: bool) -> anyhow::Result<()> {
    if !(8..=320).contains(&args.resolution) {
        return Err(usage(format!("--resolution {}: must be between 8 and 320", args.resolution)));
    }
    if let Some(t) = args.tail_times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
        return Err(usage(format!("--tail-times {t}: must be a finite time >= 0 s")));
    }
    if let Some(n) = args.counts.filter(|n| !(8..=320).contains(n)) {
        return Err(usage(format!("--counts {n}: must be between 8 and 320")));
    }
    if let Some(n) = args.densities.filter(|n| !(8..=320).contains(n)) {
        return Err(usage(format!("--densities {n}: must be between 8 and 320")));
    }
    check_separate(&args.out, "--out", &scenario_inputs(&args.input))?;
    let scenario = Scenario::resolve(args.input.scenario.as_deref(), &args.input.sets)?;
    scenario.check()?;
    scenario.refuse_sweep("exact-law")?;
    if let Some(note) = scenario.scene().ok().as_ref().and_then(crate::law::cost_note).filter(|_| !quiet) {
        eprintln!("{note}");
    }
    // on a terminal, each iteration overwrites one line; the finished resolution replaces it
    let live = !quiet && std::io::stderr().is_terminal();
    let mut progress = |l: &crate::law::Level, seconds: f64| {
        if !quiet {
            eprintln!("{}resolution {:>3}: {} iterations, {seconds:.1} s", if live { "\r\x1b[K" } else { "" }, l.n, l.iterations);
        }
    };
    // (the counts' sequence reports its sticks here: k and P(T_k <= t_a), after Table 1's)
    let counting = std::cell::Cell::new(false);
    let mut step = |n: u32, i: u32, x: f64| {
        if live && counting.get() {
            eprint!("\r\x1b[KS_T and S_L, resolution {n:>3}: stick {i}, P(T_k <= t_a) = {x:.1e}");
        } else if live {
            eprint!("\r\x1b[Kresolution {n:>3}: iteration {i}, change {x:.1e}");
        }
    };
    let mut sticks = |what: &str, n: u32, seconds: f64| {
        counting.set(true);
        if !quiet {
            eprintln!("{}{what} from the initial conditions, resolution {n:>3}: {seconds:.1} s", if live { "\r\x1b[K" } else { "" });
        }
    };
    let opts = crate::law::Options { finest: args.resolution, tail_times: args.tail_times.clone(), counts: args.counts, densities: args.densities };
    let (levels, rows, counts, densities, warning) =
        crate::law::run(&scenario, &opts, &args.out, &mut progress, &mut step, &mut sticks).context("exact-law")?;
    if !quiet {
        print!("{}", crate::law::markdown(&levels));
        println!();
        print!("{}", crate::law::sticks::markdown(&rows));
        if !counts.is_empty() {
            println!();
            print!("{}", crate::law::counts::markdown(&counts));
        }
        if !densities.is_empty() {
            println!();
            print!("{}", crate::law::densities::markdown(&densities));
        }
        if let Some(w) = warning {
            eprintln!("{w}");
        }
    }
    Ok(())
}

fn predict_command(args: PredictArgs, quiet: bool) -> anyhow::Result<()> {
    if !(8..=320).contains(&args.resolution) {
        return Err(usage(format!("--resolution {}: must be between 8 and 320", args.resolution)));
    }
    if args.futures == Some(0) {
        return Err(usage("--futures must be at least 1"));
    }
    if let Some(h) = args.horizon.filter(|h| !(h.is_finite() && *h > 0.0)) {
        return Err(usage(format!("--horizon {h}: must be a positive number of seconds")));
    }
    if let Some(out) = &args.out {
        check_separate(out, "--out", &scenario_inputs(&args.input))?;
    }
    let mut scenario = Scenario::resolve(args.input.scenario.as_deref(), &args.input.sets)?;
    Overrides { realizations: None, seed: args.seed }.apply(&mut scenario);
    scenario.check()?;
    scenario.refuse_sweep("predict")?;
    let (x, velocity, belt) = args.state;
    let state = crate::predict::State { x, velocity, belt, stuck: args.stuck };
    if let Some(n) = args.densities.filter(|n| !(8..=320).contains(n)) {
        return Err(usage(format!("--densities {n}: must be between 8 and 320")));
    }
    let opts = crate::predict::Options { resolution: args.resolution, futures: args.futures, horizon: args.horizon, densities: args.densities };
    let mut progress = |what: &str| {
        if !quiet {
            eprintln!("{what}");
        }
    };
    let p = crate::predict::run(&scenario, state, opts, args.out.as_deref(), &mut progress).context("predict")?;
    if !quiet {
        if let Some(why) = &p.exact_refused {
            eprintln!("exact: not available here ({why})");
        }
        if p.censored > 0 {
            eprintln!("warning: {} futures had not finished the slip after the next stick by the horizon {} s (raise --horizon)", p.censored, p.horizon);
        }
        print!("{}", crate::predict::markdown(&p));
    }
    Ok(())
}

/// Scenario overrides `reproduce` applies first (the user's --set come after and win).
pub const REPRODUCE_SETS: [&str; 2] = ["output.switch_times=true", "output.trajectories=3"];

/// Where `reproduce --out DIR` puts each stage's output.
pub struct ReproduceLayout {
    /// `DIR/dataset`, the `simulate` stage's output
    pub dataset: PathBuf,
    /// `DIR/analysis`, the `analyze` stage's output
    pub analysis: PathBuf,
    /// `DIR/figures`, the `figures` stage's output
    pub figures: PathBuf,
}

impl ReproduceLayout {
    /// The layout below `dir`.
    pub fn new(dir: &Path) -> ReproduceLayout {
        ReproduceLayout { dataset: dir.join("dataset"), analysis: dir.join("analysis"), figures: dir.join("figures") }
    }

    /// The report of a sweep cell (`DIR/report.html` for a plain dataset).
    pub fn report(dir: &Path, cell: &str) -> PathBuf {
        if cell.is_empty() {
            dir.join("report.html")
        } else {
            dir.join("reports").join(cell).join("report.html")
        }
    }
}

fn reproduce_command(args: ReproduceArgs, quiet: bool) -> anyhow::Result<()> {
    let dir = args.out.clone();
    let top = crate::outdir::prepare_reproduce(&dir, &scenario_inputs(&args.run.input))?;
    let layout = ReproduceLayout::new(&dir);
    // every later stage's output checked before the first runs (a file of the user's in an
    // earlier run's figures stopped it only after a new dataset and analysis had replaced theirs)
    crate::outdir::check_output(&layout.analysis, crate::outdir::Kind::Analysis, "--out")?;
    crate::outdir::check_output(&layout.figures, crate::outdir::Kind::Figures, "--out")?;
    crate::report::check_replaceable(&ReproduceLayout::report(&dir, ""))?;
    // what this run creates inside DIR (the entries absent now) is removed again should a later
    // stage fail: a failing reproduce leaves nothing it created
    let fresh: Vec<PathBuf> = ["dataset", "dataset.trajectories", "analysis", "figures", "report.html", "report.md", "reports"]
        .iter()
        .map(|n| dir.join(n))
        .filter(|p| std::fs::symlink_metadata(p).is_err())
        .collect();
    let result = reproduce_stages(args, &dir, &layout, quiet);
    if result.is_err() {
        for p in &fresh {
            match std::fs::symlink_metadata(p) {
                Ok(m) if m.is_dir() => drop(std::fs::remove_dir_all(p)),
                Ok(_) => drop(std::fs::remove_file(p)),
                Err(_) => {}
            }
        }
        return result;
    }
    top.keep();
    Ok(())
}

/// `reproduce`'s stages in order: simulate, analyze, figures, and a report per cell.
fn reproduce_stages(args: ReproduceArgs, dir: &Path, layout: &ReproduceLayout, quiet: bool) -> anyhow::Result<()> {
    let mut run = args.run;
    run.input.sets.splice(0..0, REPRODUCE_SETS.map(String::from));
    simulate_command(SimulateArgs { out: layout.dataset.clone(), shard: Shard::WHOLE, run }, quiet)?;
    let tail = analysis::tails::TailOptions { times: analysis::tails::PAPER_TAIL_TIMES.to_vec(), ..analysis::Options::default().tail };
    let opts = analysis::Options { progress: !quiet && std::io::stderr().is_terminal(), tail, ..Default::default() };
    let cells = analyze_and_print(&layout.dataset, &layout.analysis, &opts, quiet)?;
    figures_command(&layout.analysis, &layout.figures, quiet)?;
    // one report per sweep cell (a plain dataset is the single cell with the empty path)
    for cell in cells {
        let args = ReportArgs {
            dataset: layout.dataset.join(&cell),
            analysis: layout.analysis.join(&cell),
            figures: layout.figures.join(&cell),
            out: ReproduceLayout::report(dir, &cell),
            exact: None,
        };
        report_command(&args, quiet)?;
    }
    Ok(())
}

fn analyze_command(args: AnalyzeArgs, quiet: bool) -> anyhow::Result<()> {
    if crate::outdir::is_marked(&args.dataset, crate::outdir::Kind::Reproduce) {
        let d = args.dataset.join("dataset");
        return Err(usage(format!("{} is a `reproduce` output, not a dataset: did you mean {}?", args.dataset.display(), d.display())));
    }
    let mut opts = analysis::Options {
        max_index: args.max_index,
        bins: args.bins,
        permutations: args.permutations,
        allow_partial: args.allow_partial,
        progress: !quiet && std::io::stderr().is_terminal(),
        tails: !args.no_tails,
        tail: analysis::tails::TailOptions { times: args.tail_times, severity: args.severity },
        ..Default::default()
    };
    if !args.pairs.is_empty() {
        opts.pairs = args.pairs;
    }
    analyze_and_print(&args.dataset, &args.out, &opts, quiet).map(drop)
}

/// Analyse every cell below `dataset` into `out`, print the results unless `quiet`; returns the
/// cell paths (the empty path for a plain dataset).
fn analyze_and_print(dataset: &Path, out: &Path, opts: &analysis::Options, quiet: bool) -> anyhow::Result<Vec<String>> {
    let start = std::time::Instant::now();
    let cells = analysis::sweep::analyze_all(dataset, opts, out).context("analyze")?;
    let paths = cells.iter().map(|(p, _)| p.clone()).collect();
    if quiet {
        return Ok(paths);
    }
    if let [(path, a)] = cells.as_slice() {
        if path.is_empty() {
            print_analysis(a);
        }
    }
    if cells.len() > 1 || cells.iter().any(|(p, _)| !p.is_empty()) {
        println!("| cell | realizations | mean S_T | stick fraction | mean D | mean H | slope of Var T_k |\n|---|---|---|---|---|---|---|");
        for (path, a) in &cells {
            let c = analysis::sweep::summarize(path, a);
            let f = |v: Option<f64>| v.map_or("–".into(), |x| format!("{x:.4}"));
            println!("| {path} | {} | {:.3} | {:.4} | {} | {} | {} |", c.realizations, c.mean_st, c.stick_fraction, f(c.mean_d), f(c.mean_h), f(c.var_t_slope));
        }
    }
    for (path, a) in &cells {
        if !a.dataset.missing.is_empty() {
            let gaps: Vec<String> = a.dataset.missing.iter().map(|r| format!("{}..{}", r.start, r.end)).collect();
            eprintln!("PARTIAL {path}: analysed {} of the run's {} realizations; missing {}", a.dataset.rows, a.dataset.expected_rows, gaps.join(", "));
        }
    }
    let rows: u64 = cells.iter().map(|(_, a)| a.dataset.rows).sum();
    eprintln!("analysed {rows} realizations in {:.2} s -> {}", start.elapsed().as_secs_f64(), out.display());
    Ok(paths)
}

/// Whether `auto` chose a numerical method for a scene without closed forms and the scenario
/// left `[numerics]` at the paper's ode45 settings (a user's first Stribeck run would otherwise
/// take hundreds of times longer than needed without a word).
fn slow_default_numerics(sc: &Scenario) -> bool {
    use crate::solver::SolverKind;
    sc.run.solver == SolverKind::Auto && sc.solver() != SolverKind::Exact && sc.numerics == Scenario::paper().numerics
}

/// A run added to a dataset directory has the shape of what is there: a plain run beside plain
/// parts, a sweep beside the cells of a sweep of the same keys (else `analyze` would refuse the
/// directory afterwards, naming two runs).
fn same_shape(out: &Path, cells: &[crate::scenario::Cell]) -> anyhow::Result<()> {
    let Ok(entries) = std::fs::read_dir(out) else { return Ok(()) };
    let keys = |path: &str| path.split('/').next().and_then(|c| c.split_once('=')).map(|(k, _)| k.to_string());
    let ours = cells.first().and_then(|c| keys(&c.path));
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let theirs = if name.starts_with("part-") && name.ends_with(".parquet") {
            None
        } else if entry.path().is_dir() && name.contains('=') && !name.starts_with('.') {
            keys(&name)
        } else {
            continue;
        };
        if theirs != ours {
            let shown = |k: &Option<String>| k.as_ref().map_or("a plain run (part files at the top)".to_string(), |k| format!("a sweep of {k}"));
            return Err(usage(format!(
                "--out {} holds {}, and this run is {}: analyze could not read the two as one dataset; choose another --out",
                out.display(),
                shown(&theirs),
                shown(&ours)
            )));
        }
    }
    Ok(())
}

fn simulate_command(args: SimulateArgs, quiet: bool) -> anyhow::Result<()> {
    let run = &args.run;
    if let Some(s) = run.seed.filter(|&s| s > i64::MAX as u64) {
        return Err(usage(format!("--seed {s}: must be at most {}", i64::MAX)));
    }
    if let Some(n) = run.realizations.filter(|&n| n == 0 || n > crate::scenario::MAX_REALIZATIONS) {
        return Err(usage(format!("--realizations {n} (run.realizations): must be between 1 and {}", crate::scenario::MAX_REALIZATIONS)));
    }
    if let Some((_, t)) = run.target_se.iter().enumerate().find(|(i, t)| run.target_se[..*i].iter().any(|u| u.quantity == t.quantity)) {
        return Err(usage(format!("--target-se {}: the quantity is given twice; give one target per quantity", t.quantity)));
    }
    simulate::worker_threads(run.threads)?;
    let over = Overrides { realizations: run.realizations, seed: run.seed };
    let cells = Scenario::resolve_sweep(run.input.scenario.as_deref(), &run.input.sets, over)?;
    same_shape(&args.out, &cells)?;
    for cell in &cells {
        simulate::joins(&args.out.join(&cell.path), &cell.scenario, args.shard).map_err(usage)?;
    }
    let dir = DatasetDir::prepare(&args.out, &scenario_inputs(&run.input))?;
    let progress = !quiet && std::io::stderr().is_terminal();
    if let Some(sc) = cells.first().map(|c| &c.scenario).filter(|sc| !quiet && slow_default_numerics(sc)) {
        eprintln!(
            "note: this scene has no closed form, so `auto` runs {} at the default [numerics], the paper's ode45 settings (rtol = atol = 1e-9, max_step = 1e-4): accurate but slow. `stickslip tradeoff` finds the cheapest setting accurate enough for this scene (`stickslip scenes stribeck` shows one)",
            sc.solver().name()
        );
    }
    let opts = simulate::Options { out: args.out.clone(), shard: args.shard, threads: run.threads, progress };
    let summaries = simulate::sweep(&cells, &args.out, &opts, &run.target_se).context("simulate")?;
    for summary in summaries {
        if !quiet {
            let n = summary.realizations.max(1) as f64;
            eprintln!(
                "wrote {} realizations to {} in {:.2} s ({:.0} realizations/s); mean S_T = {:.3}",
                summary.realizations,
                summary.path.display(),
                summary.seconds,
                summary.realizations as f64 / summary.seconds,
                summary.total_sticks as f64 / n,
            );
        }
        // reaching the cap before a target is reported even with --quiet
        match &summary.targets {
            Some((true, se)) if !quiet => eprintln!("targets met after {} realizations: {se}", summary.realizations),
            Some((false, se)) => {
                eprintln!("warning: the cap of {} realizations (--realizations / run.realizations) was reached before every target: {se}", summary.realizations)
            }
            _ => {}
        }
    }
    dir.commit();
    Ok(())
}
