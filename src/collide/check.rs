//! Static queries at one pose: the colliding pairs, the pairs in contact
//! within a tolerance, and the smallest gap.
//!
//! The drug's atoms are placed in the receptor frame with one relative pose
//! (f64, rounded to f32 once per atom); each atom that the collider's
//! clearance map cannot prove far from every receptor atom asks the collider
//! for the receptor atoms in a ball around it and applies the contact rule
//! exactly. Groups of four atoms whose bounding ball the map proves far
//! enough are not placed at all (one test for four atoms).
//! Results are sorted by receptor atom, then drug atom, so every collider gives
//! the same list.

use glam::{DMat3, DQuat, DVec3, Vec3};
use serde::Serialize;
use wide::f32x4;

use super::clearance::Clearance;
use super::collider::{Collider, unpack_meta};
use super::drug::{DrugAtoms, Turn4};
use super::rule::{reported_distance, within};
use crate::motion::Pose;

/// A receptor–drug atom pair near or in contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pair {
    /// Receptor atom index (into the receptor molecule).
    pub receptor: u32,
    /// Drug atom index (into the drug molecule).
    pub drug: u32,
    /// Centre distance in Å.
    pub distance: f32,
    /// Contact distance `r_i + r_j − allowance`: the pair collides at or below it.
    pub contact: f32,
}

impl Pair {
    /// `distance − contact`: negative or zero means the pair collides.
    pub fn gap(&self) -> f32 {
        self.distance - self.contact
    }

    /// True when the pair collides under the rule (`d ≤ c`).
    pub fn collides(&self) -> bool {
        self.contact >= 0.0 && self.distance <= self.contact
    }

    fn key(&self) -> (u32, u32) {
        (self.receptor, self.drug)
    }
}

/// Sorts pairs by receptor atom, then drug atom.
pub fn sort_pairs(pairs: &mut [Pair]) {
    pairs.sort_unstable_by_key(Pair::key);
}

/// Visits every pair with `d ≤ c + extra` at relative pose `rel`, unsorted.
/// `f` returns `false` to stop early.
pub fn visit_pairs<F: FnMut(Pair) -> bool>(
    collider: &Collider,
    drug: &DrugAtoms,
    rel: &Pose,
    extra: f32,
    mut f: F,
) {
    let clearance = collider.clearance();
    let extra_room = extra.max(0.0);
    // As `DrugAtoms::placed` places them.
    let (m, t) = (DMat3::from_quat(rel.rotation), rel.translation);
    // The groups' bounding balls, four at a time, placed in f32 (within
    // 10⁻⁴ Å of exact where the map covers the receptor, far inside its
    // 10⁻³ Å rounding room).
    let turn = (rel.rotation != DQuat::IDENTITY).then(|| Turn4::new(rel.rotation));
    let t4 = [t.x, t.y, t.z].map(|v| f32x4::splat(v as f32));
    let groups = drug.len().div_ceil(4);
    for s in 0..groups.div_ceil(4) {
        let mut todo = (1u32 << (groups - 4 * s).min(4)) - 1;
        // A ball the map proves clear by its reach (its radius plus its
        // atoms' largest own part of the contact distance) holds no atom
        // with a pair: one test for up to four groups.
        if let (Some(map), Some(balls)) = (clearance, drug.group_balls().get(s)) {
            let c = turn
                .as_ref()
                .map_or(balls.centre, |m| m.apply(balls.centre));
            let c = [0, 1, 2].map(|k| c[k] + t4[k]);
            todo &= !map.clear_nearest4(c, balls.reach + f32x4::splat(extra_room));
        }
        while todo != 0 {
            let g = 4 * s + todo.trailing_zeros() as usize;
            todo &= todo - 1;
            if !visit_group(collider, clearance, drug, (&m, t), g, extra, &mut f) {
                return;
            }
        }
    }
}

/// [`visit_pairs`] for the atoms of group `g`, placed by `(m,
/// t)`, with the collider's map as `visit_pairs` looked it up once; false
/// when `f` asked to stop.
#[inline(always)]
fn visit_group<F: FnMut(Pair) -> bool>(
    collider: &Collider,
    clearance: Option<&Clearance>,
    drug: &DrugAtoms,
    (m, t): (&DMat3, DVec3),
    g: usize,
    extra: f32,
    f: &mut F,
) -> bool {
    let extra_room = extra.max(0.0);
    // Four atoms at a time against the map's nearest vertices, in lanes, as
    // move-to-touch does; an atom it does not prove clear is searched.
    let count = (drug.len() - 4 * g).min(4);
    let mut at = [Vec3::ZERO; 4];
    for (l, x) in at.iter_mut().enumerate().take(count) {
        *x = drug.place(m, t, drug.member(4 * g + l));
    }
    // Nothing within `c + extra` of an atom: no search.
    let d = drug.own_four(g).map(|own| own + extra_room);
    let proved = clearance.map_or(0, |map| {
        let lanes = |k: usize| f32x4::from(at.map(|x| x[k]));
        map.clear_nearest4([lanes(0), lanes(1), lanes(2)], f32x4::from(d))
    });
    for (l, &x) in at.iter().enumerate().take(count) {
        if proved & (1 << l) != 0 {
            continue;
        }
        // As `drug.contact(i, ..)`, its parts looked up once per atom.
        let searched = drug.searched(4 * g + l);
        let (i, parts) = (searched.atom, searched.parts);
        let far = searched.reach + extra_room;
        let mut go_on = true;
        collider.near(x, far, |a, meta, d2| {
            if !go_on {
                return;
            }
            let (j, polar) = unpack_meta(meta);
            let c = a.w + parts[usize::from(polar)];
            if within(d2, c + extra) {
                go_on = f(Pair {
                    receptor: j,
                    drug: i,
                    distance: reported_distance(d2, c),
                    contact: c,
                });
            }
        });
        if !go_on {
            return false;
        }
    }
    true
}

/// All pairs with `d ≤ c + extra` (`extra = 0`: the colliding pairs), sorted.
pub fn pairs_within(collider: &Collider, drug: &DrugAtoms, rel: &Pose, extra: f32) -> Vec<Pair> {
    // Gathered in a per-thread buffer and copied out at their exact size:
    // one allocation (none when there are no pairs) instead of a vector's
    // growth by reallocation, which would cost more than the search.
    let gather = |found: &mut Vec<Pair>| {
        found.clear();
        visit_pairs(collider, drug, rel, extra, |p| {
            found.push(p);
            true
        });
        sort_pairs(found);
        found.to_vec()
    };
    // A fresh buffer when re-entered (never, today) or while the thread is
    // being torn down (where `with` would panic).
    let mut out = None;
    let _ = FOUND.try_with(|cell| {
        if let Ok(mut found) = cell.try_borrow_mut() {
            out = Some(gather(&mut found));
        }
    });
    out.unwrap_or_else(|| gather(&mut Vec::new()))
}

thread_local! {
    /// [`pairs_within`]'s working buffer.
    static FOUND: std::cell::RefCell<Vec<Pair>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The colliding pairs at `rel`, sorted by receptor atom then drug atom.
pub fn check(collider: &Collider, drug: &DrugAtoms, rel: &Pose) -> Vec<Pair> {
    pairs_within(collider, drug, rel, 0.0)
}

/// True when any pair collides at `rel` (stops at the first).
pub fn any_collision(collider: &Collider, drug: &DrugAtoms, rel: &Pose) -> bool {
    let mut hit = false;
    visit_pairs(collider, drug, rel, 0.0, |_| {
        hit = true;
        false
    });
    hit
}

/// The pair with the smallest gap among pairs with `gap ≤ within`, if any.
pub fn min_gap(collider: &Collider, drug: &DrugAtoms, rel: &Pose, within: f32) -> Option<Pair> {
    let mut best: Option<Pair> = None;
    visit_pairs(collider, drug, rel, within, |p| {
        let better = match &best {
            None => true,
            Some(b) => (p.gap(), p.key()) < (b.gap(), b.key()),
        };
        if better {
            best = Some(p);
        }
        true
    });
    best
}
