//! The connected controllers and what they ask for, from a stream of raw
//! events: connect, disconnect, an axis or button value.
//!
//! The device layer (`input::gamepads`, in the window's build) only
//! translates its events into [`RawEvent`]s; everything after that is here
//! and pure, so tests drive it with synthetic streams. Devices are kept in
//! id order and grouped into boxes by their profile (a gamepad is a box, flight sticks pair up); each
//! box's velocity comes from [`JoystickMap::box_velocity`]. With one box
//! (the default) every box moves what the session's mode says; with two
//! boxes (`--two-boxes`) the first moves the view and the second the
//! selected molecule.

use std::collections::BTreeMap;

use super::map::JoystickMap;
use crate::session::{FrameInput, Motion6};

/// A device as the device layer describes it.
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceInfo {
    /// Stable id for the session (the device layer's id).
    pub id: usize,
    /// The device's name.
    pub name: String,
    /// The device layer knows it as a gamepad (SDL mapping or a driver mapping with
    /// both sticks).
    pub mapped: bool,
}

/// One thing a device did.
#[derive(Debug, Clone, PartialEq)]
pub enum RawEvent {
    /// A device appeared.
    Connected(DeviceInfo),
    /// A device went away.
    Disconnected(usize),
    /// An axis or button changed: `source` is a standard name or `code:N`.
    Value {
        /// Device id.
        device: usize,
        /// Source name.
        source: String,
        /// New value: −1..1 for axes, 0..1 for buttons.
        value: f64,
    },
}

/// How far beyond ±1 a value may stray (rounding in drivers) before it is
/// treated as garbage and ignored.
const RANGE_SLACK: f64 = 1e-3;

#[derive(Debug, Clone)]
struct Device {
    info: DeviceInfo,
    profile: Option<usize>,
    values: BTreeMap<String, f64>,
}

/// The controllers now connected.
#[derive(Debug, Clone, Default)]
pub struct Controllers {
    devices: Vec<Device>,
    ignored: u64,
}

/// What the controllers ask of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Intents {
    /// Moves what the mode says (one-box use).
    pub velocity: Motion6,
    /// Moves the view (two-box use, first box).
    pub view_velocity: Motion6,
    /// Moves the selected molecule (two-box use, second box).
    pub object_velocity: Motion6,
}

impl Intents {
    /// Puts these velocities into a frame's input (added to what is there).
    pub fn add_to(&self, input: &mut FrameInput) {
        input.velocity = input.velocity.plus(&self.velocity);
        input.view_velocity = input.view_velocity.plus(&self.view_velocity);
        input.object_velocity = input.object_velocity.plus(&self.object_velocity);
    }

    /// The torsion mode of the rotation stick: the rotation that would
    /// move the molecule (one box's, or the second box's with two) turns
    /// the selected rotatable bond instead. Returns the intents without
    /// that rotation and the bond's turn, degrees per second: the rotation
    /// vector's largest component, with its sign, so any gesture of the
    /// stick turns the bond and the opposite gesture turns it back.
    pub fn turning_torsion(&self) -> (Intents, f64) {
        let mut out = *self;
        let r = self.velocity.rotate + self.object_velocity.rotate;
        out.velocity.rotate = glam::DVec3::ZERO;
        out.object_velocity.rotate = glam::DVec3::ZERO;
        let a = r.abs();
        let largest = if a.x >= a.y && a.x >= a.z {
            r.x
        } else if a.y >= a.z {
            r.y
        } else {
            r.z
        };
        (out, largest.to_degrees())
    }

    /// True when no stick is deflected.
    pub fn is_zero(&self) -> bool {
        self.velocity.is_zero() && self.view_velocity.is_zero() && self.object_velocity.is_zero()
    }
}

impl Controllers {
    /// Applies one event; returns a message for the user when something
    /// worth saying happened (a device came or went).
    pub fn apply(&mut self, map: &JoystickMap, event: RawEvent) -> Option<String> {
        match event {
            RawEvent::Connected(info) => {
                self.devices.retain(|d| d.info.id != info.id);
                let profile = map.profile_for(&info.name, info.mapped);
                let msg = match profile {
                    Some(p) => format!(
                        "controller connected: {} (as {})",
                        info.name, map.profiles[p].name
                    ),
                    None => format!(
                        "controller connected: {} (no profile in the joystick map fits it: ignored)",
                        info.name
                    ),
                };
                let at = self.devices.partition_point(|d| d.info.id < info.id);
                self.devices.insert(
                    at,
                    Device {
                        info,
                        profile,
                        values: BTreeMap::new(),
                    },
                );
                Some(msg)
            }
            RawEvent::Disconnected(id) => {
                let k = self.devices.iter().position(|d| d.info.id == id)?;
                let d = self.devices.remove(k);
                Some(format!("controller disconnected: {}", d.info.name))
            }
            RawEvent::Value {
                device,
                source,
                value,
            } => {
                if !value.is_finite() || value.abs() > 1.0 + RANGE_SLACK {
                    self.ignored += 1;
                    return None;
                }
                if let Some(d) = self.devices.iter_mut().find(|d| d.info.id == device) {
                    d.values.insert(source, value.clamp(-1.0, 1.0));
                }
                None
            }
        }
    }

    /// Values dropped as non-finite or out of range so far.
    pub fn ignored(&self) -> u64 {
        self.ignored
    }

    /// Connected devices, in id order.
    pub fn devices(&self) -> impl Iterator<Item = &DeviceInfo> {
        self.devices.iter().map(|d| &d.info)
    }

    /// How many devices are connected.
    pub fn len(&self) -> usize {
        self.devices.len()
    }

    /// True when none is.
    pub fn is_empty(&self) -> bool {
        self.devices.is_empty()
    }

    /// The boxes, in id order: each a profile and its devices' indices. A
    /// two-stick profile pairs each device with the next one of the same
    /// profile; a leftover one is half a box (it translates only).
    fn boxes(&self, map: &JoystickMap) -> Vec<(usize, Vec<usize>)> {
        let mut boxes: Vec<(usize, Vec<usize>)> = Vec::new();
        // profile -> the box still waiting for its second stick
        let mut open: BTreeMap<usize, usize> = BTreeMap::new();
        for (k, d) in self.devices.iter().enumerate() {
            let Some(p) = d.profile else { continue };
            let Some(prof) = map.profiles.get(p) else {
                continue;
            };
            if let Some(b) = open.remove(&p) {
                boxes[b].1.push(k);
            } else {
                boxes.push((p, vec![k]));
                if prof.sticks == 2 {
                    open.insert(p, boxes.len() - 1);
                }
            }
        }
        boxes
    }

    /// What the controllers ask for now, as velocities per second.
    pub fn intents(&self, map: &JoystickMap, two_boxes: bool) -> Intents {
        let mut out = Intents::default();
        for (n, (p, members)) in self.boxes(map).iter().enumerate() {
            let sticks: Vec<&BTreeMap<String, f64>> =
                members.iter().map(|&k| &self.devices[k].values).collect();
            let v = map.box_velocity(&map.profiles[*p], &sticks);
            if !two_boxes {
                out.velocity = out.velocity.plus(&v);
            } else if n == 0 {
                out.view_velocity = v;
            } else if n == 1 {
                out.object_velocity = v;
            }
        }
        out
    }

    /// Each box as the names of its devices, in box order (box 0 moves the
    /// view with two boxes).
    pub fn describe_boxes(&self, map: &JoystickMap) -> Vec<Vec<String>> {
        self.boxes(map)
            .into_iter()
            .map(|(_, m)| {
                m.iter()
                    .map(|&k| self.devices[k].info.name.clone())
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use glam::DVec3;

    fn connect(
        c: &mut Controllers,
        m: &JoystickMap,
        id: usize,
        name: &str,
        mapped: bool,
    ) -> String {
        c.apply(
            m,
            RawEvent::Connected(DeviceInfo {
                id,
                name: name.into(),
                mapped,
            }),
        )
        .unwrap()
    }

    fn set(c: &mut Controllers, m: &JoystickMap, device: usize, source: &str, value: f64) {
        assert!(
            c.apply(
                m,
                RawEvent::Value {
                    device,
                    source: source.into(),
                    value
                }
            )
            .is_none()
        );
    }

    #[test]
    fn one_box_moves_what_the_mode_says_two_boxes_split_view_and_object() {
        let m = JoystickMap::default();
        let mut c = Controllers::default();
        let msg = connect(&mut c, &m, 3, "Xbox Controller", true);
        assert!(msg.contains("standard gamepad"), "{msg}");
        connect(&mut c, &m, 7, "Other Pad", true);
        set(&mut c, &m, 3, "LeftStickX", 1.0);
        set(&mut c, &m, 7, "LeftStickY", 1.0);
        let s = m.translate_speed;
        let one = c.intents(&m, false);
        assert_eq!(one.velocity.translate, DVec3::new(s, s, 0.0));
        assert!(one.view_velocity.is_zero() && one.object_velocity.is_zero());
        let two = c.intents(&m, true);
        assert!(two.velocity.is_zero());
        assert_eq!(two.view_velocity.translate, DVec3::new(s, 0.0, 0.0));
        assert_eq!(two.object_velocity.translate, DVec3::new(0.0, s, 0.0));
        let mut input = FrameInput::default();
        two.add_to(&mut input);
        assert_eq!(input.view_velocity, two.view_velocity);
    }

    #[test]
    fn the_torsion_mode_turns_the_bond_with_the_molecules_rotation() {
        let m = JoystickMap::default();
        let mut c = Controllers::default();
        connect(&mut c, &m, 5, "T.16000M rotation", false);
        connect(&mut c, &m, 2, "T.16000M translation", false);
        set(&mut c, &m, 2, "LeftStickX", 1.0);
        set(&mut c, &m, 5, "RightZ", -1.0);
        let i = c.intents(&m, false);
        let (rest, turn) = i.turning_torsion();
        assert!((turn + m.rotate_speed).abs() < 1e-9, "{turn}");
        assert_eq!(rest.velocity.translate, i.velocity.translate);
        assert!(rest.velocity.rotate == DVec3::ZERO);
        // With two boxes the view box keeps its rotation.
        let two = Intents {
            view_velocity: Motion6 {
                translate: DVec3::ZERO,
                rotate: DVec3::new(0.3, 0.0, 0.0),
            },
            object_velocity: Motion6 {
                translate: DVec3::X,
                rotate: DVec3::new(0.1, -0.5, 0.2),
            },
            ..Intents::default()
        };
        let (rest, turn) = two.turning_torsion();
        assert_eq!(turn, (-0.5f64).to_degrees());
        assert_eq!(rest.view_velocity, two.view_velocity);
        assert_eq!(rest.object_velocity.translate, DVec3::X);
        assert!(rest.object_velocity.rotate == DVec3::ZERO);
        assert_eq!(Intents::default().turning_torsion().1, 0.0);
    }

    #[test]
    fn flight_sticks_pair_in_id_order() {
        let m = JoystickMap::default();
        let mut c = Controllers::default();
        // Connected out of order: the lower id is the translation stick.
        connect(&mut c, &m, 5, "T.16000M rotation", false);
        connect(&mut c, &m, 2, "T.16000M translation", false);
        assert_eq!(
            c.describe_boxes(&m),
            vec![vec![
                "T.16000M translation".to_string(),
                "T.16000M rotation".to_string()
            ]]
        );
        set(&mut c, &m, 2, "LeftStickX", 1.0);
        set(&mut c, &m, 5, "RightZ", 1.0);
        let v = c.intents(&m, false).velocity;
        assert_eq!(v.translate, DVec3::new(m.translate_speed, 0.0, 0.0));
        assert_eq!(v.rotate, DVec3::new(0.0, m.rotate_speed.to_radians(), 0.0));
    }

    #[test]
    fn hot_plug_and_bad_values_never_disturb_the_state() {
        let m = JoystickMap::default();
        let mut c = Controllers::default();
        connect(&mut c, &m, 1, "Pad", true);
        set(&mut c, &m, 1, "LeftStickX", 0.9);
        let before = c.intents(&m, false);
        assert!(!before.is_zero());
        // NaN, infinities and values far beyond the range are dropped.
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1.5, -40.0] {
            set(&mut c, &m, 1, "LeftStickX", bad);
        }
        assert_eq!(c.ignored(), 5);
        assert_eq!(c.intents(&m, false), before);
        // A hair beyond 1 (driver rounding) counts as full deflection.
        set(&mut c, &m, 1, "LeftStickX", 1.0005);
        assert_eq!(c.intents(&m, false).velocity.translate.x, m.translate_speed);
        // Values for unknown devices are ignored quietly.
        set(&mut c, &m, 99, "LeftStickX", 1.0);
        // Unplugging stops its motion; a second unplug says nothing.
        let msg = c.apply(&m, RawEvent::Disconnected(1)).unwrap();
        assert!(msg.contains("disconnected: Pad"));
        assert!(c.apply(&m, RawEvent::Disconnected(1)).is_none());
        assert!(c.intents(&m, false).is_zero());
        assert!(c.is_empty());
        // Plugged back in, it starts from rest.
        connect(&mut c, &m, 1, "Pad", true);
        assert!(c.intents(&m, false).is_zero());
    }

    #[test]
    fn a_device_no_profile_fits_is_reported_and_ignored() {
        let mut m = JoystickMap::default();
        m.profiles
            .retain(|p| p.fallback != Some(super::super::map::Fallback::Unmapped));
        let mut c = Controllers::default();
        let msg = connect(&mut c, &m, 1, "Weird Box", false);
        assert!(msg.contains("ignored"), "{msg}");
        set(&mut c, &m, 1, "code:196608", 1.0);
        assert!(c.intents(&m, false).is_zero());
    }
}
