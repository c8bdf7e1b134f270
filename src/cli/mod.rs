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
    /// Files to open in the docking window: a receptor (or a complex to split
    /// with --ligand), then drugs and any other molecules. None: the built-in
    /// scene (the thesis's triple ring and E).
    files: Vec<std::path::PathBuf>,
    /// With one complex file: the drug residue (RESNAME, RESNAME:CHAIN:SEQ or auto).
    #[arg(long)]
    ligand: Option<String>,
    /// Collider: brute, grid or hashed.
    #[arg(long, default_value = "hashed")]
    collider: String,
    /// Radius table: bondi or thesis.
    #[arg(long, default_value = "bondi")]
    radii: String,
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
        None => window(&cli),
    }
}

/// `bump [FILES]` without a subcommand: the docking window. A file that
/// cannot be read is reported (in the window and on stderr) and skipped.
fn window(cli: &Cli) -> anyhow::Result<()> {
    use bump::collide::ColliderKind;
    use bump::model::{self, LigandSpec, LoadOptions, RadiiSet, builtin};
    use bump::session::{Session, Settings};
    let radii = RadiiSet::parse(&cli.radii)
        .ok_or_else(|| anyhow::anyhow!("unknown radii `{}` (bondi or thesis)", cli.radii))?;
    let collider = ColliderKind::parse(&cli.collider).ok_or_else(|| {
        anyhow::anyhow!(
            "unknown collider `{}` (brute, grid or hashed)",
            cli.collider
        )
    })?;
    let opts = LoadOptions {
        radii,
        ..LoadOptions::default()
    };
    let mut molecules = Vec::new();
    let mut messages = Vec::new();
    for (k, f) in cli.files.iter().enumerate() {
        let loaded = match model::load(f, &opts) {
            Ok(l) => l,
            Err(e) => {
                messages.push(e.to_string());
                continue;
            }
        };
        messages.extend(loaded.warnings.iter().cloned());
        // A single file is a complex: split off the drug.
        let split = k == 0 && (cli.files.len() == 1 || cli.ligand.is_some());
        let result = if split {
            let text = cli.ligand.as_deref().unwrap_or("auto");
            LigandSpec::parse(text)
                .map_err(|e| format!("--ligand {text}: {e}"))
                .and_then(|spec| {
                    model::split_complex(&loaded.structure, &spec).map_err(|e| e.to_string())
                })
                .map(|(r, d)| vec![r, d])
        } else {
            model::receptor_only(&loaded.structure)
                .map(|m| vec![m])
                .map_err(|e| e.to_string())
        };
        match result {
            Ok(ms) => molecules.extend(ms),
            Err(e) => {
                messages.push(e);
                // Keep the whole file when the split fails.
                if let Ok(m) = model::receptor_only(&loaded.structure) {
                    molecules.push(m);
                }
            }
        }
    }
    if molecules.is_empty() {
        if !cli.files.is_empty() {
            messages.push("nothing could be loaded: showing the built-in scene".into());
        }
        let (r, d) = builtin::scene(radii);
        molecules = vec![r, d];
    }
    for m in &messages {
        eprintln!("bump: {m}");
    }
    let settings = Settings {
        collider,
        ..Settings::default()
    };
    let session = Session::new(molecules, settings)?;
    bump::app::run(session, messages)?;
    Ok(())
}
