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
    xvfb: Kill,
}

impl Drop for Screen {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.runtime);
    }
}

/// Starts Xvfb on a display of its own choosing, with a runtime folder
/// named after `tag`, or `None` (with a message; a failure under CI) when a
/// tool is missing.
///
/// Xvfb picks the display itself (`-displayfd`) and names it only once it
/// listens on all its sockets. Choosing a number here and polling it could
/// let a server that was not ours answer the readiness check (one holding
/// that display's abstract socket, seen by every process in the same network
/// namespace whatever its /tmp) and then leave the program with nothing to
/// connect to: once, in CI, the check passed and the program found no
/// server. `-noreset` keeps the server from regenerating when the check's
/// connection closes, just before the program connects.
pub fn screen(tag: &str) -> Option<Screen> {
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
    let runtime = std::env::temp_dir().join(format!("bump-xdg-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    let xlog = runtime.join("xvfb.log");
    let mut xvfb = Kill(
        Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x800x24",
                "-nolisten",
                "tcp",
                "-noreset",
            ])
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&xlog).expect("Xvfb log"))
            .spawn()
            .expect("Xvfb"),
    );
    let number = read_display_number(&mut xvfb);
    let log = || std::fs::read_to_string(&xlog).unwrap_or_default();
    let Some(number) = number else {
        panic!("Xvfb named no display in 30 s; its log:\n{}", log());
    };
    let display = format!(":{number}");
    assert!(
        accepts_clients(&display, &mut xvfb),
        "Xvfb on {display} takes no connections; its log:\n{}",
        log()
    );
    Some(Screen {
        display,
        runtime,
        xvfb,
    })
}

/// The display number Xvfb writes to its stdout once it is ready, or
/// `None` when it exits first or 30 s pass.
fn read_display_number(xvfb: &mut Kill) -> Option<u32> {
    use std::io::BufRead;
    let stdout = xvfb.0.stdout.take()?;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = std::io::BufReader::new(stdout).read_line(&mut line);
        let _ = tx.send(line);
    });
    let line = rx.recv_timeout(Duration::from_secs(30)).ok()?;
    line.trim().parse().ok()
}

/// Whether the server on `display` takes connections and is still ours
/// (Xvfb has not exited); polls for up to 30 s.
fn accepts_clients(display: &str, xvfb: &mut Kill) -> bool {
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(30) {
        if xvfb.0.try_wait().ok().flatten().is_some() {
            return false;
        }
        if answers(display) {
            return xvfb.0.try_wait().ok().flatten().is_none();
        }
        sleep(Duration::from_millis(100));
    }
    false
}

/// Whether an X server answers on `display`.
fn answers(display: &str) -> bool {
    Command::new("xdotool")
        .arg("getdisplaygeometry")
        .env("DISPLAY", display)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
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

    /// Starts `bump` with `args` (stderr to `log`, stdout piped when
    /// `piped`), waits for its window (titled `bump…`), focuses it and
    /// returns the program.
    ///
    /// Fails at once, with the program's log, if the program exits first,
    /// except when it could not connect to a server that is still up and
    /// still takes connections: that is the machine, not the program, so it
    /// is said on stderr and the program is started again (twice at most).
    pub fn open(&mut self, args: &[&str], log: &std::path::Path, piped: bool) -> Kill {
        let stdout = || if piped { Stdio::piped() } else { Stdio::null() };
        let mut tries = 1;
        let mut app = self.launch(args, log, stdout());
        let t0 = Instant::now();
        let text = || std::fs::read_to_string(log).unwrap_or_default();
        let window = loop {
            let w = xdotool(&self.display, &["search", "--name", "^bump"]);
            if let Some(id) = w.lines().next().filter(|s| !s.is_empty()) {
                break id.to_string();
            }
            if let Some(status) = app.0.try_wait().expect("wait") {
                let said = text();
                let server = self.server_state();
                let unreachable = said.contains("cannot open a window");
                if unreachable && server.is_none() && tries < 3 {
                    eprintln!(
                        "bump could not reach {} (try {tries}) although the \
                         server is up; starting it again. Its log:\n{said}",
                        self.display
                    );
                    tries += 1;
                    app = self.launch(args, log, stdout());
                    continue;
                }
                panic!(
                    "bump exited ({status}) before its window appeared{}:\n{said}",
                    server.map_or(String::new(), |s| format!(" ({s})"))
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
        xdotool(&self.display, &["windowfocus", "--sync", &window]);
        sleep(Duration::from_millis(700)); // let the focus change reach the app
        app
    }

    /// `None` when Xvfb runs and takes connections; otherwise what is
    /// wrong, with Xvfb's log.
    fn server_state(&mut self) -> Option<String> {
        let xlog = std::fs::read_to_string(self.runtime.join("xvfb.log")).unwrap_or_default();
        if let Ok(Some(status)) = self.xvfb.0.try_wait() {
            return Some(format!("Xvfb exited ({status}); its log:\n{xlog}"));
        }
        (!answers(&self.display))
            .then(|| format!("Xvfb runs but takes no connections; its log:\n{xlog}"))
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

/// A screenshot of the whole screen (ImageMagick's `import`), as RGB pixels.
#[cfg(feature = "app")]
pub fn shot(display: &str, path: &std::path::Path) -> image::RgbImage {
    let ok = Command::new("import")
        .args(["-window", "root", path.to_str().expect("path")])
        .env("DISPLAY", display)
        .status()
        .expect("import");
    assert!(ok.success(), "screenshot failed");
    image::open(path).expect("read screenshot").to_rgb8()
}

/// Pixels in the middle of the screen (the scene; the HUD's bars and
/// boxes, whose values change, lie outside it) where a channel of `a` and
/// `b` differs by more than `tolerance`.
#[cfg(feature = "app")]
pub fn centre_difference(a: &image::RgbImage, b: &image::RgbImage, tolerance: u8) -> usize {
    let (w, h) = a.dimensions();
    let mut n = 0;
    for y in h / 4..3 * h / 4 {
        for x in w / 4..3 * w / 4 {
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            if p.iter().zip(q).any(|(u, v)| u.abs_diff(v) > tolerance) {
                n += 1;
            }
        }
    }
    n
}

/// CPU seconds (user + system) process `pid` has used.
pub fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("/proc stat");
    // Fields after the command's closing parenthesis; utime and stime are
    // the 14th and 15th of the whole line.
    let rest = &stat[stat.rfind(')').expect("stat") + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f[11].parse::<f64>().expect("utime") + f[12].parse::<f64>().expect("stime");
    let hz = Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .trim()
                .parse::<f64>()
                .ok()
        })
        .unwrap_or(100.0);
    ticks / hz
}

/// Presses `key` (with `shift`) for 100 ms, then waits 250 ms.
pub fn tap(display: &str, key: &str, shift: bool) {
    if shift {
        xdotool(display, &["keydown", "shift"]);
    }
    xdotool(display, &["keydown", key]);
    sleep(Duration::from_millis(100));
    xdotool(display, &["keyup", key]);
    if shift {
        xdotool(display, &["keyup", "shift"]);
    }
    sleep(Duration::from_millis(250));
}

/// Waits until `f` holds (checked every 0.5 s, up to 20 s).
pub fn eventually(mut f: impl FnMut() -> bool) -> bool {
    for _ in 0..40 {
        if f() {
            return true;
        }
        sleep(Duration::from_millis(500));
    }
    false
}
