//! The renderer: ray-cast sphere impostors with wgpu (shell code).
//!
//! It reads the docking session's state and decides nothing about docking.
//! Atom data go to the GPU once; a molecule's move changes one model-view
//! matrix; a contact change rewrites only the highlight words that changed.
//! [`offscreen`] renders without a window, to pixels or a PNG. Depth cues
//! ([`cues`]) and stereo ([`stereo`]) are per-frame settings in
//! [`ViewParams`]; a cue that is off costs no pass, pipeline or texture.
//! Colour by contribution ([`contrib`]) rewrites only the atoms whose
//! quantised colour changed. Ball-and-stick ([`sticks`]) shrinks the
//! pocket's atoms and draws its bonds and the hydrogen bonds as cylinder
//! impostors ([`cylinders`]), uploading the bond list only when it changes.
//! The [`ghost`] of the reference pose and the clipping [`slab`] are
//! per-frame settings.

pub mod colors;
pub mod contrib;
pub mod cues;
pub mod cylinders;
pub mod dashes;
pub mod ghost;
pub mod gpu;
pub mod offscreen;
pub mod pipelines;
pub mod slab;
pub mod spheres;
pub mod stereo;
pub mod sticks;
pub mod view;

use thiserror::Error;

pub use cues::Cues;
pub use gpu::Gpu;
pub use spheres::{FrameStats, SphereRenderer};
pub use stereo::{Stereo, StereoMode};
pub use view::ViewParams;

/// Why rendering could not happen.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No GPU or software adapter could be found.
    #[error(
        "no graphics adapter: {0} (install Mesa's Vulkan driver, e.g. `apt-get install mesa-vulkan-drivers`, for CPU rendering)"
    )]
    NoAdapter(String),
    /// The adapter refused a device.
    #[error("cannot open the graphics device: {0}")]
    Device(String),
    /// Reading the rendered image back failed.
    #[error("cannot read the rendered image back: {0}")]
    Readback(String),
    /// The image size is unusable.
    #[error("image size {0}x{1} is not between 1x1 and 8192x8192")]
    Size(u32, u32),
    /// Writing the image failed.
    #[error("{path}: cannot write the image: {reason}")]
    Write {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}
