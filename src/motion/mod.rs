//! Rigid motion: poses in f64 and the screw interpolation between two poses
//! that move-to-touch sweeps along, and the view's rocking.

pub mod pose;
pub mod range;
pub mod rock;
pub mod screw;

pub use pose::{MAX_COORDINATE, Pose};
pub use rock::Rock;
pub use screw::Screw;
