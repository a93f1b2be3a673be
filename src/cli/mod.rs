//! Command line: flags are parsed into the stages' typed requests ([`crate::stage`]); each
//! command calls its stage and prints the result.
//!
//! Files: `args.rs` the clap types; `terminal.rs` the progress sink drawn on stderr; `print.rs`
//! what the analysis prints; this one the commands.

use std::io::IsTerminal;
use std::path::Path;

use clap::Parser;

use crate::analysis;
use crate::progress::{Control, Progress, Silent};
use crate::stage::{self, Input, Source};

mod args;
mod print;
mod terminal;

use crate::blame::usage;
pub use crate::stage::{exit_code, message, Usage};
pub use args::*;
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
    let terminal = terminal::Terminal::new(std::io::stderr().is_terminal());
    let sink: &dyn Progress = if cli.quiet { &Silent } else { &terminal };
    let ctl = Control { progress: sink, ..Control::silent() };
    let quiet = cli.quiet;
    match cli.command {
        Command::Simulate(args) => simulate_command(args, quiet, ctl),
        Command::Analyze(args) => analyze_command(args, quiet, ctl),
        Command::Figures(args) => {
            let done = stage::figures::run(&stage::figures::Request { analysis: args.analysis, out: args.out }, ctl)?;
            print_figures(&done, quiet);
            Ok(())
        }
        Command::Report(args) => {
            let request = stage::report::Request { dataset: args.dataset, analysis: args.analysis, figures: args.figures, exact: args.exact, out: args.out };
            print_report(&stage::report::run(&request, ctl)?, quiet);
            Ok(())
        }
        Command::Reproduce(args) => reproduce_command(args, quiet, ctl),
        Command::Tradeoff(args) => tradeoff_command(args, quiet, ctl),
        Command::Sensitivity(args) => {
            let request = stage::sensitivity::Request { input: input(args.input), out: args.out, realizations: args.realizations, seed: args.seed };
            let done = stage::sensitivity::run(&request, ctl)?;
            if !quiet {
                print!("{}", crate::sensitivity::markdown(&done.rows, done.realizations));
            }
            Ok(())
        }
        Command::ExactLaw(args) => exact_law_command(args, quiet, ctl),
        Command::Predict(args) => predict_command(args, quiet, ctl),
        Command::Scenes(args) => scenes_command(&args),
        Command::Completions { shell } => {
            clap_complete::generate(shell, &mut <Cli as clap::CommandFactory>::command(), "stickslip", &mut std::io::stdout());
            Ok(())
        }
    }
}

/// The scenario arguments as a stage's input.
fn input(args: ScenarioArgs) -> Input {
    Input { source: args.scenario.map_or(Source::Paper, Source::File), sets: args.sets }
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

fn print_figures(done: &stage::figures::Outcome, quiet: bool) {
    if !quiet {
        eprintln!("drew {} figures (PNG + SVG) in {:.2} s -> {}", done.names.len(), done.seconds, done.out.display());
    }
}

fn print_report(done: &stage::report::Outcome, quiet: bool) {
    if !quiet {
        eprintln!("wrote {} and {}", done.html.display(), done.markdown.display());
    }
}

fn tradeoff_command(args: TradeoffArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let request = stage::tradeoff::Request { input: input(args.input), out: args.out, realizations: args.realizations, bias_fraction: args.bias_fraction };
    let done = stage::tradeoff::run(&request, ctl)?;
    if quiet {
        return Ok(());
    }
    let rows = &done.rows;
    println!("| solver | setting | evaluations/realization | CPU s/realization | RMS error [s] | max error [s] | missed | spurious | bias E[S_T] | bias E[H] | max bias/SE |\n|---|---|---|---|---|---|---|---|---|---|---|");
    let score = |r: &crate::tradeoff::Row| r.max_bias_over_se.map_or("–".into(), |b| format!("{b:.3}"));
    for r in rows {
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
    let n = done.scored_at;
    match rows.iter().find(|r| r.recommended) {
        Some(r) => println!(
            "\nrecommended at run.realizations = {n}: {} {} ({:.0} right-hand-side evaluations and {:.2e} CPU s per realization; every Table 1 bias below {} of its standard error, worst {})",
            r.solver, r.setting, r.evaluations_per_realization, r.seconds_per_realization, request.bias_fraction, score(r)
        ),
        None if request.realizations < crate::tradeoff::MIN_REALIZATIONS => println!(
            "\n{} realizations are too few to estimate a standard error (at least {}): no recommendation; run with --realizations 200 or more",
            request.realizations,
            crate::tradeoff::MIN_REALIZATIONS
        ),
        None => println!("\nno setting keeps every Table 1 bias below {} of its standard error at run.realizations = {n}", request.bias_fraction),
    }
    Ok(())
}

fn exact_law_command(args: ExactLawArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let request = stage::exact_law::Request {
        input: input(args.input),
        out: args.out,
        resolution: args.resolution,
        tail_times: args.tail_times,
        counts: args.counts,
        densities: args.densities,
    };
    let done = stage::exact_law::run(&request, ctl)?;
    if !quiet {
        print!("{}", crate::law::tables::markdown(&done.levels));
        println!();
        print!("{}", crate::law::sticks::markdown(&done.rows));
        if !done.counts.is_empty() {
            println!();
            print!("{}", crate::law::counts::markdown(&done.counts));
        }
        if !done.densities.is_empty() {
            println!();
            print!("{}", crate::law::densities::markdown(&done.densities));
        }
        if let Some(w) = done.warning {
            eprintln!("{w}");
        }
    }
    Ok(())
}

fn predict_command(args: PredictArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let request = stage::predict::Request {
        input: input(args.input),
        state: args.state,
        stuck: args.stuck,
        futures: args.futures,
        horizon: args.horizon,
        resolution: args.resolution,
        seed: args.seed,
        out: args.out,
        densities: args.densities,
    };
    let p = stage::predict::run(&request, ctl)?;
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

fn reproduce_command(args: ReproduceArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let run = args.run;
    let request = stage::reproduce::Request {
        input: input(run.input),
        out: args.out,
        realizations: run.realizations,
        seed: run.seed,
        target_se: run.target_se,
        threads: run.threads,
    };
    stage::reproduce::run(&request, ctl, &mut |done| match done {
        stage::reproduce::Done::Simulated(s) => print_simulated(s, quiet),
        stage::reproduce::Done::Analysed(a) => print_analysed(a, quiet),
        stage::reproduce::Done::Drew(f) => print_figures(f, quiet),
        stage::reproduce::Done::Reported(r) => print_report(r, quiet),
    })
}

fn analyze_command(args: AnalyzeArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let mut options = analysis::Options {
        max_index: args.max_index,
        bins: args.bins,
        permutations: args.permutations,
        allow_partial: args.allow_partial,
        tails: !args.no_tails,
        tail: analysis::tails::TailOptions { times: args.tail_times, severity: args.severity },
        ..Default::default()
    };
    if !args.pairs.is_empty() {
        options.pairs = args.pairs;
    }
    let done = stage::analyze::run(&stage::analyze::Request { dataset: args.dataset, out: Some(args.out), options }, ctl)?;
    print_analysed(&done, quiet);
    Ok(())
}

/// The analysis of a plain dataset, or the sweep's table of cells; what is missing; the time.
fn print_analysed(done: &stage::analyze::Outcome, quiet: bool) {
    if quiet {
        return;
    }
    let cells = &done.cells;
    if let [(path, a)] = cells.as_slice() {
        if path.is_empty() {
            print_analysis(a);
        }
    }
    if done.is_sweep() {
        println!("| cell | realizations | mean S_T | stick fraction | mean D | mean H | slope of Var T_k |\n|---|---|---|---|---|---|---|");
        for (path, a) in cells {
            let c = analysis::sweep::summarize(path, a);
            let f = |v: Option<f64>| v.map_or("–".into(), |x| format!("{x:.4}"));
            println!("| {path} | {} | {:.3} | {:.4} | {} | {} | {} |", c.realizations, c.mean_st, c.stick_fraction, f(c.mean_d), f(c.mean_h), f(c.var_t_slope));
        }
    }
    for (path, a) in cells {
        if !a.dataset.missing.is_empty() {
            let gaps: Vec<String> = a.dataset.missing.iter().map(|r| format!("{}..{}", r.start, r.end)).collect();
            eprintln!("PARTIAL {path}: analysed {} of the run's {} realizations; missing {}", a.dataset.rows, a.dataset.expected_rows, gaps.join(", "));
        }
    }
    let out = done.out.as_ref().map_or(String::new(), |o| format!(" -> {}", o.display()));
    eprintln!("analysed {} realizations in {:.2} s{out}", done.realizations(), done.seconds);
}

fn simulate_command(args: SimulateArgs, quiet: bool, ctl: Control) -> anyhow::Result<()> {
    let run = args.run;
    let request = stage::simulate::Request {
        input: input(run.input),
        out: args.out,
        shard: args.shard,
        realizations: run.realizations,
        seed: run.seed,
        target_se: run.target_se,
        threads: run.threads,
    };
    print_simulated(&stage::simulate::run(&request, ctl)?, quiet);
    Ok(())
}

/// Each cell's line; reaching the cap before a target is reported even with --quiet.
fn print_simulated(done: &stage::simulate::Outcome, quiet: bool) {
    for summary in &done.summaries {
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
        match &summary.targets {
            Some((true, se)) if !quiet => eprintln!("targets met after {} realizations: {se}", summary.realizations),
            Some((false, se)) => {
                eprintln!("warning: the cap of {} realizations (--realizations / run.realizations) was reached before every target: {se}", summary.realizations)
            }
            _ => {}
        }
    }
}
