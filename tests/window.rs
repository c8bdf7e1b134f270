//! A real window under Xvfb: start `bump` on a file that cannot be read (it
//! is reported and the built-in scene opens instead), type keys with xdotool
//! (object mode, collision on), push the E into the rings with typed moves,
//! take a screenshot, and check it shows the HUD and the contact highlights;
//! then quit with `q`.
//!
//! Needs `Xvfb`, `xdotool` and ImageMagick's `import` (CI installs them);
//! elsewhere a missing tool skips the test with a message.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

fn have(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

struct Kill(Child);

impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("xdotool");
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Presses `key` `n` times.
fn taps(display: &str, key: &str, n: usize) {
    for _ in 0..n {
        xdotool(display, &["key", "--delay", "20", key]);
        sleep(Duration::from_millis(30));
    }
}

#[test]
fn docking_in_a_real_window_shows_the_hud_and_highlights() {
    for tool in ["Xvfb", "xdotool", "import"] {
        if !have(tool) {
            assert!(
                std::env::var("CI").as_deref() != Ok("true"),
                "CI must have {tool} (apt-get install xvfb xdotool imagemagick)"
            );
            eprintln!("SKIP: {tool} not installed");
            return;
        }
    }
    let display = format!(":{}", 50 + std::process::id() % 200);
    let _xvfb = Kill(
        Command::new("Xvfb")
            .args([
                display.as_str(),
                "-screen",
                "0",
                "1280x800x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb"),
    );
    sleep(Duration::from_millis(800));
    let runtime = std::env::temp_dir().join(format!("bump-xdg-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    let log = runtime.join("bump.log");
    let mut app = Kill(
        Command::new(env!("CARGO_BIN_EXE_bump"))
            .arg("/nonexistent/receptor.pdb")
            .env("DISPLAY", &display)
            .env("XDG_RUNTIME_DIR", &runtime)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).expect("log"))
            .spawn()
            .expect("bump"),
    );
    // Wait for the window.
    let t0 = Instant::now();
    let wid = loop {
        let w = xdotool(&display, &["search", "--name", "^bump"]);
        if let Some(id) = w.lines().next().filter(|s| !s.is_empty()) {
            break id.to_string();
        }
        assert!(t0.elapsed() < Duration::from_secs(60), "no window appeared");
        sleep(Duration::from_millis(200));
    };
    sleep(Duration::from_secs(2)); // first frames (shader compilation on the CPU)
    // There is no window manager: focus the window, then type real key events.
    xdotool(&display, &["windowfocus", "--sync", &wid]);
    sleep(Duration::from_millis(700)); // let the focus change reach the app
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
    sleep(Duration::from_secs(1));
    let shot: PathBuf = runtime.join("shot.png");
    let ok = Command::new("import")
        .args(["-window", "root", shot.to_str().expect("path")])
        .env("DISPLAY", &display)
        .status()
        .expect("import");
    assert!(ok.success(), "screenshot failed");
    let img = image::open(&shot).expect("read screenshot").to_rgba8();
    // Kept for inspection when an assertion below fails.
    let _ = std::fs::copy(&shot, std::env::temp_dir().join("bump-window-test.png"));
    let (w, h) = img.dimensions();
    let px = |x: u32, y: u32| img.get_pixel(x, y).0;
    // The HUD: egui's panel fill along the top and bottom bars.
    let panel = |y0: u32| {
        (0..w)
            .flat_map(|x| (y0..y0 + 16).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let p = px(x, y);
                p[0] == p[1] && p[1] == p[2] && p[0] < 40
            })
            .count()
    };
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(panel(4) > (w * 16) as usize / 2, "no HUD top bar\n{text}");
    assert!(
        panel(h - 20) > (w * 16) as usize / 2,
        "no HUD bottom bar\n{text}"
    );
    // The contact highlights (magenta) where the E touches the rings.
    let magenta = (0..w)
        .flat_map(|x| (30..h - 30).map(move |y| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b, _] = px(x, y).map(i32::from);
            r > 140 && b > 120 && g < r - 60
        })
        .count();
    assert!(
        magenta > 200,
        "no highlighted contacts ({magenta} px)\n{text}"
    );
    assert!(text.contains("contact: "), "no contact reported\n{text}");
    assert!(
        text.contains("/nonexistent/receptor.pdb"),
        "bad file not reported\n{text}"
    );
    assert!(text.contains("built-in scene"), "no fallback scene\n{text}");
    // q quits cleanly.
    taps(&display, "q", 1);
    let t1 = Instant::now();
    loop {
        if let Some(status) = app.0.try_wait().expect("wait") {
            assert!(status.success(), "bump exited with {status}\n{text}");
            break;
        }
        assert!(t1.elapsed() < Duration::from_secs(20), "q did not quit");
        sleep(Duration::from_millis(100));
    }
    let _ = std::fs::remove_dir_all(&runtime);
}
