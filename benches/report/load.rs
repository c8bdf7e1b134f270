//! The benchmark report's "Loading" section: how long bump takes from
//! command to answer (`bump check FILE DRUG`, a fresh process each run) and
//! how much memory it holds at its peak, on real structures, beside gemmi
//! reading the same files (`benches/gemmi_load.py`, when Python and gemmi
//! are there; `BUMP_PYTHON` names the interpreter, default `python3`).
//!
//! `cargo bench --bench report -- --only load` prints it alone. Runs
//! alternate between the files (and between bump and gemmi) so that a burst
//! of load on a shared machine falls on all of them; each figure is the
//! minimum and the median of 7 runs (1 in a quick run). Peak resident
//! memory comes from `/usr/bin/time -v`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use super::timing::Progress;
use super::{Context, Part, Section};

/// The files timed: (file, what it is).
const FILES: [(&str, &str); 4] = [
    (
        "1f2n_assembly1.cif.gz",
        "virus capsid assembly, mmCIF, gzipped",
    ),
    ("2btv.pdb.gz", "virus capsid, PDB, gzipped"),
    ("4kya.pdb.gz", "TS–DHFR, 8 chains, PDB, gzipped"),
    ("1ubq.cif", "ubiquitin, mmCIF"),
];

/// The drug every run docks: a small SDF file beside the structures, so
/// that files without a ligand of their own answer too.
const DRUG: &str = "benzamidine_3ptb.sdf";

/// One run's figures: wall seconds, and from `/usr/bin/time -v` when it is
/// there, peak resident KiB and CPU seconds (user + system).
type Run = (f64, Option<u64>, Option<f64>);

/// One process run of `bump check file drug`.
fn run_bump(bump: &Path, file: &Path, drug: &Path) -> Option<Run> {
    let timer = Path::new("/usr/bin/time");
    let start = Instant::now();
    let out = if timer.is_file() {
        Command::new(timer)
            .arg("-v")
            .arg(bump)
            .arg("check")
            .arg(file)
            .arg(drug)
            .output()
            .ok()?
    } else {
        Command::new(bump)
            .arg("check")
            .arg(file)
            .arg(drug)
            .output()
            .ok()?
    };
    let wall = start.elapsed().as_secs_f64();
    if !out.status.success() {
        eprintln!(
            "bump check {}: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    let field = |name: &str| {
        stderr
            .lines()
            .find(|l| l.contains(name))
            .and_then(|l| l.rsplit(':').next())
            .map(|v| v.trim().to_string())
    };
    let rss = field("Maximum resident set size").and_then(|v| v.parse().ok());
    let cpu = match (field("User time (seconds)"), field("System time (seconds)")) {
        (Some(u), Some(s)) => Some(u.parse::<f64>().ok()? + s.parse::<f64>().ok()?),
        _ => None,
    };
    Some((wall, rss, cpu))
}

/// The receptor atoms `bump check` kept: its first output line is
/// `receptor NAME (N atoms), drug ...`.
fn atoms_read(bump: &Path, file: &Path, drug: &Path) -> Option<u64> {
    let out = Command::new(bump)
        .arg("check")
        .arg(file)
        .arg(drug)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let first = text.lines().next()?.split('(').nth(1)?;
    first.split(' ').next()?.replace(',', "").parse().ok()
}

/// gemmi's figures for `files`, one JSON object a file, or `None` when
/// Python or gemmi is missing.
fn gemmi(files: &[PathBuf], runs: usize) -> Option<Vec<serde_json::Value>> {
    let python = std::env::var("BUMP_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/gemmi_load.py");
    let out = Command::new(python)
        .arg(script)
        .arg("--runs")
        .arg(runs.to_string())
        .args(files)
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!(
            "gemmi_load.py: {}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        );
        return None;
    }
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).ok())
        .collect()
}

fn min_median(v: &mut [f64]) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    (v[0], median)
}

/// The "Loading" section: bump (`bump` is its binary) beside gemmi on
/// the structures of `data` (`../shared/pdb`), `runs` runs each, of
/// `files` ([`FILES`] in the report).
pub fn section(bump: &Path, data: &Path, files: &[(&str, &str)], runs: usize) -> String {
    let files: Vec<(PathBuf, &str)> = files
        .iter()
        .map(|(f, what)| (data.join(f), *what))
        .filter(|(p, _)| p.is_file())
        .collect();
    let mut walls: Vec<Vec<f64>> = vec![Vec::new(); files.len()];
    let mut rss: Vec<u64> = vec![0; files.len()];
    let mut cpus: Vec<Vec<f64>> = vec![Vec::new(); files.len()];
    for _ in 0..runs {
        for (k, (path, _)) in files.iter().enumerate() {
            if let Some((wall, peak, cpu)) = run_bump(bump, path, &data.join(DRUG)) {
                walls[k].push(wall);
                rss[k] = rss[k].max(peak.unwrap_or(0));
                cpus[k].extend(cpu);
            }
        }
    }
    let paths: Vec<PathBuf> = files.iter().map(|(p, _)| p.clone()).collect();
    let peers = gemmi(&paths, runs);
    let mut out = String::from("## Loading\n\n");
    let _ = writeln!(
        out,
        "From command to answer: `bump check FILE {DRUG}` in a fresh process (read both, build the collider, check), \
         minimum and median of {runs} runs; CPU seconds (user + system, the least of the runs: \
         on a shared machine the wall time waits for cores, the CPU time does not) and \
         peak resident memory from `/usr/bin/time -v`, bytes per atom read. \
         gemmi: `gemmi.read_structure` in a running Python (read alone), and a fresh `python -c` process that imports gemmi and reads the file ({}).\n",
        match &peers {
            Some(p) => format!(
                "gemmi {}",
                p.first().and_then(|v| v["gemmi"].as_str()).unwrap_or("?")
            ),
            None => "gemmi not found: its columns are empty".to_string(),
        }
    );
    out.push_str(
        "| file | atoms | bump check, s (min / median) | bump CPU, s | bump peak RSS | bytes per atom | gemmi read, s (min / median) | gemmi read CPU, s | gemmi process, s (CPU) | gemmi peak RSS |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for (k, (path, what)) in files.iter().enumerate() {
        if walls[k].is_empty() {
            continue;
        }
        let atoms = atoms_read(bump, path, &data.join(DRUG)).unwrap_or(0);
        let (lo, mid) = min_median(&mut walls[k]);
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let peer = peers
            .as_ref()
            .and_then(|p| p.iter().find(|v| v["file"].as_str() == Some(name.as_ref())));
        let num = |key: &str| peer.and_then(|v| v[key].as_f64());
        let gemmi_read = match (num("read_s_min"), num("read_s_median")) {
            (Some(a), Some(b)) => format!("{a:.3} / {b:.3}"),
            _ => "–".into(),
        };
        let gemmi_read_cpu = num("read_cpu_s_min").map_or("–".into(), |v| format!("{v:.3}"));
        let gemmi_process = match (num("process_s_min"), num("process_cpu_s_min")) {
            (Some(w), Some(c)) => format!("{w:.3} ({c:.2})"),
            (Some(w), None) => format!("{w:.3}"),
            _ => "–".into(),
        };
        let cpu = if cpus[k].is_empty() {
            "–".into()
        } else {
            format!("{:.2}", min_median(&mut cpus[k]).0)
        };
        let gemmi_rss =
            num("process_max_rss_kib").map_or("–".into(), |v| format!("{:.0} MiB", v / 1024.0));
        let _ = writeln!(
            out,
            "| `{name}` ({what}) | {atoms} | {lo:.3} / {mid:.3} | {cpu} | {:.0} MiB | {} | {gemmi_read} | {gemmi_read_cpu} | {gemmi_process} | {gemmi_rss} |",
            rss[k] as f64 / 1024.0,
            if atoms > 0 {
                format!("{:.0}", rss[k] as f64 * 1024.0 / atoms as f64)
            } else {
                "–".into()
            }
        );
    }
    out
}

/// The section: all files, 7 runs each (one run of the smallest file in a
/// quick run).
pub const SECTION: Section = Section {
    name: "load",
    steps,
    run,
};

fn steps(ctx: &Context) -> usize {
    ctx.one_step_with_data()
}

fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let data = match ctx.data_or_skip("Loading") {
        Ok(d) => d,
        Err(skipped) => return skipped,
    };
    progress.step("loading, beside gemmi");
    let bump = PathBuf::from(env!("CARGO_BIN_EXE_bump"));
    let md = if ctx.quick {
        section(&bump, data, &FILES[3..], 1)
    } else {
        section(&bump, data, &FILES, 7)
    };
    Part::text(md)
}
