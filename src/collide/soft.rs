//! The `soft` response: the drug may press into the receptor up to a limit.
//!
//! The contact rule says when two atoms collide; `soft` lets a pair overlap
//! up to `limit` Å beyond it. The motion runs through move-to-touch (and
//! the slide) with the *loosened* rule (the same rule with its overlap
//! allowance raised by `limit`), on a collider and a drug copy built for
//! that rule once ([`SoftIndex`]), so the drug never passes the limit and
//! never tunnels, however long the step. Inside the band between the
//! default rule and the limit, the drug meets resistance: the part of the
//! proposed motion that goes *into* the pressed pairs (its twist minus the
//! nearest twist that moves no pressed pair closer, see
//! [`super::response`]'s cone projection) is scaled by
//! `1 / (1 + 4 E / limit²)`, with `E = Σ depth²` over the pressed pairs (the
//! shape of Vina's repulsion term, quadratic in the overlap), so one pair
//! at half the limit halves the push and one at the limit leaves a fifth.
//! Motion along the contacts and out of them is not resisted: the drug
//! slides as with `slide` and moves out freely.
//!
//! What the contacts still stop of a push, the drug *glides*: the part of
//! it that runs into the receptor's smoothed surface is taken away and the
//! rest, along that surface, is slid once more under the loosened rule
//! ([`glide_normal`]). The smoothed surface is the receptor's Gaussian
//! density at [`GLIDE_SIGMA`] Å (haptics' force shading: the normals of a
//! bumpy surface are smoothed so that it feels smooth), so a push that
//! catches between atoms carries the drug over them and round the
//! receptor's body instead of holding it in the hollow.
//!
//! What that glide cannot take, the drug glides round the receptor's
//! *body*: along the surface smoothed over
//! [`BODY_SIGMA`](super::body_shape::BODY_SIGMA) Å at the drug's
//! centre ([`BodyShape`]), lifted off it by [`BODY_CLIMB`]° so that it
//! rides over the atoms in the way, and only in the measure that the
//! receptor's mass there is one-sided (as at its outer surface, not in a
//! pocket: [`body_glide_weight`]). Pushed at the receptor's far side from
//! where it is headed, the drug so works its way round the body towards
//! the near side instead of resting where the push meets the surface
//! head-on; in a pocket, where the mass is all round, nothing lifts it
//! out.
//!
//! What is still left of the push then turns the drug as the pressed
//! pairs' torque turns it ([`contact_turn`]): pushed off-centre against
//! the receptor, a real body rolls round what holds it, and a drug that
//! turns so finds the way a channel runs. The turn, too, is slid under the
//! loosened rule.
//!
//! The contacts reported are those of the default rule (the pairs within
//! the tolerance of its contact distance, and every pressed pair with its
//! depth), so the session can grade them in colour.

use glam::DVec3;

use std::sync::Arc;

use super::body_shape::BodyShape;
use super::check::{Pair, pairs_within};
use super::collider::{Collider, ColliderKind};
use super::drug::DrugAtoms;
use super::response::{Response, StepResult, contact_rows, project_onto_cone, slide};
use super::rule::{ContactRule, RuleError};
use super::sweep::TouchOptions;
use crate::model::Molecule;
use crate::motion::{Pose, Screw};

/// Default soft limit: how far beyond the contact rule a pair may press, Å.
pub const DEFAULT_LIMIT: f64 = 1.0;

/// Largest soft limit accepted, Å.
pub const MAX_LIMIT: f64 = 3.0;

/// Width of the Gaussian that smooths the receptor's surface for the
/// glide, Å: about an atom's diameter, so the hollows between neighbouring
/// atoms (3–4 Å apart) are smoothed away while the receptor's large-scale
/// shape stays.
pub const GLIDE_SIGMA: f64 = 3.0;

/// How steeply the glide round the receptor's body climbs off its smoothed
/// surface, degrees: the lift per Å along it is `tan` of this, enough to
/// ride over an atom in the way rather than wedge against it.
pub const BODY_CLIMB: f64 = 20.0;

/// One-sidedness of the receptor's mass ([`super::body_shape::BodyPoint`])
/// at and below which the drug does not glide round the body: a pocket's
/// mouth. (In the shared complexes, the file poses' centres measure
/// 0.3–0.5, the drugs held at the mouths of their pockets 0.6–0.7, and a
/// drug against the outside of the receptor 0.7–1.5.)
pub const POCKET_ONE_SIDEDNESS: f64 = 0.6;

/// One-sidedness at a flat surface, `√(2/π)` (the mean of a half-normal
/// over σ): from here outwards the drug glides round the body in full.
pub const FLAT_ONE_SIDEDNESS: f64 = 0.797_884_560_802_865_4;

/// The loosened index of one receptor and drug: built once per limit.
#[derive(Debug, Clone)]
pub struct SoftIndex {
    /// How far beyond the default rule a pair may press, Å.
    pub limit: f64,
    /// The loosened rule.
    pub rule: ContactRule,
    /// The receptor indexed for the loosened rule.
    pub collider: Collider,
    /// The drug set up for the loosened rule.
    pub drug: DrugAtoms,
    /// The receptor's body-scale shape (`None` for an empty receptor),
    /// shared by the indexes of every limit.
    pub body: Option<Arc<BodyShape>>,
}

impl SoftIndex {
    /// Indexes `receptor` and `drug` for `rule` loosened by `limit` Å,
    /// with the receptor's body-scale shape `body` when it is already
    /// built (an index for another limit has it), else building it.
    ///
    /// # Errors
    /// When `limit` is not finite, negative or above [`MAX_LIMIT`].
    pub fn build(
        receptor: &Molecule,
        drug: &Molecule,
        rule: &ContactRule,
        limit: f64,
        kind: ColliderKind,
        body: Option<Arc<BodyShape>>,
    ) -> Result<Self, RuleError> {
        let soft = loosened(rule, limit)?;
        let collider = Collider::build(receptor, &soft, kind);
        let drug = DrugAtoms::new(drug, &soft, collider.max_radius());
        let body = body.or_else(|| {
            let atoms: Vec<DVec3> = (0..collider.len() as u32)
                .map(|i| collider.atom_position(i).as_dvec3())
                .collect();
            BodyShape::build(&atoms).map(Arc::new)
        });
        Ok(Self {
            limit,
            rule: soft,
            collider,
            drug,
            body,
        })
    }
}

/// `rule` with its overlap allowance raised by `limit` Å.
///
/// # Errors
/// When `limit` is not finite, negative or above [`MAX_LIMIT`].
pub fn loosened(rule: &ContactRule, limit: f64) -> Result<ContactRule, RuleError> {
    if !(0.0..=MAX_LIMIT).contains(&limit) {
        return Err(RuleError {
            what: "soft limit",
            value: limit as f32,
        });
    }
    ContactRule::new(rule.overlap + limit as f32, rule.hbond_allowance)
}

/// How far a pair presses beyond the default rule (0 when it does not).
#[inline]
pub fn depth(p: &Pair) -> f32 {
    (p.contact - p.distance).max(0.0)
}

/// The resistance of the pressed pairs in `pairs`, in [0, 1): the fraction
/// of a push into them that `soft` takes away.
pub fn resistance(pairs: &[Pair], limit: f64) -> f64 {
    resistance_of(pairs.iter().map(depth), limit)
}

/// The resistance of pairs pressed `depths` Å beyond the default rule (see
/// [`resistance`]).
pub fn resistance_of(depths: impl IntoIterator<Item = f32>, limit: f64) -> f64 {
    if limit <= 0.0 {
        return 0.0;
    }
    let e: f64 = depths.into_iter().map(|d| f64::from(d).powi(2)).sum();
    1.0 - 1.0 / (1.0 + 4.0 * e / (limit * limit))
}

/// The `soft` response to the step from `start` to `end`: `collider` and
/// `drug` are indexed for the default rule, `soft` for the loosened one.
pub fn respond_soft(
    collider: &Collider,
    drug: &DrugAtoms,
    soft: &SoftIndex,
    start: &Pose,
    end: &Pose,
    opts: &TouchOptions,
) -> StepResult {
    let tol = opts.tolerance as f32;
    let pressed: Vec<Pair> = pairs_within(collider, drug, start, tol)
        .into_iter()
        .filter(|p| depth(p) > 0.0)
        .collect();
    let k = 1.0 - resistance(&pressed, soft.limit);
    let target = if pressed.is_empty() || k >= 1.0 {
        *end
    } else {
        resisted(collider, drug, start, end, &pressed, k)
    };
    let mut r = slide(&soft.collider, &soft.drug, start, &target, opts);
    // The part of the push the contacts stopped glides along the smoothed
    // surface (translation only: the turn was the slide's to take).
    let rest = end.translation - r.pose.translation;
    if rest.length() > opts.tolerance
        && let Some(n) = glide_normal(collider, drug, &r.pose, &r.contacts)
    {
        let into = rest.dot(n);
        if into < 0.0 {
            let along = Pose::new(r.pose.rotation, r.pose.translation + (rest - n * into));
            let glide = slide(&soft.collider, &soft.drug, &r.pose, &along, opts);
            r.legs += glide.legs;
            r.via.push(r.pose);
            r.via.extend(glide.via);
            r.pose = glide.pose;
        }
    }
    // What that glide could not take glides round the receptor's body.
    let rest = end.translation - r.pose.translation;
    if rest.length() > opts.tolerance
        && let Some(body) = &soft.body
        && let Some(along) = body_glide(body, r.pose.translation, rest)
    {
        let target = Pose::new(r.pose.rotation, r.pose.translation + along);
        let glide = slide(&soft.collider, &soft.drug, &r.pose, &target, opts);
        r.legs += glide.legs;
        r.via.push(r.pose);
        r.via.extend(glide.via);
        r.pose = glide.pose;
    }
    r.response = Response::Soft;
    r.contacts = pairs_within(collider, drug, &r.pose, tol);
    // What is still left of the push turns the drug as the pressed pairs'
    // torque does: a push held off-centre rolls it round what holds it.
    let rest = end.translation - r.pose.translation;
    if rest.length() > opts.tolerance
        && let Some(turned) = contact_turn(collider, drug, &r.pose, &r.contacts, rest)
    {
        let turn = slide(&soft.collider, &soft.drug, &r.pose, &turned, opts);
        if turn.pose != r.pose {
            r.legs += turn.legs;
            r.via.push(r.pose);
            r.via.extend(turn.via);
            r.pose = turn.pose;
            r.contacts = pairs_within(collider, drug, &r.pose, tol);
        }
    }
    r.colliding = r.contacts.iter().copied().filter(Pair::collides).collect();
    r.resistance = resistance(&r.colliding, soft.limit);
    r
}

/// The outward normal of the receptor's smoothed surface at the drug atoms
/// in `contacts` (their centroid, the drug at `pose`): minus the gradient
/// of the density `Σ exp(−|x − q|² / 2σ²)` over the receptor's atoms `q`
/// within 3σ, σ = [`GLIDE_SIGMA`]. `None` without contacts or where the
/// density is flat.
pub fn glide_normal(
    collider: &Collider,
    drug: &DrugAtoms,
    pose: &Pose,
    contacts: &[Pair],
) -> Option<DVec3> {
    let mut atoms: Vec<u32> = contacts.iter().map(|p| p.drug).collect();
    atoms.sort_unstable();
    atoms.dedup();
    if atoms.is_empty() {
        return None;
    }
    let c = atoms
        .iter()
        .map(|&i| pose.transform_point(drug.local[i as usize].as_dvec3()))
        .sum::<DVec3>()
        / atoms.len() as f64;
    let s2 = 2.0 * GLIDE_SIGMA * GLIDE_SIGMA;
    let mut g = DVec3::ZERO;
    collider.near(c.as_vec3(), (3.0 * GLIDE_SIGMA) as f32, |q, _, d2| {
        g += (c - q.truncate().as_dvec3()) * (-f64::from(d2) / s2).exp();
    });
    g.try_normalize()
}

/// How much of a push the drug glides round the receptor's body where the
/// receptor's mass is `one_sided` ([`super::body_shape::BodyPoint`]): none
/// up to [`POCKET_ONE_SIDEDNESS`], all from [`FLAT_ONE_SIDEDNESS`], linear
/// between.
pub fn body_glide_weight(one_sided: f64) -> f64 {
    ((one_sided - POCKET_ONE_SIDEDNESS) / (FLAT_ONE_SIDEDNESS - POCKET_ONE_SIDEDNESS))
        .clamp(0.0, 1.0)
}

/// The glide round the receptor's body of `rest`, the part of a push that
/// the contacts and the first glide stopped, for the drug centred at
/// `centre`: its part along the body's smoothed surface, weighed by
/// [`body_glide_weight`] and lifted off the surface by [`BODY_CLIMB`]°.
/// `None` where `rest` does not run into the body or the weight is 0.
pub fn body_glide(body: &BodyShape, centre: DVec3, rest: DVec3) -> Option<DVec3> {
    let at = body.at(centre)?;
    let weight = body_glide_weight(at.one_sidedness);
    let into = rest.dot(at.normal);
    if into >= 0.0 || weight <= 0.0 {
        return None;
    }
    let along = (rest - at.normal * into) * weight;
    Some(along + at.normal * along.length() * BODY_CLIMB.to_radians().tan())
}

/// Largest turn of [`contact_turn`] in one step, degrees: the steering
/// controller's largest turn in a frame.
pub const MAX_CONTACT_TURN: f64 = 3.0;

/// How readily the drug turns under a torque against how readily it moves
/// under a force: a sphere's in a viscous fluid, whose drag is `6πηL`
/// against a force and `8πηL³` against a torque, so it turns by
/// `(6/8) · (τ/F) / L²` radians for each Å it would move (the overdamped
/// motion of Brownian dynamics).
pub const TURN_MOBILITY: f64 = 0.75;

/// The drug at `pose` turned about its centre as the pairs in `contacts`
/// pressed beyond the default rule push it, when `rest` of a push is left
/// that they hold: each pair pushes its drug atom out along the line from
/// the receptor atom with a force equal to its depth, and the drug turns
/// about their torque `τ` by `m · |τ| / (Σ depth · L) · |rest| / L` radians
/// (the forces' lever fraction times the push left, over the drug's extent
/// `L`, with the mobility `m` = [`TURN_MOBILITY`]), at most
/// [`MAX_CONTACT_TURN`]°. `None` when nothing presses or the torque
/// vanishes.
pub fn contact_turn(
    collider: &Collider,
    drug: &DrugAtoms,
    pose: &Pose,
    contacts: &[Pair],
    rest: DVec3,
) -> Option<Pose> {
    let centre = pose.translation;
    let mut torque = DVec3::ZERO;
    let mut force = 0.0;
    for p in contacts {
        let d = f64::from(depth(p));
        if d <= 0.0 {
            continue;
        }
        let x = pose.transform_point(drug.local[p.drug as usize].as_dvec3());
        let q = collider.atom_position(p.receptor).as_dvec3();
        let Some(n) = (x - q).try_normalize() else {
            continue;
        };
        torque += (x - centre).cross(n * d);
        force += d;
    }
    let l = drug.extent.max(1.0);
    let axis = torque.try_normalize()?;
    let angle = (TURN_MOBILITY * torque.length() / (force * l) * rest.length() / l)
        .min(MAX_CONTACT_TURN.to_radians());
    (angle > 0.0).then(|| pose.moved(DVec3::ZERO, axis, angle))
}

/// The end of the step from `start` to `end` with its part into the
/// `pressed` pairs scaled by `k`.
fn resisted(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    end: &Pose,
    pressed: &[Pair],
    k: f64,
) -> Pose {
    let screw = Screw::between(*start, *end);
    let centre = start.translation;
    let v = screw.velocity_at(centre);
    let w = screw.axis() * screw.angle();
    let l = drug.extent.max(1.0);
    let rows = contact_rows(collider, drug, start, pressed, screw.angle() != 0.0);
    let x = [v.x, v.y, v.z, w.x * l, w.y * l, w.z * l];
    let free = project_onto_cone(x, &rows);
    let u: [f64; 6] = std::array::from_fn(|i| free[i] + k * (x[i] - free[i]));
    let v = DVec3::new(u[0], u[1], u[2]);
    let w = DVec3::new(u[3], u[4], u[5]) / l;
    start.twisted(v, w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::check::check;
    use crate::collide::sweep::turn;
    use crate::model::{RadiiSet, builtin};
    use crate::rng::Rng;

    /// Brute force: every pair's depth beyond the default rule, in f64.
    fn deepest(receptor: &Molecule, drug: &Molecule, rule: &ContactRule, rel: &Pose) -> f64 {
        let mut most = 0.0f64;
        for (j, a) in receptor.atoms.iter().enumerate() {
            let q = receptor.local[j].as_dvec3();
            for (i, b) in drug.atoms.iter().enumerate() {
                let x = rel.transform_point(drug.local[i].as_dvec3());
                let c = f64::from(rule.contact_distance(a.radius, a.polar, b.radius, b.polar));
                most = most.max(c - (x - q).length());
            }
        }
        most
    }

    #[test]
    fn soft_never_presses_beyond_its_limit_nor_tunnels() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let rule = ContactRule::default();
        let hard = Collider::build(&rings, &rule, ColliderKind::Hashed);
        let drug = DrugAtoms::new(&e, &rule, hard.max_radius());
        let opts = TouchOptions::default();
        let mut rng = Rng(44);
        let mut pressed_some = false;
        for limit in [0.0, 0.5, 1.0, 2.0] {
            let soft = SoftIndex::build(&rings, &e, &rule, limit, ColliderKind::Hashed, None)
                .expect("index");
            for _ in 0..40 {
                // Start clear of the rings, then push hard towards their
                // centre in steps of up to 3 Å and 20°.
                let mut pose = Pose::from_translation(
                    DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 1.0).normalize() * 14.0,
                );
                if !check(&hard, &drug, &pose).is_empty() {
                    continue;
                }
                for _ in 0..12 {
                    let to_centre = -pose.translation;
                    let step = to_centre.normalize_or_zero() * rng.range(0.5, 3.0)
                        + DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                    let axis = DVec3::new(rng.range(-1.0, 1.0), 1.0, rng.range(-1.0, 1.0));
                    let end = Pose::new(
                        turn(axis, rng.range(-20.0, 20.0)) * pose.rotation,
                        pose.translation + step,
                    );
                    let r = respond_soft(&hard, &drug, &soft, &pose, &end, &opts);
                    // Never beyond the limit at the end pose …
                    let d = deepest(&rings, &e, &rule, &r.pose);
                    assert!(d <= limit + 1e-4, "limit {limit}: {d} Å deep");
                    // … nor anywhere along the path taken (finely sampled),
                    // leg by leg.
                    let corners: Vec<Pose> = std::iter::once(pose)
                        .chain(r.via.iter().copied())
                        .chain(std::iter::once(r.pose))
                        .collect();
                    for leg in corners.windows(2) {
                        let (a, b) = (leg[0], leg[1]);
                        let path = Screw::between(a, b);
                        for s in 1..=32 {
                            let p = path.pose_at(f64::from(s) / 32.0);
                            let d = deepest(&rings, &e, &rule, &p);
                            assert!(d <= limit + 1e-3, "limit {limit}: {d} Å deep on the path");
                        }
                    }
                    pressed_some |= d > 0.05;
                    let shown = r.contacts.iter().map(|p| f64::from(depth(p)));
                    assert!(shown.fold(0.0, f64::max) <= limit + 1e-4);
                    assert!((0.0..1.0).contains(&r.resistance));
                    pose = r.pose;
                }
            }
        }
        assert!(pressed_some, "no step pressed into the band");
    }

    #[test]
    fn a_push_caught_in_a_hollow_glides_along_the_wall() {
        use crate::model::molecule::test_carbon;
        let wall = crate::model::molecule::test_wall();
        let probe = Molecule::new("probe", vec![test_carbon(1)], &[DVec3::ZERO]);
        let rule = ContactRule::default();
        let hard = Collider::build(&wall, &rule, ColliderKind::Hashed);
        let drug = DrugAtoms::new(&probe, &rule, hard.max_radius());
        let soft = SoftIndex::build(
            &wall,
            &probe,
            &rule,
            DEFAULT_LIMIT,
            ColliderKind::Hashed,
            None,
        )
        .expect("index");
        let opts = TouchOptions::default();
        // The wall's smoothed surface faces +z over its middle.
        let above = Pose::from_translation(DVec3::new(1.5, 1.5, 3.0) - wall.centre);
        let n = glide_normal(
            &hard,
            &drug,
            &above,
            &[Pair {
                receptor: 0,
                drug: 0,
                distance: 0.0,
                contact: 0.0,
            }],
        )
        .expect("normal");
        assert!(n.z > 0.99, "{n}");
        // Pushed into the wall at 45° from above a hollow: the probe presses
        // into the hollow, then glides along x over the rows of atoms, never
        // deeper than the limit (without the glide it stays in the second
        // hollow, 3.5 Å along).
        let push = DVec3::new(1.0, 0.0, -1.0).normalize() * 0.3;
        let mut pose = Pose::from_translation(DVec3::new(1.5, 1.5, 4.0) - wall.centre);
        let x0 = pose.translation.x;
        for _ in 0..120 {
            let end = Pose::new(pose.rotation, pose.translation + push);
            let r = respond_soft(&hard, &drug, &soft, &pose, &end, &opts);
            let d = deepest(&wall, &probe, &rule, &r.pose);
            assert!(d <= DEFAULT_LIMIT + 1e-4, "{d} Å deep");
            pose = r.pose;
        }
        let along = pose.translation.x - x0;
        assert!(along > 6.0, "glided {along} Å along the wall");
    }

    #[test]
    fn a_push_at_a_bodys_far_side_glides_round_it_and_a_pocket_keeps_it() {
        // A ball of atoms 15 Å in radius: at its outside the mass is
        // one-sided and the glide takes all of a push along the surface,
        // lifted by the climb; at its centre, mass all round, none.
        let atoms = crate::collide::body_shape::tests::blob(&mut Rng(11), 4000, 15.0);
        let body = BodyShape::build(&atoms).expect("shape");
        let centre = DVec3::new(0.0, 0.0, 18.0);
        // Pushed nearly head-on (10° off) into the ball's top.
        let push = DVec3::new(10f64.to_radians().sin(), 0.0, -10f64.to_radians().cos()) * 0.3;
        let along = body_glide(&body, centre, push).expect("a glide");
        let normal = body.at(centre).expect("inside the grid").normal;
        let lift = along.dot(normal);
        let tangent = along - normal * lift;
        let want = push - normal * push.dot(normal);
        assert!((tangent - want).length() < 1e-9, "{tangent} vs {want}");
        assert!(
            (lift - tangent.length() * BODY_CLIMB.to_radians().tan()).abs() < 1e-9,
            "{lift}"
        );
        // Pulled away from the ball: nothing to glide round.
        assert!(body_glide(&body, centre, -push).is_none());
        // At the ball's centre, as deep in a pocket, the drug is not lifted out.
        assert!(body_glide(&body, DVec3::new(0.3, 0.1, -0.2), push).is_none());
        assert_eq!(body_glide_weight(POCKET_ONE_SIDEDNESS), 0.0);
        assert_eq!(body_glide_weight(FLAT_ONE_SIDEDNESS), 1.0);
        assert!(
            (body_glide_weight(FLAT_ONE_SIDEDNESS.midpoint(POCKET_ONE_SIDEDNESS)) - 0.5).abs()
                < 1e-12
        );
    }

    #[test]
    fn a_push_held_at_one_end_rolls_the_drug_away_from_what_holds_it() {
        use crate::model::molecule::test_carbon;
        let atom = Molecule::new("atom", vec![test_carbon(1)], &[DVec3::ZERO]);
        let ends = [DVec3::new(-1.5, 0.0, 0.0), DVec3::new(1.5, 0.0, 0.0)];
        let stick = Molecule::new("stick", vec![test_carbon(1), test_carbon(2)], &ends);
        let rule = ContactRule::default();
        let hard = Collider::build(&atom, &rule, ColliderKind::Hashed);
        let drug = DrugAtoms::new(&stick, &rule, hard.max_radius());
        // The stick's +x end sits 2.2 Å above the atom, 0.6 Å past the rule
        // (contact 2.8 Å), pushed down: the torque about its centre is
        // 1.5 × 0.6 about +z, the whole lever (1.5 × 0.6 / (0.6 × 1.5)).
        let pose = Pose::from_translation(DVec3::new(-1.5, 2.2, 0.0));
        let pressed = Pair {
            receptor: 0,
            drug: 1,
            distance: 2.2,
            contact: 2.8,
        };
        let rest = DVec3::new(0.0, -0.03, 0.0);
        let turned = contact_turn(&hard, &drug, &pose, &[pressed], rest).expect("a turn");
        let (axis, angle) = (turned.rotation * pose.rotation.conjugate()).to_axis_angle();
        assert!(axis.z > 1.0 - 1e-9, "{axis}");
        let want = TURN_MOBILITY * 0.03 / 1.5;
        assert!((angle - want).abs() < 1e-9, "{angle} against {want}");
        assert_eq!(turned.translation, pose.translation);
        // The held end rises off the atom.
        let end = turned.transform_point(drug.local[1].as_dvec3());
        assert!(end.y > 2.2, "{end}");
        // A long push turns at most the largest turn.
        let far = contact_turn(&hard, &drug, &pose, &[pressed], rest * 100.0).expect("a turn");
        let (_, angle) = (far.rotation * pose.rotation.conjugate()).to_axis_angle();
        assert!(
            (angle - MAX_CONTACT_TURN.to_radians()).abs() < 1e-9,
            "{angle}"
        );
        // Touching without pressing, or pressing through the centre: no turn.
        let touching = Pair {
            distance: 2.8,
            ..pressed
        };
        assert!(contact_turn(&hard, &drug, &pose, &[touching], rest).is_none());
        let end_on = Pose::from_translation(DVec3::new(3.7, 0.0, 0.0));
        let in_line = Pair { drug: 0, ..pressed };
        assert!(contact_turn(&hard, &drug, &end_on, &[in_line], rest).is_none());
    }

    #[test]
    fn soft_moves_out_freely_and_resists_pushing_in() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let rule = ContactRule::default();
        let hard = Collider::build(&rings, &rule, ColliderKind::Hashed);
        let drug = DrugAtoms::new(&e, &rule, hard.max_radius());
        let soft =
            SoftIndex::build(&rings, &e, &rule, 1.0, ColliderKind::Hashed, None).expect("index");
        let opts = TouchOptions::default();
        let dir = DVec3::new(0.1, 0.2, -1.0).normalize();
        let mut pose = Pose::from_translation(-dir * 20.0);
        // Press in with 0.2 Å steps until it stops.
        let mut depths = Vec::new();
        for _ in 0..400 {
            let end = Pose::new(pose.rotation, pose.translation + dir * 0.2);
            let r = respond_soft(&hard, &drug, &soft, &pose, &end, &opts);
            depths.push(r.contacts.iter().map(depth).fold(0.0f32, f32::max));
            pose = r.pose;
        }
        let most = depths.iter().copied().fold(0.0f32, f32::max);
        assert!(most > 0.5 && most <= 1.0 + 1e-4, "pressed {most} Å");
        // Out again: the whole step is taken.
        let end = Pose::new(pose.rotation, pose.translation - dir * 0.2);
        let r = respond_soft(&hard, &drug, &soft, &pose, &end, &opts);
        assert_eq!(r.t, 1.0);
        assert!((r.pose.translation - end.translation).length() < 1e-9);
    }
}
