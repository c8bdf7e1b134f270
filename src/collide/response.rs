//! Collision responses: what the session does with a proposed step.
//!
//! - `stop`: reject the whole step if any of it collides (the thesis's first
//!   version, but judged along the whole path, so a fast step cannot jump
//!   through a wall).
//! - `touch`: move-to-touch.
//! - `slide`: touch, then project what is left of the motion onto the tangent
//!   space of the contacts and go on, a few times (the thesis's future work).
//!   The projection works on the 6-D twist: each contact with normal `n` at
//!   drug atom `x` forbids `n·(v + ω × (x − c)) < 0`; violated constraints are
//!   removed by cyclic projection (Gauss–Seidel), then the drug moves to touch
//!   along what remains.
//! - `pass`: move freely and only report contacts (what the thesis's users
//!   asked for most).

use glam::DVec3;
use serde::Serialize;

use super::check::{Pair, check, min_gap, pairs_within};
use super::collider::Collider;
use super::drug::DrugAtoms;
use super::sweep::{NEAREST_WITHIN, TouchOptions, TouchResult, move_to_touch};
use crate::motion::{Pose, Screw};

/// How the session answers a step that would collide.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Response {
    /// Reject the whole step.
    Stop,
    /// Move to touch.
    #[default]
    Touch,
    /// Touch, then slide along the contacts.
    Slide,
    /// Move freely; only report contacts.
    Pass,
}

impl Response {
    /// All responses in the order a menu lists them.
    pub const ALL: [Response; 4] = [Self::Stop, Self::Touch, Self::Slide, Self::Pass];

    /// Parses `stop`, `touch`, `slide` or `pass`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "stop" => Some(Self::Stop),
            "touch" => Some(Self::Touch),
            "slide" => Some(Self::Slide),
            "pass" => Some(Self::Pass),
            _ => None,
        }
    }

    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Stop => "stop",
            Self::Touch => "touch",
            Self::Slide => "slide",
            Self::Pass => "pass",
        }
    }
}

/// Slide iterations after the first touch.
pub const SLIDE_ITERATIONS: usize = 4;

/// Outcome of one step under a response.
#[derive(Debug, Clone)]
pub struct StepResult {
    /// The response applied.
    pub response: Response,
    /// Fraction of the proposed motion made before the first contact
    /// (`stop`: 0 or 1; `pass`: 1; `slide`: of its first leg).
    pub t: f64,
    /// Number of touch legs taken (slide: 1 + slides; others 1, pass 0).
    pub legs: usize,
    /// The drug's new pose in the receptor frame.
    pub pose: Pose,
    /// Pairs within tolerance of contact at the new pose (`stop`: the pairs
    /// the rejected step ran into), sorted.
    pub contacts: Vec<Pair>,
    /// Pairs colliding at the new pose (only with `pass`, or a colliding start).
    pub colliding: Vec<Pair>,
    /// Pairs colliding at the start pose.
    pub start_colliding: Vec<Pair>,
    /// The pair with the smallest gap at the new pose, within 4 Å of contact.
    pub nearest: Option<Pair>,
}

impl StepResult {
    fn from_touch(response: Response, r: TouchResult, legs: usize) -> Self {
        Self {
            response,
            t: r.t,
            legs,
            pose: r.pose,
            contacts: r.contacts,
            colliding: r.colliding,
            start_colliding: r.start_colliding,
            nearest: r.nearest,
        }
    }
}

/// Applies `response` to the step from `start` to `end` (drug poses relative
/// to the receptor).
pub fn respond(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    end: &Pose,
    response: Response,
    opts: &TouchOptions,
) -> StepResult {
    match response {
        Response::Touch => {
            StepResult::from_touch(response, move_to_touch(collider, drug, start, end, opts), 1)
        }
        Response::Stop => {
            let r = move_to_touch(collider, drug, start, end, opts);
            if r.t >= 1.0 {
                return StepResult::from_touch(response, r, 1);
            }
            let colliding = check(collider, drug, start);
            StepResult {
                response,
                t: 0.0,
                legs: 1,
                pose: *start,
                contacts: r.contacts,
                colliding,
                start_colliding: r.start_colliding,
                nearest: min_gap(collider, drug, start, NEAREST_WITHIN),
            }
        }
        Response::Pass => {
            let contacts = pairs_within(collider, drug, end, opts.tolerance as f32);
            let colliding = contacts.iter().copied().filter(Pair::collides).collect();
            StepResult {
                response,
                t: 1.0,
                legs: 0,
                pose: *end,
                contacts,
                colliding,
                start_colliding: check(collider, drug, start),
                nearest: min_gap(collider, drug, end, NEAREST_WITHIN),
            }
        }
        Response::Slide => slide(collider, drug, start, end, opts),
    }
}

fn slide(
    collider: &Collider,
    drug: &DrugAtoms,
    start: &Pose,
    end: &Pose,
    opts: &TouchOptions,
) -> StepResult {
    let first = move_to_touch(collider, drug, start, end, opts);
    let t_first = first.t;
    let start_colliding = first.start_colliding.clone();
    let mut r = first;
    let mut from = *start;
    let mut to = *end;
    let mut legs = 1;
    for _ in 0..SLIDE_ITERATIONS {
        if r.t >= 1.0 || r.contacts.is_empty() {
            break;
        }
        // What is left of the motion, as a twist at the touch pose.
        let screw = Screw::between(from, to);
        let rest = 1.0 - r.t;
        let centre = r.pose.translation;
        let mut v = screw.velocity_at(centre) * rest;
        let mut w = screw.axis() * (screw.angle() * rest);
        let rows: Vec<(DVec3, DVec3)> = r
            .contacts
            .iter()
            .filter_map(|p| {
                let x = r
                    .pose
                    .transform_point(drug.local[p.drug as usize].as_dvec3());
                let q = collider.atom_position(p.receptor).as_dvec3();
                let n = (x - q).try_normalize()?;
                Some((n, (x - centre).cross(n)))
            })
            .collect();
        for _ in 0..16 {
            let mut worst = 0.0f64;
            for (n, rn) in &rows {
                let j = n.dot(v) + rn.dot(w);
                if j < 0.0 {
                    let norm = n.length_squared() + rn.length_squared();
                    v -= *n * (j / norm);
                    w -= *rn * (j / norm);
                    worst = worst.min(j);
                }
            }
            if worst > -1e-12 {
                break;
            }
        }
        let travel = v.length() + w.length() * drug.extent;
        if travel < opts.tolerance.max(1e-9) {
            break;
        }
        from = r.pose;
        to = from.moved(v, w, w.length());
        r = move_to_touch(collider, drug, &from, &to, opts);
        legs += 1;
    }
    let mut out = StepResult::from_touch(Response::Slide, r, legs);
    out.t = t_first;
    out.start_colliding = start_colliding;
    out
}
