//! Headless replay of a [`SessionLog`]: the same [`Session::step`] the window
//! runs, fed the recorded inputs and time steps instead of devices.
//!
//! Time steps come from the log, never from the clock, so the result is a
//! pure function of the log and the scene: poses and contacts are
//! bit-identical across runs on the same build. The clock only feeds the
//! [`Timing`] report.

use std::time::Instant;

use super::log::SessionLog;
use super::timing::Timing;
use super::{FrameOutcome, Session};

/// What a replay did.
#[derive(Debug, Clone, Default)]
pub struct Replayed {
    /// Frames stepped.
    pub frames: usize,
    /// Frame and collision times.
    pub timing: Timing,
    /// The log asked to quit before its last frame.
    pub quit_early: bool,
}

/// Steps `session` through every frame of `log`, calling `each` with the
/// frame's index and outcome. Stops early at a quit command.
pub fn replay(
    session: &mut Session,
    log: &SessionLog,
    mut each: impl FnMut(usize, &FrameOutcome),
) -> Replayed {
    let mut done = Replayed::default();
    for (k, frame) in log.frames.iter().enumerate() {
        let t0 = Instant::now();
        let out = session.step(&frame.input, frame.dt);
        let us = t0.elapsed().as_secs_f64() * 1e6;
        done.timing.frame(us, &out.collision_calls);
        done.frames = k + 1;
        each(k, &out);
        if out.quit {
            done.quit_early = k + 1 < log.frames.len();
            break;
        }
    }
    done
}

/// Whether the session ended where the recording did: `None` when the log
/// has no final poses, else the molecules whose pose differs (empty: all
/// match bit for bit).
pub fn mismatched_finals(session: &Session, log: &SessionLog) -> Option<Vec<usize>> {
    if log.finals.is_empty() {
        return None;
    }
    let bodies = session.bodies();
    let n = bodies.len().max(log.finals.len());
    Some(
        (0..n)
            .filter(|&b| bodies.get(b).map(|x| x.pose) != log.finals.get(b).copied())
            .collect(),
    )
}
