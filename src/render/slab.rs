//! The clipping slab: two planes of constant depth, a chosen thickness
//! apart, centred on the drug's centre, between which the scene is drawn
//! (ChimeraX's near/far clip, PyMOL's slab) — a buried pocket seen without
//! making the receptor translucent.
//!
//! The planes go to the shaders in the frame uniform (mono view-space
//! depths); the sphere shader draws a clipped sphere's cut face flat on the
//! near plane and drops whatever lies beyond the far one, and the shadow
//! map drops what the slab removes. Any impostor shader clips with the same
//! test (`slab_cut` in `shaders/spheres.wgsl`).

use crate::session::Session;

/// Default thickness, Å.
pub const DEFAULT_THICKNESS: f64 = 10.0;
/// Thinnest slab, Å.
pub const MIN_THICKNESS: f64 = 1.0;
/// Thickest slab, Å.
pub const MAX_THICKNESS: f64 = 200.0;
/// How much one key press or wheel notch changes the thickness, Å.
pub const STEP: f64 = 1.0;

/// A clipping slab.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slab {
    /// Thickness, Å (kept within [`MIN_THICKNESS`]..=[`MAX_THICKNESS`]).
    pub thickness: f64,
}

impl Default for Slab {
    fn default() -> Self {
        Self {
            thickness: DEFAULT_THICKNESS,
        }
    }
}

impl Slab {
    /// A slab `thickness` Å thick, bounded to the allowed range (a
    /// non-finite thickness gives the default).
    pub fn new(thickness: f64) -> Self {
        let t = if thickness.is_finite() {
            thickness.clamp(MIN_THICKNESS, MAX_THICKNESS)
        } else {
            DEFAULT_THICKNESS
        };
        Self { thickness: t }
    }

    /// This slab made `steps` steps of [`STEP`] thicker (negative: thinner).
    pub fn thicker(self, steps: f64) -> Self {
        Self::new(self.thickness + steps * STEP)
    }

    /// The near and far planes as mono view-space z (the eye looks down
    /// −z, so near > far), centred on the drug's centre (the view centre
    /// without a drug).
    pub fn planes(&self, session: &Session) -> (f64, f64) {
        let view = session.view_camera().view_matrix();
        let centre = session
            .drug()
            .and_then(|d| session.bodies().get(d))
            .map_or(-session.view_camera().distance, |b| {
                view.transform_point3(b.pose.translation).z
            });
        let h = 0.5 * self.thickness;
        (centre + h, centre - h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};
    use crate::session::Settings;

    #[test]
    fn the_slab_is_centred_on_the_drug_and_bounded() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let s = Session::new(vec![rings, e], Settings::default()).expect("session");
        let (near, far) = Slab::default().planes(&s);
        assert!((near - far - DEFAULT_THICKNESS).abs() < 1e-12);
        let view = s.view_camera().view_matrix();
        let z = view.transform_point3(s.bodies()[1].pose.translation).z;
        assert!((0.5 * (near + far) - z).abs() < 1e-9);
        assert_eq!(Slab::new(0.1).thickness, MIN_THICKNESS);
        assert_eq!(Slab::new(f64::NAN).thickness, DEFAULT_THICKNESS);
        assert_eq!(Slab::default().thicker(-2.0).thickness, 8.0);
        assert_eq!(Slab::new(1e9).thickness, MAX_THICKNESS);
    }
}
