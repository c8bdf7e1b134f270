//! The benchmark report: every measurement in one process, written as
//! Markdown with SVG figures (`docs/benchmarks.md`, `docs/bench/*.svg`).
//!
//! ```sh
//! cargo bench --bench report                    # the whole report
//! cargo bench --bench report -- --quick         # a short run (not for figures)
//! cargo bench --bench report -- --only layers   # some sections, to stdout
//! ```
//!
//! Options after `--`: `--quick`, `--only NAME[,NAME…]` (the sections'
//! names are listed in [`SECTIONS`]; their Markdown goes to stdout unless
//! `--out` is given), `--out FILE` (default `docs/benchmarks.md`, figures
//! in `bench/` beside it), `--data DIR` (default `../shared/pdb`),
//! `--queries N` and `--reps N`. Under `cargo test` (no `--bench`) it runs
//! once, briefly, into a temporary folder and checks what it wrote: a smoke
//! test of every section.
//!
//! Each section is a module with a [`Section`] constant; adding one is
//! adding its module and a line to [`SECTIONS`]. Sections time the methods
//! they compare in the same run, alternated where the difference matters,
//! since the machine's speed drifts between runs: ratios measured together
//! are the result, absolute times belong to the machine.

mod accuracy;
mod dockability;
mod frames;
mod layers;
mod load;
mod scaling;
mod score;
mod svg;
mod table1;
mod timing;
mod versus;
mod views;

use std::path::{Path, PathBuf};
use std::time::Instant;

use timing::Progress;

/// The report's sections, in order.
const SECTIONS: &[&Section] = &[
    &accuracy::SECTION,
    &scaling::SECTION,
    &versus::SECTION,
    &layers::SECTION,
    &table1::SECTION,
    &frames::SECTION,
    &views::SECTION,
    &load::SECTION,
    &score::SECTION,
    &dockability::SECTION,
];

/// The report's first line; an existing file that does not start with it
/// is not overwritten (it may be hand-written).
const TITLE: &str = "# Benchmarks and accuracy";

/// One section of the report.
pub struct Section {
    /// Its name for `--only`.
    pub name: &'static str,
    /// Progress steps [`Section::run`] takes.
    pub steps: fn(&Context) -> usize,
    /// Measures and writes the section.
    pub run: fn(&Context, &mut Progress) -> Part,
}

/// What a section wrote.
pub struct Part {
    /// Its Markdown, starting with a `##` heading.
    pub markdown: String,
    /// SVG figures: (file name, text).
    pub figures: Vec<(String, String)>,
    /// One-line findings for the summary at the top.
    pub headline: Vec<String>,
}

impl Part {
    /// A part with text only.
    pub fn text(markdown: String) -> Self {
        Self {
            markdown,
            figures: Vec::new(),
            headline: Vec::new(),
        }
    }
}

/// What the measurements share.
pub struct Context {
    /// The structures folder, when it exists.
    pub data: Option<PathBuf>,
    /// Approach queries per scene.
    pub queries: usize,
    /// Repetitions per timing.
    pub reps: usize,
    /// A short run: fewer queries, repetitions and receptors.
    pub quick: bool,
}

impl Context {
    /// One step when the structures folder exists, none otherwise: the
    /// step count of a section that measures the shared structures only.
    pub fn one_step_with_data(&self) -> usize {
        usize::from(self.data.is_some())
    }

    /// The structures folder, or the section titled `title` saying it was
    /// skipped for want of it.
    pub fn data_or_skip(&self, title: &str) -> Result<&Path, Part> {
        self.data.as_deref().ok_or_else(|| {
            Part::text(format!(
                "## {title}\n\nSkipped: `../shared/pdb` not found.\n"
            ))
        })
    }
}

/// The command line after `--`.
struct Options {
    out: Option<PathBuf>,
    data: Option<PathBuf>,
    queries: usize,
    reps: usize,
    quick: bool,
    only: Option<Vec<String>>,
}

impl Options {
    /// Parses `args`; unknown arguments are an error when `strict` (under
    /// `cargo bench`), else ignored (`cargo test -- --nocapture` passes its
    /// own to every test binary).
    fn parse(args: &[String], strict: bool) -> Result<Self, String> {
        let mut o = Options {
            out: None,
            data: None,
            queries: 500,
            reps: 21,
            quick: false,
            only: None,
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = |name: &str| {
                it.next()
                    .cloned()
                    .ok_or_else(|| format!("{name} needs a value"))
            };
            let number = |name: &str, v: String| {
                v.parse::<usize>()
                    .map_err(|_| format!("{name}: not a count: {v:?}"))
            };
            match a.as_str() {
                "--bench" => {}
                "--quick" => o.quick = true,
                "--out" => o.out = Some(value("--out")?.into()),
                "--data" => o.data = Some(value("--data")?.into()),
                "--queries" => o.queries = number("--queries", value("--queries")?)?.max(1),
                "--reps" => o.reps = number("--reps", value("--reps")?)?.max(1),
                "--only" => {
                    let names: Vec<String> = value("--only")?
                        .split(',')
                        .map(|s| s.trim().to_string())
                        .collect();
                    for n in &names {
                        if !SECTIONS.iter().any(|s| s.name == n) {
                            return Err(format!(
                                "no section {n:?}; the sections: {}",
                                SECTIONS
                                    .iter()
                                    .map(|s| s.name)
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ));
                        }
                    }
                    o.only = Some(names);
                }
                other if strict => {
                    return Err(format!(
                        "unknown argument {other:?} (options: --quick, --only NAMES, --out FILE, --data DIR, --queries N, --reps N)"
                    ));
                }
                _ => {}
            }
        }
        Ok(o)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // `cargo bench` passes `--bench`; `cargo test` runs bench targets
    // without it.
    let result = if args.iter().any(|a| a == "--bench") {
        Options::parse(&args, true).and_then(|o| report(&o))
    } else {
        smoke_test(&args)
    };
    if let Err(e) = result {
        eprintln!("report: error: {e}");
        std::process::exit(2);
    }
}

/// The structures folder `data` (default: the shared one), when it holds
/// the structures; a warning when not, a failure under `CI=true`.
fn data_dir(data: Option<&Path>) -> Result<Option<PathBuf>, String> {
    let dir = data.map_or_else(bump_testkit::data::shared_pdb_dir, Path::to_path_buf);
    if dir.join("MANIFEST.md").is_file() {
        return Ok(Some(dir));
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        return Err(format!("{} is missing: CI must have it", dir.display()));
    }
    eprintln!(
        "report: warning: {} not found: only the built-in scene is measured",
        dir.display()
    );
    Ok(None)
}

/// Runs the sections `o` asks for and writes them.
fn report(o: &Options) -> Result<(), String> {
    let ctx = Context {
        data: data_dir(o.data.as_deref())?,
        queries: if o.quick {
            o.queries.min(20)
        } else {
            o.queries
        },
        reps: if o.quick { o.reps.min(3) } else { o.reps },
        quick: o.quick,
    };
    let chosen: Vec<&Section> = SECTIONS
        .iter()
        .copied()
        .filter(|s| {
            o.only
                .as_ref()
                .is_none_or(|only| only.iter().any(|n| n == s.name))
        })
        .collect();
    // Without `--only` the report goes to docs/benchmarks.md; with it, to
    // stdout unless `--out` says where.
    let out = match (&o.out, &o.only) {
        (Some(out), _) => Some(out.clone()),
        (None, None) => Some(PathBuf::from("docs/benchmarks.md")),
        (None, Some(_)) => None,
    };
    if let Some(out) = &out {
        may_overwrite(out)?;
    }
    let t0 = Instant::now();
    let mut progress = Progress::new(chosen.iter().map(|s| (s.steps)(&ctx)).sum());
    let parts: Vec<Part> = chosen
        .iter()
        .map(|s| (s.run)(&ctx, &mut progress))
        .collect();
    progress.finish();
    let text = assemble(&ctx, &parts, t0.elapsed().as_secs_f64());
    match &out {
        Some(out) => write(out, &text, &parts),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

/// Refuses to overwrite a file that is not a report.
fn may_overwrite(out: &Path) -> Result<(), String> {
    match std::fs::read_to_string(out) {
        Ok(text) if text.trim().is_empty() || text.starts_with(TITLE) => Ok(()),
        Ok(_) => Err(format!(
            "{} exists and does not start with {TITLE:?}: not overwriting it (choose another --out)",
            out.display()
        )),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(format!("cannot read {}: {e}", out.display())),
    }
}

/// Writes the report to `out` and its figures to `bench/` beside it.
fn write(out: &Path, text: &str, parts: &[Part]) -> Result<(), String> {
    let dir = out.parent().unwrap_or(Path::new("."));
    let figures = dir.join("bench");
    std::fs::create_dir_all(&figures)
        .map_err(|e| format!("cannot create {}: {e}", figures.display()))?;
    for p in parts {
        for (name, svg) in &p.figures {
            bump::model::write::write_atomically(&figures.join(name), svg.as_bytes())
                .map_err(|e| e.to_string())?;
        }
    }
    bump::model::write::write_atomically(out, text.as_bytes()).map_err(|e| e.to_string())?;
    eprintln!(
        "report: wrote {} and its figures in {}",
        out.display(),
        figures.display()
    );
    Ok(())
}

/// The report: title, how it was made, the summary, then the sections.
fn assemble(ctx: &Context, parts: &[Part], seconds: f64) -> String {
    let mut md = format!("{TITLE}\n\n");
    md.push_str(&format!(
        "Written by `cargo bench --bench report{}` in {seconds:.0} s. Machine: {}. \
         Absolute times belong to this machine (a shared, noisy VM: expect ±20 % \
         between runs); the **ratios between methods measured in the same run** are \
         the result.\n\n",
        if ctx.quick { " -- --quick" } else { "" },
        timing::machine()
    ));
    md.push_str("## Summary\n\n");
    for p in parts {
        for h in &p.headline {
            md.push_str(&format!("- {h}\n"));
        }
    }
    md.push('\n');
    for p in parts {
        md.push_str(&p.markdown);
        md.push('\n');
    }
    md
}

/// Under `cargo test`: every section once, briefly, into a temporary
/// folder; then checks of what was written. Prints a `test result` line
/// as the test harness does.
fn smoke_test(args: &[String]) -> Result<(), String> {
    let o = Options::parse(args, false)?;
    let dir = std::env::temp_dir().join(format!("bump-report-{}", std::process::id()));
    let out = dir.join("benchmarks.md");
    let smoke = Options {
        out: Some(out.clone()),
        data: o.data,
        queries: 4,
        reps: 1,
        quick: true,
        only: None,
    };
    let checked = report(&smoke).and_then(|()| check_smoke(&dir, &out));
    std::fs::remove_dir_all(&dir).ok();
    checked?;
    println!("test report_smoke ... ok\n\ntest result: ok. 1 passed; 0 failed; 0 ignored\n");
    Ok(())
}

/// What a smoke run must have written (and the quantiles every section
/// reports, by nearest rank, and a test figure).
fn check_smoke(dir: &Path, out: &Path) -> Result<(), String> {
    let v = [5.0, 1.0, 3.0, 2.0, 4.0];
    let ranks = [
        timing::median(&v),
        timing::quantile(&v, 0.0),
        timing::quantile(&v, 1.0),
    ];
    if ranks != [3.0, 1.0, 5.0] || timing::median(&[]) != 0.0 {
        return Err(format!("quantiles by nearest rank: {ranks:?}"));
    }
    svg::self_check()?;
    let text = std::fs::read_to_string(out).map_err(|e| e.to_string())?;
    let data = bump_testkit::data::shared_pdb_dir()
        .join("MANIFEST.md")
        .is_file();
    let mut want = vec![
        TITLE,
        "## Summary",
        "## Run time against error",
        "built-in E into the triple ring",
        "## Skip what a scene doesn't need",
        "## Optimisation layers",
        "Machine: ",
    ];
    if data {
        want.extend([
            "trimethoprim into DHFR",
            "| 1rx1.pdb | 1317 |",
            "## bump against parry3d",
            "## The thesis's Table 1",
            "| 6xg5/TOP | flexible | soft | 1 |",
            "### Settle from perturbed crystal poses",
            "| 6xg5_TOP | 2 |",
        ]);
    }
    for w in want {
        if !text.contains(w) {
            return Err(format!("the smoke report lacks {w:?}:\n{text}"));
        }
    }
    let svg = std::fs::read_to_string(dir.join("bench/time_vs_error.svg"))
        .map_err(|e| format!("no figure: {e}"))?;
    if !(svg.starts_with("<svg") && svg.contains("swept (hashed)")) {
        return Err("the figure is not an SVG plot".into());
    }
    if data && !dir.join("bench/scaling.svg").is_file() {
        return Err("no scaling figure".into());
    }
    // A file that is not a report is refused and left as it is.
    let other = dir.join("notes.md");
    std::fs::write(&other, "hand-written\n").map_err(|e| e.to_string())?;
    if may_overwrite(&other).is_ok() || may_overwrite(out).is_err() {
        return Err("overwrote a file that is not a report, or refused a report".into());
    }
    Ok(())
}
