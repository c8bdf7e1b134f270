//! The swept search's plan and its stages, each inlined where the search
//! walks the intervals (`search.rs`):
//!
//! 1. **Intervals** ([`motion_speeds`], [`Plan::new`], [`Plan::interval`]):
//!    the motion cut into base intervals in which no atom moves more than
//!    1 Å, only those near the receptor's box visited, in order.
//! 2. **Culling** ([`Plan::outside`], [`Plan::groups_left`]): an interval
//!    whose whole drug stays outside the receptor's box is skipped (up to
//!    where it could reach it); otherwise the drug's atoms are taken four
//!    at a time, and a group whose bounding ball lies outside the grown box
//!    or that the clearance map proves far from every receptor atom has no
//!    candidates.
//! 3. **Candidate search** ([`Plan::search_group`]): the atoms left are
//!    placed at mid-interval, asked of the clearance map together, and the
//!    collider searched for each one it leaves: every receptor atom it may
//!    reach during the interval.
//! 4. **Pair resolution** ([`Plan::first_touch`]): each candidate pair's
//!    first touch ([`super::pair::Mover`]).

use glam::{DMat3, DQuat, DVec3, Vec3};
use wide::f32x4;

use super::pair::{Mover, may_collide};
use crate::collide::clearance::Clearance;
use crate::collide::collider::{Collider, Search, unpack_meta};
use crate::collide::drug::{Balls4, DrugAtoms, Lanes3, Turn4};
use crate::motion::Screw;

/// Longest path, in Å, of any atom in one base interval of the swept
/// method. An interval's search ball grows with it, so shorter intervals let
/// the clearance map skip more atoms and find fewer candidates, at a fixed
/// cost per interval (a clearance test per drug atom); a touch ends the
/// search at its interval. Where an interval finds no candidates the next
/// one doubles, up to a grid cell, so open space costs fewer intervals.
const INTERVAL_SWEEP: f64 = 1.0;

/// A receptor atom that may touch drug atom `drug` during one interval.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub(super) drug: u32,
    pub(super) receptor: u32,
    pub(super) q: Vec3,
    pub(super) contact: f32,
}

/// What a query fixes before it walks the intervals: the motion, the
/// drug's speeds and offsets, the intervals, the receptor's box and the
/// drug's groups' bounding balls as a translation places them.
/// `TRANSLATION`: the motion is a pure translation (every atom at the
/// centre's speed, no rotation), decided at compile time, so each search
/// carries only its own placement.
pub(super) struct Plan<'a, const TRANSLATION: bool> {
    pub(super) collider: &'a Collider,
    pub(super) drug: &'a DrugAtoms,
    pub(super) screw: &'a Screw,
    pub(super) tol: f64,
    /// The fastest atom's speed, Å per unit of `t`.
    pub(super) s_max: f64,
    /// The drug's centre's speed.
    pub(super) centre_speed: f64,
    /// A screw's atom offsets at the start and speeds (empty for a
    /// translation, whose atoms all move at `centre_speed`).
    pub(super) ys: &'a [DVec3],
    pub(super) speeds: &'a [f64],
    /// A turned drug's start rotation (a translation's atoms get their
    /// offsets from it, one at a time, when they have candidates).
    pub(super) start_rot: Option<DMat3>,
    /// The base intervals: their number, length in `t`, the most taken
    /// at once, and the range `first..past` near the receptor's box.
    pub(super) intervals: f64,
    pub(super) dt: f64,
    pub(super) max_stride: f64,
    pub(super) first: f64,
    pub(super) past: f64,
    /// The receptor's box grown by the drug's largest reach and the
    /// tolerance.
    pub(super) blo: DVec3,
    pub(super) bhi: DVec3,
    /// A translation's groups' bounding balls, turned as the drug is,
    /// four groups at a time (none for a screw).
    pub(super) balls: &'a [Balls4],
    /// The collider's clearance map, looked up once: it may still be
    /// building on its own thread.
    pub(super) clearance: Option<&'a Clearance>,
    pub(super) mover: Mover<'a>,
}

/// One stretch `ta..tb` of the motion and what its tests share.
pub(super) struct Interval {
    pub(super) ta: f64,
    pub(super) tb: f64,
    /// Half its length in `t`.
    pub(super) half: f64,
    /// Its middle, and the drug's centre there.
    pub(super) tm: f64,
    pub(super) cm: DVec3,
}

/// What every group's tests in one interval share.
struct Reach {
    /// The rotation at mid-interval (the identity for a translation).
    rot_m: DMat3,
    /// The centre at mid-interval, in lanes.
    cm4: Lanes3,
    /// The slack of an atom moving at the centre's speed (a
    /// translation's every atom), plus rounding room.
    shared_slack: f32,
    /// The receptor's box grown by every atom's sweep, when the drug's
    /// centre lies outside it (in lanes: lower and upper corners).
    grown_box: Option<(Lanes3, Lanes3)>,
}

/// The drug's atom offsets at the start (`ys`) and speeds along `screw`
/// (for a screw; a translation's atoms all move at the centre's speed, the
/// same value `Screw::speed` gives each, without a square root per atom,
/// and only atoms with candidates need their offset in f64, so both stay
/// empty), and the fastest atom's speed.
#[inline(always)]
pub(super) fn motion_speeds<const TRANSLATION: bool>(
    drug: &DrugAtoms,
    screw: &Screw,
    ys: &mut Vec<DVec3>,
    speeds: &mut Vec<f64>,
) -> f64 {
    debug_assert_eq!(TRANSLATION, screw.is_translation());
    speeds.clear();
    ys.clear();
    if TRANSLATION {
        if drug.is_empty() {
            0.0
        } else {
            screw.speed(DVec3::ZERO)
        }
    } else {
        drug.rotated_into(screw.start(), ys);
        speeds.extend(ys.iter().map(|y| screw.speed(*y)));
        speeds.iter().copied().fold(0.0, f64::max)
    }
}

impl<'a, const TRANSLATION: bool> Plan<'a, TRANSLATION> {
    /// The plan for `screw`, whose fastest atom moves at `s_max` (from
    /// [`motion_speeds`], which filled `ys` and `speeds`), with `balls` as a
    /// working buffer.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // the query and its working buffers
    pub(super) fn new(
        collider: &'a Collider,
        drug: &'a DrugAtoms,
        screw: &'a Screw,
        tol: f64,
        s_max: f64,
        ys: &'a [DVec3],
        speeds: &'a [f64],
        balls: &'a mut Vec<Balls4>,
    ) -> Self {
        let start = *screw.start();
        // Equal base intervals in which no atom moves more than `sweep` (a
        // rounding error over a whole number of them does not add a
        // sliver); the search takes one at a time near the receptor's
        // atoms and up to a cell's worth at once where the last interval
        // had no candidates.
        let cell = f64::from(collider.cell_size());
        let sweep = cell.min(INTERVAL_SWEEP);
        let intervals = ceil((s_max / sweep) * (1.0 - 1e-9)).max(1.0);
        let (blo, bhi) = collider.bounds();
        let margin = DVec3::splat(f64::from(drug.max_reach) + tol);
        let (blo, bhi) = (blo.as_dvec3() - margin, bhi.as_dvec3() + margin);
        // A step of one or two intervals visits them all: each interval's
        // own box test skips one the drug cannot reach, and `near_box`'s
        // square root and divisions in sequence would hold up the search.
        let (first, past) = if intervals <= 2.0 {
            (0.0, intervals)
        } else {
            near_box(screw, blo, bhi, drug.extent, intervals)
        };
        // A translation tests its groups' bounding balls (turned once per
        // query) before their atoms; a screw's atoms all go on.
        let balls: &[Balls4] = if !TRANSLATION || first >= past {
            &[]
        } else if start.rotation == DQuat::IDENTITY {
            drug.group_balls()
        } else {
            drug.turned_balls_into(&Turn4::new(start.rotation), balls);
            balls
        };
        Self {
            collider,
            drug,
            screw,
            tol,
            s_max,
            centre_speed: screw.speed(DVec3::ZERO),
            ys,
            speeds,
            start_rot: (TRANSLATION && start.rotation != DQuat::IDENTITY)
                .then(|| DMat3::from_quat(start.rotation)),
            intervals,
            dt: 1.0 / intervals,
            max_stride: floor(cell / sweep).max(1.0),
            first,
            past,
            blo,
            bhi,
            balls,
            clearance: collider.clearance(),
            mover: Mover {
                screw,
                angle: screw.angle(),
                half_tol: 0.5 * tol,
                slide: screw.end().translation - screw.start().translation,
            },
        }
    }

    /// Atom `i`'s offset from the centre at the start: the value
    /// `DrugAtoms::rotated_into` gives it (a screw has them all in `ys`).
    #[inline(always)]
    fn y_of(&self, i: usize) -> DVec3 {
        match self.ys.get(i) {
            Some(y) => *y,
            None => {
                let y = self.drug.local[i].as_dvec3();
                self.start_rot.map_or(y, |m| m * y)
            }
        }
    }

    /// Atom `i`'s speed.
    #[inline(always)]
    fn speed_of(&self, i: usize) -> f64 {
        self.speeds.get(i).copied().unwrap_or(self.centre_speed)
    }

    /// The rotation matrix at `t` of a screw; `None` for a translation,
    /// which turns nothing (no matrices to build, nor products by the
    /// identity, which would change nothing).
    #[inline(always)]
    fn turned(&self, t: f64) -> Option<DMat3> {
        (!TRANSLATION).then(|| DMat3::from_quat(self.screw.rotation_at(t)))
    }

    /// The interval from base interval `k` to `next`.
    #[inline(always)]
    pub(super) fn interval(&self, k: f64, next: f64) -> Interval {
        let ta = k * self.dt;
        let tb = if next >= self.intervals {
            1.0
        } else {
            next * self.dt
        };
        let half = 0.5 * (tb - ta);
        let tm = ta + half;
        Interval {
            ta,
            tb,
            half,
            tm,
            cm: self.screw.centre_at(tm),
        }
    }

    /// The coarse cull: when the whole drug stays outside the receptor's
    /// box over `iv`, `Some` of the base interval from which it could
    /// reach it (the interval after `iv` when that cannot be told).
    #[inline(always)]
    pub(super) fn outside(&self, iv: &Interval) -> Option<f64> {
        let (cm, extent) = (iv.cm, self.drug.extent);
        let r_all = DVec3::splat(extent + self.centre_speed * iv.half);
        if !((cm + r_all).cmplt(self.blo).any() || (cm - r_all).cmpgt(self.bhi).any()) {
            return None;
        }
        // The centre moves at `centre_speed`, so the drug cannot reach the
        // box before its centre has covered the gap: skip to the interval
        // where it could. `near_box` does this in advance for translations;
        // a screw about a distant axis (a long arc) needs it here, or it
        // would walk every interval of its arc.
        let gap = (self.blo - cm).max(cm - self.bhi).max(DVec3::ZERO).length() - extent - 1.0;
        Some(if gap > 0.0 {
            floor((iv.tm + gap / self.centre_speed) * self.intervals)
        } else {
            0.0
        })
    }

    /// What the groups' tests in `iv` share.
    #[inline(always)]
    fn reach(&self, iv: &Interval) -> Reach {
        let cm = iv.cm;
        // The receptor's box (grown by the drug's reach) grown by every
        // atom's sweep over this interval, its slack and 10⁻³ Å for f32
        // rounding: every candidate of an atom lies within its box
        // distance, so a group's ball wholly outside has none. Tested only
        // while the drug's centre is outside it (a drug beside the receptor
        // rather than against it, as the E beside the rings): most groups
        // are then outside too, and six comparisons prove them for less
        // than the map's test. Against a receptor's surface it rarely
        // proves a group the map would not.
        let grow = DVec3::splat(self.s_max * iv.half + 2e-3);
        let (lo, hi) = (self.blo - grow, self.bhi + grow);
        let grown_box = (cm.cmplt(lo) | cm.cmpgt(hi)).any().then(|| {
            let splat = |v: DVec3| [v.x, v.y, v.z].map(|c| f32x4::splat(c as f32));
            (splat(lo), splat(hi))
        });
        Reach {
            rot_m: self.turned(iv.tm).unwrap_or(DMat3::IDENTITY),
            cm4: cm.as_vec3().to_array().map(f32x4::splat),
            shared_slack: (self.centre_speed * iv.half + self.tol) as f32 + 1e-3,
            grown_box,
        }
    }

    /// Culling: the groups `4s .. 4s + 4` (bits) that may have a
    /// candidate in this interval, by their bounding balls against the
    /// grown box and the clearance map (a translation's; a screw's groups
    /// all go on).
    #[inline(always)]
    fn groups_left(&self, s: usize, r: &Reach) -> u32 {
        let groups = self.drug.len().div_ceil(4);
        let mut todo = (1u32 << (groups - 4 * s).min(4)) - 1;
        let Some(b) = self.balls.get(s) else {
            return todo;
        };
        let centre = [0, 1, 2].map(|k| b.centre[k] + r.cm4[k]);
        if let Some((lo, hi)) = &r.grown_box {
            let radius = b.radius;
            todo &= !outside_box(centre, lo.map(|l| l - radius), hi.map(|h| h + radius));
        }
        // A ball proved clear by its reach and this interval's slack holds
        // no atom with a candidate, so on a receptor's surface most groups
        // are never placed. For one group left the test would save at most
        // what it costs.
        if todo.count_ones() > 1
            && let Some(map) = self.clearance
        {
            todo &= !map.clear_nearest4(centre, b.reach + f32x4::splat(r.shared_slack));
        }
        todo
    }

    /// Group `g`'s atoms at mid-interval, in lanes, and each one's slack
    /// (its sweep over half the interval and the tolerance, in f32 well
    /// above the rounding of receptor-frame coordinates, so the f32 tests
    /// keep a superset).
    #[inline(always)]
    fn place_group(&self, g: usize, iv: &Interval, r: &Reach) -> (Lanes3, f32x4) {
        let mut at = [[0.0f32; 4]; 3];
        let mut slack = [r.shared_slack; 4];
        for l in 0..(self.drug.len() - 4 * g).min(4) {
            let i = self.drug.member(4 * g + l);
            let y = self.y_of(i);
            // (A translation's rotation is the identity: no product.)
            let xm = if TRANSLATION {
                y + iv.cm
            } else {
                r.rot_m * y + iv.cm
            }
            .as_vec3();
            (at[0][l], at[1][l], at[2][l]) = (xm.x, xm.y, xm.z);
            slack[l] = (self.speed_of(i) * iv.half + self.tol) as f32 + 1e-3;
        }
        (at.map(f32x4::from), f32x4::from(slack))
    }

    /// Candidate search: the receptor atoms that group `g`'s atoms may
    /// reach during the interval, into `cands` — for each atom the
    /// clearance map does not prove clear, the collider's atoms within its
    /// reach over the whole interval.
    #[inline(always)]
    fn search_group<S: Search>(
        &self,
        search: &S,
        g: usize,
        iv: &Interval,
        r: &Reach,
        cands: &mut Vec<Candidate>,
    ) {
        let count = (self.drug.len() - 4 * g).min(4);
        let (p, slack) = self.place_group(g, iv, r);
        // Nothing within reach over the whole interval: no search. (Every
        // candidate below has `|q − xm| ≤ r_q + own + slack`.)
        let d = f32x4::from(self.drug.own_four(g)) + slack;
        let proved = self.clearance.map_or(0, |map| map.clear_nearest4(p, d));
        if proved == (1 << count) - 1 {
            return;
        }
        let slack = slack.to_array();
        let (px, py, pz) = (p[0].to_array(), p[1].to_array(), p[2].to_array());
        for l in 0..count {
            if proved & (1 << l) != 0 {
                continue;
            }
            // As `drug.contact(i, ..)`, its parts looked up once per atom,
            // not per receptor atom in reach.
            let searched = self.drug.searched(4 * g + l);
            let (i, parts, slack) = (searched.atom, searched.parts, slack[l]);
            let far = searched.reach + slack;
            search.near(Vec3::new(px[l], py[l], pz[l]), far, |a, meta, d2| {
                let (j, polar) = unpack_meta(meta);
                let contact = a.w + parts[usize::from(polar)];
                // Out of reach over the whole interval: not a candidate.
                let reach = contact + slack;
                if d2 <= reach * reach {
                    cands.push(Candidate {
                        drug: i,
                        receptor: j,
                        q: a.truncate(),
                        contact,
                    });
                }
            });
        }
    }

    /// Culling and candidate search for one interval: every receptor atom
    /// a drug atom may reach during `iv`, into `cands` (emptied first).
    #[inline(always)]
    pub(super) fn candidates<S: Search>(
        &self,
        search: &S,
        iv: &Interval,
        cands: &mut Vec<Candidate>,
    ) {
        cands.clear();
        let r = self.reach(iv);
        let groups = self.drug.len().div_ceil(4);
        for s in 0..groups.div_ceil(4) {
            let mut todo = self.groups_left(s, &r);
            while todo != 0 {
                let g = 4 * s + todo.trailing_zeros() as usize;
                todo &= todo - 1;
                self.search_group(search, g, iv, &r, cands);
            }
        }
        // A screw's second-order bound depends on how far ahead the
        // earliest touch found so far is, so a pair's computed touch time
        // can depend (in its last bits) on the order the pairs are taken
        // in: take them in one order, whatever the collider's.
        if !TRANSLATION {
            cands.sort_unstable_by_key(|k| (k.drug, k.receptor));
        }
    }

    /// Pair resolution: each candidate pair's first touch in `iv` before
    /// `t_hit`; the earliest, and whether a pair may collide at the start
    /// (asked of the first interval only).
    #[inline(always)]
    pub(super) fn first_touch(
        &self,
        iv: &Interval,
        cands: &[Candidate],
        mut t_hit: f64,
    ) -> (f64, bool) {
        // Positions at `ta` only for the atoms with candidates.
        let (ta, rot_a, cen_a) = (iv.ta, self.turned(iv.ta), self.screw.centre_at(iv.ta));
        let mut near_start = false;
        for k in cands {
            let i = k.drug as usize;
            let q = k.q.as_dvec3();
            let y = self.y_of(i);
            let c = f64::from(k.contact);
            let x0 = rot_a.map_or(y, |m| m * y) + cen_a;
            if ta == 0.0 {
                near_start |= may_collide(x0, q, c);
            }
            // End positions are needed only for pairs that overlap at an
            // interval's start (rare), so they are computed on demand, out
            // of line.
            let x_end = || end_position(self.screw, self.drug, i);
            let limit = t_hit.min(iv.tb);
            if let Some(th) =
                self.mover
                    .first_touch(y, self.speed_of(i), q, c, ta, x0, x_end, limit)
                && th < t_hit
            {
                t_hit = th;
            }
        }
        (t_hit, near_start)
    }
}

/// Where drug atom `i` is at the end of the motion (f64).
#[cold]
#[inline(never)]
fn end_position(screw: &Screw, drug: &DrugAtoms, i: usize) -> DVec3 {
    DMat3::from_quat(screw.end().rotation) * drug.local[i].as_dvec3() + screw.end().translation
}

/// Bit `k` set when point `k` (x, y, z in lanes) lies outside the box
/// `lo..hi` (each corner's coordinates in every lane, or per lane).
#[inline(always)]
fn outside_box(p: Lanes3, lo: Lanes3, hi: Lanes3) -> u32 {
    let out = p[0].simd_lt(lo[0])
        | p[0].simd_gt(hi[0])
        | p[1].simd_lt(lo[1])
        | p[1].simd_gt(hi[1])
        | p[2].simd_lt(lo[2])
        | p[2].simd_gt(hi[2]);
    out.to_bitmask() & 0b1111
}

/// `x.floor()` without the library call it is on baseline x86-64.
#[inline(always)]
fn floor(x: f64) -> f64 {
    // Below 2⁵² in magnitude the truncation to an integer is exact; above
    // it (and for infinities and NaN) `x` is its own floor.
    if x.abs() < 4.0e15 {
        let i = x as i64 as f64;
        if i > x { i - 1.0 } else { i }
    } else {
        x
    }
}

/// `x.ceil()`, as [`floor`].
#[inline(always)]
fn ceil(x: f64) -> f64 {
    -floor(-x)
}

/// The intervals `first..past` (of `intervals` equal ones) during which the
/// drug, every atom within `extent` of its centre, can be inside the box
/// `lo..hi`: the centre's progress along the motion's direction (the
/// translation, or a screw's axis) is linear in `t`, so the box's bounding
/// ball gives the range at once. A long step past a small receptor then
/// visits only the intervals near it.
fn near_box(screw: &Screw, lo: DVec3, hi: DVec3, extent: f64, intervals: f64) -> (f64, f64) {
    let c0 = screw.start().translation;
    let w = if screw.is_translation() {
        screw.end().translation - c0
    } else {
        screw.slide()
    };
    let len = w.length();
    // Room for the rounding of the centre's path (centre_at).
    let radius = 0.5 * (hi - lo).length() + extent + 1.0;
    let a = (c0 - 0.5 * (lo + hi)).dot(w) / len.max(f64::MIN_POSITIVE);
    if !(len > 0.0 && a.is_finite() && radius.is_finite()) {
        return (0.0, intervals);
    }
    // Progress along w is a + len·t; it must lie within ±radius.
    let (t_lo, t_hi) = ((-radius - a) / len, (radius - a) / len);
    let first = floor(t_lo * intervals).clamp(0.0, intervals);
    let past = ceil(t_hi * intervals).clamp(0.0, intervals);
    (first, past)
}

#[cfg(test)]
mod tests {
    use super::{ceil, floor};

    #[test]
    fn floor_and_ceil_are_the_library_ones() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999_999_999_999_999_6,
            -2.999_999_999_999_999_6,
            4.0e15 - 0.5,
            -(4.0e15 - 0.5),
            4.0e15,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        let mut rng = bump_testkit::Rng(7);
        values.extend((0..10_000).map(|_| rng.range(-1e6, 1e6)));
        for x in values {
            // Equal as numbers (a negative zero may come out positive).
            assert_eq!(floor(x), x.floor(), "floor {x}");
            assert_eq!(ceil(x), x.ceil(), "ceil {x}");
        }
        assert!(floor(f64::NAN).is_nan() && ceil(f64::NAN).is_nan());
    }
}
