//! The `bump` command line: `check`, `touch` and `stats` drive the docking
//! core directly; with no subcommand it describes the scene it would open.

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
