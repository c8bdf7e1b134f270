//! `bump bench`: the benchmark report. Runs every measurement that needs no
//! dev-dependency in one process — move-to-touch run time against error for
//! each method, scaling with receptor and drug size, collider build times,
//! Table 1, and what a session step skips — and writes a Markdown report with
//! SVG figures (by default `docs/benchmarks.md` and `docs/bench/*.svg`).
//!
//! parry3d is a dev-dependency of the library; the binary compares against it
//! only when built with `--features parry` (it then becomes a normal optional
//! dependency), adding parry3d's columns to the run-time-against-error tables
//! and a section timing bump and parry3d alternately on the scaling
//! queries (`versus`). Criterion benches (`cargo bench --bench collide`) time the same
//! queries with statistics, for regressions.
//!
//! The part of an existing report below [`KEEP_MARKER`] is kept as it is:
//! hand-measured figures (rendering, the window) that need a display.

mod accuracy;
mod frames;
#[cfg(feature = "parry")]
pub mod parry;
mod scaling;
mod surface;
mod svg;
mod table1;
mod timing;
#[cfg(feature = "parry")]
mod versus;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;

/// Everything below this line of an existing report is kept.
pub const KEEP_MARKER: &str = "<!-- Sections below are kept as they are by `bump bench`. -->";

/// Arguments of `bump bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The report to write; figures go to `bench/` beside it.
    #[arg(long, default_value = "docs/benchmarks.md")]
    out: PathBuf,
    /// Folder with the test structures.
    #[arg(long, default_value = "../shared/pdb")]
    data: PathBuf,
    /// Random approach queries per scene in the run-time-against-error comparison.
    #[arg(long, default_value_t = 500, allow_negative_numbers = true)]
    queries: usize,
    /// Repetitions of each timed query (the median is kept).
    #[arg(long, default_value_t = 21, allow_negative_numbers = true)]
    reps: usize,
    /// A short run: few queries and repetitions, the two smallest receptors
    /// (for testing the command, not for figures).
    #[arg(long)]
    quick: bool,
}

/// What the measurements share.
pub struct Context {
    /// The structures folder, when it exists.
    pub data: Option<PathBuf>,
    /// Approach queries per scene.
    pub queries: usize,
    /// Repetitions per timing.
    pub reps: usize,
    /// Short run.
    pub quick: bool,
}

/// One part of the report.
pub struct Section {
    /// Its Markdown, starting with a `##` heading.
    pub markdown: String,
    /// SVG figures: (file name, text).
    pub figures: Vec<(String, String)>,
    /// One-line findings for the summary at the top.
    pub headline: Vec<String>,
}

impl Section {
    /// A section with text only.
    pub fn text(markdown: String) -> Self {
        Self {
            markdown,
            figures: Vec::new(),
            headline: Vec::new(),
        }
    }
}

/// Runs `bump bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let data = args
        .data
        .join("MANIFEST.md")
        .is_file()
        .then(|| args.data.clone());
    if data.is_none() {
        eprintln!(
            "bump: warning: {} not found: only the built-in scene is measured",
            args.data.display()
        );
    }
    let ctx = Context {
        data,
        queries: if args.quick {
            args.queries.min(20)
        } else {
            args.queries.max(1)
        },
        reps: if args.quick {
            args.reps.min(3)
        } else {
            args.reps.max(1)
        },
        quick: args.quick,
    };
    let kept = keep_manual(&args.out)?;
    let t0 = Instant::now();
    let total = accuracy::steps(&ctx)
        + scaling::steps(&ctx)
        + versus_steps(&ctx)
        + table1::steps(&ctx)
        + frames::steps(&ctx);
    let mut progress = timing::Progress::new(total);
    let sections = vec![
        accuracy::run(&ctx, &mut progress),
        scaling::run(&ctx, &mut progress),
        versus(&ctx, &mut progress),
        table1::run(&ctx, &mut progress),
        frames::run(&ctx, &mut progress),
    ];
    progress.finish();
    let report = assemble(&ctx, &sections, t0.elapsed().as_secs_f64(), &kept);
    let dir = args.out.parent().unwrap_or(Path::new("."));
    let figures = dir.join("bench");
    std::fs::create_dir_all(&figures)
        .with_context(|| format!("cannot create {}", figures.display()))?;
    for s in &sections {
        for (name, text) in &s.figures {
            bump::model::write::write_atomically(&figures.join(name), text.as_bytes())?;
        }
    }
    bump::model::write::write_atomically(&args.out, report.as_bytes())?;
    eprintln!(
        "bump: wrote {} and its figures in {}",
        args.out.display(),
        figures.display()
    );
    Ok(())
}

/// Progress steps of the comparison with parry3d (none without it).
fn versus_steps(ctx: &Context) -> usize {
    #[cfg(feature = "parry")]
    return versus::steps(ctx);
    #[cfg(not(feature = "parry"))]
    {
        let _ = ctx;
        0
    }
}

/// bump against parry3d on the surface approaches, timed alternately; without
/// `--features parry`, a line saying how to add it.
fn versus(ctx: &Context, progress: &mut timing::Progress) -> Section {
    #[cfg(feature = "parry")]
    return versus::run(ctx, progress);
    #[cfg(not(feature = "parry"))]
    {
        let _ = (ctx, progress);
        Section::text(
            "## bump against parry3d on surface approaches, timed alternately\n\n\
             Not in this run (built without `--features parry`); \
             `cargo run --release --features parry -- bench` adds it.\n"
                .into(),
        )
    }
}

/// The kept tail of an existing report (from [`KEEP_MARKER`] on), or nothing
/// for a new file. An existing file without the marker is an error: it may
/// hold hand-written text that must not be overwritten.
fn keep_manual(out: &Path) -> anyhow::Result<String> {
    match std::fs::read_to_string(out) {
        Ok(text) if text.trim().is_empty() => Ok(String::new()),
        Ok(text) => match text.find(KEEP_MARKER) {
            Some(k) => Ok(text[k..].to_string()),
            None => anyhow::bail!(
                "{} exists and has no line `{KEEP_MARKER}`: not overwriting it (add that line above the sections to keep, or choose another --out)",
                out.display()
            ),
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(String::new()),
        Err(e) => Err(e).with_context(|| format!("cannot read {}", out.display())),
    }
}

fn assemble(ctx: &Context, sections: &[Section], seconds: f64, kept: &str) -> String {
    let mut md = String::from("# Benchmarks and accuracy\n\n");
    md.push_str(&format!(
        "Written by `bump bench{}` in {seconds:.0} s (regenerate: `cargo build --release --features parry && XDG_RUNTIME_DIR=$(mktemp -d) taskset -c 1 target/release/bump bench`). \
         Machine: {}. Absolute times belong to this machine (a shared, noisy VM: expect ±20 % between runs); \
         the **ratios between methods measured in the same run** are the result.\n\n",
        if ctx.quick { " --quick" } else { "" },
        timing::machine()
    ));
    md.push_str("## Summary\n\n");
    for s in sections {
        for h in &s.headline {
            md.push_str(&format!("- {h}\n"));
        }
    }
    md.push('\n');
    for s in sections {
        md.push_str(&s.markdown);
        md.push('\n');
    }
    if kept.is_empty() {
        md.push_str(KEEP_MARKER);
        md.push('\n');
    } else {
        md.push_str(kept);
    }
    md
}
