//! Command-line parsing and dispatch. Errors become `anyhow` here, at the
//! binary's edge; the library below speaks `thiserror`.

/// `println!` for command output: a closed stdout (`bump ... | head`) ends
/// the program quietly instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::cli::write_line(format_args!($($arg)*)) };
}

mod check;
#[cfg(feature = "app")]
mod devices;
mod dock;
mod pockets;
#[cfg(feature = "app")]
mod render;
mod report;
mod scene_args;
mod score;
mod settle;
mod stats;
mod steer;
mod touch;
mod window;

use clap::{Parser, Subcommand};

pub use scene_args::SceneArgs;

/// Interactive molecular docking with collision detection (after Turk 1989).
#[derive(Debug, Parser)]
#[command(name = "bump", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Files to open in the docking window: a receptor (or a complex to split
    /// with --ligand), then drugs and any other molecules. None: the built-in
    /// scene (the thesis's triple ring and E).
    files: Vec<std::path::PathBuf>,
    #[command(flatten)]
    window: window::WindowArgs,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Static check: the colliding pairs at the file pose (optionally moved).
    Check(check::CheckArgs),
    /// Move-to-touch: how far the drug may move along a proposed motion.
    Touch(touch::TouchArgs),
    /// AutoDock Vina's score, term by term, with the Coulomb energy beside it.
    Score(score::ScoreArgs),
    /// Minimise the score from the pose without ever colliding (Vina's optimize).
    Settle(settle::SettleArgs),
    /// Dock the drug in a box: a global search, every pose collision-free.
    Dock(dock::DockArgs),
    /// The receptor's candidate binding pockets, ranked, with docking boxes.
    Pockets(pockets::PocketsArgs),
    /// Steer the drug from outside towards its file pose through a response.
    Steer(steer::SteerArgs),
    /// Atoms per grid cell (the thesis's Table 1) for real files.
    Stats(stats::StatsArgs),
    /// Draw the scene offscreen to a PNG (no window needed).
    #[cfg(feature = "app")]
    Render(render::RenderArgs),
    /// List joysticks and gamepads and show their raw axes live.
    #[cfg(feature = "app")]
    Devices(devices::DevicesArgs),
}

/// Writes one line to stdout; exits 0 on a broken pipe, 2 on any other error.
pub fn write_line(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("bump: error: cannot write output: {e}");
        std::process::exit(2);
    }
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    scene_args::check_environment()?;
    match cli.command {
        Some(Command::Check(a)) => check::run(&a),
        Some(Command::Touch(a)) => touch::run(&a),
        Some(Command::Score(a)) => score::run(&a),
        Some(Command::Settle(a)) => settle::run(&a),
        Some(Command::Stats(a)) => stats::run(&a),
        Some(Command::Steer(a)) => steer::run(&a),
        Some(Command::Pockets(a)) => pockets::run(&a),
        Some(Command::Dock(a)) => dock::run(&a),
        #[cfg(feature = "app")]
        Some(Command::Render(a)) => render::run(&a),
        #[cfg(feature = "app")]
        Some(Command::Devices(a)) => devices::run(&a),
        None => window::run(&cli.files, &cli.window),
    }
}
