//! Joysticks and gamepads: raw device events → 6-DOF velocities.
//!
//! - [`map`]: the joystick map (TOML) and the pure function from raw axis
//!   values to a box's velocity: dead zones, curves, signs, the thesis's and
//!   its users' rotation mappings.
//! - [`controllers`]: the connected devices and their latest values, from a
//!   stream of raw events (hot-plug included); grouping into boxes; one box
//!   or two.
//! - `gamepads` (feature `app`): the only part that talks to gilrs.
//!
//! Keyboard and mouse are translated in the window's key map (`app::keymap`) and the
//! window; everything meets in a [`crate::session::FrameInput`].

pub mod controllers;
#[cfg(feature = "app")]
pub mod gamepads;
pub mod map;

pub use controllers::{Controllers, DeviceInfo, Intents, RawEvent};
pub use map::{JoystickMap, MapError, RotationMapping};
