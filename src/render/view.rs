//! From the session's camera and poses (f64) to the matrices the shader
//! uses (f32): one model-view per molecule and one projection.
//!
//! Composing in f64 before rounding keeps atoms far from the world origin
//! exact on screen: only coordinates relative to the eye reach f32.

use glam::{DMat4, DVec3, Mat4};

use crate::session::Session;

/// Camera and lighting inputs for a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewParams {
    /// Width / height of the image.
    pub aspect: f64,
    /// Direction towards the light, view space (normalised here).
    pub light: DVec3,
    /// Share of ambient light, 0..1.
    pub ambient: f32,
}

impl Default for ViewParams {
    fn default() -> Self {
        Self {
            aspect: 1.0,
            light: DVec3::new(-0.35, 0.55, 0.75),
            ambient: 0.25,
        }
    }
}

/// Model-view matrix of every molecule.
pub fn model_views(session: &Session) -> Vec<Mat4> {
    let view = session.camera().view_matrix();
    session
        .bodies()
        .iter()
        .map(|b| {
            let model = DMat4::from_rotation_translation(b.pose.rotation, b.pose.translation);
            (view * model).as_mat4()
        })
        .collect()
}

/// Near and far planes that hold every atom (view-space depths); a fixed
/// range when there is no molecule yet.
pub fn depth_range(session: &Session) -> (f64, f64) {
    if session.bodies().is_empty() {
        return (0.1, 1000.0);
    }
    let view = session.camera().view_matrix();
    let mut near = f64::INFINITY;
    let mut far: f64 = 0.0;
    for b in session.bodies() {
        let c = view.transform_point3(b.pose.translation);
        let r = b.molecule.bounding_radius() + 1.0;
        near = near.min(-c.z - r);
        far = far.max(-c.z + r);
    }
    let far = far.max(1.0);
    // Keep near positive and the depth buffer's precision usable.
    let near = near.max(far * 1e-4).max(0.05);
    (near, far.max(near * 2.0))
}

/// A right-handed perspective projection with depth 0 (near) to 1 (far), as
/// wgpu expects.
pub fn perspective(fov_y: f64, aspect: f64, near: f64, far: f64) -> DMat4 {
    let f = 1.0 / (0.5 * fov_y).tan();
    DMat4::from_cols_array(&[
        f / aspect,
        0.0,
        0.0,
        0.0,
        0.0,
        f,
        0.0,
        0.0,
        0.0,
        0.0,
        far / (near - far),
        -1.0,
        0.0,
        0.0,
        near * far / (near - far),
        0.0,
    ])
}

/// The projection for `session`'s camera and scene.
pub fn projection(session: &Session, aspect: f64) -> Mat4 {
    let (near, far) = depth_range(session);
    perspective(session.camera().fov_y, aspect, near, far).as_mat4()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Settings;
    use glam::DVec4;

    #[test]
    fn an_empty_session_still_has_a_finite_projection() {
        let s = Session::empty(Settings::default());
        let (near, far) = depth_range(&s);
        assert!(near.is_finite() && far.is_finite() && near > 0.0 && far > near);
        assert!(projection(&s, 1.5).is_finite());
    }

    #[test]
    fn perspective_maps_near_to_0_and_far_to_1() {
        let p = perspective(1.0, 1.5, 2.0, 50.0);
        let n = p * DVec4::new(0.0, 0.0, -2.0, 1.0);
        let f = p * DVec4::new(0.0, 0.0, -50.0, 1.0);
        assert!((n.z / n.w).abs() < 1e-12);
        assert!((f.z / f.w - 1.0).abs() < 1e-12);
        // A point at the top edge of the field of view lands at y = 1.
        let top = p * DVec4::new(0.0, 10.0 * 0.5f64.tan(), -10.0, 1.0);
        assert!((top.y / top.w - 1.0).abs() < 1e-12);
    }
}
