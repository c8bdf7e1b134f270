//! The viewer: where the camera looks from. View mode moves it.
//!
//! The camera orbits a centre point at a distance; `rotation` takes world
//! directions to screen directions (x right, y up, z towards the viewer).
//! Moving "everything" in view mode is done by moving the camera the
//! opposite way, so molecules' poses — and their collisions — never change.

use glam::{DMat4, DQuat, DVec3};

/// Camera state in f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// World → screen rotation.
    pub rotation: DQuat,
    /// World point at the centre of the view.
    pub centre: DVec3,
    /// Distance from the eye to `centre`, Å.
    pub distance: f64,
    /// Vertical field of view, radians.
    pub fov_y: f64,
}

impl Camera {
    /// A camera looking down −z at `centre` from far enough to see a sphere of
    /// `radius` Å.
    pub fn framing(centre: DVec3, radius: f64) -> Self {
        let fov_y = 30f64.to_radians();
        let distance = (radius.max(1.0) / (0.5 * fov_y).sin()) * 1.05;
        Self {
            rotation: DQuat::IDENTITY,
            centre,
            distance,
            fov_y,
        }
    }

    /// A screen-space vector in world coordinates.
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.rotation.conjugate() * v
    }

    /// Where the eye is, world coordinates.
    pub fn eye(&self) -> DVec3 {
        self.centre + self.to_world(DVec3::new(0.0, 0.0, self.distance))
    }

    /// World → view matrix (right-handed, looking down −z).
    pub fn view_matrix(&self) -> DMat4 {
        DMat4::from_translation(DVec3::new(0.0, 0.0, -self.distance))
            * DMat4::from_quat(self.rotation)
            * DMat4::from_translation(-self.centre)
    }

    /// Moves everything by `translate` (screen Å) and turns everything by the
    /// screen rotation vector `rotate` about the view centre.
    pub fn move_scene(&mut self, translate: DVec3, rotate: DVec3) {
        // Moving the scene right is moving the camera left.
        self.centre -= self.to_world(translate);
        let angle = rotate.length();
        if angle > 0.0 && angle.is_finite() {
            let q = DQuat::from_axis_angle(rotate / angle, angle);
            self.rotation = (q * self.rotation).normalize();
        }
    }

    /// Comes closer by `steps` mouse-wheel steps (distance × 0.9^steps),
    /// within 1 Å to 10⁶ Å.
    pub fn zoom(&mut self, steps: f64) {
        if steps.is_finite() {
            self.distance = (self.distance * 0.9f64.powf(steps)).clamp(1.0, 1e6);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_the_scene_moves_points_on_screen_as_asked() {
        let mut cam = Camera::framing(DVec3::new(5.0, 0.0, 0.0), 10.0);
        let p = DVec3::new(5.0, 0.0, 0.0);
        let before = cam.view_matrix().transform_point3(p);
        cam.move_scene(DVec3::new(1.0, 0.0, 0.0), DVec3::ZERO);
        let after = cam.view_matrix().transform_point3(p);
        assert!((after - before - DVec3::X).length() < 1e-12);
        // A quarter turn about screen y brings screen +x to screen −z.
        let mut cam = Camera::framing(DVec3::ZERO, 10.0);
        cam.move_scene(DVec3::ZERO, DVec3::Y * std::f64::consts::FRAC_PI_2);
        let v = cam.view_matrix().transform_point3(DVec3::X);
        assert!(
            (v - DVec3::new(0.0, 0.0, -1.0 - cam.distance)).length() < 1e-9,
            "{v}"
        );
    }
}
