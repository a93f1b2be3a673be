//! The `stickslip` command: parse, run, report one clear error with its exit code
//! (2 bad input or usage, 1 failure while running; see `stickslip --help`).

use std::process::ExitCode;

fn main() -> ExitCode {
    bound_malloc_arenas();
    if let Err(e) = size_polars_hot_tables() {
        eprintln!("stickslip: error: {e}");
        return ExitCode::from(2);
    }
    stickslip::interrupt::install();
    match stickslip::cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: error: {}", stickslip::cli::message(&e));
            ExitCode::from(stickslip::cli::exit_code(&e))
        }
    }
}

/// One glibc malloc arena per core, set before any thread starts. glibc's default (8 per core)
/// let the analysis' runs of polars queries, each allocating and freeing about a gigabyte, leave
/// memory behind in arenas that were not reused: peak RSS grew with the dataset (analyze of 10^7
/// realizations: 2.28 GB against 1.44 GB at 10^6; with one arena per core 1.66 against 1.16).
fn bound_malloc_arenas() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get()).max(2);
        // SAFETY: mallopt only sets a tunable of the allocator; no thread has started yet.
        unsafe {
            libc::mallopt(libc::M_ARENA_MAX, cores as libc::c_int);
        }
    }
}

/// Keys each streaming group-by of polars holds in its hot table before evicting to its
/// partitions (polars' default: 4,096; read from `POLARS_HOT_TABLE_SIZE` whenever a query is
/// planned). The tails' counts group their per-batch (key, count) pairs by 45,000 to 70,000
/// keys per count, which the default table evicts over and over: with 32,768, `analyze` of 10^6
/// paper realizations took 4.57 s against 4.95 s when polars counted every key (8 % less CPU),
/// and 3.82 s against 4.00 s now that it sums the pairs of each batch (README, "Python"). Set
/// here, before any thread starts (the environment is not safe to change later). A value the
/// user set is kept if it is a positive integer, refused otherwise (polars would panic on it).
fn size_polars_hot_tables() -> Result<(), String> {
    const HOT_TABLE: &str = "POLARS_HOT_TABLE_SIZE";
    match std::env::var_os(HOT_TABLE) {
        None => std::env::set_var(HOT_TABLE, "32768"),
        Some(v) if v.to_str().and_then(|s| s.parse::<usize>().ok()).is_some_and(|n| n > 0) => {}
        Some(v) => return Err(format!("{HOT_TABLE}={}: not a positive whole number of keys (unset it for the default)", v.to_string_lossy())),
    }
    Ok(())
}
