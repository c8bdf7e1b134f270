//! bump: interactive molecular docking with collision detection, after Greg
//! Turk's 1989 UNC thesis "Interactive Collision Detection for Molecular
//! Graphics".
//!
//! The docking core has no window, GPU, joystick or audio dependency: the
//! command line, the tests and the benchmarks drive it directly, and
//! `cargo build --no-default-features` builds it without linking any shell
//! crate, so an import of the shell from the core does not compile.
//!
//! - [`model`]: molecules, radii, loading PDB/mmCIF/SDF, the built-in scene.
//! - [`chem`]: bonds, bond orders, aromaticity, Vina atom types, rotatable
//!   bonds and the torsion tree, Gasteiger charges.
//! - [`motion`]: poses and screw interpolation.
//! - [`collide`]: the contact rule, colliders, static checks, move-to-touch,
//!   collision responses and grid statistics.
//! - [`scene`]: a receptor and a drug with a collider, the unit the commands use.
//! - [`session`]: the docking session's state machine (modes, selection,
//!   collision settings, undo), stepped one frame at a time.
//!
//! - [`text`]: reading text files: line endings, size limits, short
//!   excerpts of bad input for messages.
//! - [`input`]: the joystick map and the pure mapping from raw axes to
//!   motions (the gilrs device layer, `input::gamepads`, is part of the shell).
//!
//! The shell, behind the default feature `app`, which the core never imports:
//! - `render`: wgpu sphere impostors, offscreen rendering to PNG.
//! - `app`: the docking window (winit, egui HUD, keyboard and mouse, the beep).
//!
//! ```
//! use bump::collide::{ColliderKind, ContactRule, TouchOptions};
//! use bump::model::{RadiiSet, builtin};
//! use bump::scene::Scene;
//! use glam::DVec3;
//!
//! // The thesis's user-study objects: a triple ring and an E.
//! let (rings, e) = builtin::scene(RadiiSet::Bondi);
//! let scene = Scene::new(rings, e, ContactRule::default(), ColliderKind::Hashed);
//! let start = scene.file_relative(DVec3::ZERO);
//! assert!(scene.check(&start).is_empty());
//!
//! // Pushed straight in, the E threads the rings: the whole motion is allowed.
//! let docked = scene.file_relative(builtin::docked_offset());
//! let r = scene.move_to_touch(&start, &docked, &TouchOptions::default());
//! assert_eq!(r.t, 1.0);
//!
//! // Pushed in 5 Å too high, it stops just touching the rings.
//! let high = scene.file_relative(DVec3::new(0.0, 5.0, 0.0));
//! let r = scene.move_to_touch(&high, &high.moved(DVec3::Z * 25.0, DVec3::Z, 0.0), &TouchOptions::default());
//! assert!(r.t < 1.0 && !r.contacts.is_empty() && r.colliding.is_empty());
//! ```

#[cfg(feature = "app")]
pub mod app;
pub mod chem;
pub mod collide;
pub mod dock;
pub mod input;
pub mod model;
pub mod motion;
pub mod pocket;
#[cfg(feature = "app")]
pub mod render;
pub mod rng;
pub mod scene;
pub mod score;
pub mod session;
pub mod text;
