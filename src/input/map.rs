//! The joystick map: which device axis drives which degree of freedom, and
//! the pure function from raw axis values to a 6-DOF velocity.
//!
//! A map is read from TOML (the default is `assets/joystick-map.toml`,
//! compiled in). Each *profile* says which devices it applies to (by name, or
//! as the fallback for devices the device layer maps as gamepads, or not), how many
//! devices make one *box* (a gamepad is a box; flight sticks pair up), and
//! its *bindings*: a source axis (a standard name like `LeftStickX` or a raw `code:N`) feeding one
//! gesture (x, y, twist) of the translation or rotation stick. A raw value
//! goes through the dead zone and response curve ([`Shape::apply`]), then the
//! rotation mapping ([`RotationMapping`]) picks the axis it turns about, and
//! the speeds turn deflection into motion per second. Nothing here touches a
//! device, so all of it is unit-tested.
//!
//! A map file is at most [`MAX_MAP_BYTES`] long and UTF-8 (a bad byte is
//! named by line and column); its lines may end with LF, CRLF or a lone CR
//! (which TOML itself does not allow, so it is read as LF); brackets may
//! nest [`MAX_NESTING`] deep. Errors quote at most a short excerpt.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;
use thiserror::Error;

use crate::session::Motion6;
use crate::text::{quoted, short_number};

/// Longest map file read, bytes: maps are a few kilobytes.
pub const MAX_MAP_BYTES: u64 = 1 << 20;

/// Deepest nesting of arrays and inline tables a map may have (the TOML
/// parser recurses on each level).
pub const MAX_NESTING: usize = 32;

/// The default map, compiled in.
pub const DEFAULT_MAP: &str = include_str!("../../assets/joystick-map.toml");

/// A map file that cannot be used.
#[derive(Debug, Error)]
pub enum MapError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The TOML does not parse or does not fit the schema.
    #[error("{path}: {reason}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong (with line and column from the TOML parser).
        reason: String,
    },
}

/// Which stick a binding feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// The translation stick.
    Translate,
    /// The rotation stick.
    Rotate,
}

/// A stick's three gestures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Gesture {
    /// Left/right.
    X,
    /// Forward/back.
    Y,
    /// Twist.
    Twist,
}

/// Which rotation axis each gesture of the rotation stick turns about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RotationMapping {
    /// What the thesis's users asked for (section 6.3): twist turns about
    /// the vertical axis, forward/back about the depth axis, left/right
    /// about the horizontal axis.
    #[default]
    Users,
    /// The thesis's original: left/right about x, forward/back about y,
    /// twist about z.
    Thesis,
}

impl RotationMapping {
    /// Parses `users` or `thesis`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "users" => Some(Self::Users),
            "thesis" => Some(Self::Thesis),
            _ => None,
        }
    }

    /// The screen axis (0 = x, 1 = y, 2 = z) a gesture drives for `role`.
    pub fn axis(self, role: Role, gesture: Gesture) -> usize {
        match (role, self, gesture) {
            (_, _, Gesture::X) => 0,
            (Role::Translate, _, Gesture::Y) | (Role::Rotate, Self::Thesis, Gesture::Y) => 1,
            (Role::Translate, _, Gesture::Twist) | (Role::Rotate, Self::Thesis, Gesture::Twist) => {
                2
            }
            (Role::Rotate, Self::Users, Gesture::Y) => 2,
            (Role::Rotate, Self::Users, Gesture::Twist) => 1,
        }
    }
}

/// Dead zone, response curve and gain of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    /// Deflection (0–1) below which the axis reads zero.
    pub dead_zone: f64,
    /// Response exponent: 1 linear, > 1 finer near the centre.
    pub curve: f64,
    /// Gain (negative inverts).
    pub scale: f64,
}

impl Default for Shape {
    fn default() -> Self {
        Self {
            dead_zone: 0.12,
            curve: 1.8,
            scale: 1.0,
        }
    }
}

impl Shape {
    /// The shaped value of a raw deflection in [-1, 1]: zero inside the dead
    /// zone, then rising from 0 to 1 as `((|x| − dz)/(1 − dz))^curve`, times
    /// the gain. Non-finite input reads zero; input beyond ±1 is clamped.
    pub fn apply(&self, x: f64) -> f64 {
        if !x.is_finite() {
            return 0.0;
        }
        let x = x.clamp(-1.0, 1.0);
        let a = x.abs();
        if a <= self.dead_zone {
            return 0.0;
        }
        let u = ((a - self.dead_zone) / (1.0 - self.dead_zone)).min(1.0);
        x.signum() * u.powf(self.curve) * self.scale
    }
}

/// One source axis feeding one gesture.
#[derive(Debug, Clone, PartialEq)]
pub struct Binding {
    /// Which device of the box (0 or 1; a gamepad box has only 0).
    pub stick: usize,
    /// Translation or rotation.
    pub role: Role,
    /// Which gesture.
    pub gesture: Gesture,
    /// The source axis or button.
    pub source: String,
    /// A second source subtracted from the first (e.g. the other trigger).
    pub negative: Option<String>,
    /// Shaping.
    pub shape: Shape,
}

/// Which devices a profile applies to when no name matches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Fallback {
    /// Devices the device layer maps as gamepads.
    Mapped,
    /// Devices it does not.
    Unmapped,
}

/// How one kind of device drives a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// For messages.
    pub name: String,
    /// Case-insensitive substrings of device names this profile claims.
    pub names: Vec<String>,
    /// The devices it takes when no profile claims them by name.
    pub fallback: Option<Fallback>,
    /// Devices per box (1 or 2).
    pub sticks: usize,
    /// The bindings.
    pub bindings: Vec<Binding>,
}

/// A whole joystick map.
#[derive(Debug, Clone, PartialEq)]
pub struct JoystickMap {
    /// Rotation mapping.
    pub rotation: RotationMapping,
    /// Å per second at full deflection.
    pub translate_speed: f64,
    /// Degrees per second at full deflection.
    pub rotate_speed: f64,
    /// Rumble on a new contact.
    pub rumble: bool,
    /// Profiles, tried in order.
    pub profiles: Vec<Profile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileMap {
    version: u32,
    #[serde(default)]
    rotation: RotationMapping,
    translate_speed: f64,
    rotate_speed: f64,
    #[serde(default)]
    dead_zone: Option<f64>,
    #[serde(default)]
    curve: Option<f64>,
    #[serde(default = "yes")]
    rumble: bool,
    #[serde(default)]
    profile: Vec<FileProfile>,
}

fn yes() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileProfile {
    name: String,
    #[serde(default)]
    names: Vec<String>,
    #[serde(default)]
    fallback: Option<Fallback>,
    sticks: usize,
    bindings: Vec<FileBinding>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileBinding {
    stick: usize,
    role: Role,
    gesture: Gesture,
    source: String,
    #[serde(default)]
    negative: Option<String>,
    #[serde(default)]
    invert: bool,
    #[serde(default)]
    dead_zone: Option<f64>,
    #[serde(default)]
    curve: Option<f64>,
    #[serde(default)]
    scale: Option<f64>,
}

impl Default for JoystickMap {
    fn default() -> Self {
        // The compiled-in map is tested to parse.
        Self::parse(DEFAULT_MAP, Path::new("assets/joystick-map.toml")).unwrap_or(Self {
            rotation: RotationMapping::Users,
            translate_speed: 8.0,
            rotate_speed: 60.0,
            rumble: true,
            profiles: Vec::new(),
        })
    }
}

impl JoystickMap {
    /// Reads a map file.
    ///
    /// # Errors
    /// [`MapError`] naming the file, and the line for TOML errors.
    pub fn read(path: &Path) -> Result<Self, MapError> {
        use std::io::Read;
        let io = |source| MapError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|f| f.take(MAX_MAP_BYTES + 1).read_to_end(&mut bytes))
            .map_err(io)?;
        if bytes.len() as u64 > MAX_MAP_BYTES {
            return Err(MapError::Invalid {
                path: path.to_path_buf(),
                reason: format!(
                    "longer than {}: a joystick map is a few kilobytes of TOML",
                    crate::text::format_bytes(MAX_MAP_BYTES)
                ),
            });
        }
        Self::parse_bytes(&bytes, path)
    }

    /// Parses and validates map bytes (UTF-8 TOML, lines ended by LF, CRLF
    /// or CR); `path` names it in errors.
    ///
    /// # Errors
    /// [`MapError::Invalid`] for bytes that are not UTF-8 (naming line and
    /// column), bad TOML or values out of range.
    pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<Self, MapError> {
        let bad = |reason: String| MapError::Invalid {
            path: path.to_path_buf(),
            reason,
        };
        let mut text = String::with_capacity(bytes.len());
        for (k, line) in crate::text::split_lines(bytes).enumerate() {
            let line = std::str::from_utf8(line).map_err(|e| {
                bad(format!(
                    "line {}, column {}: not UTF-8 text",
                    k + 1,
                    e.valid_up_to() + 1
                ))
            })?;
            text.push_str(line);
            text.push('\n');
        }
        Self::parse(&text, path)
    }

    /// Parses and validates map text; `path` names it in errors.
    ///
    /// # Errors
    /// [`MapError::Invalid`] for bad TOML or values out of range.
    pub fn parse(text: &str, path: &Path) -> Result<Self, MapError> {
        let bad = |reason: String| MapError::Invalid {
            path: path.to_path_buf(),
            reason,
        };
        check_nesting(text).map_err(bad)?;
        let f: FileMap = toml::from_str(text).map_err(|e| bad(toml_error(text, &e)))?;
        if f.version != 1 {
            return Err(bad(format!(
                "version {} is not supported (this build reads version 1)",
                f.version
            )));
        }
        let positive = |what: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(bad(format!(
                    "{what} must be a positive number, not {}",
                    short_number(v)
                )))
            }
        };
        let translate_speed = positive("translate_speed", f.translate_speed)?;
        let rotate_speed = positive("rotate_speed", f.rotate_speed)?;
        let base = Shape {
            dead_zone: f.dead_zone.unwrap_or(Shape::default().dead_zone),
            curve: f.curve.unwrap_or(Shape::default().curve),
            scale: 1.0,
        };
        let mut profiles = Vec::new();
        for p in f.profile {
            let here = |what: String| bad(format!("profile {}: {what}", quoted(&p.name)));
            if !(1..=2).contains(&p.sticks) {
                return Err(here(format!("sticks must be 1 or 2, not {}", p.sticks)));
            }
            if p.names.is_empty() && p.fallback.is_none() {
                return Err(here("needs `names` or a `fallback`".into()));
            }
            let mut bindings = Vec::new();
            for b in p.bindings {
                if b.stick >= p.sticks {
                    return Err(here(format!(
                        "binding of {} names stick {} but the profile has {} stick(s)",
                        quoted(&b.source),
                        b.stick,
                        p.sticks
                    )));
                }
                let shape = Shape {
                    dead_zone: b.dead_zone.unwrap_or(base.dead_zone),
                    curve: b.curve.unwrap_or(base.curve),
                    scale: b.scale.unwrap_or(1.0) * if b.invert { -1.0 } else { 1.0 },
                };
                if !(0.0..1.0).contains(&shape.dead_zone) {
                    return Err(here(format!(
                        "dead_zone of {} must be in [0, 1), not {}",
                        quoted(&b.source),
                        short_number(shape.dead_zone)
                    )));
                }
                if !(shape.curve.is_finite() && shape.curve > 0.0 && shape.scale.is_finite()) {
                    return Err(here(format!(
                        "curve (> 0) or scale of {} is out of range",
                        quoted(&b.source)
                    )));
                }
                bindings.push(Binding {
                    stick: b.stick,
                    role: b.role,
                    gesture: b.gesture,
                    source: b.source,
                    negative: b.negative,
                    shape,
                });
            }
            profiles.push(Profile {
                name: p.name,
                names: p.names.iter().map(|n| n.to_lowercase()).collect(),
                fallback: p.fallback,
                sticks: p.sticks,
                bindings,
            });
        }
        Ok(Self {
            rotation: f.rotation,
            translate_speed,
            rotate_speed,
            rumble: f.rumble,
            profiles,
        })
    }

    /// The profile for a device: the first that claims its name, else the
    /// first fallback for its kind.
    pub fn profile_for(&self, name: &str, mapped: bool) -> Option<usize> {
        let lower = name.to_lowercase();
        self.profiles
            .iter()
            .position(|p| p.names.iter().any(|n| lower.contains(n.as_str())))
            .or_else(|| {
                let want = if mapped {
                    Fallback::Mapped
                } else {
                    Fallback::Unmapped
                };
                self.profiles.iter().position(|p| p.fallback == Some(want))
            })
    }

    /// The velocity of one box: `sticks[k]` holds the raw values of the
    /// box's k-th device (source name → value in [-1, 1]). Translation in
    /// Å/s and rotation in rad/s, in screen axes.
    pub fn box_velocity(&self, profile: &Profile, sticks: &[&BTreeMap<String, f64>]) -> Motion6 {
        let mut t = [0.0f64; 3];
        let mut r = [0.0f64; 3];
        for b in &profile.bindings {
            let Some(values) = sticks.get(b.stick) else {
                continue;
            };
            let read = |s: &str| values.get(s).copied().unwrap_or(0.0);
            let raw = read(&b.source) - b.negative.as_deref().map_or(0.0, read);
            let v = b.shape.apply(raw);
            let axis = self.rotation.axis(b.role, b.gesture);
            match b.role {
                Role::Translate => t[axis] += v,
                Role::Rotate => r[axis] += v,
            }
        }
        let clamp = |a: [f64; 3]| DVec3::from(a).clamp(DVec3::splat(-1.0), DVec3::splat(1.0));
        Motion6 {
            translate: clamp(t) * self.translate_speed,
            rotate: clamp(r) * self.rotate_speed.to_radians(),
        }
    }
}

/// A TOML error as a short message: line and column, what is wrong (cut
/// short: the parser's own message may quote a whole value), and an
/// excerpt of the line.
fn toml_error(text: &str, e: &toml::de::Error) -> String {
    let message: String = {
        let m = e.message().trim();
        match m.char_indices().nth(2 * crate::text::EXCERPT_CHARS) {
            Some((cut, _)) => format!("{}…", &m[..cut]),
            None => m.to_string(),
        }
    };
    let Some(span) = e.span() else {
        return message;
    };
    let at = span.start.min(text.len());
    let before = text.get(..at).unwrap_or_default();
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let column = crate::text::column_of(&text[start..end], at - start);
    format!(
        "line {line}, column {column}: {message} (in {})",
        crate::text::excerpt(&text[start..end])
    )
}

/// Refuses arrays and inline tables nested deeper than [`MAX_NESTING`],
/// looking past strings and comments.
fn check_nesting(text: &str) -> Result<(), String> {
    let mut depth = 0usize;
    let mut line = 1;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\n' => line += 1,
            '#' => {
                while chars.peek().is_some_and(|c| *c != '\n') {
                    chars.next();
                }
            }
            '"' | '\'' => {
                // A string to its closing quote (escapes in basic strings;
                // multi-line strings are runs of such strings and their
                // newlines count alike).
                while let Some(d) = chars.next() {
                    if d == '\n' {
                        line += 1;
                    } else if d == '\\' && c == '"' {
                        chars.next();
                    } else if d == c {
                        break;
                    }
                }
            }
            '[' | '{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(format!(
                        "line {line}: arrays and tables nest deeper than {MAX_NESTING} levels"
                    ));
                }
            }
            ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    fn values(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    #[test]
    fn the_default_map_parses_and_has_a_profile_for_every_kind() {
        let m = JoystickMap::parse(DEFAULT_MAP, Path::new("default")).unwrap();
        assert_eq!(m, JoystickMap::default());
        assert_eq!(m.rotation, RotationMapping::Users);
        let gamepad = m.profile_for("Xbox Wireless Controller", true).unwrap();
        assert_eq!(m.profiles[gamepad].sticks, 1);
        let stick = m.profile_for("Thrustmaster T.16000M", true).unwrap();
        assert_eq!(m.profiles[stick].sticks, 2);
        let raw = m.profile_for("Mystery Device", false).unwrap();
        assert!(m.profiles[raw].bindings[0].source.starts_with("code:"));
        assert!(m.rumble);
    }

    #[test]
    fn dead_zone_and_curve_shape_the_response() {
        let s = Shape {
            dead_zone: 0.2,
            curve: 2.0,
            scale: 1.0,
        };
        assert_eq!(s.apply(0.0), 0.0);
        assert_eq!(s.apply(0.2), 0.0);
        assert_eq!(s.apply(-0.19), 0.0);
        assert!((s.apply(0.6) - 0.25).abs() < 1e-12); // ((0.6-0.2)/0.8)^2
        assert!((s.apply(-0.6) + 0.25).abs() < 1e-12);
        assert_eq!(s.apply(1.0), 1.0);
        assert_eq!(s.apply(-1.0), -1.0);
        // Beyond the limits: clamped; NaN and infinities: nothing.
        assert_eq!(s.apply(7.0), 1.0);
        assert_eq!(s.apply(f64::NAN), 0.0);
        assert_eq!(s.apply(f64::INFINITY), 0.0);
        // Monotonic and continuous at the dead zone's edge.
        let mut last = 0.0;
        for k in 0..=1000 {
            let v = s.apply(f64::from(k) / 1000.0);
            assert!(v >= last);
            last = v;
        }
        assert!(s.apply(0.2 + 1e-9) < 1e-12);
        let linear = Shape {
            dead_zone: 0.0,
            curve: 1.0,
            scale: -2.0,
        };
        assert_eq!(linear.apply(0.5), -1.0);
    }

    #[test]
    fn both_rotation_mappings_send_gestures_where_the_thesis_says() {
        use Gesture::*;
        use Role::*;
        let t = RotationMapping::Thesis;
        assert_eq!(
            [t.axis(Rotate, X), t.axis(Rotate, Y), t.axis(Rotate, Twist)],
            [0, 1, 2]
        );
        let u = RotationMapping::Users;
        // Twist about the vertical (y), forward/back about depth (z).
        assert_eq!(
            [u.axis(Rotate, X), u.axis(Rotate, Y), u.axis(Rotate, Twist)],
            [0, 2, 1]
        );
        // Translation is the same in both.
        for m in [t, u] {
            assert_eq!(
                [
                    m.axis(Translate, X),
                    m.axis(Translate, Y),
                    m.axis(Translate, Twist)
                ],
                [0, 1, 2]
            );
        }
    }

    #[test]
    fn a_gamepad_box_maps_sticks_triggers_and_signs() {
        let m = JoystickMap::default();
        let p = &m.profiles[m.profile_for("Generic Gamepad", true).unwrap()];
        let full = |pairs: &[(&str, f64)]| {
            let v = values(pairs);
            m.box_velocity(p, &[&v])
        };
        let s = m.translate_speed;
        let w = m.rotate_speed.to_radians();
        assert_eq!(full(&[]), Motion6::ZERO);
        assert_eq!(
            full(&[("LeftStickX", 1.0)]).translate,
            DVec3::new(s, 0.0, 0.0)
        );
        assert_eq!(
            full(&[("LeftStickY", -1.0)]).translate,
            DVec3::new(0.0, -s, 0.0)
        );
        // Right trigger pushes away (−z), left pulls closer (+z).
        assert_eq!(
            full(&[("RightTrigger2", 1.0)]).translate,
            DVec3::new(0.0, 0.0, -s)
        );
        assert_eq!(
            full(&[("LeftTrigger2", 1.0)]).translate,
            DVec3::new(0.0, 0.0, s)
        );
        assert_eq!(
            full(&[("LeftTrigger2", 1.0), ("RightTrigger2", 1.0)]).translate,
            DVec3::ZERO
        );
        // Users' mapping: forward on the rotation stick turns about depth,
        // the shoulder-button twist about the vertical.
        assert_eq!(
            full(&[("RightStickY", 1.0)]).rotate,
            DVec3::new(0.0, 0.0, w)
        );
        assert_eq!(
            full(&[("RightTrigger", 1.0)]).rotate,
            DVec3::new(0.0, w, 0.0)
        );
        assert_eq!(
            full(&[("RightStickX", -1.0)]).rotate,
            DVec3::new(-w, 0.0, 0.0)
        );
        // Inside the dead zone nothing moves; half-way is less than half speed.
        assert_eq!(full(&[("LeftStickX", 0.1)]), Motion6::ZERO);
        let half = full(&[("LeftStickX", 0.5)]).translate.x;
        assert!(half > 0.0 && half < 0.5 * s);
        // The thesis mapping, one setting away.
        let mut thesis = m.clone();
        thesis.rotation = RotationMapping::Thesis;
        let v = values(&[("RightStickY", 1.0)]);
        assert_eq!(
            thesis.box_velocity(p, &[&v]).rotate,
            DVec3::new(0.0, w, 0.0)
        );
    }

    #[test]
    fn a_flight_stick_pair_splits_translation_and_rotation() {
        let m = JoystickMap::default();
        let p = &m.profiles[m.profile_for("Logitech Extreme 3D pro", false).unwrap()];
        let a = values(&[("LeftStickX", 1.0), ("RightZ", 1.0)]);
        let b = values(&[("RightZ", -1.0), ("LeftStickY", 1.0)]);
        let v = m.box_velocity(p, &[&a, &b]);
        let s = m.translate_speed;
        let w = m.rotate_speed.to_radians();
        assert_eq!(v.translate, DVec3::new(s, 0.0, s));
        assert_eq!(v.rotate, DVec3::new(0.0, -w, w));
        // A lone stick (half a box) translates only.
        let v = m.box_velocity(p, &[&a]);
        assert_eq!(v.rotate, DVec3::ZERO);
        assert_eq!(v.translate, DVec3::new(s, 0.0, s));
    }

    #[test]
    fn bad_maps_are_refused_with_the_reason() {
        let p = Path::new("my.toml");
        let e = JoystickMap::parse("version = 1\n", p)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("my.toml: ") && e.contains("translate_speed"),
            "{e}"
        );
        let e = JoystickMap::parse("version = 2\ntranslate_speed = 1\nrotate_speed = 1\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("version 2"), "{e}");
        let e = JoystickMap::parse("version = 1\ntranslate_speed = -1\nrotate_speed = 1\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("positive"), "{e}");
        let base = "version = 1\ntranslate_speed = 1\nrotate_speed = 1\n[[profile]]\nname = \"p\"\nfallback = \"mapped\"\nsticks = 1\n";
        let e = JoystickMap::parse(
            &format!("{base}bindings = [{{ stick = 1, role = \"rotate\", gesture = \"x\", source = \"A\" }}]\n"),
            p,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("stick 1"), "{e}");
        let e = JoystickMap::parse(
            &format!("{base}bindings = [{{ stick = 0, role = \"spin\", gesture = \"x\", source = \"A\" }}]\n"),
            p,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("spin") && e.contains("line"), "{e}");
        let e = JoystickMap::parse(
            &format!("{base}bindings = [{{ stick = 0, role = \"rotate\", gesture = \"x\", source = \"A\", dead_zone = 1.5 }}]\n"),
            p,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("dead_zone"), "{e}");
        assert!(JoystickMap::read(Path::new("/nonexistent/map.toml")).is_err());
    }
}
