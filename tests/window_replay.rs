//! Record in a real window, replay with and without one: under Xvfb, start
//! `bump --record` on the built-in scene, dock with real key and mouse events
//! (object mode, collision on, held keys, a mouse drag of the view, a wheel
//! zoom, a typed move), quit; then `--play` the log headless and in a window
//! (it exits by itself at the end). Both replays must end bit for bit where
//! the recording did, and print the timing report.

mod common;

use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::Duration;

use common::x11::{finish, screen, taps, xdotool};

#[test]
fn a_window_recording_replays_bit_for_bit_headless_and_in_a_window() {
    let Some(mut x) = screen("window-replay") else {
        return;
    };
    let d = x.display.clone();
    let rec = x.runtime.join("session.bumplog");
    let rec_s = rec.to_str().expect("path").to_string();
    let log = x.runtime.join("record.log");
    let mut app = x.open(&["--record", &rec_s], &log, true);
    taps(&d, "space", 1); // object mode
    sleep(Duration::from_millis(200));
    taps(&d, "c", 1); // collision on
    sleep(Duration::from_millis(200));
    // A held key: continuous motion over several frames.
    xdotool(&d, &["keydown", "Up"]);
    sleep(Duration::from_millis(400));
    xdotool(&d, &["keyup", "Up"]);
    // A mouse drag turns the view; the wheel zooms.
    xdotool(&d, &["mousemove", "640", "400", "mousedown", "1"]);
    for k in 1..6 {
        xdotool(&d, &["mousemove", &(640 + 20 * k).to_string(), "400"]);
        sleep(Duration::from_millis(40));
    }
    xdotool(&d, &["mouseup", "1"]);
    xdotool(&d, &["click", "4"]);
    sleep(Duration::from_millis(200));
    // A typed exact move through the rings (collisions stop it).
    xdotool(&d, &["mousemove", "280", "788", "click", "1"]);
    sleep(Duration::from_millis(300));
    xdotool(&d, &["type", "--delay", "30", "0 5 25"]);
    xdotool(&d, &["key", "Return"]);
    sleep(Duration::from_millis(800));
    taps(&d, "Escape", 1); // leave the text field
    sleep(Duration::from_millis(200));
    taps(&d, "q", 1); // the E moved: bump asks before quitting
    sleep(Duration::from_millis(500));
    taps(&d, "d", 1); // quit without saving
    let (out, text) = finish(&mut app, &log, 30, "the recording run (q, d)");
    assert!(
        out.contains("timing report"),
        "no report on exit\n{out}\n{text}"
    );
    let body = std::fs::read_to_string(&rec).expect("the log was not written");
    assert!(
        body.contains("c=mode") && body.contains("c=collision"),
        "{body}"
    );
    assert!(
        body.contains(" wn=") && body.contains(" z="),
        "mouse not recorded"
    );
    assert!(body.contains("c=move:"), "typed move not recorded");
    assert!(!x.runtime.join("session.bumplog.part").exists());

    // Headless replay: bit for bit.
    let out = Command::new(env!("CARGO_BIN_EXE_bump"))
        .args(["--play", &rec_s, "--headless"])
        .output()
        .expect("bump");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("final poses match the recording bit for bit"),
        "{stdout}"
    );
    assert!(stdout.contains("contact events (beeps): "), "{stdout}");

    // Replay in a window: runs by itself and exits at the end.
    let log2 = x.runtime.join("play.log");
    let mut player = x.launch(&["--play", &rec_s], &log2, Stdio::piped());
    let (out, text) = finish(&mut player, &log2, 90, "the window replay (ends by itself)");
    assert!(
        out.contains("final poses match the recording bit for bit"),
        "{out}\n{text}"
    );
    assert!(out.contains("collision calls:"), "{out}");
}
