//! The `penumbra` command: a thin layer over the library.
//!
//! Exit codes: 0 on success (also for a render interrupted by Ctrl-C, whose partial image
//! is written), 2 for bad input (scene file or arguments), 1 for internal errors.

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match std::panic::catch_unwind(|| cli::run(args)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(cli::Failure::BadInput(report))) => {
            eprintln!("{report:?}");
            ExitCode::from(2)
        }
        Ok(Err(cli::Failure::Internal(message))) => {
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
        Err(_) => {
            eprintln!("error: internal error (a bug in Penumbra); please report it with the scene that caused it");
            ExitCode::from(1)
        }
    }
}
