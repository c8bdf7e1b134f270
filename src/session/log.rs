//! Session logs: every frame's input, with its time step, in a versioned,
//! line-based text format (the thesis's `-l` / `-p` options).
//!
//! A log is what the devices asked for, not what happened: joystick axes are
//! stored as the intents they mapped to, keys and mouse as motions and
//! commands. Replaying it through [`super::Session::step`] with the recorded
//! time steps reproduces the session bit for bit on the same build, with or
//! without a window. Floats are written in Rust's shortest round-trip form,
//! so they read back exactly.
//!
//! # Format, version 3
//!
//! ```text
//! bump-log 3
//! # any comment line
//! meta KEY VALUE...                      scene description (files, options)
//! f DT [FIELD=VALUE]... ~CHECK           one frame
//! final BODY TX TY TZ QX QY QZ QW ~CHECK the recorded session's final poses
//! end FRAMES
//! ```
//!
//! Frame fields, each present only when non-zero: `v` (velocity, 6 numbers:
//! translation x,y,z in Å then rotation vector in rad, per second), `n`
//! (nudge), `wv`/`wn` (view velocity/nudge), `ov`/`on` (object
//! velocity/nudge), `z` (zoom steps), `c` (a command; repeated, in order)
//! and `k` (a motion key pressed or released, repeated, in order:
//! `k=down:KEY:SIZE:AT` or `k=up:KEY:SIZE:AT`, KEY as `tx+` … `rz-`, SIZE
//! `fine`, `normal` or `coarse`, AT the seconds into the frame; see
//! [`super::keys`]), `tv` and `tn` (the selected rotatable bond's turn:
//! degrees per second, and a one-off turn in degrees). Version 2 added
//! `k`, version 3 `tv`, `tn` and the torsion and settle commands
//! (`torsion:K` or `torsion:none`, `next-torsion`, `previous-torsion`,
//! `torsion-near:ATOM`, `turn:DEGREES`, `settle`); older logs read as they
//! are.
//! `~CHECK` is the FNV-1a hash (32-bit, hex) of the line before ` ~`, so a
//! damaged line is named. A log without its `end` line, or whose count
//! disagrees, was cut short and is refused.
//!
//! # Reading
//!
//! Lines may end with LF, CRLF or a lone CR. A line that is not UTF-8 is
//! named with the column of its first bad byte; every message quotes at
//! most a short excerpt of the line ([`crate::text::excerpt`]). Time steps,
//! positions and moves go through the range check every command uses
//! ([`crate::motion::range`]): a step of 1e308 s is refused, not replayed
//! as infinite time. A log is at most [`MAX_LOG_BYTES`] long.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use thiserror::Error;

use super::{Command, FrameInput, KeyEvent, Motion6, StepKey, StepSize};
use crate::collide::Response;
use crate::motion::Pose;
use crate::motion::range::{check_displacement, check_position, check_seconds};
use crate::text::{excerpt, format_bytes, quoted, split_lines};

/// Longest log read, bytes: some 3 million frames of moving input (14
/// hours at 60 frames a second). Each frame read takes about 330 bytes,
/// so the limit also bounds the memory a log can take.
pub const MAX_LOG_BYTES: u64 = 256 << 20;

/// The format version this build writes (it reads this and every earlier one).
pub const VERSION: u32 = 3;

/// The oldest format version this build reads.
pub const OLDEST_VERSION: u32 = 1;

/// A log that cannot be read or written.
#[derive(Debug, Error)]
pub enum LogError {
    /// The file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A line that does not parse or whose check fails.
    #[error("{path}:{line}: {reason}")]
    Line {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// The log ends before its `end` line.
    #[error(
        "{path}: the log is truncated after line {line} (no `end` line): the recording was cut short"
    )]
    Truncated {
        /// The file.
        path: PathBuf,
        /// The last line read.
        line: usize,
    },
}

/// One recorded frame.
#[derive(Debug, Clone, PartialEq)]
pub struct LogFrame {
    /// Time step, seconds.
    pub dt: f64,
    /// What the frame asked for.
    pub input: FrameInput,
}

/// A whole log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SessionLog {
    /// Scene description: (key, value) in order.
    pub meta: Vec<(String, String)>,
    /// The frames.
    pub frames: Vec<LogFrame>,
    /// Final poses of the recorded session, one per molecule (empty when the
    /// recorder did not write them).
    pub finals: Vec<Pose>,
}

impl SessionLog {
    /// The values of meta key `key`, in order.
    pub fn meta_values<'a>(&'a self, key: &'a str) -> impl Iterator<Item = &'a str> + 'a {
        self.meta
            .iter()
            .filter(move |(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The first value of meta key `key`.
    pub fn meta_value(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Total recorded time, seconds.
    pub fn duration(&self) -> f64 {
        self.frames.iter().map(|f| f.dt).sum()
    }

    /// Reads and checks a log file.
    ///
    /// # Errors
    /// [`LogError`] naming the file and line of the first problem.
    pub fn read(path: &Path) -> Result<Self, LogError> {
        use std::io::Read;
        let io = |source| LogError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|f| f.take(MAX_LOG_BYTES + 1).read_to_end(&mut bytes))
            .map_err(io)?;
        if bytes.len() as u64 > MAX_LOG_BYTES {
            return Err(io(std::io::Error::other(format!(
                "longer than {}, the most a session log may be",
                format_bytes(MAX_LOG_BYTES)
            ))));
        }
        Self::parse_bytes(&bytes, path)
    }

    /// Parses log bytes; `path` names the source in errors. Lines may end
    /// with LF, CRLF or CR; each must be UTF-8.
    ///
    /// # Errors
    /// As [`SessionLog::parse`], and [`LogError::Line`] naming the line and
    /// column of bytes that are not UTF-8.
    pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<Self, LogError> {
        let lines = split_lines(bytes).enumerate().map(|(k, l)| {
            std::str::from_utf8(l).map_err(|e| LogError::Line {
                path: path.to_path_buf(),
                line: k + 1,
                reason: format!(
                    "not UTF-8 text: byte {} at column {} ({})",
                    l.get(e.valid_up_to())
                        .map_or_else(String::new, |b| format!("0x{b:02X}")),
                    e.valid_up_to() + 1,
                    excerpt(&String::from_utf8_lossy(l))
                ),
            })
        });
        Self::parse_lines(lines, path)
    }

    /// Parses log text; `path` names the source in errors.
    ///
    /// # Errors
    /// [`LogError::Line`] for a bad line, [`LogError::Truncated`] when the
    /// `end` line is missing.
    pub fn parse(text: &str, path: &Path) -> Result<Self, LogError> {
        Self::parse_bytes(text.as_bytes(), path)
    }

    /// Parses log lines (each already checked to be text).
    fn parse_lines<'a>(
        lines: impl Iterator<Item = Result<&'a str, LogError>>,
        path: &Path,
    ) -> Result<Self, LogError> {
        let err = |line: usize, reason: String| LogError::Line {
            path: path.to_path_buf(),
            line,
            reason,
        };
        let mut log = SessionLog::default();
        let mut lines = lines.enumerate().map(|(k, l)| l.map(|l| (k + 1, l)));
        match lines.next().transpose()? {
            Some((_, l)) if is_header(l) => {}
            Some((n, l)) if l.starts_with("bump-log ") => {
                return Err(err(
                    n,
                    format!(
                        "log version {} is not supported (this build reads {OLDEST_VERSION} to {VERSION})",
                        quoted(&l[9..])
                    ),
                ));
            }
            Some((n, _)) => {
                return Err(err(
                    n,
                    "not a bump session log (no `bump-log` header)".into(),
                ));
            }
            None => return Err(err(1, "empty file: not a bump session log".into())),
        }
        let mut last = 1;
        for line in lines {
            let (n, raw) = line?;
            last = n;
            let line = raw.trim_end();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let (word, rest) = line.split_once(' ').unwrap_or((line, ""));
            match word {
                "meta" => {
                    let (k, v) = rest.split_once(' ').unwrap_or((rest, ""));
                    if k.is_empty() {
                        return Err(err(n, "`meta` needs a key".into()));
                    }
                    log.meta.push((k.to_string(), v.to_string()));
                }
                "f" => {
                    let body = checked(line).map_err(|r| err(n, r))?;
                    log.frames.push(parse_frame(body).map_err(|r| err(n, r))?);
                }
                "final" => {
                    let body = checked(line).map_err(|r| err(n, r))?;
                    log.finals
                        .push(parse_final(body, log.finals.len()).map_err(|r| err(n, r))?);
                }
                "end" => {
                    let count: usize = rest.trim().parse().map_err(|_| {
                        err(
                            n,
                            format!("`end` needs the frame count, found {}", quoted(rest)),
                        )
                    })?;
                    if count != log.frames.len() {
                        return Err(err(
                            n,
                            format!(
                                "`end` says {count} frames but {} were read: frame lines are missing",
                                log.frames.len()
                            ),
                        ));
                    }
                    return Ok(log);
                }
                other => return Err(err(n, format!("unknown line kind {}", quoted(other)))),
            }
        }
        Err(LogError::Truncated {
            path: path.to_path_buf(),
            line: last,
        })
    }
}

/// True for a header line of a version this build reads.
fn is_header(line: &str) -> bool {
    line.trim_end()
        .strip_prefix("bump-log ")
        .and_then(|v| v.parse::<u32>().ok())
        .is_some_and(|v| (OLDEST_VERSION..=VERSION).contains(&v))
}

/// FNV-1a, 32-bit: a cheap check that names a damaged line.
fn fnv1a(s: &str) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    for b in s.bytes() {
        h ^= u32::from(b);
        h = h.wrapping_mul(0x0100_0193);
    }
    h
}

/// The line without its ` ~CHECK` suffix, after verifying it.
fn checked(line: &str) -> Result<&str, String> {
    let (body, check) = line
        .rsplit_once(" ~")
        .ok_or("the line has no ` ~` check value: it was cut or edited")?;
    let want =
        u32::from_str_radix(check, 16).map_err(|_| format!("bad check value {}", quoted(check)))?;
    if fnv1a(body) != want {
        return Err("the line is damaged (its check value does not match)".into());
    }
    Ok(body)
}

fn num(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{} is not a number", quoted(s)))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{} is not a finite number", quoted(s)))
    }
}

fn nums<const N: usize>(s: &str) -> Result<[f64; N], String> {
    let mut out = [0.0; N];
    let mut parts = s.split(',');
    for o in &mut out {
        *o = num(parts.next().unwrap_or_default()).map_err(|e| format!("{}: {e}", quoted(s)))?;
    }
    if parts.next().is_some() {
        return Err(format!(
            "{}: expected {N} comma-separated numbers",
            quoted(s)
        ));
    }
    Ok(out)
}

/// A motion: translation (Å, or Å per second) in the range of a move,
/// rotation finite.
fn motion(s: &str) -> Result<Motion6, String> {
    let [a, b, c, d, e, f] = nums::<6>(s)?;
    let translate =
        check_displacement(DVec3::new(a, b, c)).map_err(|e| format!("translation {e}"))?;
    Ok(Motion6 {
        translate,
        rotate: DVec3::new(d, e, f),
    })
}

fn parse_frame(body: &str) -> Result<LogFrame, String> {
    let mut parts = body.split(' ');
    parts.next(); // "f"
    let dt = num(parts.next().ok_or("a frame needs its time step")?)?;
    let dt = check_seconds(dt).map_err(|e| format!("time step {e}"))?;
    let mut input = FrameInput::default();
    for p in parts {
        let (k, v) = p
            .split_once('=')
            .ok_or_else(|| format!("{} is not FIELD=VALUE", quoted(p)))?;
        match k {
            "v" => input.velocity = motion(v)?,
            "n" => input.nudge = motion(v)?,
            "wv" => input.view_velocity = motion(v)?,
            "wn" => input.view_nudge = motion(v)?,
            "ov" => input.object_velocity = motion(v)?,
            "on" => input.object_nudge = motion(v)?,
            "z" => input.zoom = num(v)?,
            "tv" => input.torsion_velocity = num(v)?,
            "tn" => input.torsion_nudge = num(v)?,
            "c" => input.commands.push(parse_command(v)?),
            "k" => input.keys.push(parse_key(v)?),
            _ => return Err(format!("unknown frame field {}", quoted(k))),
        }
    }
    Ok(LogFrame { dt, input })
}

fn parse_final(body: &str, expected: usize) -> Result<Pose, String> {
    let f: Vec<&str> = body.split(' ').collect();
    if f.len() != 9 {
        return Err("`final` needs a molecule index and 7 numbers".into());
    }
    let b: usize = f[1]
        .parse()
        .map_err(|_| format!("{} is not a molecule index", quoted(f[1])))?;
    if b != expected {
        return Err(format!("final pose {b} out of order (expected {expected})"));
    }
    let v = f[2..]
        .iter()
        .map(|s| num(s))
        .collect::<Result<Vec<_>, _>>()?;
    let q = DQuat::from_xyzw(v[3], v[4], v[5], v[6]);
    let length = q.length();
    if !(length.is_finite() && length > 0.0) {
        return Err("the final pose's rotation (a quaternion) has no length".into());
    }
    let t = check_position(DVec3::new(v[0], v[1], v[2])).map_err(|e| format!("final pose {e}"))?;
    Ok(Pose::new(q, t))
}

/// The token a motion key's event is written as: `down:tx+:coarse:0.012`.
pub fn key_token(e: &KeyEvent) -> String {
    let what = if e.pressed { "down" } else { "up" };
    format!("{what}:{}:{}:{:?}", e.key.token(), e.size.name(), e.at)
}

/// Reads a motion key's event token.
///
/// # Errors
/// A message naming the token.
pub fn parse_key(tok: &str) -> Result<KeyEvent, String> {
    let bad = || {
        format!(
            "{} is not a key event (down|up:KEY:SIZE:SECONDS)",
            quoted(tok)
        )
    };
    let mut parts = tok.split(':');
    let (Some(what), Some(key), Some(size), Some(at), None) = (
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
    ) else {
        return Err(bad());
    };
    let pressed = match what {
        "down" => true,
        "up" => false,
        _ => return Err(bad()),
    };
    let key = StepKey::parse(key).ok_or_else(bad)?;
    let size = StepSize::parse(size).ok_or_else(bad)?;
    let at = check_seconds(num(at)?).map_err(|e| format!("{}: key time {e}", quoted(tok)))?;
    Ok(KeyEvent {
        key,
        size,
        pressed,
        at,
    })
}

/// The token a command is written as.
pub fn command_token(c: &Command) -> String {
    match c {
        Command::ToggleMode => "mode".into(),
        Command::NextMolecule => "next".into(),
        Command::Select(n) => format!("select:{n}"),
        Command::ToggleCollision => "collision".into(),
        Command::SetResponse(r) => format!("response:{}", r.name()),
        Command::CycleResponse => "cycle-response".into(),
        Command::ToggleSpace => "space".into(),
        Command::Undo => "undo".into(),
        Command::Redo => "redo".into(),
        Command::ResetMolecule => "reset-molecule".into(),
        Command::ResetView => "reset-view".into(),
        Command::ViewDrug => "view-drug".into(),
        Command::CentreOnDrug => "centre-drug".into(),
        Command::FitAll => "fit-all".into(),
        Command::MoveBy {
            translate: t,
            axis: a,
            degrees,
        } => format!(
            "move:{:?},{:?},{:?},{:?},{:?},{:?},{degrees:?}",
            t.x, t.y, t.z, a.x, a.y, a.z
        ),
        Command::ToggleRocking => "rock".into(),
        Command::RockMore => "rock-more".into(),
        Command::RockLess => "rock-less".into(),
        Command::Quit => "quit".into(),
        Command::SetSoftLimit(x) => format!("soft-limit:{x:?}"),
        Command::SoftLimitMore => "soft-more".into(),
        Command::SoftLimitLess => "soft-less".into(),
        Command::SelectTorsion(Some(k)) => format!("torsion:{k}"),
        Command::SelectTorsion(None) => "torsion:none".into(),
        Command::NextTorsion => "next-torsion".into(),
        Command::PreviousTorsion => "previous-torsion".into(),
        Command::SelectTorsionNear(a) => format!("torsion-near:{a}"),
        Command::TurnTorsion { degrees } => format!("turn:{degrees:?}"),
        Command::Settle => "settle".into(),
    }
}

/// Reads a command token.
///
/// # Errors
/// A message naming the token.
pub fn parse_command(tok: &str) -> Result<Command, String> {
    let (name, arg) = tok.split_once(':').unwrap_or((tok, ""));
    let no_arg = |c: Command| {
        if arg.is_empty() {
            Ok(c)
        } else {
            Err(format!("command {} takes no argument", quoted(name)))
        }
    };
    match name {
        "mode" => no_arg(Command::ToggleMode),
        "next" => no_arg(Command::NextMolecule),
        "select" => arg
            .parse()
            .map(Command::Select)
            .map_err(|_| format!("{}: select needs a molecule index", quoted(tok))),
        "collision" => no_arg(Command::ToggleCollision),
        "response" => Response::parse(arg)
            .map(Command::SetResponse)
            .ok_or_else(|| format!("{}: unknown response", quoted(tok))),
        "cycle-response" => no_arg(Command::CycleResponse),
        "space" => no_arg(Command::ToggleSpace),
        "undo" => no_arg(Command::Undo),
        "redo" => no_arg(Command::Redo),
        "reset-molecule" => no_arg(Command::ResetMolecule),
        "reset-view" => no_arg(Command::ResetView),
        "view-drug" => no_arg(Command::ViewDrug),
        "centre-drug" => no_arg(Command::CentreOnDrug),
        "fit-all" => no_arg(Command::FitAll),
        "move" => {
            let [tx, ty, tz, ax, ay, az, degrees] = nums::<7>(arg)?;
            let translate =
                check_displacement(DVec3::new(tx, ty, tz)).map_err(|e| format!("move {e}"))?;
            Ok(Command::MoveBy {
                translate,
                axis: DVec3::new(ax, ay, az),
                degrees,
            })
        }
        "rock" => no_arg(Command::ToggleRocking),
        "rock-more" => no_arg(Command::RockMore),
        "rock-less" => no_arg(Command::RockLess),
        "quit" => no_arg(Command::Quit),
        "soft-limit" => arg
            .parse()
            .map(Command::SetSoftLimit)
            .map_err(|_| format!("{}: soft-limit needs a number of Å", quoted(tok))),
        "soft-more" => no_arg(Command::SoftLimitMore),
        "soft-less" => no_arg(Command::SoftLimitLess),
        "torsion" if arg == "none" => Ok(Command::SelectTorsion(None)),
        "torsion" => arg
            .parse()
            .map(|k| Command::SelectTorsion(Some(k)))
            .map_err(|_| format!("{}: torsion needs a bond index or `none`", quoted(tok))),
        "next-torsion" => no_arg(Command::NextTorsion),
        "previous-torsion" => no_arg(Command::PreviousTorsion),
        "torsion-near" => arg
            .parse()
            .map(Command::SelectTorsionNear)
            .map_err(|_| format!("{}: torsion-near needs an atom index", quoted(tok))),
        "turn" => num(arg)
            .map(|degrees| Command::TurnTorsion { degrees })
            .map_err(|e| format!("{}: turn needs degrees: {e}", quoted(tok))),
        "settle" => no_arg(Command::Settle),
        _ => Err(format!("unknown command {}", quoted(tok))),
    }
}

fn push_motion(line: &mut String, key: &str, m: &Motion6) {
    if !m.is_zero() {
        let (t, r) = (m.translate, m.rotate);
        let _ = write!(
            line,
            " {key}={:?},{:?},{:?},{:?},{:?},{:?}",
            t.x, t.y, t.z, r.x, r.y, r.z
        );
    }
}

/// The text of one frame line, check included (no newline).
pub fn frame_line(dt: f64, input: &FrameInput) -> String {
    let mut line = format!("f {dt:?}");
    push_motion(&mut line, "v", &input.velocity);
    push_motion(&mut line, "n", &input.nudge);
    push_motion(&mut line, "wv", &input.view_velocity);
    push_motion(&mut line, "wn", &input.view_nudge);
    push_motion(&mut line, "ov", &input.object_velocity);
    push_motion(&mut line, "on", &input.object_nudge);
    if input.zoom != 0.0 {
        let _ = write!(line, " z={:?}", input.zoom);
    }
    if input.torsion_velocity != 0.0 {
        let _ = write!(line, " tv={:?}", input.torsion_velocity);
    }
    if input.torsion_nudge != 0.0 {
        let _ = write!(line, " tn={:?}", input.torsion_nudge);
    }
    for c in &input.commands {
        let _ = write!(line, " c={}", command_token(c));
    }
    for k in &input.keys {
        let _ = write!(line, " k={}", key_token(k));
    }
    with_check(line)
}

fn with_check(mut line: String) -> String {
    let h = fnv1a(&line);
    let _ = write!(line, " ~{h:08x}");
    line
}

/// The text of a final-pose line, check included.
pub fn final_line(body: usize, pose: &Pose) -> String {
    let (t, q) = (pose.translation, pose.rotation);
    with_check(format!(
        "final {body} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        t.x, t.y, t.z, q.x, q.y, q.z, q.w
    ))
}

/// Writes a log as the session runs. Lines go to `FILE.part`; [`finish`]
/// writes the closing lines and renames it to `FILE`, so a log that exists
/// under its own name is complete (an interrupted recording stays `.part`).
///
/// [`finish`]: LogWriter::finish
pub struct LogWriter {
    path: PathBuf,
    part: PathBuf,
    out: std::io::BufWriter<std::fs::File>,
    frames: usize,
}

impl std::fmt::Debug for LogWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogWriter")
            .field("path", &self.path)
            .field("frames", &self.frames)
            .finish()
    }
}

impl LogWriter {
    /// Starts a log at `path` with the scene description `meta`.
    ///
    /// # Errors
    /// [`LogError::Io`] when the file cannot be created.
    pub fn create(path: &Path, meta: &[(String, String)]) -> Result<Self, LogError> {
        let mut part = path.as_os_str().to_owned();
        part.push(".part");
        let part = PathBuf::from(part);
        let io = |source| LogError::Io {
            path: part.clone(),
            source,
        };
        let file = std::fs::File::create(&part).map_err(io)?;
        let mut w = Self {
            path: path.to_path_buf(),
            part: part.clone(),
            out: std::io::BufWriter::new(file),
            frames: 0,
        };
        let mut head = format!(
            "bump-log {VERSION}\n# bump session log: one line per frame (see src/session/log.rs for the format)\n"
        );
        for (k, v) in meta {
            let v = v.replace(['\n', '\r'], " ");
            let _ = writeln!(head, "meta {k} {v}");
        }
        w.out.write_all(head.as_bytes()).map_err(io)?;
        Ok(w)
    }

    /// Appends one frame.
    ///
    /// # Errors
    /// [`LogError::Io`] when the write fails.
    pub fn frame(&mut self, dt: f64, input: &FrameInput) -> Result<(), LogError> {
        let line = frame_line(dt, input);
        self.frames += 1;
        writeln!(self.out, "{line}").map_err(|source| LogError::Io {
            path: self.part.clone(),
            source,
        })
    }

    /// Frames written so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Writes the final poses and the `end` line, and gives the log its name.
    ///
    /// # Errors
    /// [`LogError::Io`] when a write or the rename fails.
    pub fn finish(mut self, finals: &[Pose]) -> Result<PathBuf, LogError> {
        let io = |source| LogError::Io {
            path: self.part.clone(),
            source,
        };
        let mut tail = String::new();
        for (b, p) in finals.iter().enumerate() {
            let _ = writeln!(tail, "{}", final_line(b, p));
        }
        let _ = writeln!(tail, "end {}", self.frames);
        self.out.write_all(tail.as_bytes()).map_err(io)?;
        self.out.flush().map_err(io)?;
        self.out.get_ref().sync_all().map_err(io)?;
        std::fs::rename(&self.part, &self.path).map_err(io)?;
        Ok(self.path)
    }
}

/// A whole log as text (for tests and scripted logs).
pub fn to_text(log: &SessionLog) -> String {
    let mut s = format!("bump-log {VERSION}\n");
    for (k, v) in &log.meta {
        let _ = writeln!(s, "meta {k} {v}");
    }
    for f in &log.frames {
        let _ = writeln!(s, "{}", frame_line(f.dt, &f.input));
    }
    for (b, p) in log.finals.iter().enumerate() {
        let _ = writeln!(s, "{}", final_line(b, p));
    }
    let _ = writeln!(s, "end {}", log.frames.len());
    s
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    fn sample() -> SessionLog {
        let odd = Motion6 {
            translate: DVec3::new(0.1, -1e-300, 12345.678901234567),
            rotate: DVec3::new(f64::MIN_POSITIVE, -0.0, 1.0 / 3.0),
        };
        SessionLog {
            meta: vec![
                ("file".into(), "../shared/pdb/a b.pdb".into()),
                ("collider".into(), "grid".into()),
            ],
            frames: vec![
                LogFrame {
                    dt: 1.0 / 60.0,
                    input: FrameInput::default(),
                },
                LogFrame {
                    dt: 0.016_7,
                    input: FrameInput {
                        velocity: odd,
                        nudge: odd.scaled(2.0),
                        view_velocity: odd.scaled(-1.0),
                        view_nudge: odd,
                        object_velocity: odd.scaled(0.5),
                        object_nudge: odd,
                        zoom: -2.5,
                        torsion_velocity: 0.1,
                        torsion_nudge: -7.0,
                        commands: vec![
                            Command::ToggleMode,
                            Command::NextMolecule,
                            Command::Select(3),
                            Command::ToggleCollision,
                            Command::SetResponse(Response::Slide),
                            Command::CycleResponse,
                            Command::ToggleSpace,
                            Command::Undo,
                            Command::Redo,
                            Command::ResetMolecule,
                            Command::ResetView,
                            Command::ViewDrug,
                            Command::CentreOnDrug,
                            Command::FitAll,
                            Command::ToggleRocking,
                            Command::RockMore,
                            Command::RockLess,
                            Command::MoveBy {
                                translate: DVec3::new(1.5, -2.0, 1e-9),
                                axis: DVec3::Y,
                                degrees: 0.1,
                            },
                            Command::Quit,
                        ],
                        keys: vec![
                            KeyEvent::press(
                                StepKey::turn(crate::session::StepAxis::Y, false),
                                StepSize::Coarse,
                                0.0123,
                            ),
                            KeyEvent::release(
                                StepKey::translate(crate::session::StepAxis::Z, true),
                                1.0 / 3.0,
                            ),
                        ],
                    },
                },
            ],
            finals: vec![Pose::new(
                DQuat::from_axis_angle(DVec3::new(0.3, 0.4, 0.5).normalize(), 0.7),
                DVec3::new(1e5, -0.1, 3.0),
            )],
        }
    }

    #[test]
    fn a_log_reads_back_bit_for_bit() {
        let log = sample();
        let text = to_text(&log);
        let back = SessionLog::parse(&text, Path::new("x.log")).unwrap();
        assert_eq!(back, log);
        // -0.0 and tiny values survive exactly, not just approximately.
        let r = back.frames[1].input.velocity.rotate;
        assert!(r.y.is_sign_negative() && r.x == f64::MIN_POSITIVE);
        assert_eq!(back.meta_value("file"), Some("../shared/pdb/a b.pdb"));
    }

    #[test]
    fn a_damaged_line_is_named() {
        let text = to_text(&sample());
        // Change one digit of the second frame (line 5).
        let damaged = text.replacen("0.0167", "0.0168", 1);
        assert_ne!(damaged, text);
        let e = SessionLog::parse(&damaged, Path::new("x.log")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("x.log:5: "), "{msg}");
        assert!(msg.contains("damaged"), "{msg}");
    }

    #[test]
    fn a_truncated_log_is_refused() {
        let text = to_text(&sample());
        let cut: String = text.lines().take(4).map(|l| format!("{l}\n")).collect();
        let e = SessionLog::parse(&cut, Path::new("x.log")).unwrap_err();
        assert!(matches!(e, LogError::Truncated { line: 4, .. }), "{e}");
        assert!(e.to_string().contains("truncated"));
        // A line cut in the middle loses its check.
        let half = &text[..text.find("~").unwrap() - 3];
        let e = SessionLog::parse(half, Path::new("x.log")).unwrap_err();
        assert!(e.to_string().contains("x.log:"), "{e}");
        // A missing frame line is caught by the count.
        let lines: Vec<&str> = text.lines().collect();
        let without: String = lines
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != 3)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        let e = SessionLog::parse(&without, Path::new("x.log")).unwrap_err();
        assert!(e.to_string().contains("frames but"), "{e}");
    }

    #[test]
    fn bad_headers_and_fields_are_refused_with_their_line() {
        let p = Path::new("x.log");
        assert!(SessionLog::parse("", p).is_err());
        let e = SessionLog::parse("hello\n", p).unwrap_err().to_string();
        assert!(
            e.contains("x.log:1") && e.contains("not a bump session log"),
            "{e}"
        );
        let e = SessionLog::parse("bump-log 9\nend 0\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("version `9`"), "{e}");
        for bad in [
            "f 0.1 v=1,2,3",
            "f -1",
            "f 0.1 q=1",
            "f 0.1 c=fly",
            "f NaN",
            "f 0.1 z=inf",
            "f 0.1 k=down:tq+:normal:0",
            "f 0.1 k=down:tx+:huge:0",
            "f 0.1 k=down:tx+:normal:-1",
            "f 0.1 k=down:tx+:normal",
        ] {
            let text = format!("bump-log 2\n{}\nend 1\n", with_check(bad.to_string()));
            let e = SessionLog::parse(&text, p).unwrap_err().to_string();
            assert!(e.starts_with("x.log:2: "), "{bad}: {e}");
        }
        let e = SessionLog::parse("bump-log 1\nbogus\nend 0\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.log:2") && e.contains("bogus"), "{e}");
    }

    #[test]
    fn version_1_logs_still_read() {
        let frame = with_check("f 0.5 n=1,0,0,0,0,0 c=mode".to_string());
        let text = format!("bump-log 1\n{frame}\nend 1\n");
        let log = SessionLog::parse(&text, Path::new("old.log")).unwrap();
        assert_eq!(log.frames[0].input.commands, [Command::ToggleMode]);
        assert!(log.frames[0].input.keys.is_empty());
        assert!(to_text(&log).starts_with("bump-log 3\n"));
    }

    #[test]
    fn torsion_fields_and_commands_round_trip() {
        let input = FrameInput {
            torsion_velocity: 45.5,
            torsion_nudge: -3.25,
            commands: vec![
                Command::SelectTorsion(Some(2)),
                Command::SelectTorsion(None),
                Command::NextTorsion,
                Command::PreviousTorsion,
                Command::SelectTorsionNear(7),
                Command::TurnTorsion { degrees: -0.1 },
                Command::Settle,
            ],
            ..FrameInput::default()
        };
        let line = frame_line(0.016, &input);
        let text = format!("bump-log 3\n{line}\nend 1\n");
        let log = SessionLog::parse(&text, Path::new("t.log")).unwrap();
        assert_eq!(log.frames[0].input, input);
        let frame = with_check("f 0.5 c=turn:nan".to_string());
        let text = format!("bump-log 3\n{frame}\nend 1\n");
        assert!(SessionLog::parse(&text, Path::new("t.log")).is_err());
    }

    #[test]
    fn the_writer_names_the_file_only_when_complete() {
        let dir = std::env::temp_dir().join(format!("bump-log-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.log");
        let log = sample();
        let mut w = LogWriter::create(&path, &log.meta).unwrap();
        for f in &log.frames {
            w.frame(f.dt, &f.input).unwrap();
        }
        assert!(!path.exists(), "no complete log before finish");
        assert!(dir.join("s.log.part").exists());
        w.finish(&log.finals).unwrap();
        assert!(!dir.join("s.log.part").exists());
        let back = SessionLog::read(&path).unwrap();
        assert_eq!(back.frames, log.frames);
        assert_eq!(back.finals, log.finals);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
