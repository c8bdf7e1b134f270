//! Rocking: a gentle oscillation of the view about the screen's vertical
//! axis, a depth cue from motion parallax (thesis chapter 4.3).
//!
//! The angle is `amplitude · sin(phase)`; the phase advances by
//! `ω · speed · dt`. Everything is advanced by the frame's `dt` only, so a
//! recorded session replays bit for bit. When the user moves anything the
//! session *bakes* the current angle into the camera ([`Rock::pause`] returns
//! it) and the rock restarts from phase 0 with speed 0: the view stays
//! exactly where it is. After [`RESUME_AFTER`] seconds without user motion
//! the speed eases back in (a smoothstep over [`RAMP`] seconds), so the
//! angular velocity, too, starts from zero: no jump, no jerk. Amplitude
//! changes ease in at [`AMPLITUDE_RATE`] for the same reason.

use std::f64::consts::TAU;

/// Default half-swing, radians (10°).
pub const DEFAULT_AMPLITUDE: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Smallest half-swing, radians (1°).
pub const MIN_AMPLITUDE: f64 = std::f64::consts::PI / 180.0;
/// Largest half-swing, radians (45°).
pub const MAX_AMPLITUDE: f64 = std::f64::consts::FRAC_PI_4;
/// Seconds per full swing.
pub const PERIOD: f64 = 4.0;
/// Seconds without user motion before rocking resumes.
pub const RESUME_AFTER: f64 = 0.5;
/// Seconds over which the speed eases from 0 back to full.
pub const RAMP: f64 = 1.5;
/// How fast the amplitude follows its target, radians per second.
pub const AMPLITUDE_RATE: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// The rocking state (part of the docking session, so replays agree).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rock {
    on: bool,
    target: f64,
    amplitude: f64,
    phase: f64,
    speed: f64,
    idle: f64,
}

impl Default for Rock {
    fn default() -> Self {
        Self {
            on: false,
            target: DEFAULT_AMPLITUDE,
            amplitude: DEFAULT_AMPLITUDE,
            phase: 0.0,
            speed: 0.0,
            idle: 0.0,
        }
    }
}

fn smoothstep(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Rock {
    /// Whether rocking is on.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// The current angle about the screen's vertical axis, radians
    /// (positive turns the front of the scene to the right).
    pub fn angle(&self) -> f64 {
        if self.on {
            self.amplitude * self.phase.sin()
        } else {
            0.0
        }
    }

    /// The half-swing rocking is heading for, radians (the swing eases
    /// towards it).
    pub fn target_amplitude(&self) -> f64 {
        self.target
    }

    /// Current speed factor, 0 (paused) to 1.
    pub fn speed(&self) -> f64 {
        if self.on { self.speed } else { 0.0 }
    }

    /// Whether rocking is on but paused by user motion.
    pub fn is_paused(&self) -> bool {
        self.on && self.idle < RESUME_AFTER
    }

    /// Turns rocking on or off. Returns the angle the caller must bake into
    /// the view so that nothing jumps (non-zero only when turning off).
    pub fn toggle(&mut self) -> f64 {
        let baked = self.angle();
        self.on = !self.on;
        self.phase = 0.0;
        self.speed = 0.0;
        // Turning it on starts the ease-in at once.
        self.idle = RESUME_AFTER;
        baked
    }

    /// A wider swing (×1.25, at most [`MAX_AMPLITUDE`]); eases in.
    pub fn more(&mut self) {
        self.target = (self.target * 1.25).min(MAX_AMPLITUDE);
    }

    /// A narrower swing (×0.8, at least [`MIN_AMPLITUDE`]); eases in.
    pub fn less(&mut self) {
        self.target = (self.target * 0.8).max(MIN_AMPLITUDE);
    }

    /// The user moved something: stop where we are. Returns the angle the
    /// caller must bake into the view; afterwards [`Rock::angle`] is 0.
    pub fn pause(&mut self) -> f64 {
        let baked = self.angle();
        self.phase = 0.0;
        self.speed = 0.0;
        self.idle = 0.0;
        baked
    }

    /// Advances `dt` seconds (finite, ≥ 0). Returns whether the angle changed.
    pub fn advance(&mut self, dt: f64) -> bool {
        if !(self.on && dt.is_finite() && dt > 0.0) {
            return false;
        }
        let before = self.angle();
        self.idle += dt;
        let step = AMPLITUDE_RATE * dt;
        self.amplitude += (self.target - self.amplitude).clamp(-step, step);
        if self.idle < RESUME_AFTER {
            self.speed = 0.0;
            return false;
        }
        self.speed = smoothstep((self.idle - RESUME_AFTER) / RAMP);
        self.phase = (self.phase + TAU / PERIOD * self.speed * dt) % TAU;
        self.angle() != before
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest change of the viewed angle in one step of `dt`: full speed
    /// times the largest amplitude, plus the amplitude's own easing.
    fn max_step(dt: f64) -> f64 {
        (MAX_AMPLITUDE * TAU / PERIOD + AMPLITUDE_RATE) * dt * 1.000_001
    }

    #[test]
    fn off_by_default_and_still() {
        let mut r = Rock::default();
        assert!(!r.is_on());
        assert!(!r.advance(0.1));
        assert_eq!(r.angle(), 0.0);
    }

    #[test]
    fn it_swings_both_ways_within_the_amplitude() {
        let mut r = Rock::default();
        r.toggle();
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for _ in 0..2000 {
            r.advance(0.01);
            lo = lo.min(r.angle());
            hi = hi.max(r.angle());
            assert!(r.angle().abs() <= DEFAULT_AMPLITUDE + 1e-12);
        }
        assert!(hi > 0.99 * DEFAULT_AMPLITUDE && lo < -0.99 * DEFAULT_AMPLITUDE);
    }

    #[test]
    fn no_jump_through_pauses_resumes_toggles_and_amplitude_changes() {
        // The viewed angle is what was baked into the camera plus the
        // current angle: it must never change by more than full speed allows.
        let mut r = Rock::default();
        let mut baked = 0.0;
        let mut seen = baked + r.angle();
        let dt = 1.0 / 60.0;
        for i in 0..6000 {
            match i % 997 {
                100..=102 => baked += r.pause(),
                300 => r.more(),
                301 => r.more(),
                500 => baked += r.toggle(),
                520 => baked += r.toggle(),
                700 => r.less(),
                _ => {}
            }
            if i == 0 {
                baked += r.toggle();
            }
            r.advance(dt);
            let now = baked + r.angle();
            assert!(
                (now - seen).abs() <= max_step(dt),
                "step {i}: jumped by {}",
                now - seen
            );
            seen = now;
        }
    }

    #[test]
    fn a_pause_holds_the_view_then_speed_eases_back_in() {
        let mut r = Rock::default();
        r.toggle();
        for _ in 0..90 {
            r.advance(1.0 / 60.0);
        }
        let a = r.angle();
        assert!(a.abs() > 0.01, "it should have moved: {a}");
        let baked = r.pause();
        assert_eq!(baked, a, "the angle to bake is where it was");
        assert_eq!(r.angle(), 0.0);
        // Paused: nothing moves for RESUME_AFTER seconds.
        let mut t = 0.0;
        while t + 0.01 < RESUME_AFTER {
            assert!(!r.advance(0.01));
            assert!(r.is_paused());
            t += 0.01;
        }
        // Then the speed rises smoothly from 0 to 1.
        let mut last = 0.0;
        for _ in 0..((RAMP + 1.0) / 0.01) as usize {
            r.advance(0.01);
            assert!(r.speed() >= last && r.speed() - last < 0.02);
            last = r.speed();
        }
        assert_eq!(last, 1.0);
    }

    #[test]
    fn amplitude_is_bounded_and_eases() {
        let mut r = Rock::default();
        for _ in 0..50 {
            r.more();
        }
        assert_eq!(r.target_amplitude(), MAX_AMPLITUDE);
        for _ in 0..50 {
            r.less();
        }
        assert_eq!(r.target_amplitude(), MIN_AMPLITUDE);
    }

    #[test]
    fn same_steps_same_angles_bit_for_bit() {
        let run = || {
            let mut r = Rock::default();
            r.toggle();
            let mut v = Vec::new();
            for i in 0..500 {
                if i == 200 {
                    r.pause();
                }
                r.advance(0.013 + (i % 7) as f64 * 1e-3);
                v.push(r.angle().to_bits());
            }
            v
        };
        assert_eq!(run(), run());
    }
}
