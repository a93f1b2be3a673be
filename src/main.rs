//! The `stickslip` command: parse, run, report one clear error with its exit code
//! (2 bad input or usage, 1 failure while running; see `stickslip --help`).

use std::process::ExitCode;

fn main() -> ExitCode {
    stickslip::interrupt::install();
    match stickslip::cli::main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: error: {}", stickslip::cli::message(&e));
            ExitCode::from(stickslip::cli::exit_code(&e))
        }
    }
}
