//! The command line's arguments: the clap types, with their help texts and defaults.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::analysis;
use crate::simulation::simulate::Shard;

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
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
    pub command: Command,
    /// No progress display, tables or summary lines (errors are still printed).
    #[arg(short, long, global = true)]
    pub quiet: bool,
}

/// The subcommands.
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
    /// The law without sampling: the long-run stick fraction, the mean and variance of the stick
    /// and slip durations, sticks per second and the breakaway fraction, the paper's Table 1
    /// (means and variances of T_k, L_k, D_k, H_k, k <= 6, from the initial conditions), the law
    /// of each stick's duration D_k and, with --counts, the laws of S_T and S_L, computed from the
    /// process' equations (no Monte Carlo) at three resolutions, extrapolated, with an error
    /// estimate; writes DIR/stationary.parquet, DIR/moments.parquet, DIR/survival.parquet,
    /// DIR/convergence.parquet (with --counts DIR/counts.parquet, with --densities the densities
    /// of T_k, L_k, H_k in DIR/densities.parquet), the stationary density and its
    /// figure. Scenes: Coulomb friction (mu_s >= mu_k) with or without a dashpot, the symmetric or
    /// telegraph belt, fixed parameters.
    ExactLaw(ExactLawArgs),
    /// The next stick from a given state: the law (mean, standard deviation) of the time to its
    /// start, its duration, the slip after it and whether it ends by breakaway — computed without
    /// sampling where the scene allows (as `exact-law`), and by conditional Monte Carlo (futures
    /// simulated from the same state) with --futures N or where it does not.
    Predict(PredictArgs),
    /// List the scenario files shipped in the binary (the paper scenario and the example
    /// scenes), print one, or write it to a file to edit: `stickslip scenes damped --out my.toml`.
    Scenes(ScenesArgs),
    /// Print a shell completion script, e.g. `stickslip completions bash > /etc/bash_completion.d/stickslip`.
    Completions {
        /// The shell: bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
}

/// Where a scenario comes from: a file and `--set` overrides.
#[derive(Debug, clap::Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML); keys it omits keep the paper values. `stickslip scenes` lists the
    /// shipped ones (the paper scenario; damping, static friction, an asymmetric belt, a Markov belt that stops, viscous friction, random
    /// parameters, Stribeck friction) and writes one out to edit.
    pub scenario: Option<PathBuf>,
    /// Override a scenario key by its dotted name, e.g. --set belt.switch_rate=1.0 (repeatable). The
    /// value is TOML: a list is a sweep (--set 'model.damping=[0, 0.5, 1]'), an inline table a
    /// distribution drawn per realization
    /// (--set 'model.friction_coefficient={dist = "uniform", low = 0.3, high = 0.7}').
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

/// Arguments of `sensitivity`.
#[derive(Debug, clap::Args)]
pub struct SensitivityArgs {
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
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

/// Arguments of `tradeoff`.
#[derive(Debug, clap::Args)]
pub struct TradeoffArgs {
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
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

/// Arguments of `exact-law`.
#[derive(Debug, clap::Args)]
pub struct ExactLawArgs {
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
    pub input: ScenarioArgs,
    /// Output directory (replaced atomically when complete).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// The finest resolution N: grid nodes per c_s + v0/omega of the phase plane (the solve runs
    /// at N/4, N/2 and N; the error is second order in 1/N; 8 to 320; on 2 cores, paper scene:
    /// N = 80 takes about 55 s and 0.6 GB, N = 160 about 5 minutes and 2.4 GB and certifies every
    /// Table 1 mean to 3.2e-5 relative, N = 320 about 30 minutes and 8.3 GiB and certifies every
    /// Table 1 mean and variance to 4.3e-5).
    #[arg(long, value_name = "N", default_value_t = 80)]
    pub resolution: u32,
    /// Times t [s] at which D_k's law P(D_k > t) (survival.parquet) is also evaluated, beside its
    /// grid; the default is reproduce's, which analyze's survival curves of the paper scene share.
    #[arg(long, value_name = "T,...", value_delimiter = ',', default_values_t = crate::analysis::tails::PAPER_TAIL_TIMES)]
    pub tail_times: Vec<f64>,
    /// Also the laws of the counts S_T and S_L (P(S = n), mean, variance: counts.parquet and
    /// moments.parquet), at resolutions N/4, N/2, N of their own (8 to 320). They follow every
    /// stick that can start in [0, t_a] (about 35 on the paper scene) and carry a Laplace
    /// transform, so they cost far more than Table 1: on the paper scene and 2 cores N = 8 takes
    /// about 2.5 minutes (E[S_T] = 16.52 with an error estimate of 0.3), N = 16 about 6 (0.07).
    /// Refused for a window shorter than 20 mean times between belt flips.
    #[arg(long, value_name = "N")]
    pub counts: Option<u32>,
    /// Also the densities of T_k, L_k and H_k (k <= 6), averaged over 100 cells of [0, t_a]
    /// (densities.parquet: variable, index, t, t_lo, t_hi, density, error), at resolutions N/4,
    /// N/2, N of their own (8 to 320), from the characteristic function at 257 frequencies (a
    /// cosine series). They cost far more than Table 1: on the paper scene and 2 cores N = 8
    /// takes about 10 minutes and 1.8 GB, N = 16 about 40 minutes and 7 GB. Refused for a
    /// point initial condition (T_1 then has a point mass).
    #[arg(long, value_name = "N")]
    pub densities: Option<u32>,
}

/// Arguments of `predict`.
#[derive(Debug, clap::Args)]
pub struct PredictArgs {
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
    pub input: ScenarioArgs,
    /// The state now: position x [m], mass velocity [m/s], belt velocity [m/s] (one of the belt's
    /// states: +v0 or -v0; +v_f or -v_r for a telegraph belt), e.g. --state=-0.5,0.2,1.
    #[arg(long, value_name = "X,V,V_BELT", allow_hyphen_values = true, value_parser = parse_state)]
    pub state: (f64, f64, f64),
    /// The mass is stuck now (its velocity equals the belt's): the prediction adds the current
    /// stick's remaining time, and the next stick is the one after it.
    #[arg(long)]
    pub stuck: bool,
    /// Simulate N futures from the state (conditional Monte Carlo, beside the exact values; the
    /// default where the exact method does not hold: 100,000).
    #[arg(long, value_name = "N")]
    pub futures: Option<u64>,
    /// The futures' horizon [s] (default: 100 mean times between belt flips, at least 10 and
    /// at most 10,000 spring periods 2π/ω); futures whose next slip is cut by it are counted, not used.
    #[arg(long, value_name = "T")]
    pub horizon: Option<f64>,
    /// The exact method's finest resolution (it solves at N/4, N/2 and N and extrapolates; 8 to
    /// 320).
    #[arg(long, value_name = "N", default_value_t = 40)]
    pub resolution: u32,
    /// Random seed of the futures (overrides run.seed).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Also write DIR/prediction.parquet (variable, method, mean, variance, error, variance_error, futures) and,
    /// when exact, DIR/stick_survival.parquet (t, P(D > t) of the next stick).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also the exact densities of the time to the next stick and of the slip after it, averaged
    /// over 100 cells (DIR/densities.parquet, as exact-law's, with the point mass of the path
    /// without a flip in `point_mass`), at resolutions N/4, N/2, N of their own (8 to 320;
    /// minutes: N = 8 about 2 on the paper scene). Needs --out and a scene the exact method holds.
    #[arg(long, value_name = "N")]
    pub densities: Option<u32>,
}

/// `X,V,V_BELT`: three numbers.
fn parse_state(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("{s:?}: {e} (expected X,V,V_BELT)"))?;
    match v[..] {
        [x, v, b] if x.is_finite() && v.is_finite() && b.is_finite() => Ok((x, v, b)),
        [_, _, _] => Err(format!("{s:?}: the three numbers must be finite")),
        _ => Err(format!("{s:?}: expected three numbers X,V,V_BELT, got {}", v.len())),
    }
}

/// Arguments of `scenes`.
#[derive(Debug, clap::Args)]
pub struct ScenesArgs {
    /// The scene to print or write (without it: the list).
    pub name: Option<String>,
    /// Write the scene to this file (a new file: an existing one is never replaced).
    #[arg(long, value_name = "FILE", requires = "name")]
    pub out: Option<PathBuf>,
}

/// Arguments of `figures`.
#[derive(Debug, clap::Args)]
pub struct FiguresArgs {
    /// Analysis directory written by `analyze`.
    pub analysis: PathBuf,
    /// Output directory for the figures (replaced atomically when complete).
    #[arg(long, value_name = "FIGDIR")]
    pub out: PathBuf,
}

/// Arguments of `report`.
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
    /// An `exact-law` output directory of the same scenario: its means and variances of T_k, L_k,
    /// D_k, H_k (and S_T, S_L if it ran with --counts), without sampling, go beside Table 1's
    /// intervals, and its law of D_k beside the product-limit bands.
    #[arg(long, value_name = "LAWDIR")]
    pub exact: Option<PathBuf>,
}

/// Arguments of `analyze`.
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
    #[arg(long, conflicts_with_all = ["tail_times", "severity"])]
    pub no_tails: bool,
}

/// Arguments of `simulate`.
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
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
    pub run: RunArgs,
}

/// Arguments of `reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Output directory of the whole study: DIR/dataset, DIR/analysis, DIR/figures and
    /// DIR/report.html (created if needed; a previous reproduce output is updated in place).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
    pub run: RunArgs,
}

/// The options `simulate` and `reproduce` share.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    #[command(flatten)]
    #[allow(missing_docs)] // (clap: a doc comment here would become help text)
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
    pub target_se: Vec<crate::observables::Target>,
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}
