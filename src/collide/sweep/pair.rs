//! One candidate pair's first touch along the motion: conservative
//! advancement on its squared distance, or the closed-form root for a pure
//! translation (see the module documentation of `sweep`).

use glam::DVec3;

use super::OVERLAP_JITTER;
use crate::motion::Screw;

/// Iterations of conservative advancement per pair before stopping (safely) short.
const MAX_PAIR_ITERATIONS: usize = 100;

/// False only when the static rule (`pairs_among` in `search.rs`, in f32)
/// cannot find the drug atom at `x` (f64) colliding with the receptor atom at `q`
/// (contact distance `c`): their distance exceeds `c` by more than the f32
/// rounding of the atom's coordinates and of the distance (a few units in
/// the 24th bit of `|x|` and of `c`), with a wide margin.
#[inline]
pub(super) fn may_collide(x: DVec3, q: DVec3, c: f64) -> bool {
    let lim = c + 1e-4 + 1e-6 * (x.abs().max_element() + c.abs());
    lim >= 0.0 && (x - q).length_squared() <= lim * lim
}

/// Smallest positive root of `f + b·τ + a·τ²` (with `f ≥ 0`), or infinity.
#[inline]
fn first_positive_root(f: f64, b: f64, a: f64) -> f64 {
    if f <= 0.0 {
        return if b < 0.0 || (b == 0.0 && a < 0.0) {
            0.0
        } else if a < 0.0 {
            -b / a
        } else {
            f64::INFINITY
        };
    }
    if a == 0.0 {
        return if b < 0.0 { f / -b } else { f64::INFINITY };
    }
    let disc = b * b - 4.0 * a * f;
    if a > 0.0 {
        if b >= 0.0 || disc < 0.0 {
            f64::INFINITY
        } else {
            2.0 * f / (-b + disc.sqrt())
        }
    } else if b <= 0.0 {
        2.0 * f / (-b + disc.sqrt())
    } else {
        (b + disc.sqrt()) / (-2.0 * a)
    }
}

/// Where the atom at offset `y` from the centre at the start is at `t`.
/// A translation turns nothing (and a quaternion product by the identity
/// would cost a few dozen flops to change nothing).
#[inline(always)]
fn position_at(sc: &Screw, y: DVec3, t: f64) -> DVec3 {
    if sc.is_translation() {
        y + sc.centre_at(t)
    } else {
        sc.rotation_at(t) * y + sc.centre_at(t)
    }
}

/// Per-query constants of the screw for one atom.
pub(super) struct Mover<'a> {
    pub(super) screw: &'a Screw,
    pub(super) angle: f64,
    pub(super) half_tol: f64,
    /// The end's translation less the start's: a translation's velocity.
    pub(super) slide: DVec3,
}

impl Mover<'_> {
    /// First time in `[t0, limit)` at which the pair (drug atom at offset `y`
    /// with speed `s`, at `x0` at `t0` and at `x_end` at the end of the
    /// motion; receptor atom at `q`; contact distance `c`) is within tolerance
    /// of contact and approaching; `None` when it is not before `limit`.
    #[allow(clippy::too_many_arguments)] // one pair's state; a struct would only rename it
    #[inline(always)]
    pub(super) fn first_touch(
        &self,
        y: DVec3,
        s: f64,
        q: DVec3,
        c: f64,
        t0: f64,
        x0: DVec3,
        x_end: impl FnOnce() -> DVec3,
        limit: f64,
    ) -> Option<f64> {
        let sc = self.screw;
        // A translation's usual pair, well apart: no square root for its
        // distance (the closed form needs only its square).
        if sc.is_translation() {
            let rel = x0 - q;
            let d2 = rel.length_squared();
            // (A contact distance below zero, which no pair reaches, goes
            // the general way: its squares would not order as distances.)
            let apart = c + 2.0 * self.half_tol;
            if c >= 0.0 && d2 > apart * apart {
                return self
                    .first_touch_apart(s, rel, d2, c, limit - t0)
                    .map(|tau| t0 + tau);
            }
        }
        let mut t = t0;
        let mut x = x0;
        let mut dist = (x - q).length();
        // The target distance: contact plus a margin, but never above the
        // current distance; the pair stops the drug within `band` of it. A
        // pair already at or inside contact may not get closer — except by
        // f32 rounding on a step that leaves it no deeper at its end, so
        // overlapping atoms can always be pulled apart but never pushed (or
        // crept) further in.
        let (target, band) = if dist > c {
            (c + self.half_tol.min(0.5 * (dist - c)), self.half_tol)
        } else if (x_end() - q).length() >= dist {
            ((dist - OVERLAP_JITTER).max(0.0), 0.0)
        } else {
            (dist, 0.0)
        };
        if sc.is_translation() && dist > c {
            return self
                .first_touch_translating(s, x0 - q, dist, target, band, limit - t0)
                .map(|tau| t0 + tau);
        }
        let acc = self.angle * s; // bound on |x''| (centripetal θ²ρ ≤ θ·s)
        for _ in 0..MAX_PAIR_ITERATIONS {
            let gap = dist - target;
            let window = limit - t;
            // First-order bound: too far to come within tolerance before `limit`.
            if gap - s * window > band {
                return None;
            }
            let rel = x - q;
            let fp = 2.0 * rel.dot(sc.velocity_at(x));
            let approaching = fp < -1e-12 * s * dist.max(1.0);
            if gap <= band && approaching {
                return Some(t);
            }
            let f = (dist - target) * (dist + target);
            let a = s * s - (dist + s * window) * acc;
            let tau1 = gap.max(0.0) / s;
            let tau2 = first_positive_root(f.max(0.0), fp, a);
            let tau = tau1.max(tau2);
            // NaN or beyond the window: no touch before `limit`.
            if tau.is_nan() || tau >= window {
                return None;
            }
            if tau <= f64::EPSILON * t.abs().max(1e-300) {
                // Cannot advance (touching and not separating): stop here.
                return Some(t);
            }
            t += tau;
            x = position_at(sc, y, t);
            dist = (x - q).length();
        }
        Some(t)
    }

    /// [`Mover::first_touch_translating`] for a pair more than a
    /// tolerance (`2 · half_tol`) beyond contact `c ≥ 0`, from its squared
    /// distance `d2`: the target is then `c + half_tol` and the band
    /// `half_tol`, so the pair is not yet within it, and every test
    /// compares squares. A pair counts as approaching when the derivative
    /// of its squared distance is below `−10⁻¹² · s · max(d², 1)`: a pair
    /// left out by that (but not by `first_touch`'s `max(d, 1)`) comes
    /// closer over the whole line by at most `d⁴ · 2.5·10⁻²⁵ / (2d)`
    /// (10⁻²⁰ Å at 40 Å, where no candidate lies; 10⁻¹³ Å at 10⁴ Å),
    /// far inside the tolerance (at least 10⁻⁵ Å) it stands apart by.
    #[inline]
    fn first_touch_apart(&self, s: f64, rel: DVec3, d2: f64, c: f64, window: f64) -> Option<f64> {
        let target = c + self.half_tol;
        // First-order bound: too far to come within tolerance in time
        // (`d > target + band + s · window`, all positive).
        let reach = target + self.half_tol + s * window;
        if d2 > reach * reach {
            return None;
        }
        let fp = 2.0 * rel.dot(self.slide);
        // As `first_touch` (NaN is not approaching).
        let approaching = fp < -1e-12 * s * d2.max(1.0);
        if !approaching {
            return None;
        }
        let f = d2 - target * target;
        let disc = fp * fp - 4.0 * (s * s) * f;
        let tau = 2.0 * f / (-fp + disc.sqrt());
        // No root (NaN) or beyond the window: no touch in time.
        (tau < window).then_some(tau)
    }

    /// [`Mover::first_touch`] for a pure translation and a pair not yet in
    /// contact, in closed form: how long after the window opens (`window`
    /// long) the pair (`rel` apart, `dist = |rel|`) comes within `band` of
    /// the `target` distance while approaching. `|rel + v·τ|²` is a
    /// quadratic in `τ`, and its first root is where conservative
    /// advancement lands (its second-order bound is exact here), without
    /// the steps and their square roots and divisions in sequence.
    ///
    /// A pair that is not approaching now never will be (the derivative of
    /// the squared distance only grows), so it stops nothing: its distance
    /// is within 10⁻¹² relative of its least already. A root that is a
    /// graze (equal roots) stops the drug at the target distance, as safe
    /// as any other stop.
    #[inline]
    fn first_touch_translating(
        &self,
        s: f64,
        rel: DVec3,
        dist: f64,
        target: f64,
        band: f64,
        window: f64,
    ) -> Option<f64> {
        let gap = dist - target;
        // First-order bound: too far to come within tolerance in time.
        if gap - s * window > band {
            return None;
        }
        let fp = 2.0 * rel.dot(self.slide);
        // As `first_touch` (NaN is not approaching).
        let approaching = fp < -1e-12 * s * dist.max(1.0);
        if !approaching {
            return None;
        }
        if gap <= band {
            return Some(0.0);
        }
        // gap > band, so target = contact + band: the root keeps the
        // whole band (half the tolerance, 5·10⁻⁶ Å at least) against
        // rounding.
        let f = gap * (dist + target);
        let disc = fp * fp - 4.0 * (s * s) * f;
        let tau = 2.0 * f / (-fp + disc.sqrt());
        // No root (NaN) or beyond the window: no touch in time.
        (tau < window).then_some(tau)
    }
}

#[cfg(test)]
mod tests {
    use super::{Mover, may_collide};
    use crate::collide::sweep::MAX_RELATIVE_COORDINATE;
    use crate::motion::{Pose, Screw};
    use glam::{DVec3, Vec3};

    /// The square-root-free form for pairs well apart answers as the
    /// general closed form: a touch for the same pairs, at times equal to
    /// within rounding, and none within the band of contact.
    #[test]
    fn first_touch_apart_agrees_with_the_closed_form() {
        let mut rng = bump_testkit::Rng(5);
        let (mut touches, mut misses) = (0, 0);
        for _ in 0..20_000 {
            let step = rng.unit() * rng.range(0.01, 3.0);
            let screw = Screw::between(
                Pose::from_translation(DVec3::ZERO),
                Pose::from_translation(step),
            );
            let half_tol = 0.5 * [1e-5, 1e-3, 0.1][(rng.next_u64() % 3) as usize];
            let mover = Mover {
                screw: &screw,
                angle: screw.angle(),
                half_tol,
                slide: step,
            };
            let c = rng.range(0.5, 4.0);
            // Beyond contact by more than the tolerance, some barely.
            let beyond = 2.0 * half_tol * (1.0 + 1e-9) + rng.range(0.0, 2.0).powi(3);
            let rel = rng.unit() * (c + beyond);
            let d2 = rel.length_squared();
            let s = step.length();
            let window = rng.range(0.05, 1.0);
            let apart = mover.first_touch_apart(s, rel, d2, c, window);
            let dist = rel.length();
            let target = c + half_tol.min(0.5 * (dist - c));
            let general = mover.first_touch_translating(s, rel, dist, target, half_tol, window);
            match (apart, general) {
                (Some(a), Some(g)) => {
                    touches += 1;
                    assert!((a - g).abs() <= 1e-9 * g.max(1e-3), "{a} {g}");
                    // The stop keeps at least the band's rounding room.
                    let gap = (rel + step * a).length() - c;
                    assert!(gap > 0.5 * half_tol, "{gap}");
                }
                (None, None) => misses += 1,
                _ => panic!("{apart:?} {general:?} {rel} {step} {c} {window}"),
            }
        }
        assert!(touches > 2_000 && misses > 2_000, "{touches} {misses}");
    }

    /// The start's static-rule collisions are looked for only where
    /// `may_collide` says so: it must hold for every pair the f32 rule
    /// (`pairs_among`: the f64 position rounded to f32, the squared
    /// distance against the squared contact distance in f32) finds
    /// colliding, at any coordinates a query accepts, and still leave out
    /// pairs plainly apart.
    #[test]
    fn may_collide_holds_wherever_the_f32_rule_collides() {
        let mut rng = bump_testkit::Rng(11);
        let (mut colliding, mut apart) = (0, 0);
        for scale in [1.0, 50.0, 500.0, 1e4, MAX_RELATIVE_COORDINATE] {
            for _ in 0..2_000 {
                let q = Vec3::new(
                    rng.range(-scale, scale) as f32,
                    rng.range(-scale, scale) as f32,
                    rng.range(-scale, scale) as f32,
                );
                let dir = DVec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                )
                .normalize_or(DVec3::X);
                let c = rng.range(0.5, 4.0) as f32;
                let cd = f64::from(c);
                let ulp = f64::EPSILON * 2f64.powi(29) * cd;
                for d in (-8..=8).map(|k| cd + f64::from(k) * ulp).chain([
                    cd - 1e-5,
                    cd + 1e-6,
                    cd + 1e-5,
                    cd + 1e-4,
                    cd + 1e-3,
                ]) {
                    let x0 = q.as_dvec3() + dir * d;
                    let d2 = (q - x0.as_vec3()).length_squared();
                    if d2 <= c * c {
                        colliding += 1;
                        assert!(may_collide(x0, q.as_dvec3(), cd), "{q} {x0} {c}");
                    }
                }
                // 0.01 Å apart near the receptor's own coordinates: left out.
                if scale <= 500.0 {
                    let x0 = q.as_dvec3() + dir * (cd + 0.01);
                    assert!(!may_collide(x0, q.as_dvec3(), cd), "{q} {x0} {c}");
                    apart += 1;
                }
            }
        }
        assert!(colliding > 10_000 && apart == 6_000, "{colliding} {apart}");
    }
}
