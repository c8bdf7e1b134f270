//! Screw interpolation between two poses of one molecule.
//!
//! Any rigid displacement is a rotation by θ about some axis plus a slide
//! along that axis (Chasles). Interpolating θ and the slide linearly in `t`
//! gives the screw motion from the start pose (t = 0) to the end pose (t = 1):
//! the motion of a body under a constant twist. Every atom then moves along a
//! helix at constant speed, which is what makes conservative advancement in
//! [`crate::collide::sweep`] both simple and rigorous: the speed of atom `i`
//! is an exact Lipschitz bound on its distance to any fixed point.
//!
//! The centre's path is written without the screw axis' location so that tiny
//! rotations (10^-9 degrees) stay exact: with `y` an atom's offset from the
//! start centre `c0`, `d` the centre's displacement split into `d_par` (along
//! the axis `u`) and `d_perp`,
//!
//! `x(t) = c0 + R(θt) y + α(t) d_perp + β(t) (u × d_perp) + t d_par`
//!
//! with `α(t) = sin²(θt/2) + ½ sin(θt) / tan(θ/2)` and
//! `β(t) = sin²(θt/2) / tan(θ/2) − ½ sin(θt)`; `α(1) = 1`, `β(1) = 0`, and for
//! θ → 0 they tend to `t` and `0` without cancellation.
//! The rotation taken is the shorter one (θ ≤ 180°).

use glam::{DQuat, DVec3};

use super::Pose;

/// Turns below this angle (radians) are taken as none: an atom 100 Å from
/// the centre would move 10⁻¹¹ Å, far inside the smallest move-to-touch
/// tolerance, while the rounding left by composing and normalising unit
/// quaternions is about 10⁻¹⁵.
pub const MIN_ANGLE: f64 = 1e-13;

/// The screw motion from one pose to another.
#[derive(Debug, Clone, Copy)]
pub struct Screw {
    start: Pose,
    end: Pose,
    /// Unit rotation axis (X when there is no rotation).
    axis: DVec3,
    /// Rotation angle in radians, in [0, π].
    angle: f64,
    d_par: DVec3,
    d_perp: DVec3,
    u_x_dperp: DVec3,
    /// 1 / tan(θ/2), or 0 when θ = 0 (unused then).
    cot_half: f64,
    /// Velocity of the start centre (per unit t).
    v0: DVec3,
}

impl Screw {
    /// The screw motion taking `start` to `end`.
    pub fn between(start: Pose, end: Pose) -> Self {
        // The usual step keeps the drug's orientation: no relative rotation
        // to compute (a quaternion product, a normalisation and a length).
        if end.rotation == start.rotation {
            return Self::translation(start, end);
        }
        let mut q = (end.rotation * start.rotation.conjugate()).normalize();
        if q.w < 0.0 {
            q = -q;
        }
        let v = DVec3::new(q.x, q.y, q.z);
        let s = v.length();
        // The angle is 2·atan2(s, w) ≈ 2s for small s: below 0.4·MIN_ANGLE
        // it is under MIN_ANGLE, and the arc tangent can be skipped (the
        // usual case: a step that does not turn the drug).
        let angle = if s > 0.4 * MIN_ANGLE {
            2.0 * s.atan2(q.w)
        } else {
            0.0
        };
        // A turn too small to move an atom measurably is a translation:
        // a pure translation from a turned pose often leaves the relative
        // rotation a rounding error away from the identity, and treating
        // that as a screw would cost every query the screw's arithmetic.
        if !(angle > MIN_ANGLE && s.is_finite()) {
            return Self::translation(start, end);
        }
        let axis = v / s;
        let d = end.translation - start.translation;
        let d_par = axis * axis.dot(d);
        let d_perp = d - d_par;
        let u_x_dperp = axis.cross(d_perp);
        let half = 0.5 * angle;
        let cot_half = half.cos() / half.sin();
        // α'(0) = (θ/2)·cot(θ/2) → 1 as θ → 0; β'(0) = −θ/2.
        let v0 = d_par + d_perp * (half * cot_half) - u_x_dperp * half;
        Self {
            start,
            end,
            axis,
            angle,
            d_par,
            d_perp,
            u_x_dperp,
            cot_half,
            v0,
        }
    }

    /// The pure translation from `start` to `end` (their rotations equal,
    /// or a turn too small to count apart): the axis is X, nominally.
    fn translation(start: Pose, end: Pose) -> Self {
        let d = end.translation - start.translation;
        let d_par = DVec3::new(d.x, 0.0, 0.0);
        let d_perp = d - d_par;
        Self {
            start,
            end,
            axis: DVec3::X,
            angle: 0.0,
            d_par,
            d_perp,
            u_x_dperp: DVec3::X.cross(d_perp),
            cot_half: 0.0,
            v0: d,
        }
    }

    /// The start pose.
    pub fn start(&self) -> &Pose {
        &self.start
    }

    /// The end pose.
    pub fn end(&self) -> &Pose {
        &self.end
    }

    /// Rotation angle in radians (0..=π).
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// Unit rotation axis.
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// A point on the screw axis (the line the rotation turns about), or `None`
    /// for a pure translation.
    pub fn axis_point(&self) -> Option<DVec3> {
        (self.angle > 0.0)
            .then(|| self.start.translation + (self.d_perp + self.u_x_dperp * self.cot_half) * 0.5)
    }

    /// Translation along the screw axis over the whole motion.
    pub fn slide(&self) -> DVec3 {
        self.d_par
    }

    /// True when the motion has no rotation.
    pub fn is_translation(&self) -> bool {
        self.angle == 0.0
    }

    /// Where the centre is at `t`.
    pub fn centre_at(&self, t: f64) -> DVec3 {
        let c0 = self.start.translation;
        if self.angle == 0.0 {
            return c0 + self.v0 * t;
        }
        let phi = self.angle * t;
        let sh = (0.5 * phi).sin();
        let sin2 = sh * sh;
        let alpha = sin2 + 0.5 * phi.sin() * self.cot_half;
        let beta = sin2 * self.cot_half - 0.5 * phi.sin();
        c0 + self.d_perp * alpha + self.u_x_dperp * beta + self.d_par * t
    }

    /// The rotation accumulated by `t` (applied before the start orientation).
    pub fn rotation_at(&self, t: f64) -> DQuat {
        if self.angle == 0.0 {
            DQuat::IDENTITY
        } else {
            DQuat::from_axis_angle(self.axis, self.angle * t)
        }
    }

    /// The pose at `t`; exactly the end pose at `t = 1` and the start at `t = 0`.
    pub fn pose_at(&self, t: f64) -> Pose {
        if t == 0.0 {
            return self.start;
        }
        if t == 1.0 {
            return self.end;
        }
        if self.angle == 0.0 {
            // Nothing turns: no quaternion product and normalisation.
            return Pose {
                rotation: self.start.rotation,
                translation: self.centre_at(t),
            };
        }
        Pose {
            rotation: (self.rotation_at(t) * self.start.rotation).normalize(),
            translation: self.centre_at(t),
        }
    }

    /// Where a point at offset `y` from the start centre (already rotated by
    /// the start orientation) is at `t`.
    #[inline]
    pub fn point_at(&self, y: DVec3, rotation_t: DQuat, centre_t: DVec3) -> DVec3 {
        rotation_t * y + centre_t
    }

    /// Velocity (per unit t) of the material point that is at `p` at any time:
    /// a screw's velocity field is fixed in space.
    #[inline]
    pub fn velocity_at(&self, p: DVec3) -> DVec3 {
        self.axis.cross(p - self.start.translation) * self.angle + self.v0
    }

    /// The constant speed (per unit t) of a point at offset `y` from the
    /// start centre.
    #[inline]
    pub fn speed(&self, y: DVec3) -> f64 {
        (self.axis.cross(y) * self.angle + self.v0).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_twisted_pose_is_reached_by_the_screw_of_that_twist() {
        let from = Pose::new(
            DQuat::from_axis_angle(DVec3::new(0.2, 1.0, -0.4).normalize(), 0.4),
            DVec3::new(3.0, -1e4, 2.0),
        );
        for (v, w) in [
            (DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO),
            (DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.0, 0.0, 1e-9)),
            (DVec3::new(-2.0, 0.5, 1.0), DVec3::new(1e-3, -2e-3, 5e-3)),
            (DVec3::new(-2.0, 0.5, 1.0), DVec3::new(0.3, 0.1, -0.2)),
            (DVec3::new(0.0, 7.0, 0.0), DVec3::new(2.0, 0.5, -1.5)),
        ] {
            let screw = Screw::between(from, from.twisted(v, w));
            let v0 = screw.velocity_at(from.translation);
            let w0 = screw.axis() * screw.angle();
            assert!((v0 - v).length() < 1e-9, "{v} {w}: starts along {v0}");
            assert!((w0 - w).length() < 1e-12, "{v} {w}: turns {w0}");
        }
    }

    fn sample_screws() -> Vec<Screw> {
        let a = Pose::new(
            DQuat::from_axis_angle(DVec3::new(0.2, 1.0, -0.4).normalize(), 0.4),
            DVec3::new(3.0, -1.0, 2.0),
        );
        let mut out = Vec::new();
        for (axis, ang, d) in [
            (DVec3::Z, 0.0, DVec3::new(1.0, 2.0, 3.0)),
            (DVec3::new(1.0, 1.0, 0.0), 1e-11, DVec3::new(1.0, 0.0, 0.0)),
            (DVec3::new(1.0, -2.0, 0.5), 0.8, DVec3::new(-2.0, 0.5, 1.0)),
            (DVec3::Y, 3.0, DVec3::new(0.0, 0.0, 5.0)),
            (DVec3::X, 2.5, DVec3::ZERO),
        ] {
            out.push(Screw::between(a, a.moved(d, axis, ang)));
        }
        out
    }

    #[test]
    fn ends_match_and_speed_is_constant() {
        let y = DVec3::new(1.5, -0.7, 2.2);
        for s in sample_screws() {
            let end = s.pose_at(1.0);
            let mid_end = Pose {
                rotation: (s.rotation_at(1.0) * s.start().rotation).normalize(),
                translation: s.centre_at(1.0),
            };
            assert!((mid_end.translation - end.translation).length() < 1e-9);
            let p_end = end.transform_point(DVec3::new(0.3, 0.1, -0.2));
            let p_mid = mid_end.transform_point(DVec3::new(0.3, 0.1, -0.2));
            assert!((p_end - p_mid).length() < 1e-9, "{p_end} vs {p_mid}");
            // Finite differences of the path equal the analytic speed everywhere.
            let v = s.speed(y);
            for k in 0..10 {
                let t = k as f64 / 10.0;
                let h = 1e-6;
                let at = |t: f64| s.point_at(y, s.rotation_at(t), s.centre_at(t));
                let fd = (at(t + h) - at(t - h)).length() / (2.0 * h);
                assert!((fd - v).abs() < 1e-5 * (1.0 + v), "fd {fd} vs {v}");
                let vel = s.velocity_at(at(t));
                let fdv = (at(t + h) - at(t - h)) / (2.0 * h);
                assert!((vel - fdv).length() < 1e-5 * (1.0 + v));
            }
        }
    }

    #[test]
    fn axis_point_is_fixed_up_to_the_slide() {
        for s in sample_screws() {
            // A tiny rotation puts the axis ~1e17 Å away: nothing to check there.
            let Some(a) = s.axis_point().filter(|_| s.angle() > 1e-6) else {
                continue;
            };
            for t in [0.0, 0.3, 0.8, 1.0] {
                let y = a - s.start().translation;
                let p = s.point_at(y, s.rotation_at(t), s.centre_at(t));
                assert!((p - (a + s.slide() * t)).length() < 1e-9, "{p} vs {a}");
            }
        }
    }

    /// Moving a turned pose without turning it leaves the relative rotation
    /// a rounding error from the identity: that is a translation, whose end
    /// is still exactly the end pose. A turn of 10⁻¹¹ rad is not.
    #[test]
    fn rounding_sized_turns_are_translations() {
        let a = Pose::new(
            DQuat::from_axis_angle(DVec3::new(0.3, -1.0, 0.7).normalize(), 2.1),
            DVec3::new(4.0, 1.0, -3.0),
        );
        let mut b = a;
        for k in 0..100 {
            b = b.moved(DVec3::new(0.1, -0.2, 0.05 * f64::from(k)), DVec3::Y, 0.0);
        }
        let s = Screw::between(a, b);
        assert!(s.is_translation(), "angle {}", s.angle());
        assert_eq!(s.pose_at(1.0), b);
        assert!((s.centre_at(1.0) - b.translation).length() < 1e-12);
        let turned = Screw::between(a, a.moved(DVec3::X, DVec3::Z, 1e-11));
        assert!(!turned.is_translation());
    }

    /// Skipping the arc tangent for tiny turns changes no answer: around
    /// `MIN_ANGLE`, from a turned start, a motion is a translation exactly
    /// when the angle the arc tangent gives is not above it.
    #[test]
    fn tiny_turns_are_classified_as_the_arc_tangent_says() {
        let a = Pose::new(
            DQuat::from_axis_angle(DVec3::new(-0.4, 0.2, 1.0).normalize(), 1.3),
            DVec3::new(-2.0, 5.0, 1.0),
        );
        let axis = DVec3::new(0.6, 0.8, 0.0);
        let (mut screws, mut translations) = (0, 0);
        for k in 0..=400 {
            let theta = MIN_ANGLE * (0.2 + 0.01 * f64::from(k));
            let b = Pose::new(
                (DQuat::from_axis_angle(axis, theta) * a.rotation).normalize(),
                a.translation + DVec3::new(0.5, 0.0, -0.25),
            );
            let mut q = (b.rotation * a.rotation.conjugate()).normalize();
            if q.w < 0.0 {
                q = -q;
            }
            let angle = 2.0 * DVec3::new(q.x, q.y, q.z).length().atan2(q.w);
            let s = Screw::between(a, b);
            assert_eq!(
                s.is_translation(),
                angle <= MIN_ANGLE,
                "θ {theta}, angle {angle}"
            );
            if s.is_translation() {
                translations += 1;
            } else {
                screws += 1;
            }
        }
        // Both sides of the threshold were taken.
        assert!(screws > 100 && translations > 50, "{screws} {translations}");
    }

    #[test]
    fn tiny_rotation_is_a_translation_in_the_limit() {
        let a = Pose::IDENTITY;
        let s = Screw::between(a, a.moved(DVec3::new(2.0, 0.0, 0.0), DVec3::Z, 1e-12));
        let c = s.centre_at(0.5);
        assert!((c - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-9);
    }
}
