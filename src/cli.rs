//! Command line: flags are parsed and checked here, then handed to the stages.

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::Context;
use clap::{Parser, Subcommand};

use crate::analysis;
use crate::scenario::Scenario;
use crate::simulate::{self, Shard};

/// Stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.
#[derive(Debug, Parser)]
#[command(name = "stickslip", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
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
    /// The whole reproduction in one go: simulate into DIR, then DIR/analysis, DIR/figures and
    /// DIR/report.html (+ .md). Takes the same scenario options as `simulate`; stores the switch
    /// times and samples 3 trajectories (Figs 6 and 4 need them) unless --set says otherwise.
    Reproduce(SimulateArgs),
    /// Measure the speed/accuracy trade: the same realizations through every solver over a ladder
    /// of tolerances and steps, against `exact`; writes DIR/tradeoff.parquet and a work-precision plot.
    Tradeoff(TradeoffArgs),
}

/// Where a scenario comes from: a file and `--set` overrides.
#[derive(Debug, clap::Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML); keys it omits keep the paper values. See pipelines/paper.toml.
    pub scenario: Option<PathBuf>,
    /// Override a scenario key by its dotted name, e.g. --set belt.switch_rate=1.0 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
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
    /// No table on stdout.
    #[arg(long)]
    pub quiet: bool,
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
    /// Joint histogram + independence test of a pair, e.g. --pair D1,D2 (repeatable;
    /// default: T1,T2 and D1,D2).
    #[arg(long = "pair", value_name = "A,B")]
    pub pairs: Vec<crate::analysis::series::Pair>,
    /// Permutations of the mutual-information null distribution.
    #[arg(long, value_name = "P", default_value_t = analysis::DEFAULT_PERMUTATIONS)]
    pub permutations: u32,
    /// Do not print the Table 1 comparison.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub input: ScenarioArgs,
    /// Output dataset directory (created if needed); the part file is replaced atomically.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Number of realizations (overrides run.realizations).
    #[arg(long, value_name = "N")]
    pub realizations: Option<u64>,
    /// Random seed (overrides run.seed).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Run only shard I of N (0-based): a contiguous block of realization indices. The parts of
    /// all N shards written into one DIR form the same dataset as an unsharded run.
    #[arg(long, value_name = "I/N", default_value = "0/1")]
    pub shard: Shard,
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
    /// No progress bar and no summary line.
    #[arg(long)]
    pub quiet: bool,
}

/// Parse the process arguments and run.
pub fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Simulate(args) => simulate_command(args),
        Command::Analyze(args) => analyze_command(args),
        Command::Figures(args) => figures_command(&args.analysis, &args.out, false),
        Command::Report(args) => report_command(&args, false),
        Command::Reproduce(args) => reproduce_command(args),
        Command::Tradeoff(args) => tradeoff_command(args),
    }
}

fn figures_command(adir: &std::path::Path, out: &std::path::Path, quiet: bool) -> anyhow::Result<()> {
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

fn tradeoff_command(args: TradeoffArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.realizations > 0, "--realizations must be at least 1");
    let scenario = Scenario::resolve(args.input.scenario.as_deref(), &args.input.sets)?;
    let rows = crate::tradeoff::run(&scenario, args.realizations, &args.out).context("tradeoff")?;
    if !args.quiet {
        println!("| solver | setting | CPU s/realization | RMS error [s] | max error [s] | missed | spurious | bias E[S_T] | bias E[H] |\n|---|---|---|---|---|---|---|---|---|");
        for r in &rows {
            println!(
                "| {} | {} | {:.2e} | {:.1e} | {:.1e} | {} | {} | {:+.3} | {:+.4} |",
                r.solver, r.setting, r.seconds_per_realization, r.error_rms, r.error_max, r.missed_sticks, r.spurious_sticks, r.bias_st, r.bias_h
            );
        }
    }
    Ok(())
}

/// Scenario overrides `reproduce` applies first (the user's --set come after and win).
pub const REPRODUCE_SETS: [&str; 2] = ["output.switch_times=true", "output.trajectories=3"];

fn reproduce_command(mut args: SimulateArgs) -> anyhow::Result<()> {
    let (dir, quiet) = (args.out.clone(), args.quiet);
    args.input.sets.splice(0..0, REPRODUCE_SETS.map(String::from));
    simulate_command(args)?;
    let analysis = dir.join("analysis");
    let cells = analyze_and_print(&dir, &analysis, &analysis::Options::default(), quiet)?;
    let figures = dir.join("figures");
    figures_command(&analysis, &figures, quiet)?;
    // one report per sweep cell (a plain dataset is the single cell with the empty path)
    for cell in cells {
        let report = dir.join(&cell).join("report.html");
        let args = ReportArgs { dataset: dir.join(&cell), analysis: analysis.join(&cell), figures: figures.join(&cell), out: report };
        report_command(&args, quiet)?;
    }
    Ok(())
}

fn analyze_command(args: AnalyzeArgs) -> anyhow::Result<()> {
    let mut opts = analysis::Options { max_index: args.max_index, bins: args.bins, permutations: args.permutations, ..Default::default() };
    if !args.pairs.is_empty() {
        opts.pairs = args.pairs;
    }
    anyhow::ensure!(opts.bins != Some(0), "--bins must be at least 1");
    analyze_and_print(&args.dataset, &args.out, &opts, args.quiet).map(drop)
}

/// Analyse every cell below `dataset` into `out`, print the results unless `quiet`; returns the
/// cell paths (the empty path for a plain dataset).
fn analyze_and_print(dataset: &std::path::Path, out: &std::path::Path, opts: &analysis::Options, quiet: bool) -> anyhow::Result<Vec<String>> {
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
            println!(
                "| {path} | {} | {:.3} | {:.4} | {} | {} | {} |",
                c.realizations, c.mean_st, c.stick_fraction, f(c.mean_d), f(c.mean_h), f(c.var_t_slope)
            );
        }
    }
    let rows: u64 = cells.iter().map(|(_, a)| a.dataset.rows).sum();
    eprintln!("analysed {rows} realizations in {:.2} s -> {}", start.elapsed().as_secs_f64(), out.display());
    Ok(paths)
}

fn print_analysis(a: &analysis::Analysis) {
    println!("{}", analysis::output::table1_markdown(a));
    for j in &a.joints {
        if let Some(t) = &j.test {
            println!(
                "{} vs {}: chi2 = {:.1} (df {}), p = {:.3}; G p = {:.3}; MI = {:.2e} nats, permutation p = {:.3} -> {}",
                j.pair.0, j.pair.1, t.chi2, t.df, t.chi2_p_value, t.g_p_value, t.mutual_information, t.mi_p_value,
                analysis::output::verdict(t.chi2_p_value)
            );
        }
    }
    if let Some(r) = &a.renewal {
        println!(
            "renewal check: E[S_T] predicted {:.2}, measured {:.2}; Var[S_T] predicted {:.2}, measured {:.2}",
            r.predicted_mean, r.measured_mean, r.predicted_variance, r.measured_variance
        );
    }
}

fn simulate_command(args: SimulateArgs) -> anyhow::Result<()> {
    let mut sets = args.input.sets;
    if let Some(n) = args.realizations {
        sets.push(format!("run.realizations={n}"));
    }
    if let Some(s) = args.seed {
        anyhow::ensure!(s <= i64::MAX as u64, "--seed {s}: must be at most {}", i64::MAX);
        sets.push(format!("run.seed={s}"));
    }
    let cells = Scenario::resolve_sweep(args.input.scenario.as_deref(), &sets)?;
    let progress = !args.quiet && std::io::stderr().is_terminal();
    let mut written: Vec<std::path::PathBuf> = Vec::new();
    for cell in &cells {
        let out = if cell.path.is_empty() { args.out.clone() } else { args.out.join(&cell.path) };
        let opts = simulate::Options { out, shard: args.shard, threads: args.threads, progress };
        let summary = match simulate::run(&cell.scenario, &opts) {
            Ok(s) => s,
            Err(e) => {
                remove_parts(&written, &args.out);
                let cell = if cell.path.is_empty() { String::new() } else { format!(" (sweep cell {})", cell.path) };
                return Err(anyhow::Error::new(e).context(format!("simulate{cell}")));
            }
        };
        if !args.quiet {
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
        written.push(summary.path);
    }
    Ok(())
}

/// Undo a failed sweep: remove the part files it wrote and the directories left empty below `top`.
fn remove_parts(parts: &[std::path::PathBuf], top: &std::path::Path) {
    for path in parts {
        let _ = std::fs::remove_file(path);
        let mut dir = path.parent();
        while let Some(d) = dir.filter(|d| d.starts_with(top)) {
            if std::fs::remove_dir(d).is_err() {
                break;
            }
            dir = d.parent();
        }
    }
}
