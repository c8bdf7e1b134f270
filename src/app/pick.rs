//! Picking: which atom is under a pixel. A ray from the eye through the pixel
//! is intersected with every atom's sphere (world coordinates, f64). With
//! the clipping slab on, only what the slab shows is picked: an atom cut by
//! its near plane at its cap, none in front of it or behind its far plane.

use glam::DVec3;

use crate::session::Session;

/// The nearest atom hit by the ray through pixel (`x`, `y`) of a
/// `width`×`height` view: (molecule, atom).
pub fn pick(session: &Session, x: f64, y: f64, width: f64, height: f64) -> Option<(usize, usize)> {
    pick_in(session, x, y, width, height, width / height.max(1e-9))
}

/// As [`pick`], for a `width`×`height` viewport whose projection has
/// `aspect` (width/height of the view volume; a half-width stereo viewport
/// shows a full-frame projection squeezed, so its aspect differs from its
/// pixels').
pub fn pick_in(
    session: &Session,
    x: f64,
    y: f64,
    width: f64,
    height: f64,
    aspect: f64,
) -> Option<(usize, usize)> {
    pick_clipped(session, x, y, width, height, aspect, None)
}

/// As [`pick_in`], seeing only what lies between the slab's `(near, far)`
/// planes (mono view-space z, as [`crate::render::slab::Slab::planes`]).
pub fn pick_clipped(
    session: &Session,
    x: f64,
    y: f64,
    width: f64,
    height: f64,
    aspect: f64,
    slab: Option<(f64, f64)>,
) -> Option<(usize, usize)> {
    if !(width > 0.0 && height > 0.0 && aspect > 0.0) {
        return None;
    }
    let cam = session.view_camera();
    let ndc_x = 2.0 * x / width - 1.0;
    let ndc_y = 1.0 - 2.0 * y / height;
    let half = (0.5 * cam.fov_y).tan();
    let dir_view = DVec3::new(ndc_x * half * aspect, ndc_y * half, -1.0).normalize();
    let dir = cam.to_world(dir_view);
    let eye = cam.eye();
    let mut best: Option<(f64, usize, usize)> = None;
    for (k, b) in session.bodies().iter().enumerate() {
        for (i, (p, a)) in b.molecule.local.iter().zip(&b.molecule.atoms).enumerate() {
            let c = b.pose.transform_point(p.as_dvec3()) - eye;
            let t_mid = c.dot(dir);
            let d2 = c.length_squared() - t_mid * t_mid;
            let r = f64::from(a.radius);
            if d2 > r * r || t_mid <= 0.0 {
                continue;
            }
            let mut t = t_mid - (r * r - d2).sqrt();
            if let Some((near, far)) = slab {
                // View-space depth along the ray is t · dir_view.z (< 0).
                let z = t * dir_view.z;
                if z < far {
                    continue;
                }
                if z > near {
                    let t_cap = near / dir_view.z;
                    if t_cap > t_mid + (r * r - d2).sqrt() {
                        continue;
                    }
                    t = t_cap;
                }
            }
            if best.is_none_or(|(bt, _, _)| t < bt) {
                best = Some((t, k, i));
            }
        }
    }
    best.map(|(_, k, i)| (k, i))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};
    use crate::session::Settings;

    #[test]
    fn the_centre_pixel_picks_what_is_in_front() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let s = Session::new(vec![rings.clone(), e], Settings::default()).expect("session");
        // The camera looks down −z at the scene's centre; a ring atom at the
        // top of the middle ring projects above the centre.
        let (w, h) = (800.0, 600.0);
        assert_eq!(pick(&s, 0.0, 0.0, w, h), None);
        let cam = s.view_camera();
        let atom = rings.file_position(4); // (5 cos 80°, 5 sin 80°, 0) in the middle ring? any atom works
        let v = cam.view_matrix().transform_point3(atom);
        let f = 1.0 / (0.5 * cam.fov_y).tan();
        let x = (v.x / -v.z * f / (w / h) + 1.0) * 0.5 * w;
        let y = (1.0 - v.y / -v.z * f) * 0.5 * h;
        let hit = pick(&s, x, y, w, h).expect("hit");
        assert_eq!(hit.0, 0, "a ring atom, not the E behind");
    }

    #[test]
    fn a_squeezed_half_viewport_picks_what_the_full_frame_shows() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let s = Session::new(vec![rings, e], Settings::default()).expect("session");
        let (w, h) = (800.0, 600.0);
        // Every pixel of the full frame, squeezed into the left half (as
        // side-by-side-half shows it), picks the same atom.
        let mut hits = 0;
        for (x, y) in [(400.0, 300.0), (380.0, 250.0), (430.0, 330.0), (10.0, 10.0)] {
            let full = pick(&s, x, y, w, h);
            hits += usize::from(full.is_some());
            let half = pick_in(&s, x / 2.0, y, w / 2.0, h, w / h);
            assert_eq!(full, half, "at {x},{y}");
        }
        assert!(hits >= 2, "the test needs atoms under the pointer");
        assert_eq!(pick_in(&s, 1.0, 1.0, 10.0, 10.0, 0.0), None);
    }

    #[test]
    fn the_slab_hides_what_it_clips_from_the_pointer() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let s = Session::new(vec![rings, e], Settings::default()).expect("session");
        let (w, h) = (800.0, 600.0);
        let (x, y) = (400.0, 300.0);
        let hit = pick(&s, x, y, w, h).expect("an atom under the centre");
        // A slab far behind everything shows nothing; one around the scene
        // shows what the pointer hits without it.
        let d = s.view_camera().distance;
        let behind = Some((-d - 500.0, -d - 510.0));
        assert_eq!(pick_clipped(&s, x, y, w, h, w / h, behind), None);
        let around = Some((-d + 500.0, -d - 500.0));
        assert_eq!(pick_clipped(&s, x, y, w, h, w / h, around), Some(hit));
    }
}
