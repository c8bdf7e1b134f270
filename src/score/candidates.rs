//! Per-cell candidate lists for the exact evaluator: for a cell of the
//! receptor's cell list, every receptor atom within 8 Å of some point of the
//! cell, in cell order, with f32 copies of their coordinates relative to the
//! cell's centre, four atoms to a lane group.
//!
//! A drug atom then finds its pairs by testing its own cell's list four
//! atoms at a time, with no cell visit: one contiguous list of about twice
//! the atoms its 8 Å ball holds. The f32 test has a margin, so it keeps
//! every atom within 8 Å and a few beyond; the f64 table read decides, and
//! the atoms it keeps come in cell order, as the one-atom cell visit gives
//! them, so both give the same sums to the bit.
//!
//! Lists are built the first time a drug atom lands in their cell and kept
//! (behind a lock, so threads share them) until their total passes
//! [`BUDGET`]; then all are dropped and built again as needed. A list is a
//! function of its cell alone, so what is kept never changes a result, and
//! memory stays bounded whatever the receptor's size: the lists' budget,
//! and 4 bytes per cell of the grid for the index of built lists (the cell
//! list's cells are at most about 8 per receptor atom plus a million).

use std::sync::{RwLock, RwLockReadGuard, RwLockWriteGuard};

use glam::DVec3;
use wide::f32x4;

use super::function::{CUTOFF, CUTOFF2};
use super::receptor::Cells;

/// Most lane groups and lists kept (64 and 40 bytes each: at most
/// 32 MiB).
pub(crate) const BUDGET: usize = 1 << 19;

/// Where the padding lanes lie: far beyond any cutoff.
const FAR: f32 = 1.0e6;

/// The f32 test's bound on r²: coordinates relative to a cell's centre
/// are within about 10 Å, so the f32 distance of a pair within 8 Å errs by
/// far less than this margin and no such pair is missed.
const NEAR2: f32 = (CUTOFF2 + 0.25) as f32;

/// The lists built so far.
#[derive(Debug, Default)]
pub(crate) struct Lists {
    /// Per cell of the index grid (the receptor's cells and a border as
    /// wide as the cutoff reaches), 1 + the list's number, or 0 before it
    /// is built; allocated on first use.
    slot: Vec<u32>,
    /// Per list: its centre, its lane groups' range and its grid cell.
    spans: Vec<(DVec3, u32, u32, u32)>,
    /// The lists' coordinates relative to their centres, per axis.
    lanes: Vec<[f32x4; 3]>,
    /// Per lane, the atom's index in the cell-ordered atoms.
    atoms: Vec<u32>,
}

/// The index grid's geometry: the receptor's cells extended on every side
/// by as many cells as the cutoff reaches, so a drug atom outside that grid
/// has no receptor atom within 8 Å.
#[derive(Debug, Clone, Copy)]
struct Border {
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
}

impl Border {
    fn of(cells: &Cells) -> Self {
        let cell = cells.cell();
        let cells_wide = (CUTOFF / cell).ceil() as usize + 1;
        let d = cells.dims();
        Self {
            origin: cells.origin() - DVec3::splat(cells_wide as f64 * cell),
            cell,
            dims: d.map(|n| n + 2 * cells_wide),
        }
    }

    /// The grid cell holding `x`, or `None` outside the grid (or for a
    /// coordinate that is not finite).
    fn cell_of(&self, x: DVec3) -> Option<usize> {
        let c = (x - self.origin) / self.cell;
        let mut index = 0;
        for axis in (0..3).rev() {
            let v = c[axis];
            // Also false for NaN.
            if !(v >= 0.0 && v < self.dims[axis] as f64) {
                return None;
            }
            index = index * self.dims[axis] + v as usize;
        }
        Some(index)
    }

    /// The centre of grid cell `index`.
    fn centre(&self, index: usize) -> DVec3 {
        let [nx, ny, _] = self.dims;
        let (x, y, z) = (index % nx, (index / nx) % ny, index / (nx * ny));
        self.origin + (DVec3::new(x as f64, y as f64, z as f64) + 0.5) * self.cell
    }

    fn len(&self) -> usize {
        self.dims.iter().product()
    }
}

/// The candidate lists of one receptor's cells.
#[derive(Debug)]
pub(crate) struct CandidateLists {
    lists: RwLock<Lists>,
    /// Most lane groups and lists kept.
    budget: usize,
}

impl Default for CandidateLists {
    fn default() -> Self {
        Self::with_budget(BUDGET)
    }
}

impl Clone for CandidateLists {
    /// A fresh, empty set with the same budget: lists are built again as
    /// needed.
    fn clone(&self) -> Self {
        Self::with_budget(self.budget)
    }
}

/// A view of the built lists, read or written.
pub(crate) enum Guard<'a> {
    /// Every list asked for was built.
    Read(RwLockReadGuard<'a, Lists>),
    /// Some were built now.
    Write(RwLockWriteGuard<'a, Lists>),
}

impl Guard<'_> {
    fn lists(&self) -> &Lists {
        match self {
            Guard::Read(g) => g,
            Guard::Write(g) => g,
        }
    }

    /// Writes to `out` the indices (into the cell-ordered atoms) of the
    /// atoms of list `list` that may lie within 8 Å of `x`: all that do and
    /// a few beyond, in cell order. Returns how many.
    ///
    /// Branch-free: every lane's index is written and the count advances by
    /// the lane's test, so no branch depends on which atoms pass.
    #[inline]
    pub(crate) fn select(&self, list: u32, x: DVec3, out: &mut Vec<u32>) -> usize {
        let l = self.lists();
        let (centre, a, b, _) = l.spans[list as usize];
        let (a, b) = (a as usize, b as usize);
        let r = (x - centre).as_vec3();
        let (sx, sy, sz) = (f32x4::splat(r.x), f32x4::splat(r.y), f32x4::splat(r.z));
        let bound = f32x4::splat(NEAR2);
        if out.len() < 4 * (b - a) {
            out.resize(4 * (b - a), 0);
        }
        let mut n = 0;
        for (g, [lx, ly, lz]) in l.lanes[a..b].iter().enumerate() {
            let (dx, dy, dz) = (*lx - sx, *ly - sy, *lz - sz);
            let r2 = dx * dx + dy * dy + dz * dz;
            let mask = r2.simd_lt(bound).to_bitmask();
            let atoms = &l.atoms[4 * (a + g)..4 * (a + g) + 4];
            for (lane, &atom) in atoms.iter().enumerate() {
                out[n] = atom;
                n += ((mask >> lane) & 1) as usize;
            }
        }
        n
    }
}

impl CandidateLists {
    /// Drops every list built so far: the next evaluations build them
    /// again (what a drug pays on entering cells it has not visited).
    pub(crate) fn forget(&self) {
        if let Ok(mut lists) = self.lists.write() {
            lists.clear();
            lists.atoms.clear();
        }
    }

    /// An empty set that keeps at most `budget` lane groups and lists.
    pub(crate) fn with_budget(budget: usize) -> Self {
        Self {
            lists: RwLock::default(),
            budget,
        }
    }

    /// Finds the list of each of `at`'s atoms, building those not built
    /// yet: writes to `which` each atom's list number, or `None` for an
    /// atom that takes the one-atom path: outside the grid (no receptor
    /// atom within 8 Å), a position that is not finite, or a list dropped
    /// for the budget while this call built others (a drug of thousands of
    /// atoms). Returns the view to read them through, or `None` when the
    /// lock is poisoned (a thread panicked while building), for the caller
    /// to take the one-atom path for every atom.
    pub(crate) fn find(
        &self,
        cells: &Cells,
        at: &[DVec3],
        which: &mut Vec<Option<u32>>,
    ) -> Option<Guard<'_>> {
        let border = Border::of(cells);
        let slots = |lists: &Lists, which: &mut Vec<Option<u32>>| {
            which.clear();
            let mut missing = false;
            for &x in at {
                let slot = border
                    .cell_of(x)
                    .map(|c| lists.slot.get(c).copied().unwrap_or(0));
                which.push(slot.and_then(|s| s.checked_sub(1)));
                missing |= slot == Some(0);
            }
            missing
        };
        {
            let lists = self.lists.read().ok()?;
            if !slots(&lists, which) {
                return Some(Guard::Read(lists));
            }
        }
        let mut lists = self.lists.write().ok()?;
        if lists.slot.len() != border.len() {
            lists.slot = vec![0; border.len()];
        }
        for &x in at {
            let Some(c) = border.cell_of(x) else {
                continue;
            };
            if lists.slot[c] == 0 {
                lists.build(cells, &border, c, self.budget);
            }
        }
        slots(&lists, which);
        Some(Guard::Write(lists))
    }
}

impl Lists {
    /// Drops every list (the atoms' indices are the caller's to drop).
    fn clear(&mut self) {
        for &(_, _, _, c) in &self.spans {
            self.slot[c as usize] = 0;
        }
        self.lanes.clear();
        self.spans.clear();
    }

    /// Builds grid cell `c`'s list; drops every other list when it would
    /// pass the budget (of lane groups and lists).
    fn build(&mut self, cells: &Cells, border: &Border, c: usize, budget: usize) {
        let centre = border.centre(c);
        // Every point of the cell is within half its diagonal of the
        // centre; the f32 margin's worth more keeps the test's slack.
        let reach = CUTOFF + border.cell * 3f64.sqrt() / 2.0 + 0.05;
        let start = self.atoms.len();
        let all = cells.atoms();
        cells.visit_indices(centre, reach, |i| {
            if (all[i].position - centre).length_squared() < reach * reach {
                self.atoms.push(i as u32);
            }
        });
        let count = self.atoms.len() - start;
        let groups = count.div_ceil(4);
        // An empty list (a cell of the border) counts too, as its span.
        if self.lanes.len() + self.spans.len() + groups + 1 > budget && !self.spans.is_empty() {
            // Keep the new list's atoms, drop the rest.
            self.atoms.drain(..start);
            self.clear();
        }
        let start = self.atoms.len() - count;
        let first = self.lanes.len();
        for chunk in self.atoms[start..].chunks(4) {
            let mut v = [[FAR; 4]; 3];
            for (l, &i) in chunk.iter().enumerate() {
                let r = (all[i as usize].position - centre).as_vec3();
                (v[0][l], v[1][l], v[2][l]) = (r.x, r.y, r.z);
            }
            self.lanes.push(v.map(f32x4::from));
        }
        // The padding lanes' atoms: any index, as they never pass.
        self.atoms.resize(start + 4 * groups, 0);
        self.spans
            .push((centre, first as u32, self.lanes.len() as u32, c as u32));
        self.slot[c] = self.spans.len() as u32;
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::rng::Rng;
    use crate::score::receptor::CellAtom;

    /// Against brute force: every listed atom's candidates are in cell
    /// order, hold every receptor atom within 8 Å and none beyond 8.05 Å;
    /// an atom without a list has no receptor atom within 8 Å unless the
    /// budget dropped its list. With a budget of a few lists, lists are
    /// dropped and built again within one call and across calls; every few
    /// calls all are forgotten.
    #[test]
    fn lists_hold_every_atom_within_8_a_in_cell_order() {
        let mut rng = Rng(17);
        let atoms: Vec<CellAtom> = (0..800)
            .map(|i| CellAtom {
                position: rng.in_box(DVec3::splat(16.0)),
                xs: 0,
                atom: i,
            })
            .collect();
        let cells = Cells::new(&atoms);
        let sorted = cells.atoms();
        for budget in [BUDGET, 200] {
            let lists = CandidateLists::with_budget(budget);
            let (mut which, mut out) = (Vec::new(), Vec::new());
            let (mut listed, mut dropped) = (0, 0);
            for round in 0..40 {
                if round % 10 == 9 {
                    lists.forget();
                }
                let centre = rng.in_box(DVec3::splat(30.0));
                let spread = [2.0, 8.0, 40.0][round % 3];
                let mut at: Vec<DVec3> = (0..25)
                    .map(|_| centre + rng.in_box(DVec3::splat(spread)))
                    .collect();
                at.push(DVec3::NAN);
                let guard = lists.find(&cells, &at, &mut which).unwrap();
                assert_eq!(which.len(), at.len());
                for (&x, w) in at.iter().zip(&which) {
                    let within: Vec<u32> = (0..sorted.len() as u32)
                        .filter(|&i| (sorted[i as usize].position - x).length_squared() < 64.0)
                        .collect();
                    let Some(l) = *w else {
                        if !within.is_empty() {
                            assert!(budget < BUDGET, "{x} has no list");
                            dropped += 1;
                        }
                        continue;
                    };
                    listed += 1;
                    let n = guard.select(l, x, &mut out);
                    let got = &out[..n];
                    assert!(got.windows(2).all(|w| w[0] < w[1]), "cell order");
                    for &i in got {
                        let r = (sorted[i as usize].position - x).length();
                        assert!(r < 8.05, "{r} Å kept");
                    }
                    let kept: Vec<u32> = got
                        .iter()
                        .copied()
                        .filter(|&i| (sorted[i as usize].position - x).length_squared() < 64.0)
                        .collect();
                    assert_eq!(kept, within, "at {x}");
                }
            }
            assert!(listed > 300, "{listed} listed");
            if budget < BUDGET {
                assert!(dropped > 0, "the small budget dropped no list");
            }
        }
    }
}
