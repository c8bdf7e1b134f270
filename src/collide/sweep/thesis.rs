//! The thesis's move-to-touch (Turk's `pg_move_to_touch`), kept to
//! measure its speed and its failures: the pairs colliding at the end pose,
//! then bisection on that list only.

use glam::{DMat3, Vec3};

use crate::collide::check::check;
use crate::collide::collider::Collider;
use crate::collide::drug::DrugAtoms;
use crate::motion::{Pose, Screw};

/// The thesis's method: pairs colliding at the end pose, bisection on them.
pub(super) fn thesis(
    collider: &Collider,
    drug: &DrugAtoms,
    screw: &Screw,
    tol: f64,
) -> (f64, Pose) {
    let end = *screw.end();
    let list = check(collider, drug, &end);
    if list.is_empty() {
        return (1.0, end);
    }
    let start = *screw.start();
    let ys = drug.rotated(&start);
    let s_max = ys.iter().map(|y| screw.speed(*y)).fold(0.0, f64::max);
    let hits = |t: f64| {
        let p = screw.pose_at(t);
        let m = DMat3::from_quat(p.rotation);
        list.iter().any(|pair| {
            let i = pair.drug as usize;
            let x = (m * drug.local[i].as_dvec3() + p.translation).as_vec3();
            let q = collider_atom(collider, pair.receptor);
            let d = (x - q).length();
            pair.contact >= 0.0 && d <= pair.contact
        })
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while (hi - lo) * s_max > tol && hi - lo > f64::EPSILON {
        let mid = 0.5 * (lo + hi);
        if hits(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo, screw.pose_at(lo))
}

/// Position of receptor atom `index` in the receptor frame.
fn collider_atom(collider: &Collider, index: u32) -> Vec3 {
    collider.atom_position(index)
}
