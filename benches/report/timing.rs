//! Measuring: medians of repeated timings, the machine's description and
//! a progress bar on stderr.

use std::io::{IsTerminal, Write};
use std::time::Instant;

/// Median of `values` (0 for none); sorts a copy.
pub fn median(values: &[f64]) -> f64 {
    quantile(values, 0.5)
}

/// The `q` quantile (nearest rank) of `values`; 0 for none.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let k = ((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1;
    v[k]
}

/// Median wall time of `f` in µs over `reps` runs, each of `inner` calls
/// (several calls per timing when one call is too short for the clock).
pub fn median_us<R>(reps: usize, inner: usize, mut f: impl FnMut() -> R) -> f64 {
    let inner = inner.max(1);
    let mut times = Vec::with_capacity(reps);
    std::hint::black_box(f()); // warm caches
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        for _ in 0..inner {
            std::hint::black_box(f());
        }
        times.push(t0.elapsed().as_secs_f64() * 1e6 / inner as f64);
    }
    median(&times)
}

/// One line describing the machine, OS, compiler and build.
pub fn machine() -> String {
    let read = |p: &str| std::fs::read_to_string(p).unwrap_or_default();
    let cpu = read("/proc/cpuinfo")
        .lines()
        .find_map(|l| {
            l.strip_prefix("model name")
                .map(|r| r.trim_start_matches([' ', '\t', ':']).to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let online = read("/proc/cpuinfo")
        .lines()
        .filter(|l| l.starts_with("processor"))
        .count();
    let usable = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cores = if online > usable {
        format!("{online} (this run pinned to {usable})")
    } else {
        usable.to_string()
    };
    let mem = read("/proc/meminfo")
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:").map(|r| r.trim().to_string()))
        .and_then(|r| r.trim_end_matches(" kB").trim().parse::<f64>().ok())
        .map_or(String::new(), |kb| {
            format!(", {:.0} GiB RAM", kb / 1024.0 / 1024.0)
        });
    let os = read("/etc/os-release")
        .lines()
        .find_map(|l| {
            l.strip_prefix("PRETTY_NAME=")
                .map(|s| s.trim_matches('"').to_string())
        })
        .unwrap_or_else(|| std::env::consts::OS.to_string());
    let rustc = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or_else(|| "rustc unknown".to_string(), |s| s.trim().to_string());
    let build = if cfg!(debug_assertions) {
        "DEBUG build (times are not representative)"
    } else {
        "release build"
    };
    format!("{cpu}, {cores} logical cores{mem}; {os}; {rustc}; {build}")
}

/// A progress bar on stderr (one line per step when stderr is not a terminal).
pub struct Progress {
    total: usize,
    done: usize,
    tty: bool,
    start: Instant,
}

impl Progress {
    /// A bar for `total` steps.
    pub fn new(total: usize) -> Self {
        Self {
            total: total.max(1),
            done: 0,
            tty: std::io::stderr().is_terminal(),
            start: Instant::now(),
        }
    }

    /// Marks the start of a step called `label`.
    pub fn step(&mut self, label: &str) {
        self.done = (self.done + 1).min(self.total);
        let width = 30;
        let filled = width * self.done / self.total;
        let bar: String = "#".repeat(filled) + &"-".repeat(width - filled);
        let secs = self.start.elapsed().as_secs_f64();
        let mut err = std::io::stderr().lock();
        // Progress output is best effort: a closed stderr must not stop the run.
        let _ = if self.tty {
            write!(
                err,
                "\r\x1b[K[{bar}] {}/{} {secs:5.0} s  {label}",
                self.done, self.total
            )
        } else {
            writeln!(
                err,
                "[{bar}] {}/{} {secs:5.0} s  {label}",
                self.done, self.total
            )
        };
        let _ = err.flush();
    }

    /// Ends the bar.
    pub fn finish(&self) {
        if self.tty {
            eprintln!();
        }
    }
}
