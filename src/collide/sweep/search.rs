//! The swept search: the intervals near the receptor walked in order, each
//! culled, searched for candidates and its pairs resolved (the stages of
//! [`super::plan`]), until one touches; then **confirmation**
//! ([`confirm`]): the stop checked with the static (f32) rule, backing off
//! where rounding disagrees, and the answer written.
//!
//! # Performance
//! A query allocates nothing but what its answer needs (the working lists
//! are kept per thread); every static question it answers comes from the
//! candidates it gathered anyway. The stages are inlined into one function
//! per kind of motion (translation or screw) and way of asking the collider
//! (with padded rows or without).

use glam::{DMat3, DQuat, DVec3, Vec3};

use super::plan::{Candidate, Plan, motion_speeds};
use super::{TouchResult, deepens, finish, violates};
use crate::collide::check::{Pair, check, pairs_within};
use crate::collide::collider::{Collider, PlainSearch, RowSearch, Search};
use crate::collide::drug::{Balls4, DrugAtoms};
use crate::collide::rule::{reported_distance, within};
use crate::motion::{Pose, Screw};

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
/// way of asking `collider`) for the receptor atoms near a drug atom: the
/// intervals near the receptor in order, each culled, searched for
/// candidates and its pairs resolved, until one touches; then the stop is
/// confirmed.
///
/// # Performance
/// One function per kind of motion and of search, each with its stages
/// inlined (so not inlined itself into [`swept`], which would then carry
/// all four).
#[inline(never)]
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
    let s_max = motion_speeds::<TRANSLATION>(drug, screw, ys, speeds);
    if s_max.is_nan() || s_max <= 0.0 || collider.is_empty() || drug.is_empty() {
        // Nothing moves, or nothing can touch.
        let colliding = check(collider, drug, &start);
        return finish(out, 1.0, *screw.end(), colliding, |p, v| {
            *v = pairs_within(collider, drug, p, tol as f32);
        });
    }
    let plan = Plan::<TRANSLATION>::new(collider, drug, screw, tol, s_max, ys, speeds, balls);
    let mut start_colliding: Vec<Pair> = Vec::new();
    let mut t_hit = 1.0f64;
    let mut last_ta = 0.0f64;
    let (mut k, mut stride) = (plan.first, 1.0);
    cands.clear();
    while k < plan.past {
        let next = (k + stride).min(plan.past);
        let iv = plan.interval(k, next);
        k = next;
        cands.clear();
        last_ta = iv.ta;
        if let Some(enter) = plan.outside(&iv) {
            if enter > k {
                k = enter.min(plan.past);
            }
        } else {
            plan.candidates(search, &iv, cands);
            let near_start;
            (t_hit, near_start) = plan.first_touch(&iv, cands, t_hit);
            // The start's collisions by the static (f32) rule, looked for
            // only when a pair comes near contact at the start (rarely: a
            // query usually starts where the last one stopped, in contact
            // within tolerance but not colliding).
            if near_start && pairs_among(cands, drug, &start, 0.0, found) {
                start_colliding = colliding_of(found);
            }
        }
        if t_hit <= iv.tb {
            break;
        }
        // Candidates are the same for every collider (the map only skips
        // atoms that have none), so the intervals are too.
        stride = if cands.is_empty() {
            (2.0 * stride).min(plan.max_stride)
        } else {
            1.0
        };
        if k >= plan.past && iv.tb < 1.0 {
            // The rest of the motion is clear of the receptor's box: no
            // candidates near the end pose.
            cands.clear();
            last_ta = iv.tb;
        }
    }
    let stop = Stop {
        t: t_hit,
        last_ta,
        start_colliding,
    };
    confirm(&plan, stop, cands, found, out);
}

/// Where the intervals stopped: the touch time, the start of the last
/// interval whose candidates are in hand, and the pairs colliding at the
/// start.
struct Stop {
    t: f64,
    last_ta: f64,
    start_colliding: Vec<Pair>,
}

/// Confirms `stop` with the static rule, backing off if f32 rounding
/// disagrees, and writes the answer. Pairs near the final pose are all
/// among the last interval's candidates (`cands`) when it lies in that
/// interval.
#[inline(always)]
fn confirm<const TRANSLATION: bool>(
    plan: &Plan<'_, TRANSLATION>,
    stop: Stop,
    cands: &[Candidate],
    found: &mut Vec<(Pair, bool)>,
    out: &mut TouchResult,
) {
    let (collider, drug, screw) = (plan.collider, plan.drug, plan.screw);
    let Stop {
        mut t,
        last_ta,
        start_colliding,
    } = stop;
    let start = *screw.start();
    let tol32 = plan.tol as f32;
    let mut pose = screw.pose_at(t);
    let mut back = plan.tol / plan.s_max;
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
