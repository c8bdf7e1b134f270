//! Discrete motion keys as events: one press moves exactly one step;
//! holding a key repeats the step after a delay, at a fixed rate, on the
//! time the key events carry, never on the frame rate.
//!
//! The window (or a test, or a replayed log) gives each frame the key
//! presses and releases that happened during it, each with its time from the
//! start of the frame's interval; [`KeySteps::advance`] turns them, and the
//! keys still held, into the steps due in that interval, in time order.
//! A key held for `T` seconds gives `1 + floor((T − delay) · rate)` steps
//! (one for `T < delay`), however the frames fall: a tap on a slow frame is
//! one step, a 3 s hold the same count at 5 or 500 frames per second.
//! Times are counted in whole microseconds, so the counts are exact and a
//! replay of the same events gives the same steps.
//!
//! Step sizes are documented constants ([`StepSize`]); joystick deflection
//! is not a key and stays a velocity (see [`super::FrameInput::velocity`]).

use glam::DVec3;

use super::Motion6;

/// Seconds a key is held before its step repeats.
pub const REPEAT_DELAY: f64 = 0.4;
/// Steps per second while a key repeats.
pub const REPEAT_RATE: u32 = 20;
/// Longest interval a frame may cover for the keys, seconds: a stalled
/// frame (a large file read in the window's thread) counts as this long, so
/// a held key never releases a burst of repeats after a stall.
pub const MAX_INTERVAL: f64 = 1.0;

const DELAY_US: i64 = 400_000;
const PERIOD_US: i64 = 1_000_000 / REPEAT_RATE as i64;

/// An axis of screen (or object) coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum StepAxis {
    /// Right.
    X,
    /// Up.
    Y,
    /// Towards the viewer.
    Z,
}

impl StepAxis {
    fn unit(self) -> DVec3 {
        match self {
            Self::X => DVec3::X,
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }
}

/// A motion key: a translation or a turn about one axis, one way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StepKey {
    /// A turn (else a translation).
    pub turn: bool,
    /// The axis.
    pub axis: StepAxis,
    /// Along (or, for a turn, right-handed about) the positive axis.
    pub positive: bool,
}

impl StepKey {
    /// A translation key.
    pub const fn translate(axis: StepAxis, positive: bool) -> Self {
        Self {
            turn: false,
            axis,
            positive,
        }
    }

    /// A turn key.
    pub const fn turn(axis: StepAxis, positive: bool) -> Self {
        Self {
            turn: true,
            axis,
            positive,
        }
    }

    /// The same key the other way.
    pub const fn reversed(self) -> Self {
        Self {
            positive: !self.positive,
            ..self
        }
    }

    /// The motion of one step of `size`: Å along the axis, or radians about it.
    pub fn motion(self, size: StepSize) -> Motion6 {
        let sign = if self.positive { 1.0 } else { -1.0 };
        let v = self.axis.unit() * sign;
        if self.turn {
            Motion6 {
                translate: DVec3::ZERO,
                rotate: v * size.degrees().to_radians(),
            }
        } else {
            Motion6 {
                translate: v * size.angstroms(),
                rotate: DVec3::ZERO,
            }
        }
    }

    /// The key as a log token: `tx+`, `rz-`, ….
    pub fn token(self) -> &'static str {
        const T: [[&str; 2]; 3] = [["tx-", "tx+"], ["ty-", "ty+"], ["tz-", "tz+"]];
        const R: [[&str; 2]; 3] = [["rx-", "rx+"], ["ry-", "ry+"], ["rz-", "rz+"]];
        let table = if self.turn { &R } else { &T };
        table[self.axis as usize][usize::from(self.positive)]
    }

    /// Reads a token written by [`StepKey::token`].
    pub fn parse(s: &str) -> Option<Self> {
        let b = s.as_bytes();
        if b.len() != 3 {
            return None;
        }
        let turn = match b[0] {
            b't' => false,
            b'r' => true,
            _ => return None,
        };
        let axis = match b[1] {
            b'x' => StepAxis::X,
            b'y' => StepAxis::Y,
            b'z' => StepAxis::Z,
            _ => return None,
        };
        let positive = match b[2] {
            b'+' => true,
            b'-' => false,
            _ => return None,
        };
        Some(Self {
            turn,
            axis,
            positive,
        })
    }
}

/// How far one step goes: fine (Alt), normal, coarse (Shift).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum StepSize {
    /// Alt: a fifth of normal.
    Fine,
    /// No modifier.
    #[default]
    Normal,
    /// Shift: five times normal.
    Coarse,
}

impl StepSize {
    /// All sizes, fine to coarse.
    pub const ALL: [StepSize; 3] = [Self::Fine, Self::Normal, Self::Coarse];

    /// Translation of one step, Å.
    pub const fn angstroms(self) -> f64 {
        match self {
            Self::Fine => 0.04,
            Self::Normal => 0.2,
            Self::Coarse => 1.0,
        }
    }

    /// Turn of one step, degrees.
    pub const fn degrees(self) -> f64 {
        match self {
            Self::Fine => 0.45,
            Self::Normal => 2.25,
            Self::Coarse => 11.25,
        }
    }

    /// The name a log and the HUD use.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Fine => "fine",
            Self::Normal => "normal",
            Self::Coarse => "coarse",
        }
    }

    /// Reads a name written by [`StepSize::name`].
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|z| z.name() == s)
    }
}

/// A motion key pressed or released during a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyEvent {
    /// Which key.
    pub key: StepKey,
    /// The step size its modifiers chose when it was pressed (a release's
    /// size is not used).
    pub size: StepSize,
    /// Pressed (else released).
    pub pressed: bool,
    /// Seconds after the start of the frame's interval (clamped into it).
    pub at: f64,
}

impl KeyEvent {
    /// A press of `key` at `at` seconds into the frame.
    pub fn press(key: StepKey, size: StepSize, at: f64) -> Self {
        Self {
            key,
            size,
            pressed: true,
            at,
        }
    }

    /// A release of `key` at `at` seconds into the frame.
    pub fn release(key: StepKey, at: f64) -> Self {
        Self {
            key,
            size: StepSize::Normal,
            pressed: false,
            at,
        }
    }
}

/// One step due in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// Which key.
    pub key: StepKey,
    /// Its size.
    pub size: StepSize,
    /// The press itself (else a repeat): a new gesture for undo.
    pub first: bool,
}

impl Step {
    /// The step's motion.
    pub fn motion(&self) -> Motion6 {
        self.key.motion(self.size)
    }
}

#[derive(Debug, Clone, PartialEq)]
struct Held {
    key: StepKey,
    size: StepSize,
    since_us: i64,
    /// Steps given so far, the press included.
    steps: i64,
}

/// The motion keys held and the key clock.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeySteps {
    clock_us: i64,
    held: Vec<Held>,
}

/// Seconds as whole microseconds (non-finite or negative: 0).
fn micros(s: f64) -> i64 {
    if s.is_finite() && s > 0.0 {
        (s.min(MAX_INTERVAL) * 1e6).round() as i64
    } else {
        0
    }
}

/// Steps due after holding a key `held_us` µs, the press included.
fn due(held_us: i64) -> i64 {
    if held_us < DELAY_US {
        1
    } else {
        1 + (held_us - DELAY_US) / PERIOD_US
    }
}

impl KeySteps {
    /// Advances the key clock by a frame of `dt` seconds (at most
    /// [`MAX_INTERVAL`]) in which `events` happened; returns the steps due
    /// in it, in time order (a press before its repeats; keys due at the
    /// same microsecond in the order they were pressed).
    pub fn advance(&mut self, events: &[KeyEvent], dt: f64) -> Vec<Step> {
        let start = self.clock_us;
        let end = start + micros(dt);
        let mut timed: Vec<(i64, usize, Step)> = Vec::new();
        let mut order = 0usize;
        let mut events: Vec<(i64, &KeyEvent)> = events
            .iter()
            .map(|e| ((start + micros(e.at)).min(end), e))
            .collect();
        events.sort_by_key(|(t, _)| *t);
        for (t, e) in events {
            self.repeats_until(t, &mut timed, &mut order);
            let k = self.held.iter().position(|h| h.key == e.key);
            match (e.pressed, k) {
                (true, None) => {
                    self.held.push(Held {
                        key: e.key,
                        size: e.size,
                        since_us: t,
                        steps: 1,
                    });
                    timed.push((
                        t,
                        order,
                        Step {
                            key: e.key,
                            size: e.size,
                            first: true,
                        },
                    ));
                    order += 1;
                }
                (false, Some(k)) => {
                    self.held.remove(k);
                }
                // A press of a key already held (a lost release) or a
                // release of one not held changes nothing.
                _ => {}
            }
        }
        self.repeats_until(end, &mut timed, &mut order);
        self.clock_us = end;
        timed.sort_by_key(|(t, o, _)| (*t, *o));
        timed.into_iter().map(|(_, _, s)| s).collect()
    }

    /// Books every repeat of the held keys due at or before `t`.
    fn repeats_until(&mut self, t: i64, timed: &mut Vec<(i64, usize, Step)>, order: &mut usize) {
        for h in &mut self.held {
            let want = due(t - h.since_us);
            while h.steps < want {
                let at = h.since_us + DELAY_US + h.steps * PERIOD_US;
                timed.push((
                    at,
                    *order,
                    Step {
                        key: h.key,
                        size: h.size,
                        first: false,
                    },
                ));
                *order += 1;
                h.steps += 1;
            }
        }
    }

    /// True while a motion key is held.
    pub fn any_held(&self) -> bool {
        !self.held.is_empty()
    }

    /// Seconds from the end of the last frame until the next repeat, while
    /// a key is held (the window sleeps until then).
    pub fn next_repeat_in(&self) -> Option<f64> {
        self.held
            .iter()
            .map(|h| h.since_us + DELAY_US + h.steps * PERIOD_US - self.clock_us)
            .min()
            .map(|us| us.max(0) as f64 * 1e-6)
    }

    /// The keys held now, in the order they were pressed.
    pub fn held(&self) -> impl Iterator<Item = (StepKey, StepSize)> + '_ {
        self.held.iter().map(|h| (h.key, h.size))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RIGHT: StepKey = StepKey::translate(StepAxis::X, true);
    const UP: StepKey = StepKey::translate(StepAxis::Y, true);

    /// Steps of one key held from `t0` to `t1` (absolute seconds) with a
    /// frame every `frame` seconds.
    fn hold(t0: f64, t1: f64, frame: f64) -> usize {
        let mut k = KeySteps::default();
        let mut n = 0;
        let mut now = 0.0;
        while now < t1 + 2.0 {
            let next = now + frame;
            let mut ev = Vec::new();
            if t0 >= now && t0 < next {
                ev.push(KeyEvent::press(RIGHT, StepSize::Normal, t0 - now));
            }
            if t1 >= now && t1 < next {
                ev.push(KeyEvent::release(RIGHT, t1 - now));
            }
            n += k.advance(&ev, frame).len();
            now = next;
        }
        n
    }

    #[test]
    fn a_hold_gives_one_step_then_repeats_at_the_rate_whatever_the_frames() {
        for frame in [0.001, 1.0 / 60.0, 0.1, 0.25, 0.6] {
            assert_eq!(hold(0.05, 0.15, frame), 1, "tap, frame {frame}");
            assert_eq!(hold(0.05, 0.44, frame), 1, "under the delay, frame {frame}");
            // Past 0.4 s + one period: the first repeat.
            assert_eq!(hold(0.05, 0.53, frame), 2, "frame {frame}");
            // 3.02 s: 1 + floor(2.62 × 20) = 53.
            assert_eq!(hold(0.05, 3.07, frame), 53, "3 s, frame {frame}");
        }
    }

    #[test]
    fn steps_come_in_time_order_with_presses_first() {
        let mut k = KeySteps::default();
        let s = k.advance(
            &[
                KeyEvent::press(UP, StepSize::Coarse, 0.3),
                KeyEvent::press(RIGHT, StepSize::Fine, 0.1),
                KeyEvent::release(RIGHT, 0.2),
            ],
            0.5,
        );
        assert_eq!(
            s,
            [
                Step {
                    key: RIGHT,
                    size: StepSize::Fine,
                    first: true
                },
                Step {
                    key: UP,
                    size: StepSize::Coarse,
                    first: true
                }
            ]
        );
        assert!(k.any_held());
        assert!((k.next_repeat_in().expect("held") - 0.25).abs() < 1e-9);
        // A second press of a held key is not a second step.
        assert!(
            k.advance(&[KeyEvent::press(UP, StepSize::Coarse, 0.0)], 0.0)
                .is_empty()
        );
    }

    #[test]
    fn tokens_and_motions() {
        for turn in [false, true] {
            for axis in [StepAxis::X, StepAxis::Y, StepAxis::Z] {
                for positive in [false, true] {
                    let k = StepKey {
                        turn,
                        axis,
                        positive,
                    };
                    assert_eq!(StepKey::parse(k.token()), Some(k));
                }
            }
        }
        assert_eq!(StepKey::parse("tx"), None);
        let m = StepKey::turn(StepAxis::Y, false).motion(StepSize::Coarse);
        assert_eq!(m.rotate, DVec3::new(0.0, -(11.25f64.to_radians()), 0.0));
        assert_eq!(RIGHT.motion(StepSize::Coarse).translate, DVec3::X);
        for z in StepSize::ALL {
            assert_eq!(StepSize::parse(z.name()), Some(z));
        }
    }
}
