//! The `stickslip` command: parse, run, report one clear error with its exit code
//! (2 bad input or usage, 1 failure while running; see `stickslip --help`).

use std::process::ExitCode;

fn main() -> ExitCode {
    bound_malloc_arenas();
    if let Err(e) = check_polars_hot_table_size().and_then(|()| stickslip::analysis::decode_on_every_core()) {
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
/// let 0.2.0's runs of polars queries, each allocating and freeing about a gigabyte, leave
/// memory behind in arenas that were not reused: peak RSS grew with the dataset (analyze of 10^7
/// realizations: 2.28 GB against 1.44 GB at 10^6; with one arena per core 1.66 against 1.16).
/// Today's runs hold about 0.4 GiB (the book's Benchmarks); the bound stays, as it costs nothing.
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

/// `POLARS_HOT_TABLE_SIZE`: the keys each streaming group-by of polars holds in its hot table
/// before evicting to its partitions (polars' default: 4,096; read whenever a query is planned).
/// polars panics on a value that is not a positive integer, so one the user set is checked
/// before anything runs and refused with one line. (This command once raised the default to
/// 32,768 for the tails' counts, 8 % faster when polars counted every key; since the counts are
/// made per batch it changes nothing: 3.89 s against 3.85 s at 10^6, the book's Benchmarks, "The tails".)
fn check_polars_hot_table_size() -> Result<(), String> {
    const HOT_TABLE: &str = "POLARS_HOT_TABLE_SIZE";
    match std::env::var_os(HOT_TABLE) {
        None => {}
        Some(v) if v.to_str().and_then(|s| s.parse::<usize>().ok()).is_some_and(|n| n > 0) => {}
        Some(v) => return Err(format!("{HOT_TABLE}={}: not a positive whole number of keys (unset it for the default)", v.to_string_lossy())),
    }
    Ok(())
}
