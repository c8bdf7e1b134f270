//! Joysticks, recording and replay end to end, without a window or a device:
//! synthetic controller event streams drive a session through the same
//! mapping and `Session::step` the window uses; the inputs are recorded,
//! replayed and compared bit for bit; damaged logs are refused with the line
//! named; and the shipped session (trimethoprim docked into DHFR) replays
//! with every collider without an overlapping pose.

// A test that fails on an unexpected error may just unwrap.
#![allow(clippy::unwrap_used)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command as Process;

use bump::collide::ColliderKind;
use bump::input::{Controllers, DeviceInfo, JoystickMap, RawEvent};
use bump::model::{self, LigandSpec, LoadOptions, Molecule, RadiiSet, builtin};
use bump::motion::Pose;
use bump::session::{
    Command, FrameInput, LogFrame, LogWriter, Mode, Motion6, Session, SessionLog, Settings, replay,
};
use bump_testkit::sphere_directions;
use glam::{DQuat, DVec3};

const DT: f64 = 1.0 / 60.0;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bump-replay-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn builtin_session(collider: ColliderKind) -> Session {
    let (r, e) = builtin::scene(RadiiSet::Bondi);
    Session::new(
        vec![r, e],
        Settings {
            collider,
            ..Settings::default()
        },
    )
    .unwrap()
}

fn pad(id: usize, name: &str) -> RawEvent {
    RawEvent::Connected(DeviceInfo {
        id,
        name: name.into(),
        mapped: true,
    })
}

fn axis(device: usize, source: &str, value: f64) -> RawEvent {
    RawEvent::Value {
        device,
        source: source.into(),
        value,
    }
}

/// A scripted stream: what happens before each frame (device events and
/// key commands).
fn script() -> Vec<(Vec<RawEvent>, Vec<Command>)> {
    let mut s: Vec<(Vec<RawEvent>, Vec<Command>)> = Vec::new();
    // Frame 0: a gamepad appears; Space switches to object mode; collision on.
    s.push((
        vec![pad(4, "Test Pad")],
        vec![Command::ToggleMode, Command::ToggleCollision],
    ));
    // Push the E towards the rings (screen −z is away from the viewer) and
    // twist a little, with a NaN and an out-of-range spike in the stream.
    for k in 0..120 {
        let mut ev = vec![axis(4, "RightTrigger2", 1.0), axis(4, "RightStickX", 0.3)];
        if k == 30 {
            ev.push(axis(4, "RightTrigger2", f64::NAN));
            ev.push(axis(4, "LeftStickX", 55.0));
        }
        s.push((ev, Vec::new()));
    }
    // Hot-plug: the pad goes away mid-push (motion stops), then comes back.
    s.push((vec![RawEvent::Disconnected(4)], Vec::new()));
    for _ in 0..10 {
        s.push((Vec::new(), Vec::new()));
    }
    s.push((vec![pad(4, "Test Pad")], Vec::new()));
    // Back to view mode: the same stick turns the camera.
    s.push((vec![axis(4, "RightStickX", 1.0)], vec![Command::ToggleMode]));
    for _ in 0..30 {
        s.push((Vec::new(), Vec::new()));
    }
    s.push((vec![axis(4, "RightStickX", 0.0)], vec![Command::Undo]));
    s
}

/// Runs the script through controllers → intents → session, returning the
/// frames as recorded and the per-frame poses of the E.
fn drive(session: &mut Session, map: &JoystickMap, two_boxes: bool) -> (Vec<LogFrame>, Vec<Pose>) {
    let mut c = Controllers::default();
    let mut frames = Vec::new();
    let mut poses = Vec::new();
    for (events, commands) in script() {
        for e in events {
            c.apply(map, e);
        }
        let mut input = FrameInput {
            commands,
            ..FrameInput::default()
        };
        c.intents(map, two_boxes).add_to(&mut input);
        let out = session.step(&input, DT);
        assert!(out.contacts.iter().all(|k| k.gap() > 0.0), "overlap");
        frames.push(LogFrame { dt: DT, input });
        poses.push(session.bodies()[1].pose);
    }
    (frames, poses)
}

#[test]
fn synthetic_controller_streams_drive_a_headless_session() {
    let map = JoystickMap::default();
    let mut s = builtin_session(ColliderKind::Hashed);
    let start = s.bodies()[1].pose;
    let cam0 = *s.camera();
    let (frames, poses) = drive(&mut s, &map, false);
    // The trigger pushed the E away from the viewer: along the camera's −z.
    let away = cam0.rotation.conjugate() * DVec3::NEG_Z;
    let moved = poses[120].translation - start.translation;
    assert!(moved.dot(away) > 3.0, "moved {moved}");
    // The right stick's x turned it (users' mapping: about screen x).
    assert!(poses[120].rotation.angle_between(start.rotation) > 0.05);
    // The NaN and the spike changed nothing: frames 30 and 31 are as fast as 29.
    let step = |k: usize| (poses[k].translation - poses[k - 1].translation).length();
    assert!((step(31) - step(29)).abs() < 1e-9 * step(29).max(1.0) || step(31) < step(29));
    assert_eq!(frames[31].input.velocity, frames[29].input.velocity);
    // Unplugged: the E stops at once.
    assert_eq!(poses[122], poses[121]);
    assert_eq!(poses[131], poses[121]);
    assert!(frames[125].input.is_empty());
    // In view mode the stick turns the camera, not the E.
    assert_eq!(s.mode(), Mode::View);
    assert_ne!(s.camera().rotation, cam0.rotation);
    // Undo put the E back where the last move began.
    assert_ne!(s.bodies()[1].pose, poses[131]);
}

#[test]
fn two_boxes_move_view_and_molecule_at_once() {
    let map = JoystickMap::default();
    let mut s = builtin_session(ColliderKind::Grid);
    let mut c = Controllers::default();
    c.apply(&map, pad(1, "View Pad"));
    c.apply(&map, pad(2, "Object Pad"));
    c.apply(&map, axis(1, "RightStickX", 1.0)); // view box: turn
    c.apply(&map, axis(2, "LeftStickX", 1.0)); // object box: move right
    let (cam0, e0) = (*s.camera(), s.bodies()[1].pose);
    for _ in 0..30 {
        let mut input = FrameInput::default();
        c.intents(&map, true).add_to(&mut input);
        s.step(&input, DT);
    }
    // Mode is still View: yet the E moved, and so did the camera.
    assert_eq!(s.mode(), Mode::View);
    assert_ne!(s.camera().rotation, cam0.rotation);
    let moved = s.bodies()[1].pose.translation - e0.translation;
    assert!(moved.length() > 2.0, "{moved}");
}

#[test]
fn recorded_sessions_replay_bit_for_bit_in_process_and_from_the_command_line() {
    let map = JoystickMap::default();
    let mut live = builtin_session(ColliderKind::Hashed);
    let (frames, _) = drive(&mut live, &map, false);
    let dir = temp_dir("bits");
    let path = dir.join("builtin.bumplog");
    let meta = vec![
        ("collider".to_string(), "hashed".to_string()),
        (
            "atoms".to_string(),
            format!(
                "{},{}",
                live.bodies()[0].molecule.len(),
                live.bodies()[1].molecule.len()
            ),
        ),
    ];
    let mut w = LogWriter::create(&path, &meta).unwrap();
    for f in &frames {
        w.frame(f.dt, &f.input).unwrap();
    }
    let finals: Vec<Pose> = live.bodies().iter().map(|b| b.pose).collect();
    w.finish(&finals).unwrap();

    // In process: the same log, a fresh session, identical everything.
    let log = SessionLog::read(&path).unwrap();
    assert_eq!(log.frames, frames);
    for _ in 0..2 {
        let mut again = builtin_session(ColliderKind::Hashed);
        let done = replay::replay(&mut again, &log, |_, _| {});
        assert_eq!(done.frames, frames.len());
        assert_eq!(replay::mismatched_finals(&again, &log), Some(vec![]));
        assert_eq!(again.camera().rotation, live.camera().rotation);
        assert_eq!(again.camera().centre, live.camera().centre);
        assert_eq!(again.contacts(), live.contacts());
        assert_eq!(again.mode(), live.mode());
    }
    // Any collider gives the same answer: they return the same pairs.
    let mut grid = builtin_session(ColliderKind::Grid);
    replay::replay(&mut grid, &log, |_, _| {});
    assert_eq!(replay::mismatched_finals(&grid, &log), Some(vec![]));

    // From the command line, headless.
    let out = Process::new(env!("CARGO_BIN_EXE_bump"))
        .args(["--play", path.to_str().unwrap(), "--headless"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("final poses match the recording bit for bit"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!(
            "replayed {} of {} frames",
            frames.len(),
            frames.len()
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains("timing report (collider hashed, method swept)"),
        "{stdout}"
    );
    assert!(stdout.contains("collision calls:"), "{stdout}");
    assert!(
        stdout.contains("share of frame time spent colliding"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn damaged_or_truncated_logs_are_refused_naming_the_line() {
    let map = JoystickMap::default();
    let mut live = builtin_session(ColliderKind::Hashed);
    let (frames, _) = drive(&mut live, &map, false);
    let log = SessionLog {
        meta: vec![("collider".into(), "hashed".into())],
        frames,
        finals: Vec::new(),
    };
    let text = bump::session::log::to_text(&log);
    let dir = temp_dir("damaged");
    let cases = [
        (
            "flipped.bumplog",
            text.replacen("c=mode", "c=mods", 1),
            ":3: ",
        ),
        (
            "cut.bumplog",
            text.lines().take(40).map(|l| format!("{l}\n")).collect(),
            "truncated",
        ),
        (
            "midline.bumplog",
            text[..text.find(" c=collision").unwrap()].to_string(),
            ":3: ",
        ),
        ("garbage.bumplog", "\u{0}\u{1}binary".to_string(), ":1: "),
    ];
    for (name, body, want) in cases {
        let p = dir.join(name);
        std::fs::write(&p, body).unwrap();
        let out = Process::new(env!("CARGO_BIN_EXE_bump"))
            .args(["--play", p.to_str().unwrap(), "--headless"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(
            stderr.contains(name) && stderr.contains(want),
            "{name}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---- the shipped session: trimethoprim docked into DHFR ----

const SHIPPED: &str = "assets/sessions/tmp-dhfr.bumplog";
const COMPLEX: &str = "6xg5_tmp_prepared.pdb";

fn tmp_dhfr(dir: &Path) -> Vec<Molecule> {
    let loaded = model::load(&dir.join(COMPLEX), &LoadOptions::default()).unwrap();
    let (r, d) =
        model::split_complex(&loaded.structure, &LigandSpec::parse("TOP").unwrap()).unwrap();
    vec![r, d]
}

fn rmsd(m: &Molecule, a: &Pose, b: &Pose) -> f64 {
    let s: f64 = m
        .local
        .iter()
        .map(|p| {
            (a.transform_point(p.as_dvec3()) - b.transform_point(p.as_dvec3())).length_squared()
        })
        .sum();
    (s / m.len() as f64).sqrt()
}

#[test]
fn the_shipped_session_docks_trimethoprim_without_overlap_with_every_collider() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SHIPPED);
    let log = SessionLog::read(&path).unwrap();
    assert_eq!(
        log.meta_value("file"),
        Some(format!("../shared/pdb/{COMPLEX}").as_str())
    );
    let mut finals = Vec::new();
    for kind in ColliderKind::ALL {
        let molecules = tmp_dhfr(&dir);
        let counts = format!("{},{}", molecules[0].len(), molecules[1].len());
        assert_eq!(log.meta_value("atoms"), Some(counts.as_str()));
        let mut s = Session::new(
            molecules,
            Settings {
                collider: kind,
                ..Settings::default()
            },
        )
        .unwrap();
        let (mut beeps, mut calls, mut worst) = (0, 0, f32::INFINITY);
        let done = replay::replay(&mut s, &log, |_, out| {
            beeps += usize::from(out.new_contact);
            calls += out.collision_calls.len();
            for c in &out.contacts {
                worst = worst.min(c.gap());
            }
        });
        assert_eq!(done.frames, log.frames.len());
        assert!(worst > 0.0, "{kind:?}: an overlapping pose (gap {worst})");
        assert!(
            beeps > 0 && calls > 100,
            "{kind:?}: {beeps} beeps, {calls} calls"
        );
        let drug = &s.bodies()[1];
        let off = rmsd(&drug.molecule, &drug.pose, &drug.loaded);
        assert!(
            off < 1.0,
            "{kind:?}: ends {off:.3} Å RMSD from the crystal pose"
        );
        finals.push(drug.pose);
    }
    // Same pairs from every collider: the same session, bit for bit.
    assert!(finals.windows(2).all(|w| w[0] == w[1]));
}

/// Writes `assets/sessions/tmp-dhfr.bumplog`: a scripted docking of
/// trimethoprim into DHFR's pocket, steered like a user would with one
/// joystick box. Trimethoprim is buried (few straight paths in are free), so
/// the script picks a direction whose straight path back from 9 Å is free,
/// starts 16 Å out along it and turned 30° with collision on, turns the
/// view, switches to object mode, steers (translation and rotation intents
/// in screen axes) to square up 9 Å out, flies straight in, pushes on into
/// the pocket (it stops touching) and lets go. Run with
/// `cargo test --release --test replay -- --ignored write_the_shipped_session`.
#[test]
#[ignore = "regenerates the shipped session log"]
fn write_the_shipped_session() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let molecules = tmp_dhfr(&dir);
    let counts = format!("{},{}", molecules[0].len(), molecules[1].len());
    let settings = Settings::default();
    let probe = Session::new(molecules.clone(), settings).unwrap();
    let crystal = probe.bodies()[1].pose;
    let turned = DQuat::from_axis_angle(DVec3::new(0.3, 1.0, 0.2).normalize(), 30f64.to_radians());
    let mut found = None;
    for d in sphere_directions(300) {
        let Some(near) = [4.0, 3.0, 2.0, 1.0]
            .into_iter()
            .find(|&x| straight_path_free(&molecules, settings, d, x))
        else {
            continue;
        };
        // Far out and turned, then square and `near` Å out, then home.
        let way_out = [
            crystal,
            Pose::new(crystal.rotation, crystal.translation + d * near),
            Pose::new(turned * crystal.rotation, crystal.translation + d * 16.0),
        ];
        if let Some(frames) = fly_in(&molecules, settings, &way_out) {
            found = Some((d, frames));
            break;
        }
    }
    let (d, frames) = found.expect("no direction docks");
    eprintln!("approach along {d}: {} frames", frames.len());
    let meta = vec![
        (
            "bump-version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
        ("file".into(), format!("../shared/pdb/{COMPLEX}")),
        ("ligand".into(), "TOP".into()),
        ("radii".into(), "bondi".into()),
        ("collider".into(), "hashed".into()),
        ("method".into(), "swept".into()),
        ("two-boxes".into(), "false".into()),
        ("atoms".into(), counts),
        (
            "script".into(),
            "scripted docking along a found way out, reversed (tests/replay.rs)".into(),
        ),
    ];
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SHIPPED);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let mut s = Session::new(molecules, settings).unwrap();
    let log = SessionLog {
        meta: meta.clone(),
        frames: frames.clone(),
        finals: Vec::new(),
    };
    replay::replay(&mut s, &log, |_, _| {});
    let finals: Vec<Pose> = s.bodies().iter().map(|b| b.pose).collect();
    let mut w = LogWriter::create(&path, &meta).unwrap();
    for f in &frames {
        w.frame(f.dt, &f.input).unwrap();
    }
    w.finish(&finals).unwrap();
}

/// Whether the drug, moved `dist` Å out along `d`, can come straight back.
fn straight_path_free(molecules: &[Molecule], settings: Settings, d: DVec3, dist: f64) -> bool {
    let mut s = Session::new(molecules.to_vec(), settings).unwrap();
    let out = s.step(
        &FrameInput {
            commands: vec![
                Command::MoveBy {
                    translate: d * dist,
                    axis: DVec3::Z,
                    degrees: 0.0,
                },
                Command::ToggleCollision,
            ],
            ..FrameInput::default()
        },
        DT,
    );
    if !out.contacts.is_empty() {
        return false;
    }
    let back = s.step(
        &FrameInput {
            commands: vec![Command::MoveBy {
                translate: -d * dist,
                axis: DVec3::Z,
                degrees: 0.0,
            }],
            ..FrameInput::default()
        },
        DT,
    );
    back.t == 1.0
}

/// Steers the drug from the end of `way_out` back to its start (the crystal
/// pose) through the waypoints in reverse; `None` when it gets stuck.
fn fly_in(molecules: &[Molecule], settings: Settings, way_out: &[Pose]) -> Option<Vec<LogFrame>> {
    let mut s = Session::new(molecules.to_vec(), settings).ok()?;
    let crystal = way_out[0];
    let mut frames = Vec::new();
    let step = |s: &mut Session, input: FrameInput, frames: &mut Vec<LogFrame>| {
        let out = s.step(&input, DT);
        frames.push(LogFrame { dt: DT, input });
        out
    };
    // Out there with collision off (as a user would start), then collision on.
    let start = way_out[way_out.len() - 1];
    let (axis, angle) = (start.rotation * crystal.rotation.inverse()).to_axis_angle();
    let out = step(
        &mut s,
        FrameInput {
            commands: vec![Command::MoveBy {
                translate: start.translation - crystal.translation,
                axis,
                degrees: angle.to_degrees(),
            }],
            ..FrameInput::default()
        },
        &mut frames,
    );
    assert!(
        out.contacts.is_empty(),
        "collision {} contacts {}",
        s.settings().collision,
        out.contacts.len()
    );
    // Turn the view by 25° about the vertical for a better look (view mode).
    for _ in 0..60 {
        step(
            &mut s,
            FrameInput {
                velocity: Motion6 {
                    translate: DVec3::ZERO,
                    rotate: DVec3::new(0.0, 25f64.to_radians(), 0.0),
                },
                ..FrameInput::default()
            },
            &mut frames,
        );
    }
    step(
        &mut s,
        FrameInput {
            commands: vec![Command::ToggleMode],
            ..FrameInput::default()
        },
        &mut frames,
    );
    // Fly in: proportional steering to each waypoint, at most 5 Å/s and
    // 60°/s, in screen axes; the next waypoint when close.
    let m = s.bodies()[1].molecule.clone();
    let mut k = way_out.len() - 1;
    let mut stalled = 0;
    let mut commands = Vec::new();
    while frames.len() < 20_000 {
        let pose = s.bodies()[1].pose;
        while k > 0 && rmsd(&m, &pose, &way_out[k]) < 0.02 {
            k -= 1;
            if k == 0 {
                // In front of the pocket: collision on (the thesis's way).
                commands.push(Command::ToggleCollision);
            }
        }
        if k == 0 && rmsd(&m, &pose, &crystal) < 0.02 {
            break;
        }
        let goal = way_out[k];
        let e = goal.translation - pose.translation;
        let r = (goal.rotation * pose.rotation.inverse()).normalize();
        let r = if r.w < 0.0 { -r } else { r };
        let v = (e * 8.0).clamp_length_max(5.0);
        let w = (r.to_scaled_axis() * 8.0).clamp_length_max(60f64.to_radians());
        let cam = s.camera().rotation;
        let out = step(
            &mut s,
            FrameInput {
                velocity: Motion6 {
                    translate: cam * v,
                    rotate: cam * w,
                },
                commands: std::mem::take(&mut commands),
                ..FrameInput::default()
            },
            &mut frames,
        );
        if !s.settings().collision && k == 0 {
            return None;
        }
        stalled = if out.t < 1e-3 { stalled + 1 } else { 0 };
        if stalled > 120 {
            eprintln!(
                "stuck at waypoint {k}: collision {} t {} rmsd {}",
                s.settings().collision,
                out.t,
                rmsd(&m, &s.bodies()[1].pose, &way_out[k])
            );
            return None;
        }
    }
    let left = rmsd(&m, &s.bodies()[1].pose, &crystal);
    if left > 0.3 {
        eprintln!("ended {left:.2} Å RMSD from the crystal pose");
        return None;
    }
    // Feel the pocket: turn about each screen axis into the walls (it
    // stops touching, beeping), steer back, then push on into the pocket
    // for half a second, and let go.
    let home = |s: &Session| {
        let pose = s.bodies()[1].pose;
        let e = crystal.translation - pose.translation;
        let r = (crystal.rotation * pose.rotation.inverse()).normalize();
        let r = if r.w < 0.0 { -r } else { r };
        let cam = s.camera().rotation;
        Motion6 {
            translate: cam * (e * 8.0).clamp_length_max(5.0),
            rotate: cam * (r.to_scaled_axis() * 8.0).clamp_length_max(60f64.to_radians()),
        }
    };
    for turn in [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z] {
        let twist = Motion6 {
            translate: DVec3::ZERO,
            rotate: turn * 30f64.to_radians(),
        };
        hold(&mut s, &mut frames, 20, |_| twist);
        hold(&mut s, &mut frames, 40, home);
    }
    let deeper = (crystal.translation - way_out[1].translation).normalize_or_zero();
    let cam = s.camera().rotation;
    for _ in 0..30 {
        step(
            &mut s,
            FrameInput {
                velocity: Motion6 {
                    translate: cam * (deeper * 2.0),
                    rotate: DVec3::ZERO,
                },
                ..FrameInput::default()
            },
            &mut frames,
        );
    }
    for _ in 0..30 {
        step(&mut s, FrameInput::default(), &mut frames);
    }
    Some(frames)
}

#[test]
fn the_same_stick_moves_along_screen_axes_or_the_molecules_own() {
    let map = JoystickMap::default();
    let mut c = Controllers::default();
    c.apply(&map, pad(1, "Pad"));
    c.apply(&map, axis(1, "LeftStickX", 1.0));
    let push = |s: &mut Session| {
        let before = s.bodies()[1].pose.translation;
        let mut input = FrameInput::default();
        c.intents(&map, false).add_to(&mut input);
        s.step(&input, 0.1);
        (s.bodies()[1].pose.translation - before).normalize()
    };
    let mut s = builtin_session(ColliderKind::Hashed);
    // Object mode; the E turned 90° about the world's y axis.
    s.step(
        &FrameInput {
            commands: vec![
                Command::ToggleMode,
                Command::MoveBy {
                    translate: DVec3::ZERO,
                    axis: DVec3::Y,
                    degrees: 90.0,
                },
            ],
            ..FrameInput::default()
        },
        DT,
    );
    let screen_x = s.camera().rotation.conjugate() * DVec3::X;
    assert!(push(&mut s).dot(screen_x) > 1.0 - 1e-9);
    s.step(
        &FrameInput {
            commands: vec![Command::ToggleSpace],
            ..FrameInput::default()
        },
        DT,
    );
    let own_x = s.bodies()[1].pose.rotation * DVec3::X;
    assert!(push(&mut s).dot(own_x) > 1.0 - 1e-9);
    assert!(
        own_x.dot(screen_x).abs() < 0.99,
        "the test needs distinct axes"
    );
}

#[test]
fn joystick_values_at_and_beyond_their_limits_never_break_the_session() {
    let map = JoystickMap::default();
    let mut c = Controllers::default();
    let mut s = builtin_session(ColliderKind::Hashed);
    s.step(&FrameInput::docking(), DT);
    c.apply(&map, pad(1, "Pad"));
    let mut rng = common::Rng(0xdead_beef);
    let sources = [
        "LeftStickX",
        "LeftStickY",
        "RightStickX",
        "RightStickY",
        "LeftTrigger2",
        "RightTrigger2",
        "LeftTrigger",
        "RightTrigger",
    ];
    let specials = [
        1.0,
        -1.0,
        1.0005,
        -1.0005,
        0.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
        -2.0,
        f64::MIN_POSITIVE,
    ];
    for frame in 0..5000 {
        for src in sources {
            let v = if rng.f64() < 0.3 {
                specials[(rng.next_u64() % specials.len() as u64) as usize]
            } else {
                rng.range(-1.0, 1.0)
            };
            c.apply(&map, axis(1, src, v));
        }
        let intents = c.intents(&map, false);
        assert!(intents.velocity.is_finite());
        // Never faster than full deflection on every axis at once.
        assert!(intents.velocity.translate.length() <= map.translate_speed * 3f64.sqrt() + 1e-9);
        let mut input = FrameInput::default();
        intents.add_to(&mut input);
        // Extreme frame times too: zero, tiny, long, negative.
        let dt = [DT, 0.0, 1e-9, 0.5, -1.0][frame % 5];
        let out = s.step(&input, dt);
        assert!(
            out.contacts.iter().all(|k| k.gap() > 0.0),
            "overlap at frame {frame}"
        );
        let p = s.bodies()[1].pose;
        assert!(p.is_finite(), "non-finite pose at frame {frame}");
        assert!((p.rotation.length() - 1.0).abs() < 1e-12);
    }
    assert!(c.ignored() > 0);
}

/// Steps `n` frames of 1/60 s at the velocity `v` asks for in each, recording them.
fn hold(s: &mut Session, frames: &mut Vec<LogFrame>, n: usize, v: impl Fn(&Session) -> Motion6) {
    for _ in 0..n {
        let input = FrameInput {
            velocity: v(s),
            ..FrameInput::default()
        };
        s.step(&input, DT);
        frames.push(LogFrame { dt: DT, input });
    }
}
