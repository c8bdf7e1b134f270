//! parry3d as the move-to-touch baseline, shared by the benchmarks (the
//! report and `benches/collide.rs`) and the test `tests/move_to_touch.rs`,
//! so the benchmarks time the code the test checks against bump.
//!
//! The contact rule becomes parry's sphere model: a `Compound` of balls of
//! radius `r − overlap/2`, which is the rule without the N/O hydrogen-bond
//! allowance. [`cast`] is parry's own answer to "how far may the drug move"
//! (`cast_shapes`): the time of impact and nothing else. bump's move-to-touch
//! also returns the pairs within tolerance of contact at the stop (the atoms
//! that change colour), so [`touch`] adds them the cheapest way parry offers:
//! one query of the receptor compound's BVH per drug ball at the stop pose,
//! then the exact sphere gap for each leaf it returns.

use bump::collide::ContactRule;
use bump::model::Molecule;
use bump::motion::Pose;
use glam::Vec3;
use parry3d::bounding_volume::Aabb;
use parry3d::math::{Pose as PPose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Compound, SharedShape};

/// A molecule as parry sees it: the compound of balls, and the balls'
/// centres (molecule frame) and radii, indexed like the compound's leaves.
pub struct Spheres {
    /// The balls, with parry's BVH over them.
    pub compound: Compound,
    centres: Vec<Vec3>,
    radii: Vec<f32>,
}

impl Spheres {
    /// `m`'s atoms as balls of radius `r − overlap/2` (at least 0.01 Å).
    pub fn new(m: &Molecule, rule: &ContactRule) -> Self {
        let half = rule.overlap / 2.0;
        let centres = m.local.clone();
        let radii: Vec<f32> = m
            .atoms
            .iter()
            .map(|a| (a.radius - half).max(0.01))
            .collect();
        let compound = Compound::new(
            centres
                .iter()
                .zip(&radii)
                .map(|(c, r)| (PPose::from_translation(*c), SharedShape::ball(*r)))
                .collect(),
        );
        Self {
            compound,
            centres,
            radii,
        }
    }
}

/// `p` as parry's pose (f32).
pub fn pose(p: &Pose) -> PPose {
    PPose::from_parts(p.translation.as_vec3(), p.rotation.as_quat())
}

/// Time of impact of the translation from `start` to `end` (1 when free).
pub fn cast(rec: &Spheres, dr: &Spheres, start: &Pose, end: &Pose) -> f64 {
    let v = (end.translation - start.translation).as_vec3();
    match query::cast_shapes(
        &PPose::IDENTITY,
        Vector::ZERO,
        &rec.compound,
        &pose(start),
        v,
        &dr.compound,
        ShapeCastOptions::with_max_time_of_impact(1.0),
    ) {
        Ok(Some(h)) => f64::from(h.time_of_impact),
        _ => 1.0,
    }
}

/// The (receptor, drug) leaf pairs whose sphere gap is at most `tolerance`
/// with the drug at `at`, sorted by receptor then drug (as bump's pairs).
pub fn contacts(rec: &Spheres, dr: &Spheres, at: &Pose, tolerance: f32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    contacts_into(rec, dr, at, tolerance, &mut out);
    out
}

/// [`contacts`] into `out` (emptied first), whose storage is reused.
pub fn contacts_into(
    rec: &Spheres,
    dr: &Spheres,
    at: &Pose,
    tolerance: f32,
    out: &mut Vec<(u32, u32)>,
) {
    out.clear();
    let place = pose(at);
    let bvh = rec.compound.bvh();
    for (j, (c, r)) in dr.centres.iter().zip(&dr.radii).enumerate() {
        let x = place.transform_point(*c);
        // A leaf box (q ± r_i) meets this one iff |q − x|∞ ≤ r_i + r_j + tol.
        let reach = Vec3::splat(r + tolerance);
        let aabb = Aabb::new(x - reach, x + reach);
        for i in bvh.intersect_aabb(&aabb) {
            let k = i as usize;
            let lim = rec.radii[k] + r + tolerance;
            if rec.centres[k].distance_squared(x) <= lim * lim {
                out.push((i, j as u32));
            }
        }
    }
    out.sort_unstable();
}

/// What bump's move-to-touch answers, done with parry3d: the fraction of the
/// translation from `start` to `end` allowed ([`cast`]) and the pairs within
/// `tolerance` of contact there ([`contacts`]), those into `contacts`
/// (emptied first, its storage reused, as bump's timed queries reuse
/// theirs).
pub fn touch(
    rec: &Spheres,
    dr: &Spheres,
    start: &Pose,
    end: &Pose,
    tolerance: f32,
    contacts: &mut Vec<(u32, u32)>,
) -> f64 {
    let t = cast(rec, dr, start, end);
    let at = Pose::new(
        start.rotation,
        start.translation + (end.translation - start.translation) * t,
    );
    contacts_into(rec, dr, &at, tolerance, contacts);
    t
}
