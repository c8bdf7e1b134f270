//! Move-to-touch: how far along a proposed motion the drug may go.
//!
//! The motion is the screw from a start pose to an end pose ([`Screw`]); the
//! answer is the largest fraction `t` for which no pair collides anywhere on
//! `[0, t]`, the pose there and the pairs within `tolerance` of contact.
//!
//! # The swept method (default)
//! Every atom moves along a helix at a constant speed `s_i`. The motion is cut
//! into intervals in which no atom moves more than 1 Å (up to a grid cell
//! after an interval that found nothing), and only those during which the
//! drug can be near the receptor's box are visited. In an interval, atom `i`
//! stays inside a ball around its mid-interval position of radius
//! `s_i·Δt/2`, so the collider's box query around that ball finds every
//! receptor atom it could reach (nothing is skipped, however long the step).
//! Atoms are taken four at a time (a group), and most never get that far: a
//! group whose bounding ball lies wholly outside the receptor's box grown by
//! its reach and sweep (tested while the drug's centre is outside that box),
//! or whose ball the collider's clearance map proves far enough from every
//! receptor atom, has no candidates (in a pure translation, four groups'
//! bounding balls are tested at once, before any atom is placed), and an
//! atom whose ball the map proves empty has none either (by the nearest
//! lattice vertices of four atoms at once,
//! [`super::clearance::Clearance::clear_nearest4`]). No test changes the
//! answer, only what it costs. Intervals are taken in order
//! and the first hit ends the search.
//!
//! For each candidate pair the first time its gap reaches the target is found
//! by conservative advancement on `f(t) = |x(t) − q|² − c²`: from `t`, the
//! step is the first root of a lower bound of `f` — the larger of the
//! first-order bound (`|d'| ≤ s_i`) and a second-order one
//! (`f'' ≥ 2 s_i² − 2 |x − q| θ s_i`, exact for pure translations, where the
//! step lands on the closed-form time of impact, so a translation takes that
//! root at once). Steps never cross the root,
//! so the stop time is collision-free; the target contact distance is raised by
//! `tolerance/2` so rounding cannot turn "touching" into "colliding", and a
//! pair stops the drug only while it is approaching, so a drug at rest in
//! contact can always move away. The final pose is checked once more with the
//! static (f32) rule, backing off if rounding disagrees.
//!
//! A start pose that already collides is reported; its colliding pairs may not
//! get any closer (their target distance is their start distance; a dip of
//! f32 rounding size is tolerated on a step that ends no deeper, so atoms
//! coincident to 10⁻⁶ Å can be pulled apart), and a stop short of the end
//! leaves them no closer (in f64) than at the start, or the drug stays there:
//! a push repeated from each stop cannot sink it by that dip every time.
//! Every other pair obeys the rule as usual.
//!
//! # The thesis method ([`Method::Thesis`])
//! Turk's `pg_move_to_touch`: the colliding pairs at the end pose, then
//! bisection on that list only. It misses pairs that collide mid-path but not
//! at the end, so it can tunnel and can return overlapping poses; it is kept to
//! measure exactly that.
//!
//! # Layout
//! This file holds the query's interface and the rules every answer obeys
//! (a colliding start may not sink); `search.rs` the swept search's walk
//! over the intervals and its confirmation, `plan.rs` its stages
//! (intervals, culling, candidate search, pair resolution); `pair.rs` one
//! pair's first touch; `thesis.rs` the thesis's method.

mod pair;
mod plan;
mod search;
mod thesis;

use glam::{DQuat, DVec3};
use serde::Serialize;

use super::check::{Pair, check, pairs_within};
use super::collider::Collider;
use super::drug::DrugAtoms;
use crate::motion::{MAX_COORDINATE, Pose, Screw};
use search::swept;
use thesis::thesis;

/// Smallest tolerance accepted, in Å: below it f32 coordinates cannot tell
/// touching from colliding.
pub const MIN_TOLERANCE: f64 = 1e-5;

/// How much a pair that already overlaps may dip, in Å, during a step that
/// leaves it no deeper at its end: the rounding of f32 coordinates, so that
/// atoms "coincident" to 10⁻⁶ Å can be pulled apart in any direction.
pub(super) const OVERLAP_JITTER: f64 = 1e-5;

/// Which move-to-touch algorithm to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Swept conservative advancement: never overlaps, never tunnels.
    #[default]
    Swept,
    /// Turk 1989: end-pose pair list, then bisection on it.
    Thesis,
}

impl Method {
    /// Parses `swept` or `thesis`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "swept" | "bump" | "exact" => Some(Self::Swept),
            "thesis" | "turk" => Some(Self::Thesis),
            _ => None,
        }
    }

    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Swept => "swept",
            Self::Thesis => "thesis",
        }
    }
}

/// Parameters of a move-to-touch query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TouchOptions {
    /// Distance tolerance in Å: the drug stops when a pair's gap is within it
    /// (and never below zero). Clamped to at least [`MIN_TOLERANCE`].
    pub tolerance: f64,
    /// Algorithm.
    pub method: Method,
}

impl Default for TouchOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-3,
            method: Method::Swept,
        }
    }
}

/// What a move-to-touch query found. A caller that asks many queries
/// (a haptic loop, a benchmark) can keep one and pass it to
/// [`move_to_touch_into`], which reuses its lists' storage.
#[derive(Debug, Clone, Default)]
pub struct TouchResult {
    /// Fraction of the motion allowed, in [0, 1].
    pub t: f64,
    /// The drug's pose (in the receptor frame) at `t`.
    pub pose: Pose,
    /// Pairs within `tolerance` of contact (or colliding) at `pose`, sorted.
    pub contacts: Vec<Pair>,
    /// Pairs colliding at `pose`: empty unless the start already collided (those
    /// pairs, not deeper) or the thesis method failed.
    pub colliding: Vec<Pair>,
    /// Pairs colliding at the start pose.
    pub start_colliding: Vec<Pair>,
}

impl TouchResult {
    /// True when the start pose already collided.
    pub fn start_collides(&self) -> bool {
        !self.start_colliding.is_empty()
    }
}

/// Farthest a drug's pose may lie from its receptor, per axis, in Å: two
/// molecules within [`MAX_COORDINATE`] of the origin. Beyond it a step's
/// length in Å (its count of intervals) outgrows the integers an `f64`
/// holds exactly and its squared speed overflows.
pub const MAX_RELATIVE_COORDINATE: f64 = 2.0 * MAX_COORDINATE;

/// True when `pose` is finite and within [`MAX_RELATIVE_COORDINATE`].
#[inline]
fn in_reach(pose: &Pose) -> bool {
    // Every query asks this twice, so without `is_finite`'s seven tests:
    // a comparison with NaN is false, so the bounds test the translation's
    // finiteness too, and a quaternion's components times zero sum to zero
    // exactly when all are finite (an infinity or NaN gives NaN).
    let (r, t) = (pose.rotation, pose.translation.abs());
    r.x * 0.0 + r.y * 0.0 + r.z * 0.0 + r.w * 0.0 == 0.0
        && t.x <= MAX_RELATIVE_COORDINATE
        && t.y <= MAX_RELATIVE_COORDINATE
        && t.z <= MAX_RELATIVE_COORDINATE
}

/// Moves the drug from `start` towards `end` (both relative to the receptor)
/// and stops it at first touch. See the module documentation.
///
/// # Panics
/// Never; a pose that is not finite, or lies beyond
/// [`MAX_RELATIVE_COORDINATE`], gives `t = 0` at the start pose.
pub fn move_to_touch(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    end: &Pose,
    opts: &TouchOptions,
) -> TouchResult {
    let mut out = TouchResult::default();
    move_to_touch_into(collider, drug, start, end, opts, &mut out);
    out
}

/// [`move_to_touch`], its answer written into `out` (every field
/// replaced), whose lists keep their storage: a caller that passes the
/// same result query after query allocates nothing for the usual stop
/// (which takes its contacts from the search's own working list).
pub fn move_to_touch_into(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    end: &Pose,
    opts: &TouchOptions,
    out: &mut TouchResult,
) {
    let tol = if opts.tolerance.is_finite() {
        opts.tolerance.max(MIN_TOLERANCE)
    } else {
        MIN_TOLERANCE
    };
    let contacts_at =
        |p: &Pose, v: &mut Vec<Pair>| *v = pairs_within(collider, drug, p, tol as f32);
    if !in_reach(start) || !in_reach(end) {
        let colliding = check(collider, drug, start);
        return finish(out, 0.0, *start, colliding, contacts_at);
    }
    let screw = Screw::between(*start, *end);
    match opts.method {
        Method::Swept => swept(collider, drug, &screw, tol, out),
        Method::Thesis => {
            let (t, pose) = thesis(collider, drug, &screw, tol);
            finish(out, t, pose, check(collider, drug, start), contacts_at);
        }
    }
}

/// Writes a query's answer into `out`: `contacts` fills the (emptied)
/// contact list for the stop `pose`, and the pairs colliding there are
/// taken from it.
#[inline(always)]
pub(super) fn finish(
    out: &mut TouchResult,
    t: f64,
    pose: Pose,
    start_colliding: Vec<Pair>,
    contacts: impl FnOnce(&Pose, &mut Vec<Pair>),
) {
    out.t = t;
    out.pose = pose;
    out.contacts.clear();
    contacts(&pose, &mut out.contacts);
    out.colliding.clear();
    out.colliding
        .extend(out.contacts.iter().copied().filter(Pair::collides));
    // Usually empty: then the kept list is only emptied.
    if start_colliding.is_empty() {
        out.start_colliding.clear();
    } else {
        out.start_colliding = start_colliding;
    }
}

/// True when `colliding` (the pairs colliding at some pose) holds a pair the
/// start did not have, or one it had, deeper.
pub(super) fn violates(colliding: &[Pair], start_colliding: &[Pair]) -> bool {
    colliding.iter().any(|p| {
        match start_colliding.binary_search_by_key(&(p.receptor, p.drug), |s| (s.receptor, s.drug))
        {
            // Allowed to stay, not to get closer (f32 rounding slack).
            Ok(k) => {
                f64::from(p.distance)
                    < f64::from(start_colliding[k].distance) - 2.0 * OVERLAP_JITTER
            }
            Err(_) => true,
        }
    })
}

/// True when a pair of `start_colliding` is closer at `pose` than at
/// `start`, in f64. Out of line: only a colliding start gets here.
#[cold]
#[inline(never)]
pub(super) fn deepens(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    pose: &Pose,
    start_colliding: &[Pair],
) -> bool {
    let at = |p: &Pose, i: usize| p.rotation * drug.local[i].as_dvec3() + p.translation;
    start_colliding.iter().any(|p| {
        let q = collider.atom_position(p.receptor).as_dvec3();
        let i = p.drug as usize;
        (at(pose, i) - q).length_squared() < (at(start, i) - q).length_squared()
    })
}

/// Convenience: a rotation quaternion from an axis (any length) and degrees.
pub fn turn(axis: DVec3, degrees: f64) -> DQuat {
    if axis.length_squared() > 0.0 && degrees != 0.0 {
        DQuat::from_axis_angle(axis.normalize(), degrees.to_radians())
    } else {
        DQuat::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::{MAX_RELATIVE_COORDINATE, in_reach};
    use crate::motion::Pose;
    use glam::{DQuat, DVec3};

    #[test]
    fn in_reach_is_finite_and_within_bounds() {
        let max = MAX_RELATIVE_COORDINATE;
        let turned = DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 2.0);
        for (t, ok) in [
            (DVec3::ZERO, true),
            (DVec3::new(-max, max, 0.0), true),
            (DVec3::new(0.0, 0.0, -max * (1.0 + 1e-15)), false),
            (DVec3::new(0.0, f64::NAN, 0.0), false),
            (DVec3::new(f64::INFINITY, 0.0, 0.0), false),
            (DVec3::new(0.0, 0.0, f64::NEG_INFINITY), false),
        ] {
            for r in [DQuat::IDENTITY, turned] {
                let pose = Pose::new(r, t);
                let expected = pose.is_finite() && pose.translation.abs().max_element() <= max;
                assert_eq!(expected, ok, "{t}");
                assert_eq!(in_reach(&pose), ok, "{t} {r}");
            }
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for k in 0..4 {
                let mut q = [0.0, 0.0, 0.0, 1.0];
                q[k] = bad;
                let pose = Pose::new(DQuat::from_array(q), DVec3::ZERO);
                assert!(!in_reach(&pose), "{q:?}");
            }
        }
    }
}
