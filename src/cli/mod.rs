//! Command-line parsing and dispatch. Errors become `anyhow` here, at the
//! binary's edge; the library below speaks `thiserror`.

/// `println!` for command output: a closed stdout (`bump ... | head`) ends
/// the program quietly instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::cli::write_line(format_args!($($arg)*)) };
}

mod check;
mod render;
mod report;
mod scene_args;
mod stats;
mod touch;

use clap::{Parser, Subcommand};

pub use scene_args::SceneArgs;

/// Interactive molecular docking with collision detection (after Turk 1989).
#[derive(Debug, Parser)]
#[command(name = "bump", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Scene files when no subcommand is given (none: the built-in scene).
    files: Vec<std::path::PathBuf>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Static check: the colliding pairs at the file pose (optionally moved).
    Check(check::CheckArgs),
    /// Move-to-touch: how far the drug may move along a proposed motion.
    Touch(touch::TouchArgs),
    /// Atoms per grid cell (the thesis's Table 1) for real files.
    Stats(stats::StatsArgs),
    /// Draw the scene offscreen to a PNG (no window needed).
    Render(render::RenderArgs),
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
    match cli.command {
        Some(Command::Check(a)) => check::run(&a),
        Some(Command::Touch(a)) => touch::run(&a),
        Some(Command::Stats(a)) => stats::run(&a),
        Some(Command::Render(a)) => render::run(&a),
        None => describe(&cli.files),
    }
}

/// `bump [FILES]` without a subcommand: load the scene and describe it.
fn describe(files: &[std::path::PathBuf]) -> anyhow::Result<()> {
    let args = SceneArgs::from_files(files)?;
    let loaded = args.load()?;
    let scene = &loaded.scene;
    outln!(
        "receptor: {} ({} atoms)\ndrug:     {} ({} atoms)",
        scene.receptor.name,
        scene.receptor.len(),
        scene.drug.name,
        scene.drug.len()
    );
    let pairs = scene.check(&scene.file_relative(glam::DVec3::ZERO));
    outln!("colliding pairs at the file pose: {}", pairs.len());
    outln!(
        "The docking window is not built yet; use `bump check`, `bump touch` or `bump stats` (see `bump --help`)."
    );
    Ok(())
}
