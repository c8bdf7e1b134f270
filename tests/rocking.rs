//! Rocking through the session: it is driven by `dt` alone (so replays
//! agree bit for bit), it pauses while the user moves anything without
//! moving the view, and it resumes from where the view is.

use bump::model::{RadiiSet, builtin};
use bump::session::{Command, FrameInput, Session, Settings};
use glam::{DQuat, DVec3};

fn session() -> Session {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    Session::new(vec![rings, e], Settings::default()).expect("session")
}

fn turned(a: DQuat, b: DQuat) -> f64 {
    a.angle_between(b)
}

#[test]
fn rocking_turns_the_view_camera_only_and_replays_bit_for_bit() {
    let run = || {
        let mut s = session();
        let home = s.camera().rotation;
        s.step(&FrameInput::with_commands(&[Command::ToggleRocking]), 0.0);
        let mut views = Vec::new();
        for i in 0..300 {
            let out = s.step(&FrameInput::default(), 1.0 / 60.0 + (i % 3) as f64 * 1e-4);
            if i > 60 {
                assert!(out.changed, "frame {i}: a rocking view must be redrawn");
            }
            views.push(s.view_camera().rotation);
        }
        // The docking camera and the molecules did not move: only the view.
        assert_eq!(s.camera().rotation, home);
        views
    };
    let a = run();
    let b = run();
    assert_eq!(a, b);
    let max = a
        .iter()
        .map(|q| turned(*q, DQuat::IDENTITY))
        .fold(0.0, f64::max);
    assert!(max > 5f64.to_radians(), "it rocked only {max} rad");
}

#[test]
fn moving_pauses_rocking_where_the_view_is_and_it_resumes_without_a_jump() {
    let mut s = session();
    s.step(&FrameInput::with_commands(&[Command::ToggleRocking]), 0.0);
    for _ in 0..120 {
        s.step(&FrameInput::default(), 1.0 / 60.0);
    }
    let before = s.view_camera().rotation;
    assert!(
        turned(before, s.camera().rotation) > 1e-3,
        "it should be mid-swing"
    );
    // A zero-length motion request is no motion; a real one pauses.
    let nudge = FrameInput::nudged(DVec3::new(0.1, 0.0, 0.0), DVec3::ZERO);
    s.step(&nudge, 0.0);
    // Pausing baked the angle into the camera: the view did not turn.
    assert!(turned(s.view_camera().rotation, before) < 1e-12);
    assert!(s.rock().is_paused());
    let held = s.view_camera().rotation;
    for _ in 0..20 {
        s.step(&FrameInput::default(), 1.0 / 60.0);
        assert!(turned(s.view_camera().rotation, held) < 1e-12, "paused");
    }
    // Then it resumes: each frame's turn stays small (no jump) and grows.
    let mut last = s.view_camera().rotation;
    let mut moved = false;
    for _ in 0..240 {
        s.step(&FrameInput::default(), 1.0 / 60.0);
        let now = s.view_camera().rotation;
        let step = turned(now, last);
        assert!(step < 0.5f64.to_radians(), "jumped {step} rad in one frame");
        moved |= step > 0.0;
        last = now;
    }
    assert!(moved, "rocking resumed");
    // Turning it off keeps the view where it is.
    let v = s.view_camera().rotation;
    s.step(&FrameInput::with_commands(&[Command::ToggleRocking]), 0.0);
    assert!(turned(s.view_camera().rotation, v) < 1e-12);
    assert!(!s.rock().is_on());
}

#[test]
fn a_mouse_drag_on_the_camera_pauses_rocking_too() {
    let mut s = session();
    s.step(
        &FrameInput::with_commands(&[Command::ToggleRocking, Command::RockMore]),
        0.0,
    );
    for _ in 0..120 {
        s.step(&FrameInput::default(), 1.0 / 60.0);
    }
    let before = s.view_camera().rotation;
    s.camera_mut().move_scene(DVec3::ZERO, DVec3::ZERO);
    assert!(turned(s.view_camera().rotation, before) < 1e-12);
    assert!(s.rock().is_paused());
}

#[test]
fn mouse_drags_and_the_wheel_through_the_frame_input_pause_rocking() {
    for input in [
        FrameInput {
            view_nudge: bump::session::Motion6 {
                translate: DVec3::ZERO,
                rotate: DVec3::new(0.0, 0.01, 0.0),
            },
            ..FrameInput::default()
        },
        FrameInput {
            zoom: 1.0,
            ..FrameInput::default()
        },
        FrameInput {
            object_velocity: bump::session::Motion6 {
                translate: DVec3::X,
                rotate: DVec3::ZERO,
            },
            ..FrameInput::default()
        },
    ] {
        let mut s = session();
        s.step(
            &FrameInput::with_commands(&[Command::ToggleRocking, Command::RockMore]),
            0.0,
        );
        for _ in 0..120 {
            s.step(&FrameInput::default(), 1.0 / 60.0);
        }
        assert!(!s.rock().is_paused());
        s.step(&input, 1.0 / 60.0);
        assert!(s.rock().is_paused(), "{input:?} did not pause rocking");
    }
}
