//! The `bump` command line: with no subcommand the docking window (or a
//! headless replay); `check`, `touch`, `stats`, `render` and `devices`
//! drive the docking core (and the renderer) directly.

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bump: error: {e:#}");
            ExitCode::from(2)
        }
    }
}
