//! Where the camera looks from: fitting every molecule, centring on the
//! drug, and the view on load that shows the drug.
//!
//! A drug docked in its pocket is buried: from an arbitrary side the
//! receptor hides it. The load view looks at the drug from the side where
//! the fewest receptor atoms stand between it and the eye, found by trying
//! [`DIRECTIONS`] directions spread evenly over the sphere (a Fibonacci
//! lattice) and counting, for each, the other molecules' atoms within the
//! cylinder from the drug towards the eye. Ties go to the direction nearest
//! the default view (+z), so an unburied drug keeps the usual view. The
//! drug is put at the centre of the view, far enough back that every
//! molecule is in view.

use glam::{DMat3, DQuat, DVec3};

use super::{Body, Camera};

/// Directions tried for the load view.
pub const DIRECTIONS: usize = 200;

/// The centre (atoms weighted by count) and radius of a sphere holding
/// every atom of `bodies` at their current poses; `None` without atoms.
pub fn bounds(bodies: &[Body]) -> Option<(DVec3, f64)> {
    let n: f64 = bodies.iter().map(|b| b.molecule.len() as f64).sum();
    if n <= 0.0 {
        return None;
    }
    let centre = bodies
        .iter()
        .map(|b| b.pose.translation * b.molecule.len() as f64)
        .sum::<DVec3>()
        / n;
    let radius = reach(bodies, centre);
    Some((centre, radius))
}

/// Distance from `point` to the farthest atom surface of `bodies` (at
/// least 1 Å), through each molecule's bounding sphere.
fn reach(bodies: &[Body], point: DVec3) -> f64 {
    bodies
        .iter()
        .map(|b| (b.pose.translation - point).length() + b.molecule.bounding_radius())
        .fold(1.0, f64::max)
}

/// The camera that frames every molecule, turned as `rotation`.
pub fn fit_all(bodies: &[Body], rotation: DQuat) -> Option<Camera> {
    let (centre, radius) = bounds(bodies)?;
    let mut c = Camera::framing(centre, radius);
    c.rotation = rotation;
    Some(c)
}

/// The camera centred on molecule `b`, turned as `rotation`, close enough
/// that the molecule and a few Å around it fill the view.
pub fn centre_on(bodies: &[Body], b: usize, rotation: DQuat) -> Option<Camera> {
    let body = bodies.get(b)?;
    let mut c = Camera::framing(body.pose.translation, body.molecule.bounding_radius() + 4.0);
    c.rotation = rotation;
    Some(c)
}

/// The load view: the drug `b` at the centre, seen from the side where the
/// other molecules hide it least, every molecule in view. `None` when `b`
/// is not a molecule or has no atoms.
pub fn drug_view(bodies: &[Body], b: usize) -> Option<Camera> {
    let drug = bodies.get(b).filter(|d| !d.molecule.is_empty())?;
    let c = drug.pose.translation;
    let towards_eye = clearest_direction(bodies, b);
    let mut cam = Camera::framing(c, reach(bodies, c));
    cam.rotation = looking_along(towards_eye);
    Some(cam)
}

/// The world → screen rotation whose screen +z (towards the viewer) is the
/// world direction `z`, with the world's +y as near screen up as it goes.
pub fn looking_along(z: DVec3) -> DQuat {
    let z = z.try_normalize().unwrap_or(DVec3::Z);
    let up = if z.y.abs() > 0.99 { DVec3::Z } else { DVec3::Y };
    let x = up.cross(z).normalize();
    let y = z.cross(x);
    // Columns: the screen axes in world coordinates (screen → world).
    DQuat::from_mat3(&DMat3::from_cols(x, y, z))
        .conjugate()
        .normalize()
}

/// The direction from drug `b` towards the eye in which the fewest atoms
/// of the other molecules lie within the drug's radius of the ray; among
/// equals, the one with the fewest within a wider cylinder (the middle of
/// an opening rather than its rim), then the one nearest +z.
fn clearest_direction(bodies: &[Body], b: usize) -> DVec3 {
    let drug = &bodies[b];
    let c = drug.pose.translation;
    let r = drug.molecule.bounding_radius();
    let dirs = fibonacci_sphere(DIRECTIONS);
    // (atoms hiding the drug, atoms near the line of sight) per direction.
    let mut counts = vec![(0u32, 0u32); dirs.len()];
    for (k, other) in bodies.iter().enumerate() {
        if k == b {
            continue;
        }
        for (p, a) in other.molecule.local.iter().zip(&other.molecule.atoms) {
            let v = other.pose.transform_point(p.as_dvec3()) - c;
            let v2 = v.length_squared();
            let hide = r + f64::from(a.radius);
            let near = 2.0 * hide + 4.0;
            for (d, n) in dirs.iter().zip(counts.iter_mut()) {
                let t = v.dot(*d);
                if t <= 0.0 {
                    continue;
                }
                let off2 = v2 - t * t;
                if off2 < near * near {
                    n.1 += 1;
                    if off2 < hide * hide {
                        n.0 += 1;
                    }
                }
            }
        }
    }
    let mut best = 0;
    for k in 1..dirs.len() {
        if (counts[k], -dirs[k].z) < (counts[best], -dirs[best].z) {
            best = k;
        }
    }
    dirs[best]
}

/// `n` directions spread evenly over the unit sphere, +z first.
fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{AtomInfo, Molecule};
    use crate::motion::Pose;

    fn atom(name: &str) -> AtomInfo {
        AtomInfo {
            serial: 1,
            name: name.into(),
            residue: "X".into(),
            seq: 1,
            insertion: Default::default(),
            chain: "A".into(),
            element: "C".into(),
            radius: 1.7,
            polar: false,
            hetero: false,
        }
    }

    fn body(points: &[DVec3]) -> Body {
        let m = Molecule::new("m", points.iter().map(|_| atom("C")).collect(), points);
        let pose = Pose::from_translation(m.centre);
        Body {
            molecule: m,
            pose,
            loaded: pose,
        }
    }

    #[test]
    fn the_load_view_looks_through_the_open_side_of_a_cup() {
        // A hemispherical shell of atoms open towards +x, the drug inside.
        let mut shell = Vec::new();
        for i in 0..40 {
            for j in 0..40 {
                let th = std::f64::consts::PI * (i as f64 + 0.5) / 40.0;
                let ph = std::f64::consts::PI * (j as f64 + 0.5) / 40.0;
                // x ≤ 0 half: the opening faces +x.
                let d = DVec3::new(-ph.sin() * th.sin(), th.cos(), ph.cos() * th.sin());
                shell.push(d * 12.0);
            }
        }
        let bodies = vec![
            body(&shell),
            body(&[DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0)]),
        ];
        let cam = drug_view(&bodies, 1).expect("a view");
        let towards_eye = cam.to_world(DVec3::Z);
        assert!(towards_eye.x > 0.8, "{towards_eye}");
        assert!((cam.centre - bodies[1].pose.translation).length() < 1e-12);
        // Every atom in view: the camera is farther than the farthest atom.
        assert!(cam.distance > 12.0 + 1.7);
        // Screen up stays near world up.
        assert!(cam.to_world(DVec3::Y).y > 0.0);
    }

    #[test]
    fn a_drug_in_the_open_keeps_the_default_view() {
        let bodies = vec![
            body(&[DVec3::new(0.0, 0.0, -30.0)]),
            body(&[DVec3::ZERO, DVec3::X]),
        ];
        let cam = drug_view(&bodies, 1).expect("a view");
        assert!((cam.to_world(DVec3::Z) - DVec3::Z).length() < 0.1);
        let fitted = fit_all(&bodies, cam.rotation).expect("fits");
        assert_eq!(fitted.rotation, cam.rotation);
        assert!(drug_view(&bodies, 5).is_none());
    }

    #[test]
    fn looking_along_puts_the_direction_towards_the_viewer() {
        for z in [DVec3::X, -DVec3::Y, DVec3::new(1.0, 2.0, -3.0), DVec3::Y] {
            let q = looking_along(z);
            let c = Camera {
                rotation: q,
                ..Camera::framing(DVec3::ZERO, 1.0)
            };
            assert!(
                (c.to_world(DVec3::Z) - z.normalize()).length() < 1e-12,
                "{z}"
            );
        }
    }
}
