//! A settle shown as a short animation. The session settles in one step
//! and is at the end pose when the frame returns; the window then draws
//! the drug along the way for [`DURATION`]: its pose moved and turned
//! (translation interpolated, rotation by slerp) and its torsions turned
//! together, eased in and out. Only the drawing moves: the session, the
//! log and a replay see the single settle step.

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::motion::Pose;
use crate::session::SettlePath;

/// How long the animation lasts.
pub const DURATION: Duration = Duration::from_millis(600);

/// A settle being shown.
#[derive(Debug, Clone)]
pub struct SettleShow {
    /// What the settle did.
    pub path: Arc<SettlePath>,
    start: Instant,
}

impl SettleShow {
    /// Starts showing `path` at `start`.
    pub fn new(path: Arc<SettlePath>, start: Instant) -> Self {
        Self { path, start }
    }

    /// The share of the way shown at `now`, eased (0 at the start, 1 at
    /// the end and after).
    pub fn share(&self, now: Instant) -> f64 {
        let t = now.saturating_duration_since(self.start).as_secs_f64() / DURATION.as_secs_f64();
        let t = t.clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    /// Whether the animation is over at `now`.
    pub fn done(&self, now: Instant) -> bool {
        now.saturating_duration_since(self.start) >= DURATION
    }

    /// The drug's pose and torsions at share `u` of the way (0..1).
    pub fn at(&self, u: f64) -> (Pose, Vec<f64>) {
        let p = &self.path;
        if u >= 1.0 {
            return (p.to, p.to_torsions.clone());
        }
        let pose = Pose {
            rotation: p.from.rotation.slerp(p.to.rotation, u).normalize(),
            translation: p.from.translation.lerp(p.to.translation, u),
        };
        let torsions = p
            .from_torsions
            .iter()
            .zip(&p.to_torsions)
            .map(|(a, b)| a + (b - a) * u)
            .collect();
        (pose, torsions)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DQuat, DVec3};

    fn path() -> Arc<SettlePath> {
        Arc::new(SettlePath {
            body: 1,
            from: Pose {
                rotation: DQuat::IDENTITY,
                translation: DVec3::new(1.0, 2.0, 3.0),
            },
            from_torsions: vec![0.0, 1.0],
            to: Pose {
                rotation: DQuat::from_rotation_z(0.5),
                translation: DVec3::new(2.0, 2.0, 3.0),
            },
            to_torsions: vec![0.4, 0.0],
            inter: (-5.0, -6.0),
            rmsd: 0.7,
            steps: 12,
        })
    }

    #[test]
    fn it_runs_from_the_start_to_exactly_the_end() {
        let t0 = Instant::now();
        let s = SettleShow::new(path(), t0);
        assert_eq!(s.share(t0), 0.0);
        let (start, tors) = s.at(0.0);
        assert!((start.translation - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12);
        assert!(start.rotation.angle_between(DQuat::IDENTITY) < 1e-12);
        assert_eq!(tors, [0.0, 1.0]);
        let half = s.share(t0 + DURATION / 2);
        assert!((half - 0.5).abs() < 1e-9, "{half}");
        let (mid, tors) = s.at(0.5);
        assert!((mid.translation.x - 1.5).abs() < 1e-12);
        assert!((mid.rotation.angle_between(DQuat::IDENTITY) - 0.25).abs() < 1e-9);
        assert!((tors[0] - 0.2).abs() < 1e-12 && (tors[1] - 0.5).abs() < 1e-12);
        assert!(!s.done(t0 + DURATION / 2));
        let end = t0 + DURATION;
        assert!(s.done(end));
        assert_eq!(s.share(end + DURATION), 1.0);
        let (last, tors) = s.at(s.share(end));
        assert_eq!(last, path().to);
        assert_eq!(tors, path().to_torsions);
    }
}
