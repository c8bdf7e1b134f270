//! A log replayed in the window, paced at its recorded times: a frame is
//! stepped only when its recorded time has come, with the recorded input
//! and time step, so the window ends where the recording did.

use std::time::{Duration, Instant};

use crate::session::{FrameInput, SessionLog};

/// A log being replayed.
#[derive(Debug)]
pub struct Player {
    log: SessionLog,
    next: usize,
    started: Option<Instant>,
    elapsed: f64,
}

/// What the player has for a frame.
#[derive(Debug)]
pub enum Due {
    /// This recorded frame: its input and time step.
    Frame(Box<FrameInput>, f64),
    /// Nothing yet: the next frame's time has not come.
    Wait,
    /// The log is over.
    End,
}

impl Player {
    /// A player at the start of `log`.
    pub fn new(log: SessionLog) -> Self {
        Self {
            log,
            next: 0,
            started: None,
            elapsed: 0.0,
        }
    }

    /// Frames played so far.
    pub fn played(&self) -> usize {
        self.next
    }

    /// `Playing N/M` for the HUD.
    pub fn progress(&self) -> String {
        format!("Playing {}/{}", self.next, self.log.frames.len())
    }

    /// The frame due at `now` (the clock starts at the first call).
    pub fn due(&mut self, now: Instant) -> Due {
        let started = *self.started.get_or_insert(now);
        let Some(f) = self.log.frames.get(self.next) else {
            return Due::End;
        };
        if self.elapsed + f.dt > now.duration_since(started).as_secs_f64() {
            return Due::Wait;
        }
        self.elapsed += f.dt;
        self.next += 1;
        Due::Frame(Box::new(f.input.clone()), f.dt)
    }

    /// When the next recorded frame is due (now, before the first).
    pub fn next_at(&self, now: Instant) -> Instant {
        self.started.map_or(now, |s| {
            let ahead = self
                .log
                .frames
                .get(self.next)
                .map_or(0.0, |f| self.elapsed + f.dt);
            s + Duration::from_secs_f64(ahead)
        })
    }
}
