//! Exact answers to measure move-to-touch against, in f64.
//!
//! - [`translation_toi`]: the closed-form time of impact of a pure
//!   translation, over every receptor–drug pair (the reference; O(N·M)).
//! - [`closed_form_touch`]: the same closed form as a move-to-touch *method*,
//!   fast enough to time: the collider gathers the receptor atoms near each
//!   drug atom's straight path, and each pair's first root of
//!   `|x + t d − q|² = c²` is solved exactly. It stops *at* contact (gap 0),
//!   not before it, so by the rule (`d ≤ c` collides) its pose touches.
//! - [`min_gap`]: the smallest `d − c` over all pairs at a pose.
//! - [`dense_screw_toi`]: the first contact along a screw by dense sampling
//!   and bisection (the reference for rotations).
//! - [`certify_free_path`]: a proof that no pose on `[0, t]` of a screw
//!   overlaps: the smallest gap is Lipschitz in `t` with constant
//!   `s_max` (the fastest atom's speed), so an interval whose end gaps `g_a`,
//!   `g_b` satisfy `g_a + g_b > s_max·(b − a)` holds no contact; other
//!   intervals are halved. It cannot miss a thin wall, however long the step.
//!
//! Positions are the molecules' own (f32 relative to their centres) taken to
//! f64, so the references see exactly the coordinates the colliders see.

use bump::collide::collider::unpack_meta;
use bump::collide::{Collider, ContactRule, DrugAtoms};
use bump::model::{AtomInfo, Molecule};
use bump::motion::{Pose, Screw};
use glam::DVec3;

/// Contact distance of a receptor/drug atom pair, f64.
pub fn contact(rule: &ContactRule, a: &AtomInfo, b: &AtomInfo) -> f64 {
    f64::from(rule.contact_distance(a.radius, a.polar, b.radius, b.polar))
}

/// First root in `(0, 1]` of `|w + t d|² = c²` for a pair at offset `w`
/// (drug minus receptor) moving by `d`, when it is outside contact now and
/// approaching; `None` otherwise.
#[inline]
fn pair_toi(w: DVec3, d: DVec3, dd: f64, c: f64) -> Option<f64> {
    let cc = w.length_squared() - c * c;
    if cc <= 0.0 {
        return None; // already in contact: not a time of impact
    }
    let bb = w.dot(d);
    let disc = bb * bb - dd * cc;
    if bb >= 0.0 || disc < 0.0 {
        return None;
    }
    // The smaller root, written without cancellation.
    let t = cc / (-bb + disc.sqrt());
    (t <= 1.0).then_some(t)
}

/// Exact time of impact for a pure translation `d` of `drug` from the
/// relative pose `start`: the smallest per-pair root of `|x + t d − q|² = c²`
/// in `[0, 1]`, over every pair (O(N·M)). Pairs already in contact at the
/// start are skipped. `None`: no pair touches on the way.
pub fn translation_toi(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    start: &Pose,
    d: DVec3,
) -> Option<f64> {
    let dd = d.length_squared();
    if dd == 0.0 || !dd.is_finite() {
        return None;
    }
    let mut best: Option<f64> = None;
    for (i, b) in drug.atoms.iter().enumerate() {
        let x = start.transform_point(drug.local[i].as_dvec3());
        for (j, a) in receptor.atoms.iter().enumerate() {
            let w = x - receptor.local[j].as_dvec3();
            if let Some(t) = pair_toi(w, d, dd, contact(rule, a, b))
                && best.is_none_or(|b| t < b)
            {
                best = Some(t);
            }
        }
    }
    best
}

/// The closed-form method: the exact time of impact of the translation from
/// `start` to `start` moved by `d`, with the collider's candidates (receptor
/// atoms in the box around each drug atom's path). Same answer as
/// [`translation_toi`] with the collider's rule; `None` when nothing is hit.
///
/// # Performance
/// One box query per drug atom, as long as its path: made for the short
/// steps of a frame, not for 1000 Å jumps.
pub fn closed_form_touch(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    d: DVec3,
) -> Option<f64> {
    let dd = d.length_squared();
    if dd == 0.0 || !dd.is_finite() || !start.is_finite() {
        return None;
    }
    let mut best: Option<f64> = None;
    let rot = glam::DMat3::from_quat(start.rotation);
    for (i, p) in drug.local.iter().enumerate() {
        let x = rot * p.as_dvec3() + start.translation;
        let reach = f64::from(drug.reach[i]) + 1e-3;
        let lo = (x.min(x + d) - DVec3::splat(reach)).as_vec3();
        let hi = (x.max(x + d) + DVec3::splat(reach)).as_vec3();
        collider.visit(lo, hi, |a, meta| {
            let (_, polar) = unpack_meta(meta);
            let c = f64::from(drug.contact(i, a.w, polar));
            let w = x - a.truncate().as_dvec3();
            if let Some(t) = pair_toi(w, d, dd, c)
                && best.is_none_or(|b| t < b)
            {
                best = Some(t);
            }
        });
    }
    best
}

/// Smallest gap `d − c` over all receptor–drug pairs at relative pose `pose`
/// (f64, every pair). Zero or below: the pose collides by the rule.
pub fn min_gap(rule: &ContactRule, receptor: &Molecule, drug: &Molecule, pose: &Pose) -> f64 {
    let mut g = f64::INFINITY;
    for (i, b) in drug.atoms.iter().enumerate() {
        let x = pose.transform_point(drug.local[i].as_dvec3());
        for (j, a) in receptor.atoms.iter().enumerate() {
            let d = (x - receptor.local[j].as_dvec3()).length();
            g = g.min(d - contact(rule, a, b));
        }
    }
    g
}

/// First contact time along `screw` by sampling `samples` poses, then
/// bisection to 10⁻¹² in `t`. It can miss contacts thinner than a sample
/// step (use [`certify_free_path`] for a proof).
pub fn dense_screw_toi(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    screw: &Screw,
    samples: usize,
) -> Option<f64> {
    let hit = |t: f64| min_gap(rule, receptor, drug, &screw.pose_at(t)) <= 0.0;
    let samples = samples.max(1);
    let mut prev = 0.0;
    for k in 1..=samples {
        let t = k as f64 / samples as f64;
        if hit(t) {
            let (mut lo, mut hi) = (prev, t);
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                if hit(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = t;
    }
    None
}

/// True when any pair collides (f64) at `pose`.
pub fn collides(rule: &ContactRule, receptor: &Molecule, drug: &Molecule, pose: &Pose) -> bool {
    min_gap(rule, receptor, drug, pose) <= 0.0
}

/// Largest atom speed (Å per unit `t`) of `drug` along `screw`.
pub fn max_speed(drug: &Molecule, screw: &Screw) -> f64 {
    let rot = screw.start().rotation;
    drug.local
        .iter()
        .map(|p| screw.speed(rot * p.as_dvec3()))
        .fold(0.0, f64::max)
}

/// Where a path could not be proved free of contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathFault {
    /// A time at which the gap was not positive (or the search gave up).
    pub t: f64,
    /// The smallest gap there, Å.
    pub gap: f64,
}

/// Proves that no pose of `screw` on `[0, t_end]` collides: every pair's
/// gap stays above zero. Returns the number of poses evaluated, or where the
/// proof failed (a pose with gap ≤ 0, or an interval narrower than 10⁻¹⁴
/// that could not be certified).
///
/// # Performance
/// Each evaluation is O(N·M); a path that ends within `g` of contact needs
/// about `log2(s_max·t_end / g)` extra evaluations near its end.
pub fn certify_free_path(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    screw: &Screw,
    t_end: f64,
) -> Result<usize, PathFault> {
    let s = max_speed(drug, screw);
    let gap = |t: f64| min_gap(rule, receptor, drug, &screw.pose_at(t));
    let mut evals = 2;
    let (g0, g1) = (gap(0.0), gap(t_end));
    for (t, g) in [(0.0, g0), (t_end, g1)] {
        if g.is_nan() || g <= 0.0 {
            return Err(PathFault { t, gap: g });
        }
    }
    // Depth-first over intervals, earliest first.
    let mut stack = vec![(0.0, g0, t_end, g1)];
    while let Some((a, ga, b, gb)) = stack.pop() {
        if ga + gb > s * (b - a) {
            continue;
        }
        if b - a < 1e-14 {
            return Err(PathFault {
                t: a,
                gap: ga.min(gb),
            });
        }
        let m = 0.5 * (a + b);
        let gm = gap(m);
        evals += 1;
        if gm.is_nan() || gm <= 0.0 {
            return Err(PathFault { t: m, gap: gm });
        }
        stack.push((m, gm, b, gb));
        stack.push((a, ga, m, gm));
    }
    Ok(evals)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bump::collide::ColliderKind;

    fn one_atom(x: f64) -> Molecule {
        Molecule::new(
            "a",
            vec![crate::atom(1, "C", 1.7)],
            &[DVec3::new(x, 0.0, 0.0)],
        )
    }

    #[test]
    fn head_on_pair_touches_at_the_contact_distance() {
        // C–C contact distance 1.7 + 1.7 − 0.6 = 2.8 Å; start 10 Å apart.
        let rule = ContactRule::default();
        let (r, d) = (one_atom(0.0), one_atom(0.0));
        let start = Pose::from_translation(DVec3::new(10.0, 0.0, 0.0));
        let step = DVec3::new(-10.0, 0.0, 0.0);
        let t = translation_toi(&rule, &r, &d, &start, step).expect("hit");
        assert!((t - 0.72).abs() < 1e-6, "{t}"); // (10 − 2.8) / 10, f32 radii
        let col = Collider::build(&r, &rule, ColliderKind::Hashed);
        let atoms = DrugAtoms::new(&d, &rule, col.max_radius());
        let t2 = closed_form_touch(&col, &atoms, &start, step).expect("hit");
        assert!((t - t2).abs() < 1e-6, "{t} vs {t2}"); // contact summed in another order
        // Moving away or stopping short: no contact.
        assert!(translation_toi(&rule, &r, &d, &start, -step).is_none());
        assert!(translation_toi(&rule, &r, &d, &start, step * 0.5).is_none());
        assert!(min_gap(&rule, &r, &d, &start) > 7.0);
    }

    #[test]
    fn the_certificate_finds_a_wall_a_long_step_jumps_over() {
        let rule = ContactRule::default();
        let (r, d) = (one_atom(0.0), one_atom(0.0));
        let start = Pose::from_translation(DVec3::new(-500.0, 0.3, 0.0));
        let end = Pose::from_translation(DVec3::new(500.0, 0.3, 0.0));
        let screw = Screw::between(start, end);
        // Both ends are free; the middle passes through the atom.
        let fault = certify_free_path(&rule, &r, &d, &screw, 1.0).expect_err("hits");
        assert!(
            fault.gap <= 0.0 && (fault.t - 0.5).abs() < 0.01,
            "{fault:?}"
        );
        // Up to just before contact it is free.
        let t = translation_toi(&rule, &r, &d, &start, end.translation - start.translation)
            .expect("hit");
        assert!(certify_free_path(&rule, &r, &d, &screw, t - 1e-6).is_ok());
        assert!(
            dense_screw_toi(&rule, &r, &d, &screw, 1000).is_some_and(|td| (td - t).abs() < 1e-9)
        );
    }
}
