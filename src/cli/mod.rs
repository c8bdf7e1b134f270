//! Command-line parsing and dispatch. Errors become `anyhow` here, at the
//! binary's edge; the library below speaks `thiserror`.

/// `println!` for command output: a closed stdout (`bump ... | head`) ends
/// the program quietly instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::cli::write_line(format_args!($($arg)*)) };
}

mod bench;
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
    /// The benchmark report: run time against error, scaling, Table 1, frame costs.
    Bench(bench::BenchArgs),
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
        Some(Command::Bench(a)) => bench::run(&a),
        None => window(&cli),
    }
}

/// `bump [FILES]` without a subcommand: the docking window. Files are read
/// on another thread while the window is already up; a file that cannot be
/// read is reported (in the window and on stderr) and skipped.
fn window(cli: &Cli) -> anyhow::Result<()> {
    use bump::app::LoadEvent;
    use bump::collide::ColliderKind;
    use bump::model::{LoadOptions, RadiiSet, builtin};
    use bump::session::{Session, Settings};
    let radii = RadiiSet::parse(&cli.radii)
        .ok_or_else(|| anyhow::anyhow!("unknown radii `{}` (bondi or thesis)", cli.radii))?;
    let collider = ColliderKind::parse(&cli.collider).ok_or_else(|| {
        anyhow::anyhow!(
            "unknown collider `{}` (brute, grid or hashed)",
            cli.collider
        )
    })?;
    let settings = Settings {
        collider,
        ..Settings::default()
    };
    if cli.files.is_empty() {
        let (r, d) = builtin::scene(radii);
        let session = Session::new(vec![r, d], settings)?;
        bump::app::run(session, Vec::new(), None)?;
        return Ok(());
    }
    let opts = LoadOptions {
        radii,
        ..LoadOptions::default()
    };
    let files = cli.files.clone();
    let ligand = cli.ligand.clone();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let single = files.len() == 1;
        for (k, f) in files.iter().enumerate() {
            let label = f.display().to_string();
            if tx.send(LoadEvent::Reading(label.clone())).is_err() {
                return; // the window is gone
            }
            let t0 = std::time::Instant::now();
            let split = k == 0 && (single || ligand.is_some());
            let event = match load_for_window(f, split, ligand.as_deref(), &opts) {
                Ok((molecules, warnings)) => LoadEvent::Loaded {
                    label,
                    molecules,
                    warnings,
                    seconds: t0.elapsed().as_secs_f64(),
                },
                Err(e) => LoadEvent::Failed(e),
            };
            if let LoadEvent::Failed(e) = &event {
                eprintln!("bump: {e}");
            }
            if tx.send(event).is_err() {
                return;
            }
        }
    });
    bump::app::run(Session::empty(settings), Vec::new(), Some(rx))?;
    Ok(())
}

/// Reads one file for the window: a complex split into receptor and drug
/// (`split`), or the whole file as one molecule. When the split fails the
/// whole file is kept and the reason returned as a warning.
fn load_for_window(
    f: &std::path::Path,
    split: bool,
    ligand: Option<&str>,
    opts: &bump::model::LoadOptions,
) -> Result<(Vec<bump::model::Molecule>, Vec<String>), String> {
    use bump::model::{self, LigandSpec};
    let loaded = model::load(f, opts).map_err(|e| e.to_string())?;
    let mut warnings = loaded.warnings.clone();
    if split {
        let text = ligand.unwrap_or("auto");
        let parts = LigandSpec::parse(text)
            .map_err(|e| format!("--ligand {text}: {e}"))
            .and_then(|spec| {
                model::split_complex(&loaded.structure, &spec).map_err(|e| e.to_string())
            });
        match parts {
            Ok((r, d)) => return Ok((vec![r, d], warnings)),
            Err(e) => warnings.push(e),
        }
    }
    let m = model::receptor_only(&loaded.structure).map_err(|e| e.to_string())?;
    Ok((vec![m], warnings))
}
