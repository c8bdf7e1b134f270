//! A rigid pose in f64: a rotation about the molecule's own centre followed by
//! the placement of that centre.
//!
//! A molecule's atoms are stored relative to its centre, so a pose maps
//! molecule-local coordinates to the frame it is expressed in:
//! `x = rotation * local + translation`. `translation` is therefore where the
//! centre sits. Poses compose in f64 so that coordinates far from the origin
//! (10^5 Å) keep their sub-micro-ångström precision.

use glam::{DQuat, DVec3};
use serde::Serialize;

/// Largest coordinate a pose may reach, Å. Collision math runs in the
/// receptor's frame, so a far scene enters only through one f64 composition
/// of world poses, whose rounding is |x|·2⁻⁵² ≈ 2·10⁻⁷ Å at 10⁹ Å: still far
/// below the f32 rounding of atom coordinates (10⁻⁶ Å) and the touch
/// tolerance (10⁻³ Å). Beyond it the session refuses to move a molecule.
pub const MAX_COORDINATE: f64 = 1e9;

/// Rotation (unit quaternion) and translation, both f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Orientation; applied about the molecule's centre.
    pub rotation: DQuat,
    /// Position of the molecule's centre.
    pub translation: DVec3,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// No rotation, centre at the origin.
    pub const IDENTITY: Pose = Pose {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A pose from its parts; the rotation is normalised.
    pub fn new(rotation: DQuat, translation: DVec3) -> Self {
        Self {
            rotation: rotation.normalize(),
            translation,
        }
    }

    /// A pure translation.
    pub fn from_translation(translation: DVec3) -> Self {
        Self {
            rotation: DQuat::IDENTITY,
            translation,
        }
    }

    /// Maps a molecule-local point into this pose's frame.
    #[inline]
    pub fn transform_point(&self, local: DVec3) -> DVec3 {
        self.rotation * local + self.translation
    }

    /// The inverse pose.
    pub fn inverse(&self) -> Self {
        let inv = self.rotation.conjugate();
        Self {
            rotation: inv,
            translation: -(inv * self.translation),
        }
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn compose(&self, other: &Pose) -> Self {
        Self {
            rotation: (self.rotation * other.rotation).normalize(),
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// This pose moved by `translation` of the centre and a rotation of
    /// `angle_rad` about `axis` through the centre (the axis need not be unit
    /// length; a zero axis means no rotation).
    pub fn moved(&self, translation: DVec3, axis: DVec3, angle_rad: f64) -> Self {
        let q = if axis.length_squared() > 0.0 && angle_rad != 0.0 {
            DQuat::from_axis_angle(axis.normalize(), angle_rad)
        } else {
            DQuat::IDENTITY
        };
        Self {
            rotation: (q * self.rotation).normalize(),
            translation: self.translation + translation,
        }
    }

    /// The pose reached from this one after unit time under the constant
    /// twist with angular velocity `w` (rad) and velocity `v` (Å) at the
    /// centre. [`super::Screw::between`] this pose and the result moves
    /// with exactly that twist (for `|w| < π`), so every atom starts along
    /// `v + w × (x − centre)`; [`Pose::moved`] by the same `v` and `w` would
    /// move the centre along the chord `v` of its arc, which starts in
    /// another direction.
    pub fn twisted(&self, v: DVec3, w: DVec3) -> Self {
        let theta = w.length();
        // The centre moves by J·v, J the left Jacobian of the rotations:
        // I + (1 − cos θ)/θ² [w]× + (θ − sin θ)/θ³ [w]×², whose
        // coefficients lose their digits to cancellation at small θ (where
        // their series are exact to rounding).
        let (a, b) = if theta < 1e-2 {
            let t2 = theta * theta;
            (
                0.5 - t2 / 24.0 + t2 * t2 / 720.0,
                1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0,
            )
        } else {
            (
                (1.0 - theta.cos()) / (theta * theta),
                (theta - theta.sin()) / (theta * theta * theta),
            )
        };
        let wv = w.cross(v);
        self.moved(v + wv * a + w.cross(wv) * b, w, theta)
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.rotation.is_finite() && self.translation.is_finite()
    }

    /// True when the centre is within [`MAX_COORDINATE`] of the origin on every axis.
    pub fn within_range(&self) -> bool {
        self.translation.abs().max_element() <= MAX_COORDINATE
    }

    /// The rotation as a unit axis and an angle in degrees in [0, 180].
    pub fn axis_angle_deg(&self) -> (DVec3, f64) {
        let mut q = self.rotation.normalize();
        if q.w < 0.0 {
            q = -q;
        }
        let v = DVec3::new(q.x, q.y, q.z);
        let s = v.length();
        if s == 0.0 {
            return (DVec3::X, 0.0);
        }
        (v / s, 2.0 * s.atan2(q.w).to_degrees())
    }

    /// A serialisable summary: centre, rotation axis, angle and quaternion.
    pub fn summary(&self) -> PoseSummary {
        let (axis, angle_deg) = self.axis_angle_deg();
        PoseSummary {
            centre: self.translation.to_array(),
            axis: axis.to_array(),
            angle_deg,
            quaternion_xyzw: self.rotation.to_array(),
        }
    }
}

/// A pose as reported by the command line.
#[derive(Debug, Clone, Serialize)]
pub struct PoseSummary {
    /// Where the centre is.
    pub centre: [f64; 3],
    /// Rotation axis (unit).
    pub axis: [f64; 3],
    /// Rotation angle in degrees.
    pub angle_deg: f64,
    /// The rotation quaternion, x y z w.
    pub quaternion_xyzw: [f64; 4],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_and_compose_round_trip() {
        let p = Pose::new(
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            DVec3::new(1e5, -2.0, 3.5),
        );
        let x = DVec3::new(0.3, -1.2, 7.0);
        let back = p.inverse().transform_point(p.transform_point(x));
        assert!((back - x).length() < 1e-9);
        let id = p.compose(&p.inverse());
        assert!(id.translation.length() < 1e-9);
    }

    #[test]
    fn moved_rotates_about_the_centre() {
        let p = Pose::from_translation(DVec3::new(10.0, 0.0, 0.0));
        let q = p.moved(DVec3::ZERO, DVec3::Z, std::f64::consts::FRAC_PI_2);
        assert_eq!(q.translation, p.translation);
        let x = q.transform_point(DVec3::X);
        assert!((x - DVec3::new(10.0, 1.0, 0.0)).length() < 1e-12);
        let (axis, deg) = q.axis_angle_deg();
        assert!((deg - 90.0).abs() < 1e-9 && (axis - DVec3::Z).length() < 1e-12);
    }
}
