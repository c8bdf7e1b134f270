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
//!   removed by cyclic projection (Gauss–Seidel) in the metric
//!   `|Δv|² + L²|Δω|²` (`L` the drug's size), then the drug moves to touch
//!   along what remains. A pure translation is projected as a translation, so
//!   pushing never makes the drug spin. The step's own twist is one more
//!   constraint of every leg, and a leg with nothing left along it ends the
//!   slide: the drug never slides back against the push.
//! - `soft`: press in up to a limit beyond the contact rule, against a
//!   resistance that grows with the overlap, sliding as `slide` does
//!   ([`super::soft`]; [`respond`] has no loosened index, so here its limit
//!   is 0 and it moves as `slide`).
//! - `pass`: move freely and only report contacts (what the thesis's users
//!   asked for most).

use glam::DVec3;
use serde::Serialize;

use super::check::{Pair, check, pairs_within};
use super::collider::Collider;
use super::drug::DrugAtoms;
use super::sweep::{TouchOptions, TouchResult, move_to_touch};
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
    /// Press in up to a limit against a growing resistance, sliding.
    Soft,
    /// Move freely; only report contacts.
    Pass,
}

impl Response {
    /// All responses in the order a menu lists them.
    pub const ALL: [Response; 5] = [Self::Stop, Self::Touch, Self::Slide, Self::Soft, Self::Pass];

    /// Parses `stop`, `touch`, `slide`, `soft` or `pass`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "stop" => Some(Self::Stop),
            "touch" => Some(Self::Touch),
            "slide" => Some(Self::Slide),
            "soft" => Some(Self::Soft),
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
            Self::Soft => "soft",
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
    /// `soft`: the resistance of the pairs pressed in at the new pose, in
    /// [0, 1) (see [`super::soft::resistance`]); 0 for the others.
    pub resistance: f64,
    /// The poses where each leg after the first began, in order (`slide`
    /// and `soft`; `soft`'s glide is one more leg or more): the drug went
    /// from the start through each of them to `pose`, each leg a screw.
    pub via: Vec<Pose>,
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
            resistance: 0.0,
            via: Vec::new(),
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
            StepResult {
                response,
                t: 0.0,
                legs: 1,
                pose: *start,
                contacts: r.contacts,
                colliding: r.start_colliding.clone(),
                start_colliding: r.start_colliding,
                resistance: 0.0,
                via: Vec::new(),
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
                resistance: 0.0,
                via: Vec::new(),
            }
        }
        Response::Slide => slide(collider, drug, start, end, opts),
        Response::Soft => {
            let mut r = slide(collider, drug, start, end, opts);
            r.response = Response::Soft;
            r
        }
    }
}

pub(super) fn slide(
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
    // The step's own direction, as a twist in the projection's coordinates:
    // every leg is kept from opposing it. Each leg projects the leg before,
    // so without it a few legs against differently tilted contacts could
    // turn the motion round and carry the drug back against the push.
    let mut push: Option<[f64; 6]> = None;
    let mut via = Vec::new();
    for _ in 0..SLIDE_ITERATIONS {
        if r.t >= 1.0 || r.contacts.is_empty() {
            break;
        }
        // What is left of the motion, as a twist at the touch pose.
        let screw = Screw::between(from, to);
        let rest = 1.0 - r.t;
        let centre = r.pose.translation;
        let v = screw.velocity_at(centre) * rest;
        let w = screw.axis() * (screw.angle() * rest);
        // Pure pushes slide without turning; motions that turn project the
        // twist with rotations weighted by the drug's size, i.e. in the
        // coordinates u = (v, L·ω), so sliding does not become spinning.
        let l = drug.extent.max(1.0);
        let mut rows = contact_rows(collider, drug, &r.pose, &r.contacts, screw.angle() != 0.0);
        let x = [v.x, v.y, v.z, w.x * l, w.y * l, w.z * l];
        let push = *push.get_or_insert(x);
        rows.push(push);
        let u = project_onto_cone(x, &rows);
        // Nothing left along the push (only across it, or none): stop.
        if dot6(&u, &push) <= 1e-9 * dot6(&u, &u).sqrt() * dot6(&push, &push).sqrt() {
            break;
        }
        let mut v = DVec3::new(u[0], u[1], u[2]);
        let mut w = DVec3::new(u[3], u[4], u[5]) / l;
        // A screw turns at most half a turn: a longer one would be taken
        // the other way round, so shorten the whole twist.
        let most = 0.99 * std::f64::consts::PI;
        if w.length() > most {
            let k = most / w.length();
            (v, w) = (v * k, w * k);
        }
        let travel = v.length() + w.length() * drug.extent;
        if travel < opts.tolerance.max(1e-9) {
            break;
        }
        // The screw that starts with exactly this twist: the constraints
        // above hold for its first instant, so the touching pairs slide
        // (a screw that only ended at `moved(v, ω)` would start along
        // another direction and run straight back into them).
        from = r.pose;
        to = from.twisted(v, w);
        via.push(from);
        r = move_to_touch(collider, drug, &from, &to, opts);
        legs += 1;
    }
    let mut out = StepResult::from_touch(Response::Slide, r, legs);
    out.t = t_first;
    out.start_colliding = start_colliding;
    out.via = via;
    out
}

/// The pairs in `contacts` as rows of the cone of motions that move none of
/// them closer ([`project_onto_cone`]), for the drug at `pose` moved by a
/// twist about its centre in the coordinates `(v, L·ω)`, `L` the drug's
/// extent: each row is the pair's normal `n` (from the receptor atom to the
/// drug atom) and, for a motion that `turns`, the lever `(x − c) × n / L`
/// of the drug atom `x` about the centre `c` (zero for a pure push, so that
/// sliding does not become spinning).
pub(super) fn contact_rows(
    collider: &Collider,
    drug: &DrugAtoms,
    pose: &Pose,
    contacts: &[Pair],
    turns: bool,
) -> Vec<[f64; 6]> {
    let centre = pose.translation;
    let l = drug.extent.max(1.0);
    contacts
        .iter()
        .filter_map(|p| {
            let x = pose.transform_point(drug.local[p.drug as usize].as_dvec3());
            let q = collider.atom_position(p.receptor).as_dvec3();
            let n = (x - q).try_normalize()?;
            let rn = if turns {
                (x - centre).cross(n) / l
            } else {
                DVec3::ZERO
            };
            Some([n.x, n.y, n.z, rn.x, rn.y, rn.z])
        })
        .collect()
}

fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Euclidean projection of `x` onto the cone `{u : row·u ≥ 0 for every row}`.
/// The result `p` satisfies `p·x = |p|² ≥ 0`: sliding never opposes the push.
///
/// By Moreau's decomposition `p = x + Rᵀμ` with `μ ≥ 0` the non-negative
/// least-squares solution of `min |Rᵀμ + x|`, found exactly in a few steps
/// by Lawson and Hanson's active-set method ([`cone_by_active_set`]: at
/// most six rows are ever active in six dimensions). Dykstra's alternating
/// projections ([`cone_by_dykstra`]) are the fallback where the active set
/// does not settle (rows nearly parallel); they reach the same point but
/// slowly (hundreds of sweeps for the ten-odd contacts of a pressed drug).
pub(super) fn project_onto_cone(x: [f64; 6], rows: &[[f64; 6]]) -> [f64; 6] {
    let u = cone_by_active_set(x, rows).unwrap_or_else(|| cone_by_dykstra(x, rows));
    clip_into_cone(u, rows)
}

/// Solves `a z = b` (`k × k`, row-major in the first `k` rows and columns)
/// by Gaussian elimination with partial pivoting; `None` when singular.
fn solve_small(a: &mut [[f64; 6]; 6], b: &mut [f64; 6], k: usize) -> Option<[f64; 6]> {
    let scale = (0..k).map(|i| a[i][i].abs()).fold(0.0f64, f64::max);
    for c in 0..k {
        let p = (c..k).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        // Also refuses a NaN pivot.
        if a[p][c].abs().partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c];
        for r in c + 1..k {
            let f = a[r][c] / pivot[c];
            for (x, y) in a[r][c..k].iter_mut().zip(&pivot[c..k]) {
                *x -= f * y;
            }
            b[r] -= f * b[c];
        }
    }
    let mut z = [0.0; 6];
    for r in (0..k).rev() {
        let tail: f64 = (r + 1..k).map(|cc| a[r][cc] * z[cc]).sum();
        z[r] = (b[r] - tail) / a[r][r];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
}

/// The projection by Lawson and Hanson's non-negative least squares on
/// `min |Rᵀμ + x|, μ ≥ 0` (`p = x + Rᵀμ`); `None` when it does not settle.
fn cone_by_active_set(x: [f64; 6], rows: &[[f64; 6]]) -> Option<[f64; 6]> {
    let m = rows.len();
    let mut mu = vec![0.0f64; m];
    let mut active: Vec<usize> = Vec::with_capacity(6);
    let p_of = |mu: &[f64]| -> [f64; 6] {
        let mut p = x;
        for (row, &w) in rows.iter().zip(mu) {
            if w != 0.0 {
                for k in 0..6 {
                    p[k] += w * row[k];
                }
            }
        }
        p
    };
    let size = dot6(&x, &x).sqrt() * rows.iter().map(|r| dot6(r, r).sqrt()).fold(0.0, f64::max);
    let tol = 1e-12 * size;
    for _ in 0..3 * m + 12 {
        // The most violated row not yet active (the gradient of the
        // objective is −row·p).
        let p = p_of(&mu);
        let next = (0..m)
            .filter(|i| !active.contains(i))
            .map(|i| (i, -dot6(&rows[i], &p)))
            .filter(|&(_, w)| w > tol)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((j, _)) = next else {
            return Some(p);
        };
        if active.len() == 6 {
            return None;
        }
        active.push(j);
        // Least squares on the active rows, stepping back while any
        // multiplier would turn negative.
        loop {
            let k = active.len();
            let mut g = [[0.0f64; 6]; 6];
            let mut b = [0.0f64; 6];
            for (r, &i) in active.iter().enumerate() {
                for (c, &jj) in active.iter().enumerate() {
                    g[r][c] = dot6(&rows[i], &rows[jj]);
                }
                b[r] = -dot6(&rows[i], &x);
            }
            let z = solve_small(&mut g, &mut b, k)?;
            if z[..k].iter().all(|&v| v > 0.0) {
                for (r, &i) in active.iter().enumerate() {
                    mu[i] = z[r];
                }
                break;
            }
            let alpha = active
                .iter()
                .enumerate()
                .filter(|&(r, _)| z[r] <= 0.0)
                .map(|(r, &i)| mu[i] / (mu[i] - z[r]))
                .fold(f64::INFINITY, f64::min);
            for (r, &i) in active.iter().enumerate() {
                mu[i] += alpha * (z[r] - mu[i]);
            }
            let largest = active.iter().map(|&i| mu[i]).fold(0.0, f64::max);
            active.retain(|&i| mu[i] > 1e-12 * largest);
            for (i, w) in mu.iter_mut().enumerate() {
                if !active.contains(&i) {
                    *w = 0.0;
                }
            }
            if active.is_empty() {
                break;
            }
        }
    }
    None
}

/// The projection by Dykstra's alternating projections (plain cyclic
/// projection would find a feasible point but not the nearest one, and
/// could push the drug backwards).
fn cone_by_dykstra(x: [f64; 6], rows: &[[f64; 6]]) -> [f64; 6] {
    let mut u = x;
    let mut corr = vec![[0.0f64; 6]; rows.len()];
    for _ in 0..200 {
        let mut change = 0.0f64;
        for (row, c) in rows.iter().zip(corr.iter_mut()) {
            let nn = dot6(row, row);
            if nn == 0.0 {
                continue;
            }
            let y: [f64; 6] = std::array::from_fn(|k| u[k] + c[k]);
            let j = dot6(row, &y);
            let next: [f64; 6] = if j < 0.0 {
                std::array::from_fn(|k| y[k] - row[k] * (j / nn))
            } else {
                y
            };
            for k in 0..6 {
                c[k] = y[k] - next[k];
                change = change.max((next[k] - u[k]).abs());
            }
            u = next;
        }
        if change < 1e-12 {
            break;
        }
    }
    u
}

/// `u` with the last rounding clipped into the cone (either method meets
/// it from outside).
fn clip_into_cone(mut u: [f64; 6], rows: &[[f64; 6]]) -> [f64; 6] {
    for row in rows {
        let nn = dot6(row, row);
        let j = dot6(row, &u);
        if nn > 0.0 && j < 0.0 {
            for k in 0..6 {
                u[k] -= row[k] * (j / nn);
            }
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against Dykstra's projections on random cones (up to 14 rows in
    /// six dimensions, some nearly parallel): the active-set answer is
    /// feasible, is the nearest point (`p·x = |p|²`, `x − p` orthogonal to
    /// `p`) and no farther from `x` than Dykstra's.
    #[test]
    fn active_set_projection_agrees_with_dykstra() {
        let mut rng = crate::rng::Rng(44);
        let (mut settled, mut compared) = (0, 0);
        for case in 0..2000 {
            let m = 1 + case % 14;
            let mut rows: Vec<[f64; 6]> = (0..m)
                .map(|_| std::array::from_fn(|_| rng.f64() * 2.0 - 1.0))
                .collect();
            if case % 5 == 0 && m > 1 {
                // A nearly parallel pair, as contacts of neighbouring atoms.
                rows[1] = std::array::from_fn(|k| rows[0][k] + 1e-7 * (rng.f64() - 0.5));
            }
            let x: [f64; 6] = std::array::from_fn(|_| (rng.f64() * 2.0 - 1.0) * 3.0);
            let scale = dot6(&x, &x).max(1e-300);
            // Dykstra's answer after its sweeps, where it is feasible (it
            // meets the cone from outside and may stop short).
            let d = clip_into_cone(cone_by_dykstra(x, &rows), &rows);
            let Some(p) = cone_by_active_set(x, &rows).map(|p| clip_into_cone(p, &rows)) else {
                continue;
            };
            settled += 1;
            for r in &rows {
                assert!(
                    dot6(r, &p) >= -1e-9 * scale.sqrt(),
                    "case {case}: infeasible"
                );
            }
            assert!(
                (dot6(&p, &x) - dot6(&p, &p)).abs() <= 1e-7 * scale,
                "case {case}: not the nearest point"
            );
            let dist = |q: &[f64; 6]| (0..6).map(|k| (q[k] - x[k]).powi(2)).sum::<f64>();
            if rows.iter().all(|r| dot6(r, &d) >= 0.0) {
                compared += 1;
                assert!(
                    dist(&p) <= dist(&d) + 1e-7 * scale,
                    "case {case}: farther than Dykstra's"
                );
            }
        }
        // The fallback is for degenerate cones, not the rule.
        assert!(
            settled >= 1900,
            "the active set settled in only {settled} of 2000"
        );
        assert!(
            compared >= 400,
            "Dykstra's answer was feasible only {compared} times"
        );
    }

    #[test]
    fn cone_projection_is_the_nearest_feasible_motion() {
        // A V-shaped wedge: normals (∓a, −b, −c); pushing into it leaves only
        // the motion along the wedge's edge.
        let (a, b, c) = (0.31f64, 0.11, 0.944);
        let rows = [[-a, -b, -c, 0.0, 0.0, 0.0], [a, -b, -c, 0.0, 0.0, 0.0]];
        let x = [0.0, 1.38, 8.65, 0.0, 0.0, 0.0];
        let p = project_onto_cone(x, &rows);
        for r in &rows {
            assert!(dot6(r, &p) >= -1e-9);
        }
        // Nearest: p·x = |p|² and x − p is orthogonal to p.
        assert!((dot6(&p, &x) - dot6(&p, &p)).abs() < 1e-6);
        assert!(dot6(&p, &x) >= 0.0);
        assert!(p[0].abs() < 1e-6, "no sideways drift: {p:?}");
        // A single flat contact keeps the tangential part exactly.
        let p = project_onto_cone(
            [3.0, 0.0, -2.0, 0.0, 0.0, 0.0],
            &[[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]],
        );
        assert!((p[0] - 3.0).abs() < 1e-12 && p[2].abs() < 1e-12);
    }
}
