//! The swept search: the motion cut into intervals, the drug's atoms
//! taken four at a time against the receptor's box and clearance map, the
//! collider searched for the atoms left, each candidate pair's first touch
//! ([`super::pair::Mover`]), and the stop confirmed by the static rule.

use glam::{DMat3, DQuat, DVec3, Vec3};
use wide::f32x4;

use super::pair::{Mover, may_collide};
use super::{TouchResult, deepens, finish, violates};
use crate::collide::check::{Pair, check, pairs_within};
use crate::collide::collider::{Collider, PlainSearch, RowSearch, Search, unpack_meta};
use crate::collide::drug::{Balls4, DrugAtoms, Lanes3, Turn4};
use crate::collide::rule::{reported_distance, within};
use crate::motion::{Pose, Screw};

/// Longest path, in Å, of any atom in one base interval of the swept
/// method. An interval's search ball grows with it, so shorter intervals let
/// the clearance map skip more atoms and find fewer candidates, at a fixed
/// cost per interval (a clearance test per drug atom); a touch ends the
/// search at its interval. Where an interval finds no candidates the next
/// one doubles, up to a grid cell, so open space costs fewer intervals.
const INTERVAL_SWEEP: f64 = 1.0;

/// A receptor atom that may touch drug atom `drug` during one interval.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    drug: u32,
    receptor: u32,
    q: Vec3,
    contact: f32,
}

/// The candidates with `d ≤ c + extra` with the drug at `pose` (placed as
/// the static check places it), into `found`, sorted, each marked when
/// `d ≤ c` (colliding); true when one is. The static rule applied to a
/// candidate list. Only the candidates' drug atoms are placed, each once
/// (a drug atom's candidates are consecutive).
fn pairs_among(
    cands: &[Candidate],
    drug: &DrugAtoms,
    pose: &Pose,
    extra: f32,
    found: &mut Vec<(Pair, bool)>,
) -> bool {
    found.clear();
    // Open space, the usual joystick step: nothing to place or sort.
    if cands.is_empty() {
        return false;
    }
    // An unturned drug (the usual pose) is placed without a rotation
    // matrix: the identity's products are exact, so the positions are the
    // same.
    let m = (pose.rotation != DQuat::IDENTITY).then(|| DMat3::from_quat(pose.rotation));
    let mut placed: Option<(u32, Vec3)> = None;
    for k in cands {
        let x = match placed {
            Some((i, x)) if i == k.drug => x,
            _ => {
                let i = k.drug as usize;
                let x = match &m {
                    Some(m) => drug.place(m, pose.translation, i),
                    None => (drug.local[i].as_dvec3() + pose.translation).as_vec3(),
                };
                placed = Some((k.drug, x));
                x
            }
        };
        let d2 = (k.q - x).length_squared();
        if within(d2, k.contact + extra) {
            let pair = Pair {
                receptor: k.receptor,
                drug: k.drug,
                distance: reported_distance(d2, k.contact),
                contact: k.contact,
            };
            found.push((pair, within(d2, k.contact)));
        }
    }
    if found.len() > 1 {
        found.sort_unstable_by_key(|(p, _)| (p.receptor, p.drug));
    }
    found.iter().any(|(_, c)| *c)
}

/// The pairs of `found` (from [`pairs_among`]) that collide.
fn colliding_of(found: &[(Pair, bool)]) -> Vec<Pair> {
    found.iter().filter(|(_, c)| *c).map(|(p, _)| *p).collect()
}

/// The swept method. Every static question it answers (the start's
/// collisions, the final contacts, the final check) comes from the candidate
/// pairs it gathered anyway: every pair within reach at the start is a
/// candidate of the first interval, every pair within reach at the end one of
/// the last.
pub(super) fn swept(
    collider: &Collider,
    drug: &DrugAtoms,
    screw: &Screw,
    tol: f64,
    out: &mut TouchResult,
) {
    // One copy of the search for each way of asking the collider (with the
    // grid's padded rows or without), so each carries one search.
    let mut run = |scratch: &mut Scratch| match collider.padded_rows() {
        Some(rows) => by_motion(
            scratch,
            collider,
            &RowSearch { collider, rows },
            drug,
            screw,
            tol,
            out,
        ),
        None => by_motion(
            scratch,
            collider,
            &PlainSearch(collider),
            drug,
            screw,
            tol,
            out,
        ),
    };
    // `try_with` rather than `with`, which panics while the thread is being
    // torn down (fresh buffers then).
    let mut done = false;
    let _ = SCRATCH.try_with(|cell| {
        // Re-entered from inside a query (never, today): fresh buffers.
        if let Ok(mut scratch) = cell.try_borrow_mut() {
            run(&mut scratch);
            done = true;
        }
    });
    if !done {
        run(&mut Scratch::default());
    }
}

/// [`swept_with`] for the kind of motion `screw` is: a translation gets
/// its own copy of the search, with every branch between the two kinds of
/// motion decided at compile time.
#[inline(always)]
fn by_motion<S: Search>(
    scratch: &mut Scratch,
    collider: &Collider,
    search: &S,
    drug: &DrugAtoms,
    screw: &Screw,
    tol: f64,
    out: &mut TouchResult,
) {
    if screw.is_translation() {
        swept_with::<true, S>(scratch, collider, search, drug, screw, tol, out)
    } else {
        swept_with::<false, S>(scratch, collider, search, drug, screw, tol, out)
    }
}

/// Working buffers of [`swept`], kept per thread so a query allocates
/// nothing but its result.
#[derive(Default)]
struct Scratch {
    ys: Vec<DVec3>,
    speeds: Vec<f64>,
    cands: Vec<Candidate>,
    balls: Vec<Balls4>,
    found: Vec<(Pair, bool)>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// [`swept`] with its working buffers, for a pure translation
/// (`TRANSLATION`, which `screw` must be) or a screw, asking `search` (one
/// way of asking `collider`) for the receptor atoms near a drug atom.
fn swept_with<const TRANSLATION: bool, S: Search>(
    scratch: &mut Scratch,
    collider: &Collider,
    search: &S,
    drug: &DrugAtoms,
    screw: &Screw,
    tol: f64,
    out: &mut TouchResult,
) {
    let Scratch {
        ys,
        speeds,
        cands,
        balls,
        found,
    } = scratch;
    let start = *screw.start();
    let n = drug.len();
    speeds.clear();
    debug_assert_eq!(TRANSLATION, screw.is_translation());
    let translation = TRANSLATION;
    let s_max = if translation {
        // A pure translation: every atom has the centre's speed (the same
        // value `Screw::speed` gives each, without a square root per atom;
        // `speed_of`), and only atoms with candidates need their offset in
        // f64 (`y_of`).
        ys.clear();
        if n == 0 {
            0.0
        } else {
            screw.speed(DVec3::ZERO)
        }
    } else {
        drug.rotated_into(&start, ys);
        speeds.extend(ys.iter().map(|y| screw.speed(*y)));
        speeds.iter().copied().fold(0.0, f64::max)
    };
    let tol32 = tol as f32;
    if s_max.is_nan() || s_max <= 0.0 || collider.is_empty() || drug.is_empty() {
        let colliding = check(collider, drug, &start);
        return finish(out, 1.0, *screw.end(), colliding, |p, v| {
            *v = pairs_within(collider, drug, p, tol32);
        });
    }
    let mover = Mover {
        screw,
        angle: screw.angle(),
        half_tol: 0.5 * tol,
        slide: screw.end().translation - screw.start().translation,
    };
    // Equal base intervals in which no atom moves more than `sweep` (a
    // rounding error over a whole number of them does not add a sliver);
    // the search takes one at a time near the receptor's atoms and up to a
    // cell's worth at once where the last interval had no candidates.
    let cell = f64::from(collider.cell_size());
    let sweep = cell.min(INTERVAL_SWEEP);
    let intervals = ceil((s_max / sweep) * (1.0 - 1e-9)).max(1.0);
    let dt = 1.0 / intervals;
    let max_stride = floor(cell / sweep).max(1.0);
    let centre_speed = screw.speed(DVec3::ZERO);
    let (blo, bhi) = collider.bounds();
    let margin = f64::from(drug.max_reach) + tol;
    let (blo, bhi) = (
        blo.as_dvec3() - DVec3::splat(margin),
        bhi.as_dvec3() + DVec3::splat(margin),
    );
    // A step of one or two intervals visits them all: each interval's own
    // box test (below) skips one the drug cannot reach, and `near_box`'s
    // square root and divisions in sequence would hold up the search.
    let (first, past) = if intervals <= 2.0 {
        (0.0, intervals)
    } else {
        near_box(screw, blo, bhi, drug.extent, intervals)
    };
    // A translation places the atoms four at a time from their offsets at
    // the start, in lanes (a screw places each in f64): the drug's own for
    // an unturned drug, else turned group by group, only for the groups
    // whose bounding balls (turned once per query) come near the receptor.
    let (turn4, balls): (Option<Turn4>, &[Balls4]) = if !translation || first >= past {
        (None, &[])
    } else if start.rotation == DQuat::IDENTITY {
        (None, drug.group_balls())
    } else {
        let turn = Turn4::new(start.rotation);
        drug.turned_balls_into(&turn, balls);
        (Some(turn), balls)
    };

    // End positions are needed only for pairs that overlap at an interval's
    // start (rare), so they (and their rotation matrix) are computed on
    // demand, out of line: inlined, the matrix was hoisted out of the loop
    // and built for every query.
    let x_end = |i: usize| end_position(screw, drug, i);
    // Atom `i`'s offset from the centre at the start: the value
    // `DrugAtoms::rotated_into` gives it (a screw has them all in `ys`).
    let start_rot = (translation && start.rotation != DQuat::IDENTITY)
        .then(|| DMat3::from_quat(start.rotation));
    let speed_of = |speeds: &[f64], i: usize| speeds.get(i).copied().unwrap_or(centre_speed);
    let y_of = |ys: &[DVec3], i: usize| match ys.get(i) {
        Some(y) => *y,
        None => {
            let y = drug.local[i].as_dvec3();
            start_rot.map_or(y, |m| m * y)
        }
    };
    // Looked up once: the map may still be building on its own thread.
    let clearance = collider.clearance();
    let mut start_colliding: Vec<Pair> = Vec::new();
    let mut t_hit = 1.0f64;
    let mut last_ta = 0.0f64;
    let mut k = first;
    let mut stride = 1.0;
    cands.clear();
    while k < past {
        let next = (k + stride).min(past);
        let ta = k * dt;
        let tb = if next >= intervals { 1.0 } else { next * dt };
        k = next;
        let half = 0.5 * (tb - ta);
        let tm = ta + half;
        let cm = screw.centre_at(tm);
        cands.clear();
        last_ta = ta;
        // Coarse cull: the whole drug over this interval against the receptor's box.
        let r_all = drug.extent + centre_speed * half;
        let outside = (cm + DVec3::splat(r_all)).cmplt(blo).any()
            || (cm - DVec3::splat(r_all)).cmpgt(bhi).any();
        if outside {
            // The centre moves at `centre_speed`, so the drug cannot reach
            // the box before its centre has covered the gap: skip to the
            // interval where it could. `near_box` does this in advance for
            // translations; a screw about a distant axis (a long arc) needs
            // it here, or it would walk every interval of its arc.
            let gap = (blo - cm).max(cm - bhi).max(DVec3::ZERO).length() - drug.extent - 1.0;
            if gap > 0.0 {
                let enter = tm + gap / centre_speed;
                let skip_to = floor(enter * intervals);
                if skip_to > k {
                    k = skip_to.min(past);
                }
            }
        } else {
            // A translation turns nothing: no rotation matrices to build
            // (nor products by the identity, which would change nothing).
            let turned = |t: f64| (!translation).then(|| DMat3::from_quat(screw.rotation_at(t)));
            let rot_m = turned(tm).unwrap_or(DMat3::IDENTITY);
            // Four atoms at a time: a translation first tests their groups'
            // bounding balls, four groups at once; the atoms of the groups
            // left are placed and asked about together (the map's nearest
            // vertices), and only those it leaves get the search.
            let cm32 = cm.as_vec3();
            let shared_slack = (centre_speed * half + tol) as f32 + 1e-3;
            let shared_slack4 = f32x4::splat(shared_slack);
            let cm4 = cm32.to_array().map(f32x4::splat);
            // The receptor's box (grown by `margin`) grown by every atom's
            // sweep over this interval, its slack and 10⁻³ Å for f32
            // rounding: every candidate of an atom lies within its box
            // distance, so a group's ball wholly outside has none. Tested
            // only while the drug's centre is outside it (a drug beside the
            // receptor rather than against it, as the E beside the rings):
            // most groups are then outside too, and six comparisons prove
            // them for less than the map's test. Against a receptor's
            // surface it rarely proves a group the map would not.
            let grow = DVec3::splat(s_max * half + 2e-3);
            let grown_box = (cm.cmplt(blo - grow) | cm.cmpgt(bhi + grow))
                .any()
                .then(|| {
                    let splat = |v: DVec3| [v.x, v.y, v.z].map(|c| f32x4::splat(c as f32));
                    (splat(blo - grow), splat(bhi + grow))
                });
            let groups = n.div_ceil(4);
            for s in 0..groups.div_ceil(4) {
                // The groups 4s .. 4s + 4 that exist (bits).
                let mut todo = (1u32 << (groups - 4 * s).min(4)) - 1;
                if let Some(b) = balls.get(s) {
                    let centre = [0, 1, 2].map(|k| b.centre[k] + cm4[k]);
                    if let Some((lo, hi)) = &grown_box {
                        let r = b.radius;
                        todo &= !outside_box(centre, lo.map(|l| l - r), hi.map(|h| h + r));
                    }
                    // A ball proved clear by its reach and this interval's
                    // slack holds no atom with a candidate, so on a
                    // receptor's surface most groups are never placed. For
                    // one group left the test would save at most what it
                    // costs.
                    if todo.count_ones() > 1
                        && let Some(map) = clearance
                    {
                        todo &= !map.clear_nearest4(centre, b.reach + shared_slack4);
                    }
                }
                while todo != 0 {
                    let g = 4 * s + todo.trailing_zeros() as usize;
                    todo &= todo - 1;
                    let first_atom = 4 * g;
                    let count = (n - first_atom).min(4);
                    let lanes = if translation {
                        drug.local_fours().get(g)
                    } else {
                        None
                    };
                    let (p, slack) = if let Some(&local) = lanes {
                        // Every atom has the centre's speed and no rotation.
                        let offset = turn4.as_ref().map_or(local, |m| m.apply(local));
                        ([0, 1, 2].map(|k| offset[k] + cm4[k]), shared_slack4)
                    } else {
                        let mut at = [[0.0f32; 4]; 3];
                        let mut slack = [shared_slack; 4];
                        for l in 0..count {
                            let i = drug.member(first_atom + l);
                            let xm = (rot_m * y_of(ys, i) + cm).as_vec3();
                            (at[0][l], at[1][l], at[2][l]) = (xm.x, xm.y, xm.z);
                            // f32 slack well above the rounding of receptor-frame
                            // coordinates, so the f32 tests below keep a superset.
                            slack[l] = (speed_of(speeds, i) * half + tol) as f32 + 1e-3;
                        }
                        (at.map(f32x4::from), f32x4::from(slack))
                    };
                    // Nothing within reach over the whole interval: no search.
                    // (Every candidate below has `|q − xm| ≤ r_q + own + slack`.)
                    let d = f32x4::from(drug.own_four(g)) + slack;
                    let proved = clearance.map_or(0, |map| map.clear_nearest4(p, d));
                    if proved == (1 << count) - 1 {
                        continue;
                    }
                    let slack = slack.to_array();
                    let (px, py, pz) = (p[0].to_array(), p[1].to_array(), p[2].to_array());
                    for l in 0..count {
                        let xm32 = Vec3::new(px[l], py[l], pz[l]);
                        if proved & (1 << l) != 0 {
                            continue;
                        }
                        // As `drug.contact(i, ..)`, its parts looked up
                        // once per atom, not per receptor atom in reach.
                        let searched = drug.searched(first_atom + l);
                        let (i, parts, slack) = (searched.atom, searched.parts, slack[l]);
                        let far = searched.reach + slack;
                        search.near(xm32, far, |a, meta, d2| {
                            let q = a.truncate();
                            let (j, polar) = unpack_meta(meta);
                            let contact = a.w + parts[usize::from(polar)];
                            // Out of reach over the whole interval: not a candidate.
                            let reach = contact + slack;
                            if d2 <= reach * reach {
                                cands.push(Candidate {
                                    drug: i,
                                    receptor: j,
                                    q,
                                    contact,
                                });
                            }
                        });
                    }
                }
            }
            // A screw's second-order bound depends on how far ahead the
            // earliest touch found so far is, so a pair's computed touch
            // time can depend (in its last bits) on the order the pairs
            // are taken in: take them in one order, whatever the collider's.
            if !translation {
                cands.sort_unstable_by_key(|k| (k.drug, k.receptor));
            }
            // Positions at `ta` only for the atoms with candidates.
            let rot_a = turned(ta);
            let cen_a = screw.centre_at(ta);
            // Whether a pair may collide at the start (first interval only).
            let mut near_start = false;
            for k in cands.iter() {
                let i = k.drug as usize;
                let limit = t_hit.min(tb);
                let q = k.q.as_dvec3();
                let y = y_of(ys, i);
                let c = f64::from(k.contact);
                let x0 = rot_a.map_or(y, |m| m * y) + cen_a;
                if ta == 0.0 {
                    near_start |= may_collide(x0, q, c);
                }
                if let Some(th) =
                    mover.first_touch(y, speed_of(speeds, i), q, c, ta, x0, || x_end(i), limit)
                    && th < t_hit
                {
                    t_hit = th;
                }
            }
            // The start's collisions by the static (f32) rule, looked for
            // only when a pair comes near contact at the start (rarely: a
            // query usually starts where the last one stopped, in contact
            // within tolerance but not colliding).
            if near_start && pairs_among(cands, drug, &start, 0.0, found) {
                start_colliding = colliding_of(found);
            }
        }
        if t_hit <= tb {
            break;
        }
        // Candidates are the same for every collider (the map only skips
        // atoms that have none), so the intervals are too.
        stride = if cands.is_empty() {
            (2.0 * stride).min(max_stride)
        } else {
            1.0
        };
        if k >= past && tb < 1.0 {
            // The rest of the motion is clear of the receptor's box: no
            // candidates near the end pose.
            cands.clear();
            last_ta = tb;
        }
    }

    // Confirm with the static rule; back off if f32 rounding disagrees. Pairs
    // near the final pose are all among the last interval's candidates.
    let mut t = t_hit;
    let mut pose = screw.pose_at(t);
    let mut back = tol / s_max;
    let mut tries = 0;
    // Whether the final pose's pairs came from its candidates (then in
    // `found`, and the contacts are taken from there).
    let mut among_candidates;
    loop {
        among_candidates = t >= last_ta;
        let colliding = if among_candidates {
            if pairs_among(cands, drug, &pose, tol32, found) {
                colliding_of(found)
            } else {
                Vec::new()
            }
        } else {
            check(collider, drug, &pose)
        };
        // A stop short of the end must leave every pair that collided at
        // the start no closer (in f64) than there: the dip its target
        // tolerates is for a whole motion that ends no deeper, not for a
        // pose on the way (a push repeated from each stop would sink the
        // drug by the dip every time). The stop is then the start itself:
        // such a pair usually approaches from the start on (one that first
        // recedes, on a screw, could have gone a little way).
        let sinks = !start_colliding.is_empty()
            && t < 1.0
            && deepens(collider, drug, &start, &pose, &start_colliding);
        if t <= 0.0 || !(sinks || violates(&colliding, &start_colliding)) {
            break;
        }
        tries += 1;
        t = if tries > 40 || sinks {
            0.0
        } else {
            (t - back).max(0.0)
        };
        back *= 2.0;
        pose = screw.pose_at(t);
    }
    if among_candidates {
        finish(out, t, pose, start_colliding, |_, v| {
            v.extend(found.iter().map(|(p, _)| *p));
        });
    } else {
        finish(out, t, pose, start_colliding, |p, v| {
            *v = pairs_within(collider, drug, p, tol32);
        });
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
