//! Motion keys through the session with slow and fast frame clocks: one
//! press is exactly one documented step, a hold repeats after the delay at
//! the fixed rate, whatever the frame rate (issue 42's taps that moved
//! 33.75° or 56.25° for a documented 11.25°).

use bump::model::{RadiiSet, builtin};
use bump::session::keys::{REPEAT_DELAY, REPEAT_RATE};
use bump::session::{
    Command, FrameInput, KeyEvent, Session, Settings, StepAxis, StepKey, StepSize,
};
use glam::{DQuat, DVec3};

const RIGHT: StepKey = StepKey::translate(StepAxis::X, true);
const LEFT: StepKey = StepKey::translate(StepAxis::X, false);
const TOWARDS: StepKey = StepKey::translate(StepAxis::Z, true);
const TURN_RIGHT: StepKey = StepKey::turn(StepAxis::Y, true);

/// Frame periods from 1 kHz to a slow CPU renderer's 0.6 s.
const CLOCKS: [f64; 6] = [0.001, 1.0 / 144.0, 1.0 / 60.0, 0.1, 0.25, 0.6];

fn object_mode() -> Session {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s
}

/// A press at `down` and a release at `up` (absolute seconds).
#[derive(Clone, Copy)]
struct Hold {
    key: StepKey,
    size: StepSize,
    down: f64,
    up: f64,
}

/// Steps `s` with a frame every `frame` seconds until every hold has ended
/// and a second more has passed, each event in the frame whose interval
/// holds it, at its time from the interval's start.
fn drive(s: &mut Session, holds: &[Hold], frame: f64) {
    let end = holds.iter().map(|h| h.up).fold(0.0, f64::max) + 1.0;
    let mut k = 0u64;
    loop {
        let (t0, t1) = (k as f64 * frame, (k + 1) as f64 * frame);
        if t0 > end {
            break;
        }
        let mut keys = Vec::new();
        for h in holds {
            if h.down >= t0 && h.down < t1 {
                keys.push(KeyEvent::press(h.key, h.size, h.down - t0));
            }
            if h.up >= t0 && h.up < t1 {
                keys.push(KeyEvent::release(h.key, h.up - t0));
            }
        }
        s.step(
            &FrameInput {
                keys,
                ..FrameInput::default()
            },
            frame,
        );
        k += 1;
    }
}

/// `n` taps of `key`, each held `held` seconds, one every `every` seconds.
fn taps(key: StepKey, size: StepSize, n: usize, held: f64, every: f64, from: f64) -> Vec<Hold> {
    (0..n)
        .map(|i| {
            let down = from + 0.013 + i as f64 * every;
            Hold {
                key,
                size,
                down,
                up: down + held,
            }
        })
        .collect()
}

fn drug_centre(s: &Session) -> DVec3 {
    s.bodies()[1].pose.translation
}

#[test]
fn a_tap_is_exactly_one_step_at_any_frame_rate() {
    for frame in CLOCKS {
        for (held, every) in [(0.1, 0.1), (0.1, 0.6), (0.3, 0.35)] {
            let mut s = object_mode();
            let start = drug_centre(&s);
            drive(
                &mut s,
                &taps(TOWARDS, StepSize::Coarse, 10, held, every + held, 0.0),
                frame,
            );
            let moved = drug_centre(&s) - start;
            assert!(
                (moved - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-9,
                "10 coarse taps of {held} s, frame {frame} s: moved {moved}"
            );
        }
    }
}

#[test]
fn six_coarse_turn_taps_turn_exactly_six_documented_steps() {
    for frame in CLOCKS {
        let mut s = object_mode();
        let start = s.bodies()[1].pose.rotation;
        drive(
            &mut s,
            &taps(TURN_RIGHT, StepSize::Coarse, 6, 0.1, 0.2, 0.0),
            frame,
        );
        let turn: DQuat = s.bodies()[1].pose.rotation * start.conjugate();
        let (axis, angle) = turn.to_axis_angle();
        assert!(
            (angle.to_degrees() - 6.0 * 11.25).abs() < 1e-9,
            "frame {frame}: {}°",
            angle.to_degrees()
        );
        assert!((axis - DVec3::Y).length() < 1e-9, "{axis}");
    }
}

#[test]
fn a_hold_steps_once_then_repeats_at_the_documented_rate() {
    for frame in CLOCKS {
        for held in [0.2, 0.47, 1.03, 3.02] {
            let mut s = object_mode();
            let start = drug_centre(&s);
            let down = 0.05;
            drive(
                &mut s,
                &[Hold {
                    key: RIGHT,
                    size: StepSize::Normal,
                    down,
                    up: down + held,
                }],
                frame,
            );
            let steps = 1.0
                + ((held - REPEAT_DELAY) * f64::from(REPEAT_RATE))
                    .floor()
                    .max(0.0);
            let moved = (drug_centre(&s) - start).x;
            assert!(
                (moved - steps * StepSize::Normal.angstroms()).abs() < 1e-9,
                "held {held} s, frame {frame} s: moved {moved} Å, expected {steps} steps"
            );
        }
    }
}

#[test]
fn ten_taps_out_and_ten_back_return_to_the_start() {
    for frame in CLOCKS {
        let mut s = object_mode();
        let start = s.bodies()[1].pose;
        let mut holds = taps(RIGHT, StepSize::Coarse, 10, 0.1, 0.2, 0.0);
        holds.extend(taps(LEFT, StepSize::Coarse, 10, 0.1, 0.2, 2.5));
        holds.extend(taps(TURN_RIGHT, StepSize::Fine, 3, 0.05, 0.1, 5.0));
        holds.extend(taps(
            TURN_RIGHT.reversed(),
            StepSize::Fine,
            3,
            0.05,
            0.1,
            6.0,
        ));
        drive(&mut s, &holds, frame);
        let end = s.bodies()[1].pose;
        assert!(
            (end.translation - start.translation).length() < 1e-9,
            "frame {frame}: {} Å off",
            (end.translation - start.translation).length()
        );
        assert!(end.rotation.angle_between(start.rotation) < 1e-9);
    }
}

#[test]
fn a_tap_is_one_undo_entry_and_a_hold_is_one_too() {
    let mut s = object_mode();
    let start = drug_centre(&s);
    let mut holds = taps(RIGHT, StepSize::Normal, 2, 0.05, 0.1, 0.0);
    holds.push(Hold {
        key: TOWARDS,
        size: StepSize::Normal,
        down: 1.0,
        up: 2.0,
    });
    drive(&mut s, &holds, 0.1);
    assert_eq!(s.history().undo_len(), 3);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    let after = drug_centre(&s) - start;
    assert!(
        (after - DVec3::new(0.4, 0.0, 0.0)).length() < 1e-9,
        "{after}"
    );
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert!((drug_centre(&s) - start - DVec3::new(0.2, 0.0, 0.0)).length() < 1e-9);
}

#[test]
fn in_view_mode_a_tap_moves_the_view_one_step() {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
    let before = s.camera().centre;
    drive(&mut s, &taps(RIGHT, StepSize::Fine, 1, 0.1, 0.2, 0.0), 0.25);
    // Moving the scene right moves the camera left.
    assert!((before - s.camera().centre - DVec3::new(0.04, 0.0, 0.0)).length() < 1e-12);
    assert!(!s.keys().any_held());
}
