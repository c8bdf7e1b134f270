//! A real window under Xvfb: start `bump` on a file that cannot be read (it
//! is reported and the built-in scene opens instead), type keys with xdotool
//! (object mode, collision on), push the E into the rings with typed moves,
//! and check screenshots until they show the HUD and the contact highlights;
//! then quit with `q` (which asks, as the E moved) and `d` (without saving).
//!
//! Needs `Xvfb`, `xdotool` and ImageMagick's `import` (CI installs them);
//! elsewhere a missing tool skips the test with a message.

mod common;

use std::path::PathBuf;
use std::thread::sleep;
use std::time::{Duration, Instant};

use common::x11::{screen, taps, xdotool};

#[test]
fn docking_in_a_real_window_shows_the_hud_and_highlights() {
    let Some(mut x) = screen("window") else {
        return;
    };
    let display = x.display.clone();
    let runtime = x.runtime.clone();
    let log = runtime.join("bump.log");
    let mut app = x.open(&["/nonexistent/receptor.pdb"], &log, false);
    taps(&display, "space", 1); // object mode
    sleep(Duration::from_millis(300));
    taps(&display, "c", 1); // collision on
    sleep(Duration::from_millis(300));
    taps(&display, "Left", 3); // keyboard steps (sideways, harmless)
    // Exact moves typed into the HUD's move field (bottom bar): 5 Å up, so
    // the prongs meet the rings' tops, then 25 Å towards the viewer, through
    // the rings were it not for collisions.
    for typed in ["0 5 0", "0 0 25"] {
        xdotool(&display, &["mousemove", "280", "788", "click", "1"]);
        sleep(Duration::from_millis(300));
        xdotool(&display, &["type", "--delay", "30", typed]);
        xdotool(&display, &["key", "Return"]);
        sleep(Duration::from_millis(500));
    }
    // The moves' frames render on the CPU: on a loaded machine they can
    // land after any fixed pause, so look again until the picture shows
    // them (or 30 s pass) rather than judge the first screenshot.
    let shot: PathBuf = runtime.join("shot.png");
    let t0 = Instant::now();
    let seen = loop {
        sleep(Duration::from_secs(1));
        let seen = look(&display, &shot);
        if seen.hud_top && seen.hud_bottom && seen.magenta > 200 {
            break seen;
        }
        if t0.elapsed() > Duration::from_secs(30) {
            break seen;
        }
    };
    // Kept for inspection when an assertion below fails.
    let _ = std::fs::copy(&shot, std::env::temp_dir().join("bump-window-test.png"));
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(seen.hud_top, "no HUD top bar\n{text}");
    assert!(seen.hud_bottom, "no HUD bottom bar\n{text}");
    assert!(
        seen.magenta > 200,
        "no highlighted contacts ({} px)\n{text}",
        seen.magenta
    );
    assert!(text.contains("contact: "), "no contact reported\n{text}");
    assert!(
        text.contains("/nonexistent/receptor.pdb"),
        "bad file not reported\n{text}"
    );
    assert!(text.contains("built-in scene"), "no fallback scene\n{text}");
    // q asks (the E moved since it was loaded); d quits without saving.
    taps(&display, "q", 1);
    sleep(Duration::from_millis(500));
    assert!(app.0.try_wait().expect("wait").is_none(), "q quit unasked");
    taps(&display, "d", 1);
    let t1 = Instant::now();
    loop {
        if let Some(status) = app.0.try_wait().expect("wait") {
            assert!(status.success(), "bump exited with {status}\n{text}");
            break;
        }
        assert!(t1.elapsed() < Duration::from_secs(20), "q, d did not quit");
        sleep(Duration::from_millis(100));
    }
}

/// What a screenshot shows.
struct Seen {
    /// egui's panel fill along the top bar.
    hud_top: bool,
    /// egui's panel fill along the bottom bar.
    hud_bottom: bool,
    /// Pixels of the contact highlight (magenta) in the view.
    magenta: usize,
}

/// Takes a screenshot of `display` into `shot` and reads it.
fn look(display: &str, shot: &std::path::Path) -> Seen {
    let img = common::x11::shot(display, shot);
    let (w, h) = img.dimensions();
    let px = |x: u32, y: u32| img.get_pixel(x, y).0;
    let panel = |y0: u32| {
        let dark = (0..w)
            .flat_map(|x| (y0..y0 + 16).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let p = px(x, y);
                p[0] == p[1] && p[1] == p[2] && p[0] < 40
            })
            .count();
        dark > (w * 16) as usize / 2
    };
    let magenta = (0..w)
        .flat_map(|x| (30..h - 30).map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b] = px(x, y).map(i32::from);
            r > 140 && b > 120 && g < r - 60
        })
        .count();
    Seen {
        hud_top: panel(4),
        hud_bottom: panel(h - 20),
        magenta,
    }
}
