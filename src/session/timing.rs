//! The timing report printed on exit (the thesis, section 5.4): how many
//! collision queries ran and how long they took, how many frames and how
//! long they took, and the share of frame time spent colliding.
//!
//! The driver (window or headless replay) books each frame's wall time and
//! the per-query times the session reports in
//! [`super::FrameOutcome::collision_calls`]; the statistics are computed once,
//! at the end, from the sorted samples.

use std::fmt::Write as _;

/// Summary statistics of a set of durations, µs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Summary {
    /// How many samples.
    pub count: usize,
    /// Sum, µs.
    pub total: f64,
    /// Mean, µs.
    pub mean: f64,
    /// Median, µs.
    pub median: f64,
    /// 99th percentile (nearest rank), µs.
    pub p99: f64,
    /// Largest, µs.
    pub max: f64,
}

impl Summary {
    /// Statistics of `samples` (µs, any order; non-finite ones are skipped).
    pub fn of(samples: &[f64]) -> Self {
        let mut v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Self::default();
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let total: f64 = v.iter().sum();
        let rank = |p: f64| v[((p * n as f64).ceil() as usize).clamp(1, n) - 1];
        Self {
            count: n,
            total,
            mean: total / n as f64,
            median: if n % 2 == 1 {
                v[n / 2]
            } else {
                0.5 * (v[n / 2 - 1] + v[n / 2])
            },
            p99: rank(0.99),
            max: v[n - 1],
        }
    }
}

/// Collects frame and collision times over a session.
#[derive(Debug, Clone, Default)]
pub struct Timing {
    frames_us: Vec<f64>,
    collisions_us: Vec<f64>,
}

impl Timing {
    /// Books one frame of `frame_us` whose collision queries took `calls_us`.
    pub fn frame(&mut self, frame_us: f64, calls_us: &[f64]) {
        self.frames_us.push(frame_us);
        self.collisions_us.extend_from_slice(calls_us);
    }

    /// Frame-time statistics.
    pub fn frames(&self) -> Summary {
        Summary::of(&self.frames_us)
    }

    /// Collision-query statistics.
    pub fn collisions(&self) -> Summary {
        Summary::of(&self.collisions_us)
    }

    /// Share of the frame time spent in collision queries, 0–1.
    pub fn collision_share(&self) -> f64 {
        let f = self.frames();
        if f.total > 0.0 {
            (self.collisions().total / f.total).min(1.0)
        } else {
            0.0
        }
    }

    /// The report, several lines, for a terminal. `what` names the run
    /// (e.g. the collider and method).
    pub fn report(&self, what: &str) -> String {
        let (c, f) = (self.collisions(), self.frames());
        let mut s = format!("timing report ({what})\n");
        let _ = writeln!(
            s,
            "  collision calls: {:>7}   mean {:>9}   median {:>9}   p99 {:>9}   max {:>9}   total {}",
            c.count,
            us(c.mean),
            us(c.median),
            us(c.p99),
            us(c.max),
            us(c.total)
        );
        let _ = writeln!(
            s,
            "  frames:          {:>7}   mean {:>9}   median {:>9}   p99 {:>9}   max {:>9}   total {}",
            f.count,
            us(f.mean),
            us(f.median),
            us(f.p99),
            us(f.max),
            us(f.total)
        );
        let _ = write!(
            s,
            "  share of frame time spent colliding: {:.1} %",
            100.0 * self.collision_share()
        );
        s
    }
}

/// A duration in µs, in the unit that reads best.
pub fn us(x: f64) -> String {
    if x >= 1e6 {
        format!("{:.2} s", x / 1e6)
    } else if x >= 1e3 {
        format!("{:.2} ms", x / 1e3)
    } else {
        format!("{x:.2} µs")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summaries_are_exact_on_small_sets() {
        let s = Summary::of(&[5.0, 1.0, 3.0, f64::NAN, 2.0, 4.0]);
        assert_eq!(s.count, 5);
        assert_eq!((s.mean, s.median, s.max, s.total), (3.0, 3.0, 5.0, 15.0));
        assert_eq!(s.p99, 5.0);
        let s = Summary::of(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(s.median, 2.5);
        let v: Vec<f64> = (1..=1000).map(f64::from).collect();
        assert_eq!(Summary::of(&v).p99, 990.0);
        assert_eq!(Summary::of(&[]), Summary::default());
    }

    #[test]
    fn the_share_is_collision_time_over_frame_time() {
        let mut t = Timing::default();
        t.frame(100.0, &[10.0, 15.0]);
        t.frame(100.0, &[]);
        t.frame(200.0, &[25.0]);
        assert_eq!(t.collisions().count, 3);
        assert_eq!(t.frames().count, 3);
        assert!((t.collision_share() - 50.0 / 400.0).abs() < 1e-12);
        let r = t.report("grid");
        assert!(r.contains("collision calls:       3"), "{r}");
        assert!(r.contains("12.5 %"), "{r}");
    }
}
