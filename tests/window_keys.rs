//! Keyboard docking in a real window under Xvfb (issue 42): the window
//! idles (its CPU time over 5 s with nothing to do is measured from
//! /proc and printed), each 100 ms tap of a motion key moves the drug
//! exactly one documented step (checked on the recorded session's final
//! pose), F1 opens the help and Escape closes it (screenshots), Escape
//! with nothing open and a moved drug asks before quitting, Escape cancels
//! that, and Q then D quits without saving.
//!
//! Needs `Xvfb`, `xdotool` and ImageMagick's `import` (CI installs them);
//! elsewhere a missing tool skips the test with a message.

mod common;

use std::thread::sleep;
use std::time::Duration;

use common::x11::{
    centre_difference, cpu_seconds, eventually, finish, screen, shot, tap, taps, wait_exit,
};

#[test]
fn keys_step_exactly_escape_closes_dialogs_quitting_asks_and_the_window_idles() {
    let Some(mut x) = screen("window-keys") else {
        return;
    };
    let d = x.display.clone();
    let rec = x.runtime.join("keys.bumplog");
    let rec_s = rec.to_str().expect("path").to_string();
    let log = x.runtime.join("keys.log");
    let mut app = x.open(&["--record", &rec_s], &log, true);
    let pid = app.0.id();
    let text = || std::fs::read_to_string(&log).unwrap_or_default();

    // Idle: let the start-up messages expire, then measure 5 s.
    sleep(Duration::from_secs(7));
    let c0 = cpu_seconds(pid);
    sleep(Duration::from_secs(5));
    let idle = (cpu_seconds(pid) - c0) / 5.0 * 100.0;
    eprintln!("idle CPU of the window over 5 s: {idle:.1} % of a core");
    assert!(
        idle < 5.0,
        "the idle window used {idle:.1} % of a core\n{}",
        text()
    );

    // Object mode, then taps: 5 × → (normal, 0.2 Å) and 3 × Shift+Page Up
    // (coarse, 1 Å), each held 100 ms.
    taps(&d, "space", 1);
    sleep(Duration::from_millis(300));
    for _ in 0..5 {
        tap(&d, "Right", false);
    }
    for _ in 0..3 {
        tap(&d, "Prior", true);
    }

    // F1 opens the help over the scene; Escape closes it.
    let dir = x.runtime.clone();
    let before = shot(&d, &dir.join("a.png"));
    taps(&d, "F1", 1);
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("b.png")), 24) > 5000),
        "F1 showed no help\n{}",
        text()
    );
    taps(&d, "Escape", 1);
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("c.png")), 24) < 500),
        "Escape did not close the help\n{}",
        text()
    );
    assert!(
        app.0.try_wait().expect("wait").is_none(),
        "Escape quit with the help open"
    );

    // Escape with nothing open and a moved drug asks; Escape cancels.
    taps(&d, "Escape", 1);
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("d.png")), 24) > 2000),
        "no confirmation before quitting with unsaved moves\n{}",
        text()
    );
    assert!(app.0.try_wait().expect("wait").is_none(), "quit unasked");
    taps(&d, "Escape", 1);
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("e.png")), 24) < 500),
        "Escape did not cancel the confirmation\n{}",
        text()
    );
    // Q asks again; D quits without saving.
    taps(&d, "q", 1);
    sleep(Duration::from_secs(1));
    assert!(app.0.try_wait().expect("wait").is_none(), "Q quit unasked");
    taps(&d, "d", 1);
    assert!(wait_exit(&mut app, 30).is_some(), "D did not quit");
    let (_, said) = finish(&mut app, &log, 5, "the window (Q, D)");
    assert!(!said.contains("saved drug"), "{said}");

    // Exactly one step per tap: the recorded final pose of the drug is
    // (5 × 0.2 Å along screen x) + (3 × 1 Å along screen z) from its start.
    let body = std::fs::read_to_string(&rec).expect("the log");
    assert_eq!(body.matches(" k=down:tx+:normal:").count(), 5, "{body}");
    assert_eq!(body.matches(" k=down:tz+:coarse:").count(), 3, "{body}");
    let session = bump::session::SessionLog::read(&rec).expect("read log");
    let (_, e) = bump::model::builtin::scene(bump::model::RadiiSet::Bondi);
    let moved = session.finals[1].translation - e.centre;
    let want = (1.0f64 + 9.0).sqrt();
    assert!(
        (moved.length() - want).abs() < 1e-9,
        "the drug moved {} Å, not 5 normal and 3 coarse steps ({want} Å)",
        moved.length()
    );
}
