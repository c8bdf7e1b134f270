//! Real-window helpers: an Xvfb server, xdotool, processes killed on drop.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

/// Whether a command is on the PATH.
pub fn have(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// A child process killed when dropped.
pub struct Kill(pub Child);

impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Runs xdotool on `display`, returning its output.
pub fn xdotool(display: &str, args: &[&str]) -> String {
    let out = Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("xdotool");
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Presses `key` `n` times.
pub fn taps(display: &str, key: &str, n: usize) {
    for _ in 0..n {
        xdotool(display, &["key", "--delay", "20", key]);
        sleep(Duration::from_millis(30));
    }
}

/// A running Xvfb and a runtime folder for the program.
pub struct Screen {
    /// `:N`.
    pub display: String,
    /// XDG_RUNTIME_DIR for the program; logs and screenshots go here.
    pub runtime: PathBuf,
    _xvfb: Kill,
}

impl Drop for Screen {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.runtime);
    }
}

/// Starts Xvfb on a display derived from `offset` and the process id, or
/// `None` (with a message; a failure under CI) when a tool is missing.
pub fn screen(offset: u32) -> Option<Screen> {
    for tool in ["Xvfb", "xdotool", "import"] {
        if !have(tool) {
            assert!(
                std::env::var("CI").as_deref() != Ok("true"),
                "CI must have {tool} (apt-get install xvfb xdotool imagemagick)"
            );
            eprintln!("SKIP: {tool} not installed");
            return None;
        }
    }
    // A display taken by another server makes Xvfb exit: try the next.
    let first = offset + std::process::id() % 200;
    let (display, xvfb) = (first..first + 20)
        .find_map(|n| {
            let display = format!(":{n}");
            let mut xvfb = Kill(
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
            accepts_clients(&display, &mut xvfb).then_some((display, xvfb))
        })
        .expect("no free X display for Xvfb");
    let runtime = std::env::temp_dir().join(format!("bump-xdg-{offset}-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    Some(Screen {
        display,
        runtime,
        _xvfb: xvfb,
    })
}

/// Waits until the server on `display` takes connections (a fixed pause
/// was too short on a loaded machine: the program then found no display and
/// the test waited for a window that could not come); false when Xvfb
/// exits first or 30 s pass.
fn accepts_clients(display: &str, xvfb: &mut Kill) -> bool {
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(30) {
        if xvfb.0.try_wait().ok().flatten().is_some() {
            return false;
        }
        let ok = Command::new("xdotool")
            .arg("getdisplaygeometry")
            .env("DISPLAY", display)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            return true;
        }
        sleep(Duration::from_millis(100));
    }
    false
}

impl Screen {
    /// Starts `bump` with `args` on this screen; stderr goes to `log`.
    pub fn launch(&self, args: &[&str], log: &std::path::Path, stdout: Stdio) -> Kill {
        Kill(
            Command::new(env!("CARGO_BIN_EXE_bump"))
                .args(args)
                .env("DISPLAY", &self.display)
                .env("XDG_RUNTIME_DIR", &self.runtime)
                .env_remove("WAYLAND_DISPLAY")
                .stdout(stdout)
                .stderr(std::fs::File::create(log).expect("log"))
                .spawn()
                .expect("bump"),
        )
    }

    /// Waits for `app`'s window (titled `bump…`), focuses it and returns
    /// its id. Fails at once, with the program's log (`log`), if the
    /// program exits first.
    pub fn window(&self, app: &mut Kill, log: &std::path::Path) -> String {
        let t0 = Instant::now();
        let text = || std::fs::read_to_string(log).unwrap_or_default();
        let wid = loop {
            let w = xdotool(&self.display, &["search", "--name", "^bump"]);
            if let Some(id) = w.lines().next().filter(|s| !s.is_empty()) {
                break id.to_string();
            }
            if let Some(status) = app.0.try_wait().expect("wait") {
                panic!(
                    "bump exited ({status}) before its window appeared:\n{}",
                    text()
                );
            }
            assert!(
                t0.elapsed() < Duration::from_secs(120),
                "no window appeared in 120 s; bump's log so far:\n{}",
                text()
            );
            sleep(Duration::from_millis(200));
        };
        sleep(Duration::from_secs(2)); // first frames (shader compilation on the CPU)
        // There is no window manager: focus the window, then type real key events.
        xdotool(&self.display, &["windowfocus", "--sync", &wid]);
        sleep(Duration::from_millis(700)); // let the focus change reach the app
        wid
    }
}

/// Waits up to `secs` for `child` to exit; its exit status.
pub fn wait_exit(child: &mut Kill, secs: u64) -> Option<std::process::ExitStatus> {
    let t0 = Instant::now();
    loop {
        if let Some(status) = child.0.try_wait().expect("wait") {
            return Some(status);
        }
        if t0.elapsed() > Duration::from_secs(secs) {
            return None;
        }
        sleep(Duration::from_millis(100));
    }
}

/// Waits up to `secs` for `child` (started with piped stdout) to exit
/// successfully; its stdout, and its stderr log for messages.
pub fn finish(child: &mut Kill, log: &std::path::Path, secs: u64, what: &str) -> (String, String) {
    let status = wait_exit(child, secs).unwrap_or_else(|| panic!("{what}: did not exit"));
    let text = std::fs::read_to_string(log).unwrap_or_default();
    assert!(status.success(), "{what} failed: {status}\n{text}");
    let mut out = String::new();
    if let Some(mut so) = child.0.stdout.take() {
        use std::io::Read;
        let _ = so.read_to_string(&mut out);
    }
    (out, text)
}
