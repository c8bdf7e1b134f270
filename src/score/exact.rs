//! The exact evaluator: every receptor atom within 8 Å of a drug atom, from
//! the receptor's cell list, each pair read from Vina's table — what
//! `Vina::score()` computes (`non_cache::eval`).
//!
//! Its cost depends on the drug's size and the atom density around it, not
//! on the receptor's size. The continuous energy it gives the optimiser
//! interpolates the table's samples linearly in r² ([`super::table`]).
//!
//! A whole drug is evaluated at once ([`Field::atoms_energy_gradient`]):
//! each drug atom tests its cell's candidate list (`super::candidates`: the
//! receptor atoms within 8 Å of some point of the cell, in cell order) four
//! at a time in f32 with a margin, then reads the table, in f64, for those
//! that pass: first every pair's table index in a batch, then the reads
//! and the sums. The pairs within 8 Å come in the order the cell visit of
//! one atom gives them and the rest add exact zeros, so the sums are the
//! one-atom path's to the bit (for finite positions). An atom beyond the
//! lists' grid (no receptor atom within 8 Å) takes the one-atom path.

use std::cell::RefCell;

use glam::DVec3;

use super::field::Field;
use super::function::{CUTOFF, CUTOFF2, Scoring};
use super::receptor::Receptor;
use super::table::{FACTOR, Table, index, smooth_at, smooth_from};
use crate::chem::XsType;

/// The exact evaluator over one receptor.
#[derive(Debug, Clone, Copy)]
pub struct Exact<'a> {
    receptor: &'a Receptor,
    table: &'static Table,
}

impl<'a> Exact<'a> {
    /// The exact evaluator of `scoring` over `receptor`.
    pub fn new(receptor: &'a Receptor, scoring: Scoring) -> Self {
        Self {
            receptor,
            table: Table::of(scoring),
        }
    }

    /// The receptor.
    pub fn receptor(&self) -> &'a Receptor {
        self.receptor
    }

    /// The scoring function.
    pub fn scoring(&self) -> Scoring {
        self.table.scoring()
    }

    /// Calls `f(receptor atom, r²)` for every receptor atom within the cutoff
    /// of `x` (r² < 64), in cell order.
    #[inline]
    pub fn neighbours(&self, x: DVec3, mut f: impl FnMut(usize, f64)) {
        self.receptor.cells().visit(x, CUTOFF, |a| {
            let r2 = (a.position - x).length_squared();
            if r2 < CUTOFF2 {
                f(a.atom as usize, r2);
            }
        });
    }
}

/// Each thread's buffers for one evaluation, kept between evaluations so
/// that none allocates once they have grown.
#[derive(Debug, Default)]
struct Scratch {
    /// Each drug atom's candidate list, or `None` for the one-atom path.
    which: Vec<Option<u32>>,
    /// One drug atom's candidates.
    list: Vec<u32>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Pairs whose table indices are found before their reads.
const BATCH: usize = 16;

impl Exact<'_> {
    /// Calls `f(i, type, position, candidates)` once for each atom `i` of
    /// the first `len` of `xs` and `at` (as a zip would, no more than
    /// either has), with its candidates from its cell's list (indices into
    /// the cell-ordered atoms: all within 8 Å and a few beyond, in cell
    /// order), or with `None` for the one-atom path. Returns how many atoms
    /// had a list.
    fn each_atom(
        &self,
        xs: &[XsType],
        at: &[DVec3],
        len: usize,
        mut f: impl FnMut(usize, XsType, DVec3, Option<&[u32]>),
    ) -> usize {
        let at = &at[..at.len().min(xs.len()).min(len)];
        SCRATCH.with(|scratch| {
            // A re-entrant call (none is made) would find it borrowed and
            // take the one-atom path.
            let Ok(mut scratch) = scratch.try_borrow_mut() else {
                (0..at.len()).for_each(|i| f(i, xs[i], at[i], None));
                return 0;
            };
            let Scratch { which, list } = &mut *scratch;
            let cells = self.receptor.cells();
            let Some(lists) = self.receptor.candidates().find(cells, at, which) else {
                (0..at.len()).for_each(|i| f(i, xs[i], at[i], None));
                return 0;
            };
            let mut listed = 0;
            for (i, w) in which.iter().enumerate() {
                match *w {
                    Some(l) => {
                        let n = lists.select(l, at[i], list);
                        f(i, xs[i], at[i], Some(&list[..n]));
                        listed += 1;
                    }
                    None => f(i, xs[i], at[i], None),
                }
            }
            listed
        })
    }
}

impl Field for Exact<'_> {
    fn atoms_energy(&self, xs: &[XsType], at: &[DVec3], out: &mut [f64]) {
        let atoms = self.receptor.cells().atoms();
        self.each_atom(xs, at, out.len(), |i, t, x, candidates| {
            out[i] = match candidates {
                Some(list) => {
                    let rows = self.table.fast_rows(t);
                    let mut e = 0.0;
                    for &k in list {
                        let a = &atoms[k as usize];
                        e += rows[a.xs as usize][index((a.position - x).length_squared())];
                    }
                    e
                }
                None => self.atom_energy(t, x),
            };
        });
    }

    fn atoms_energy_gradient(&self, xs: &[XsType], at: &[DVec3], out: &mut [(f64, DVec3)]) {
        let atoms = self.receptor.cells().atoms();
        self.each_atom(xs, at, out.len(), |i, t, x, candidates| {
            out[i] = match candidates {
                Some(list) => {
                    let rows = self.table.smooth_rows(t);
                    let (mut e, mut g) = (0.0, DVec3::ZERO);
                    // In batches: first every pair's offset and table
                    // index, then the table reads and the sums. A pair's
                    // chain from its position to its sum is long; split,
                    // the reads of a batch are in flight together.
                    let mut d = [DVec3::ZERO; BATCH];
                    let mut at_k = [(0usize, 0.0f64, 0u32); BATCH];
                    for chunk in list.chunks(BATCH) {
                        for ((&k, d), at_k) in chunk.iter().zip(&mut d).zip(&mut at_k) {
                            let a = &atoms[k as usize];
                            *d = x - a.position;
                            let r2 = d.length_squared();
                            let k = index(r2);
                            *at_k = (k, FACTOR * r2 - k as f64, a.xs);
                        }
                        for (&d, &(k, rem, u)) in d.iter().zip(&at_k).take(chunk.len()) {
                            let (v, dv) = smooth_from(rows[u as usize], k, rem);
                            e += v;
                            g += d * (2.0 * dv);
                        }
                    }
                    (e, g)
                }
                None => self.atom_energy_gradient(t, x),
            };
        });
    }

    fn table(&self) -> &'static Table {
        self.table
    }

    #[inline]
    fn atom_energy(&self, t: XsType, x: DVec3) -> f64 {
        let rows = self.table.fast_rows(t);
        let mut e = 0.0;
        // Branch-free: at r² ≥ 64 the index is 2048, whose value is 0.
        self.receptor.cells().visit(x, CUTOFF, |a| {
            let r2 = (a.position - x).length_squared();
            e += rows[a.xs as usize][index(r2)];
        });
        e
    }

    #[inline]
    fn atom_energy_gradient(&self, t: XsType, x: DVec3) -> (f64, DVec3) {
        let rows = self.table.smooth_rows(t);
        let (mut e, mut g) = (0.0, DVec3::ZERO);
        // Branch-free: from r² = 64 on, both samples read are 0.
        self.receptor.cells().visit(x, CUTOFF, |a| {
            let d = x - a.position;
            let r2 = d.length_squared();
            let (v, dv) = smooth_at(rows[a.xs as usize], r2);
            e += v;
            g += d * (2.0 * dv);
        });
        (e, g)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::rng::Rng;

    fn receptor(seed: u64, n: usize, size: f64) -> Receptor {
        let mut rng = Rng(seed);
        let pos: Vec<DVec3> = (0..n).map(|_| rng.in_box(DVec3::splat(size))).collect();
        let xs: Vec<Option<XsType>> = (0..n)
            .map(|i| {
                Some(
                    [
                        XsType::C_H,
                        XsType::O_A,
                        XsType::N_D,
                        XsType::C_P,
                        XsType::Met_D,
                    ][i % 5],
                )
            })
            .collect();
        Receptor::new(&pos, &xs, &[])
    }

    /// The whole-drug path (candidate lists) gives the one-atom path's
    /// values to the bit: for compact and spread drugs, drugs of one atom
    /// and atoms beyond the receptor's box, with lists built in the call or
    /// before it.
    #[test]
    fn whole_drug_path_gives_the_one_atom_values_exactly() {
        let r = receptor(21, 1500, 18.0);
        let exact = Exact::new(&r, Scoring::Vina);
        let mut rng = Rng(5);
        let types = [XsType::C_H, XsType::N_A, XsType::O_DA, XsType::C_P];
        let (mut listed, mut alone) = (0, 0);
        for case in 0..60 {
            let n = [1, 3, 4, 7, 21, 40][case % 6];
            let spread = [2.0, 5.0, 30.0][case % 3];
            let centre = rng.in_box(DVec3::splat(14.0));
            let at: Vec<DVec3> = (0..n)
                .map(|_| centre + rng.in_box(DVec3::splat(spread)))
                .collect();
            let xs: Vec<XsType> = (0..n).map(|i| types[(i + case) % types.len()]).collect();
            let mut e = vec![0.0; n];
            exact.atoms_energy(&xs, &at, &mut e);
            let mut eg = vec![(0.0, DVec3::ZERO); n];
            exact.atoms_energy_gradient(&xs, &at, &mut eg);
            let l = exact.each_atom(&xs, &at, n, |_, _, _, _| ());
            (listed, alone) = (listed + l, alone + n - l);
            for k in 0..n {
                let want = exact.atom_energy(xs[k], at[k]);
                assert_eq!(e[k].to_bits(), want.to_bits(), "case {case} atom {k}");
                let (we, wg) = exact.atom_energy_gradient(xs[k], at[k]);
                assert_eq!(eg[k].0.to_bits(), we.to_bits(), "case {case} atom {k}");
                for a in 0..3 {
                    assert_eq!(
                        eg[k].1[a].to_bits(),
                        wg[a].to_bits(),
                        "case {case} atom {k}"
                    );
                }
            }
        }
        // Both paths were taken.
        assert!(listed > 100 && alone > 10, "{listed} listed, {alone} alone");
    }
}
