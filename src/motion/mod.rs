//! Rigid motion: poses in f64 and the screw interpolation between two poses
//! that move-to-touch sweeps along.

pub mod pose;
pub mod screw;

pub use pose::{MAX_COORDINATE, Pose};
pub use screw::Screw;
