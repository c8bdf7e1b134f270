//! bump: interactive molecular docking with collision detection, after Greg
//! Turk's 1989 UNC thesis "Interactive Collision Detection for Molecular
//! Graphics".
//!
//! This library is the docking core. It has no window, GPU, joystick or audio
//! dependency: the command line, the tests and the benchmarks drive it directly.
//!
//! - [`model`]: molecules, radii, loading PDB/mmCIF/SDF, the built-in scene.
//! - [`motion`]: poses and screw interpolation.
//! - [`collide`]: the contact rule, colliders, static checks, move-to-touch,
//!   collision responses and grid statistics.
//! - [`scene`]: a receptor and a drug with a collider, the unit the commands use.

pub mod collide;
pub mod model;
pub mod motion;
pub mod scene;
