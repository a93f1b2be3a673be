//! Command line: flags are parsed and checked here, then handed to the stages.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Parser, Subcommand};

use crate::analysis;
use crate::outdir::{check_separate, DatasetDir};
use crate::scenario::{Overrides, Scenario};
use crate::simulate::{self, Shard};

/// Stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.
#[derive(Debug, Parser)]
#[command(
    name = "stickslip",
    version,
    about,
    long_about = None,
    after_help = "Exit status: 0 success, 2 bad input or usage (the message names the key, value, file or column), 1 a failure while running, 130/143 interrupted (SIGINT/SIGTERM; temporaries removed)."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// No progress display, tables or summary lines (errors are still printed).
    #[arg(short, long, global = true)]
    pub quiet: bool,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate realizations and write the event dataset (Parquet) into --out DIR.
    ///
    /// Without SCENARIO the paper scenario runs (Lima & Sampaio: m = 1 kg, k = 4 N/m,
    /// n = 9.8 N, mu = 0.51, v0 = 1 m/s, lambda = 5 /s, t_a = 10 s, 18,000 realizations).
    Simulate(SimulateArgs),
    /// Analyse a dataset: moments (Table 1), histograms, joint histograms, independence tests,
    /// growth of the start instants with their index; tidy Parquet tables + summary.json in ADIR.
    Analyze(AnalyzeArgs),
    /// Draw the paper's figures (PNG and SVG) from an analysis directory into --out FIGDIR.
    Figures(FiguresArgs),
    /// Write a self-contained HTML report (figures inlined) and its Markdown twin.
    Report(ReportArgs),
    /// The whole reproduction in one go: simulate into DIR/dataset, then DIR/analysis,
    /// DIR/figures and DIR/report.html (+ .md; a sweep: DIR/reports/CELL/report.html). Takes the same scenario options as `simulate`; stores the switch
    /// times and samples 3 trajectories (Figs 6 and 4 need them) unless --set says otherwise.
    Reproduce(ReproduceArgs),
    /// Measure the speed/accuracy trade: the same realizations through every solver over a ladder
    /// of tolerances and steps, against `exact`; writes DIR/tradeoff.parquet and a work-precision plot.
    Tradeoff(TradeoffArgs),
    /// Global sensitivity: first-order and total Sobol indices of S_T, the stick fraction and the
    /// mean stick and slip durations with respect to each random scene key and to the intrinsic
    /// randomness (pick-freeze, N·(d+3) realizations); writes DIR/sobol.parquet, sobol.png, sobol.md.
    Sensitivity(SensitivityArgs),
    /// List the scenario files shipped in the binary (the paper scenario and the example
    /// scenes), print one, or write it to a file to edit: `stickslip scenes damped --out my.toml`.
    Scenes(ScenesArgs),
    /// Print a shell completion script, e.g. `stickslip completions bash > /etc/bash_completion.d/stickslip`.
    Completions {
        /// The shell: bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
}

/// A usage error found after parsing (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Usage(pub String);

fn usage(message: impl Into<String>) -> anyhow::Error {
    Usage(message.into()).into()
}

/// Exit code of a failed run: 2 when the input (a flag, key, value, file or output directory)
/// is at fault, 1 for a failure while running.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if e.chain().any(is_bad_input) {
        2
    } else {
        1
    }
}

/// Whether an error (one link of a chain) blames the input; transparent wrappers are looked
/// through, since their inner error is not a link of its own.
fn is_bad_input(e: &(dyn std::error::Error + 'static)) -> bool {
    use crate::analysis::{input::InputError, AnalysisError};
    use crate::dataset::DatasetError;
    use crate::figures::FigureError;
    use crate::outdir::OutDirError;
    use crate::report::ReportError;
    use crate::simulate::SimulateError;
    use crate::tradeoff::TradeoffError;
    let out = |o: &OutDirError| o.refused;
    if e.is::<Usage>() || e.is::<crate::scenario::ScenarioError>() || e.is::<InputError>() {
        return true;
    }
    if let Some(o) = e.downcast_ref::<OutDirError>() {
        return out(o);
    }
    if let Some(a) = e.downcast_ref::<AnalysisError>() {
        return match a {
            AnalysisError::Input(_) | AnalysisError::Options(_) | AnalysisError::Read { .. } => true,
            AnalysisError::Out(o) => out(o),
            AnalysisError::Write { .. } => false,
        };
    }
    let dataset = |d: &DatasetError| match d {
        DatasetError::Layout { .. } => true,
        DatasetError::Out(o) => out(o),
        DatasetError::Write { .. } => false,
    };
    if let Some(d) = e.downcast_ref::<DatasetError>() {
        return dataset(d);
    }
    if let Some(s) = e.downcast_ref::<SimulateError>() {
        return match s {
            SimulateError::Threads(_) | SimulateError::Scenario(_) => true,
            SimulateError::Dataset(d) => dataset(d),
            SimulateError::Out(o) => out(o),
            SimulateError::Run(_) | SimulateError::Pool(_) => false,
        };
    }
    if let Some(r) = e.downcast_ref::<ReportError>() {
        return match r {
            ReportError::Read { .. } | ReportError::Mismatch { .. } | ReportError::Dataset(_) => true,
            ReportError::Out(o) => out(o),
            ReportError::Write { .. } => false,
        };
    }
    if let Some(f) = e.downcast_ref::<FigureError>() {
        return match f {
            FigureError::Read { .. } => true,
            FigureError::Out(o) => out(o),
            _ => false,
        };
    }
    if let Some(t) = e.downcast_ref::<TradeoffError>() {
        return match t {
            TradeoffError::Scenario(_) => true,
            TradeoffError::Out(o) => out(o),
            _ => false,
        };
    }
    if let Some(s) = e.downcast_ref::<crate::sensitivity::SensitivityError>() {
        use crate::sensitivity::SensitivityError as S;
        return match s {
            S::Scenario(_) | S::NoRandomKey | S::TooLarge { .. } => true,
            S::Out(o) => out(o),
            S::Run(_) | S::Write { .. } => false,
        };
    }
    false
}

/// The error and its causes on one printable line, each cause once (a cause whose text is
/// already shown, as when a message quotes its `source`, is not repeated). Whatever a cause
/// quotes — a user's 100,000-character `--set` value, a file's control bytes — is made
/// printable and shortened ([`printable`]).
pub fn message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = printable(&cause.to_string());
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out += ": ";
        }
        out += &text;
    }
    out
}

/// `text` on one line: control characters (newlines included) become spaces, runs of spaces
/// one, and a run of more than 200 characters without a space keeps its first 80 and says how
/// long it was.
fn printable(text: &str) -> String {
    let clean: String = text.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let words: Vec<String> = clean
        .split_whitespace()
        .map(|w| {
            let n = w.chars().count();
            if n > 200 {
                format!("{}… ({n} characters)", w.chars().take(80).collect::<String>())
            } else {
                w.to_string()
            }
        })
        .collect();
    words.join(" ")
}

/// Where a scenario comes from: a file and `--set` overrides.
#[derive(Debug, clap::Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML); keys it omits keep the paper values. `stickslip scenes` lists the
    /// shipped ones (the paper scenario; damping, static friction, an asymmetric belt, random
    /// parameters, Stribeck friction) and writes one out to edit.
    pub scenario: Option<PathBuf>,
    /// Override a scenario key by its dotted name, e.g. --set belt.switch_rate=1.0 (repeatable). The
    /// value is TOML: a list is a sweep (--set 'model.damping=[0, 0.5, 1]'), an inline table a
    /// distribution drawn per realization
    /// (--set 'model.friction_coefficient={dist = "uniform", low = 0.3, high = 0.7}').
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

#[derive(Debug, clap::Args)]
pub struct SensitivityArgs {
    #[command(flatten)]
    pub input: ScenarioArgs,
    /// Output directory (replaced atomically when complete).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Pick-freeze samples N (the run simulates N·(d+3) realizations for d random keys).
    #[arg(long, value_name = "N", default_value_t = 2000)]
    pub realizations: u64,
    /// Random seed (overrides run.seed).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
}

#[derive(Debug, clap::Args)]
pub struct TradeoffArgs {
    #[command(flatten)]
    pub input: ScenarioArgs,
    /// Output directory (replaced atomically when complete).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Realizations per setting (all settings run the same ones, on one thread).
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub realizations: u64,
    /// Recommend the cheapest setting whose bias on every Table 1 statistic is below this
    /// fraction of its Monte Carlo standard error at the scenario's run.realizations.
    #[arg(long, value_name = "F", default_value_t = crate::tradeoff::BIAS_FRACTION)]
    pub bias_fraction: f64,
}

#[derive(Debug, clap::Args)]
pub struct ScenesArgs {
    /// The scene to print or write (without it: the list).
    pub name: Option<String>,
    /// Write the scene to this file (a new file: an existing one is never replaced).
    #[arg(long, value_name = "FILE", requires = "name")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, clap::Args)]
pub struct FiguresArgs {
    /// Analysis directory written by `analyze`.
    pub analysis: PathBuf,
    /// Output directory for the figures (replaced atomically when complete).
    #[arg(long, value_name = "FIGDIR")]
    pub out: PathBuf,
}

#[derive(Debug, clap::Args)]
pub struct ReportArgs {
    /// Dataset directory (for provenance).
    pub dataset: PathBuf,
    /// Analysis directory.
    pub analysis: PathBuf,
    /// Figures directory.
    pub figures: PathBuf,
    /// The HTML file to write; the Markdown twin goes next to it with the extension .md.
    #[arg(long, value_name = "FILE", default_value = "report.html")]
    pub out: PathBuf,
}

#[derive(Debug, clap::Args)]
pub struct AnalyzeArgs {
    /// Dataset directory written by `simulate` (all part-*.parquet files below it).
    pub dataset: PathBuf,
    /// Output directory (replaced atomically when the analysis is complete).
    #[arg(long, value_name = "ADIR")]
    pub out: PathBuf,
    /// Largest event index k analysed for T_k, L_k, D_k, H_k.
    #[arg(long, value_name = "K", default_value_t = analysis::DEFAULT_MAX_INDEX)]
    pub max_index: u32,
    /// Fixed number of histogram bins (default: Scott's rule, 10..200 bins).
    #[arg(long, value_name = "N")]
    pub bins: Option<usize>,
    /// Joint histogram + independence test of two observables: T_k, L_k, D_k, H_k, Y_k or a
    /// scalar such as S_T or stick_fraction (a name it does not know lists them all), e.g.
    /// --pair D1,D2 (repeatable; default: T1,T2 and D1,D2).
    #[arg(long = "pair", value_name = "A,B")]
    pub pairs: Vec<crate::analysis::Pair>,
    /// Permutations of the mutual-information null distribution.
    #[arg(long, value_name = "P", default_value_t = analysis::DEFAULT_PERMUTATIONS)]
    pub permutations: u32,
    /// Analyse the parts present although realization ranges of the run are missing (the
    /// summary and the report say which); without it an incomplete dataset is refused.
    #[arg(long)]
    pub allow_partial: bool,
    /// Times t [s] at which the survival curves P(D > t), P(H > t) are also evaluated, and the
    /// thresholds T of P(longest stick > T), e.g. --tail-times 0.5,1,2 (survival.parquet,
    /// tails.parquet; printed).
    #[arg(long, value_name = "T,...", value_delimiter = ',')]
    pub tail_times: Vec<f64>,
    /// Thresholds s of P(severity > s), severity = (max ẋ − min ẋ)/(2 v0).
    #[arg(long, value_name = "S,...", value_delimiter = ',', default_values_t = analysis::DEFAULT_SEVERITY)]
    pub severity: Vec<f64>,
    /// Skip the tails (survival curves, conditional estimator, extremes).
    #[arg(long)]
    pub no_tails: bool,
}

#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Output dataset directory (created if needed); the part file is replaced atomically.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Run only shard I of N (0-based): a contiguous block of realization indices. The parts of
    /// all N shards written into one DIR form the same dataset as an unsharded run.
    #[arg(long, value_name = "I/N", default_value = "0/1")]
    pub shard: Shard,
    #[command(flatten)]
    pub run: RunArgs,
}

#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Output directory of the whole study: DIR/dataset, DIR/analysis, DIR/figures and
    /// DIR/report.html (created if needed; a previous reproduce output is updated in place).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
}

/// The options `simulate` and `reproduce` share.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub input: ScenarioArgs,
    /// Number of realizations (overrides run.realizations).
    #[arg(long, value_name = "N")]
    pub realizations: Option<u64>,
    /// Random seed (overrides run.seed).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Stop when the standard error of the mean of VAR is at most SE (repeatable; all must be
    /// met). VAR: S_T, S_L, T_k, D_k, L_k, H_k (k >= 1), stick_fraction, mean_stick_duration or
    /// mean_slip_duration (a duration cut at t_a is censored, left out, as everywhere). Checked after every
    /// chunk of realizations in index order, so the dataset is the first N rows of a fixed-N run;
    /// --realizations (run.realizations) is the cap. With --shard, each shard applies the targets
    /// to its own block (its standard errors, not the union's).
    #[arg(long = "target-se", value_name = "VAR=SE")]
    pub target_se: Vec<crate::precision::Target>,
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}

/// Parse the process arguments and run.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    let quiet = cli.quiet;
    match cli.command {
        Command::Simulate(args) => simulate_command(args, quiet),
        Command::Analyze(args) => analyze_command(args, quiet),
        Command::Figures(args) => figures_command(&args.analysis, &args.out, quiet),
        Command::Report(args) => report_command(&args, quiet),
        Command::Reproduce(args) => reproduce_command(args, quiet),
        Command::Tradeoff(args) => tradeoff_command(args, quiet),
        Command::Sensitivity(args) => sensitivity_command(args, quiet),
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
        None => print!("{}", scene.text),
        Some(path) => crate::outdir::write_new_file(path, scene.text.as_bytes(), "--out")?,
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
    let [html, md] = crate::report::run(&args.dataset, &args.analysis, &args.figures, &args.out).context("report")?;
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

/// Scenario overrides `reproduce` applies first (the user's --set come after and win).
pub const REPRODUCE_SETS: [&str; 2] = ["output.switch_times=true", "output.trajectories=3"];

/// Where `reproduce --out DIR` puts each stage's output.
pub struct ReproduceLayout {
    pub dataset: PathBuf,
    pub analysis: PathBuf,
    pub figures: PathBuf,
}

impl ReproduceLayout {
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
            out: ReproduceLayout::report(&dir, &cell),
        };
        report_command(&args, quiet)?;
    }
    top.keep();
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

fn print_analysis(a: &analysis::Analysis) {
    let p_is = crate::figures::format::p_relation;
    println!("{}", analysis::output::table1_markdown(a));
    for j in &a.joints {
        if let Some(t) = &j.test {
            println!(
                "{} vs {}: chi2 = {:.1} (df {}), p {}; G p {}; MI = {:.2e} nats, permutation p {} -> {}",
                j.pair.0,
                j.pair.1,
                t.chi2,
                t.df,
                p_is(t.chi2_p_value),
                p_is(t.g_p_value),
                t.mutual_information,
                p_is(t.mi_p_value),
                analysis::output::verdict(t.chi2_p_value)
            );
        }
    }
    if let Some(t) = &a.tails {
        t.lines(&a.options.tail.times).iter().for_each(|l| println!("{l}"));
        if let Some(why) = &t.conditional_refused {
            eprintln!("note: no conditional tail estimate: {why}");
        }
    }
    if let Some(r) = &a.renewal {
        println!(
            "renewal check: E[S_T] predicted {:.2}, measured {:.2}; Var[S_T] predicted {:.2}, measured {:.2}",
            r.predicted_mean, r.measured_mean, r.predicted_variance, r.measured_variance
        );
    }
}

/// Whether `auto` chose a numerical method for a scene without closed forms and the scenario
/// left `[numerics]` at the paper's ode45 settings (a user's first Stribeck run would otherwise
/// take hundreds of times longer than needed without a word).
fn slow_default_numerics(sc: &Scenario) -> bool {
    use crate::solver::SolverKind;
    sc.run.solver == SolverKind::Auto && sc.solver() != SolverKind::Exact && sc.numerics == Scenario::paper().numerics
}

fn simulate_command(args: SimulateArgs, quiet: bool) -> anyhow::Result<()> {
    let run = &args.run;
    if let Some(s) = run.seed.filter(|&s| s > i64::MAX as u64) {
        return Err(usage(format!("--seed {s}: must be at most {}", i64::MAX)));
    }
    if let Some(n) = run.realizations.filter(|&n| n == 0 || n > crate::scenario::MAX_REALIZATIONS) {
        return Err(usage(format!("--realizations {n} (run.realizations): must be between 1 and {}", crate::scenario::MAX_REALIZATIONS)));
    }
    simulate::worker_threads(run.threads)?;
    let over = Overrides { realizations: run.realizations, seed: run.seed };
    let cells = Scenario::resolve_sweep(run.input.scenario.as_deref(), &run.input.sets, over)?;
    let dir = DatasetDir::prepare(&args.out, &scenario_inputs(&run.input))?;
    let progress = !quiet && std::io::stderr().is_terminal();
    if let Some(sc) = cells.first().map(|c| &c.scenario).filter(|sc| !quiet && slow_default_numerics(sc)) {
        eprintln!(
            "note: this scene has no closed form, so `auto` runs {} at the default [numerics], the paper's ode45 settings (rtol = atol = 1e-9, max_step = 1e-4): accurate but slow. `stickslip tradeoff` finds the cheapest setting accurate enough for this scene (`stickslip scenes stribeck` shows one)",
            sc.solver().name()
        );
    }
    // A sweep is committed whole: every cell is simulated into a temporary part first, and the
    // parts are renamed into place only when all cells succeeded (a failure leaves the previous
    // sweep, if any, untouched).
    let mut pending = Vec::with_capacity(cells.len());
    for cell in &cells {
        let out = if cell.path.is_empty() { args.out.clone() } else { args.out.join(&cell.path) };
        let opts = simulate::Options { out, shard: args.shard, threads: run.threads, progress };
        match simulate::compute_until(&cell.scenario, &opts, &run.target_se) {
            Ok(p) => pending.push(p),
            Err(e) => {
                drop(pending); // (each part's temporary and the cell directories it created go)
                let cell = if cell.path.is_empty() { String::new() } else { format!(" (sweep cell {})", cell.path) };
                return Err(anyhow::Error::new(e).context(format!("simulate{cell}")));
            }
        }
    }
    for p in pending {
        let summary = p.commit().context("simulate")?;
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
