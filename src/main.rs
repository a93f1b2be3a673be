//! The `stickslip` command: parse, run, report one clear error.

use std::process::ExitCode;

fn main() -> ExitCode {
    match stickslip::cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
