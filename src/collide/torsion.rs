//! Turning a rotatable bond without collisions: how far one side of a drug
//! may turn about the bond before an atom pair touches.
//!
//! A turn holds one side of the bond still and turns the other (the moving
//! side) rigidly about the bond's axis: a screw motion of those atoms with
//! no translation. Two kinds of pair can meet on the way, and both are
//! checked along the whole turn, never only at its end:
//! - moving atoms against the receptor: move-to-touch of the moving atoms
//!   alone ([`super::sweep`]), in pieces of at most a quarter turn (a screw
//!   between two poses takes the shorter way round), so it never tunnels;
//! - moving atoms against the drug's fixed atoms more than three bonds away
//!   ([`InnerPair`]): for a pure rotation by `φ` a pair's squared distance
//!   is `A + B cos φ + C sin φ`, so its first approach to the contact
//!   distance is found in closed form ([`first_block`]), with no sampling.
//!
//! As with move-to-touch, the target distance of a pair is its contact
//! distance raised by half the tolerance (rounding cannot turn touching
//! into colliding), a pair stops the turn only while it approaches (a drug
//! at rest in contact can turn away), and a pair that already overlaps at
//! the start may not get any closer. The answer is the largest fraction of
//! the turn along which no pair does any of that.

use glam::{DQuat, DVec3};

use super::check::Pair;
use super::collider::Collider;
use super::drug::DrugAtoms;
use super::rule::ContactRule;
use super::sweep::{TouchOptions, move_to_touch};
use crate::model::Molecule;
use crate::motion::Pose;

/// A turn of part of a drug about an axis, in the drug's own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turn {
    /// A point on the axis.
    pub origin: DVec3,
    /// The axis, unit length.
    pub axis: DVec3,
    /// The angle, radians, right-handed about `axis`.
    pub angle: f64,
}

impl Turn {
    /// The rigid motion that turns points by `fraction` of the turn.
    pub fn at(&self, fraction: f64) -> Pose {
        let q = DQuat::from_axis_angle(self.axis, self.angle * fraction);
        Pose::new(q, self.origin - q * self.origin)
    }
}

/// A pair of drug atoms that a turn can bring together: one on the moving
/// side, one on the fixed side, more than three bonds apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InnerPair {
    /// The atom that turns.
    pub moving: u32,
    /// The atom that stays.
    pub fixed: u32,
    /// Their contact distance under the rule (they collide at or below it), Å.
    pub contact: f64,
}

/// The pairs of `pairs` (atom pairs more than three bonds apart, as
/// [`crate::chem::torsions::pairs_beyond_three_bonds`] gives) with one atom
/// on each side, `moving[i]` telling the sides apart, with their contact
/// distances under `rule`. Pairs whose contact distance is negative never
/// collide and are left out.
pub fn inner_pairs(
    drug: &Molecule,
    moving: &[bool],
    pairs: &[(u32, u32)],
    rule: &ContactRule,
) -> Vec<InnerPair> {
    pairs
        .iter()
        .filter_map(|&(i, j)| {
            let (mi, mj) = (moving.get(i as usize)?, moving.get(j as usize)?);
            let (m, f) = match (mi, mj) {
                (true, false) => (i, j),
                (false, true) => (j, i),
                _ => return None,
            };
            let (a, b) = (drug.atoms.get(m as usize)?, drug.atoms.get(f as usize)?);
            let c = rule.contact_distance(a.radius, a.polar, b.radius, b.polar);
            (c >= 0.0).then_some(InnerPair {
                moving: m,
                fixed: f,
                contact: f64::from(c),
            })
        })
        .collect()
}

/// The first angle in `[0, end]` at which a pair turning as
/// `h(φ) = A − T + B cos φ + C sin φ` (its squared distance less its
/// squared target `T`) blocks the turn: where `h ≤ 0` while `h` decreases
/// (the pair reaches its target, or approaches while within it). `None`
/// when it never does. `end` is at most 2π.
pub fn first_block(a_minus_t: f64, b: f64, c: f64, end: f64) -> Option<f64> {
    use std::f64::consts::TAU;
    let h0 = a_minus_t + b;
    let r = b.hypot(c);
    // A constant distance (an atom on the axis) never blocks.
    if r <= 1e-12 * (1.0 + a_minus_t.abs()) {
        return None;
    }
    // h(φ) = A − T + R cos(φ − δ); h'(φ) = −R sin(φ − δ); h'(0) = C.
    let delta = c.atan2(b);
    let mut best: Option<f64> = None;
    let mut take = |phi: f64| {
        if (0.0..=end).contains(&phi) && best.is_none_or(|x| phi < x) {
            best = Some(phi);
        }
    };
    if h0 <= 0.0 {
        if c < 0.0 {
            return Some(0.0);
        }
        // Within the target and not approaching: blocked where h starts to
        // fall, unless it leaves the target first.
        if a_minus_t + r <= 0.0 {
            take(delta.rem_euclid(TAU));
        }
    }
    let kappa = -a_minus_t / r;
    if kappa.abs() <= 1.0 {
        // Entering roots: cos(φ − δ) = κ with sin(φ − δ) > 0.
        let mut phi = (delta + kappa.acos()).rem_euclid(TAU);
        if phi <= 0.0 {
            phi += TAU;
        }
        take(phi);
    }
    best
}

/// The largest fraction of `turn` along which no pair of `pairs` (drug
/// atoms at `local`, the drug's frame) blocks, with the pair that blocks
/// first (an index into `pairs`), if any. See the module documentation.
pub fn inner_fraction(
    local: &[DVec3],
    pairs: &[InnerPair],
    turn: &Turn,
    tolerance: f64,
) -> (f64, Option<usize>) {
    let end = turn.angle.abs();
    if end == 0.0 {
        return (1.0, None);
    }
    let s = turn.angle.signum();
    let u = turn.axis;
    let mut best = (end, None);
    for (k, p) in pairs.iter().enumerate() {
        let (Some(&pm), Some(&qf)) = (local.get(p.moving as usize), local.get(p.fixed as usize))
        else {
            continue;
        };
        let (pv, qv) = (pm - turn.origin, qf - turn.origin);
        let along = u * pv.dot(u);
        let perp = pv - along;
        // |R(φ)p − q|² = |p|² + |q|² − 2 q·(p∥ + cos φ p⊥ + sin φ u×p⊥).
        let a = pv.length_squared() + qv.length_squared() - 2.0 * qv.dot(along);
        let b = -2.0 * qv.dot(perp);
        let c = -2.0 * qv.dot(u.cross(perp)) * s;
        let d2 = a + b;
        let a_minus_t = if d2 <= p.contact * p.contact {
            // Overlapping already: it may not get closer than it is; its
            // start is exactly on the target (−b + b is 0).
            -b
        } else {
            let t = p.contact + 0.5 * tolerance;
            a - t * t
        };
        if let Some(phi) = first_block(a_minus_t, b, c, best.0)
            && (phi < best.0 || best.1.is_none())
        {
            best = (phi, Some(k));
        }
    }
    match best {
        (_, None) => (1.0, None),
        (phi, k) => ((phi / end).clamp(0.0, 1.0), k),
    }
}

/// What a turn against the receptor found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReceptorTurn {
    /// Fraction of the turn allowed.
    pub t: f64,
    /// Pairs within tolerance of contact where the moving atoms stopped
    /// (drug indices are the whole drug's), when the turn stopped short.
    pub contacts: Vec<Pair>,
}

/// The largest fraction of `turn` the moving atoms may take against the
/// receptor indexed by `collider`: `moving` holds the moving atoms set up
/// for the collider, in a frame whose origin is `centre` of the drug's
/// frame, `index[i]` the drug atom of its atom `i`; `drug` places the
/// drug's frame in the collider's. Move-to-touch in pieces of at most a
/// quarter turn.
pub fn receptor_fraction(
    collider: &Collider,
    moving: &DrugAtoms,
    index: &[u32],
    centre: DVec3,
    drug: &Pose,
    turn: &Turn,
    opts: &TouchOptions,
) -> ReceptorTurn {
    let quarter = std::f64::consts::FRAC_PI_2;
    let pieces = (turn.angle.abs() / quarter).ceil().max(1.0) as usize;
    let offset = Pose::from_translation(centre);
    let at = |f: f64| drug.compose(&turn.at(f)).compose(&offset);
    for s in 0..pieces {
        let (f0, f1) = (s as f64 / pieces as f64, (s + 1) as f64 / pieces as f64);
        let r = move_to_touch(collider, moving, &at(f0), &at(f1), opts);
        if r.t < 1.0 {
            let contacts = r
                .contacts
                .iter()
                .map(|p| Pair {
                    drug: index.get(p.drug as usize).copied().unwrap_or(p.drug),
                    ..*p
                })
                .collect();
            return ReceptorTurn {
                t: (f0 + r.t * (f1 - f0)).clamp(0.0, 1.0),
                contacts,
            };
        }
    }
    ReceptorTurn {
        t: 1.0,
        contacts: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The first blocking angle by dense sampling (the reference).
    fn sampled(local: &[DVec3], p: &InnerPair, turn: &Turn, tol: f64) -> Option<f64> {
        let n = 20_000;
        let (pm, qf) = (local[p.moving as usize], local[p.fixed as usize]);
        let d = |f: f64| (turn.at(f).transform_point(pm) - qf).length();
        let d0 = d(0.0);
        let target = if d0 <= p.contact {
            d0
        } else {
            p.contact + 0.5 * tol
        };
        let mut prev = d0;
        for k in 0..=n {
            let f = k as f64 / n as f64;
            let x = d(f);
            if x <= target && (x < prev || (k == 0 && d(1e-9) < x)) {
                return Some(f);
            }
            prev = x;
        }
        None
    }

    #[test]
    fn the_first_block_of_a_turn_agrees_with_dense_sampling() {
        let mut rng = Rng(44);
        let mut blocked = 0;
        for _ in 0..2000 {
            let local = vec![rng.in_box(DVec3::ONE * 3.0), rng.in_box(DVec3::ONE * 3.0)];
            let turn = Turn {
                origin: rng.in_box(DVec3::ONE),
                axis: rng.unit(),
                angle: rng.range(-std::f64::consts::PI, std::f64::consts::PI),
            };
            let pair = InnerPair {
                moving: 0,
                fixed: 1,
                contact: rng.range(0.5, 4.0),
            };
            let tol = 1e-3;
            let (t, k) = inner_fraction(&local, &[pair], &turn, tol);
            let want = sampled(&local, &pair, &turn, tol);
            match want {
                None => assert!(k.is_none() && t == 1.0, "blocked at {t} but sampling never"),
                Some(f) => {
                    blocked += 1;
                    assert!(
                        k.is_some(),
                        "sampling blocks at {f}, the exact answer never"
                    );
                    // Sampling finds the block at most one sample late.
                    assert!(
                        t <= f + 1e-9 && f - t < 2e-3 + 1e-9,
                        "exact {t}, sampled {f}"
                    );
                }
            }
            // Nowhere before the answer does the pair get within its
            // contact distance (or deeper than it started).
            let (pm, qf) = (local[0], local[1]);
            let d0 = (pm - qf).length();
            for k in 0..=200 {
                let f = t * k as f64 / 200.0;
                let d = (turn.at(f).transform_point(pm) - qf).length();
                assert!(
                    d > pair.contact || d >= d0 - 1e-9,
                    "collides at {f} of {t}: {d} ≤ {}",
                    pair.contact
                );
            }
        }
        assert!(blocked > 200, "only {blocked} turns were blocked");
    }

    #[test]
    fn an_atom_on_the_axis_never_blocks() {
        let local = vec![DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, 1.5)];
        let turn = Turn {
            origin: DVec3::ZERO,
            axis: DVec3::Z,
            angle: 3.0,
        };
        let pair = InnerPair {
            moving: 0,
            fixed: 1,
            contact: 2.0,
        };
        assert_eq!(inner_fraction(&local, &[pair], &turn, 1e-3), (1.0, None));
    }
}
