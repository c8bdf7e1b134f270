//! From the session's camera and poses (f64) to the matrices the shader
//! uses (f32): one model-view per molecule and one projection.
//!
//! Composing in f64 before rounding keeps atoms far from the world origin
//! exact on screen: only coordinates relative to the eye reach f32. The
//! camera is the session's *view* camera, rocking included.

use glam::{DMat4, DVec3, Mat4};

use super::cues::Cues;
use super::ghost::Ghost;
use super::slab::Slab;
use super::stereo::Stereo;
use crate::session::Session;

/// Camera, lighting, depth-cue and stereo inputs for a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewParams {
    /// Width / height of the image (mono).
    pub aspect: f64,
    /// Direction towards the light, view space (normalised here).
    pub light: DVec3,
    /// Share of ambient light, 0..1.
    pub ambient: f32,
    /// The depth cues drawn.
    pub cues: Cues,
    /// The stereo mode and eye geometry.
    pub stereo: Stereo,
    /// Frame number (frame-sequential stereo shows the left eye on even frames).
    pub frame: u64,
    /// The ghost of the drug's reference pose, when drawn.
    pub ghost: Option<Ghost>,
    /// The clipping slab, when on.
    pub slab: Option<Slab>,
}

impl Default for ViewParams {
    fn default() -> Self {
        Self {
            aspect: 1.0,
            light: DVec3::new(-0.35, 0.55, 0.75),
            ambient: 0.25,
            cues: Cues::default(),
            stereo: Stereo::default(),
            frame: 0,
            ghost: None,
            slab: None,
        }
    }
}

/// Model-view matrix of every molecule.
pub fn model_views(session: &Session) -> Vec<Mat4> {
    let view = session.view_camera().view_matrix();
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
    let view = session.view_camera().view_matrix();
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

/// [`depth_range`], widened to hold the ghost of `params` when it is drawn.
pub fn depth_range_for(session: &Session, params: &ViewParams) -> (f64, f64) {
    let (near, far) = depth_range(session);
    let Some((d, pose)) = params.ghost.and(super::ghost::ghost_pose(session)) else {
        return (near, far);
    };
    let Some(body) = session.bodies().get(d) else {
        return (near, far);
    };
    let view = session.view_camera().view_matrix();
    let c = view.transform_point3(pose.translation);
    let r = body.molecule.bounding_radius() + 1.0;
    let far = far.max(-c.z + r);
    let near = near.min(-c.z - r).max(far * 1e-4).max(0.05);
    (near, far.max(near * 2.0))
}

/// A sphere holding every atom, in view space: centre and radius (Å).
pub fn scene_sphere(session: &Session) -> (DVec3, f64) {
    let view = session.view_camera().view_matrix();
    let spheres: Vec<(DVec3, f64)> = session
        .bodies()
        .iter()
        .map(|b| {
            (
                view.transform_point3(b.pose.translation),
                b.molecule.bounding_radius() + 1.0,
            )
        })
        .collect();
    if spheres.is_empty() {
        return (DVec3::new(0.0, 0.0, -session.camera().distance), 1.0);
    }
    let lo = spheres
        .iter()
        .fold(DVec3::INFINITY, |m, (c, r)| m.min(*c - DVec3::splat(*r)));
    let hi = spheres.iter().fold(DVec3::NEG_INFINITY, |m, (c, r)| {
        m.max(*c + DVec3::splat(*r))
    });
    let centre = 0.5 * (lo + hi);
    let radius = spheres
        .iter()
        .map(|(c, r)| (*c - centre).length() + r)
        .fold(1.0, f64::max);
    (centre, radius)
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
    perspective(session.view_camera().fov_y, aspect, near, far).as_mat4()
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
