//! The exact evaluator: every receptor atom within 8 Å of a drug atom, from
//! the receptor's cell list, each pair read from Vina's table — what
//! `Vina::score()` computes (`non_cache::eval`).
//!
//! Its cost depends on the drug's size and the atom density around it, not
//! on the receptor's size. The continuous energy it gives the optimiser
//! interpolates the table's samples linearly in r² ([`super::table`]).
//!
//! A whole drug is evaluated at once ([`Field::atoms_energy_gradient`]):
//! the receptor atoms within 8 Å of the drug's bounding sphere are gathered
//! once, in cell order, with f32 copies of their coordinates four to a
//! lane group; each drug atom then tests four of them at a time in f32 with
//! a margin, and reads the table, in f64 and in the gathered order, only
//! for those that pass. The pairs within 8 Å come in the order the cell
//! visit of one atom gives them and the rest add exact zeros, so the sums
//! are the one-atom path's to the bit (for finite positions). A drug of
//! fewer than four atoms, or spread so wide that its gathered ball
//! outweighs its atoms' own balls, takes the one-atom path.

use std::cell::RefCell;

use glam::DVec3;
use wide::f32x4;

use super::field::Field;
use super::function::{CUTOFF, CUTOFF2, Scoring};
use super::receptor::Receptor;
use super::table::{Table, index, smooth_at};
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

/// Receptor atoms gathered around a drug for one evaluation.
#[derive(Debug, Default)]
struct Near {
    /// The gathered atoms' coordinates relative to `centre` in f32, four
    /// atoms a group per axis; the last group padded with far points.
    lanes: Vec<[f32x4; 3]>,
    /// Their positions and X-Score type indices, in cell order.
    atoms: Vec<(DVec3, u32)>,
    centre: DVec3,
}

thread_local! {
    /// Each thread's gathering buffer, kept between evaluations so that
    /// none allocates once it has grown.
    static NEAR: RefCell<Near> = RefCell::new(Near::default());
}

/// Where the padding lanes lie: far beyond any cutoff.
const FAR: f32 = 1.0e6;

/// The f32 test's bound on r²: the f32 distance of a pair within 8 Å errs
/// by far less than this margin (coordinates within tens of Å of the
/// centre), so no such pair is missed; the f64 table read decides.
const NEAR2: f32 = (CUTOFF2 + 0.25) as f32;

impl Near {
    /// Gathers the receptor's atoms in the cells that the ball of
    /// `radius` + 8 Å around `centre` reaches, in cell order.
    fn gather(&mut self, receptor: &Receptor, centre: DVec3, radius: f64) {
        self.centre = centre;
        self.atoms.clear();
        receptor.cells().visit(centre, radius + CUTOFF, |a| {
            self.atoms.push((a.position, a.xs));
        });
        self.lanes.clear();
        for chunk in self.atoms.chunks(4) {
            let mut v = [[FAR; 4]; 3];
            for (l, (p, _)) in chunk.iter().enumerate() {
                let r = (*p - centre).as_vec3();
                (v[0][l], v[1][l], v[2][l]) = (r.x, r.y, r.z);
            }
            self.lanes.push(v.map(f32x4::from));
        }
    }

    /// Calls `f(position, type index)` for the gathered atoms that may lie
    /// within 8 Å of `x` (all that do, and a few beyond), in gathered order.
    #[inline]
    fn visit(&self, x: DVec3, mut f: impl FnMut(DVec3, u32)) {
        let r = (x - self.centre).as_vec3();
        let (sx, sy, sz) = (f32x4::splat(r.x), f32x4::splat(r.y), f32x4::splat(r.z));
        let bound = f32x4::splat(NEAR2);
        for (g, [lx, ly, lz]) in self.lanes.iter().enumerate() {
            let (dx, dy, dz) = (*lx - sx, *ly - sy, *lz - sz);
            let r2 = dx * dx + dy * dy + dz * dz;
            let mut mask = r2.simd_lt(bound).to_bitmask();
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let (p, t) = self.atoms[4 * g + lane];
                f(p, t);
            }
        }
    }
}

/// The centre and radius of a sphere around `at` (its box's centre).
fn bounding_sphere(at: &[DVec3]) -> (DVec3, f64) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &x in at {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    let centre = (lo + hi) * 0.5;
    let r2 = at
        .iter()
        .map(|&x| (x - centre).length_squared())
        .fold(0.0, f64::max);
    (centre, r2.sqrt())
}

impl Exact<'_> {
    /// Runs `each` with the gathered receptor atoms when gathering pays
    /// for `at` (a compact drug of a few atoms or more), or returns false.
    fn with_near(&self, at: &[DVec3], each: impl FnOnce(&Near)) -> bool {
        if at.len() < 4 {
            return false;
        }
        let (centre, radius) = bounding_sphere(at);
        // The gathered ball against the atoms' own balls of 8 Å; both
        // also read the cells' fringe, the atoms' balls more of it.
        let gathered = (radius + CUTOFF).powi(3);
        if !gathered.is_finite() || gathered > 1.5 * at.len() as f64 * CUTOFF.powi(3) {
            return false;
        }
        NEAR.with(|near| {
            // A re-entrant call (none is made) would find it borrowed and
            // take the one-atom path.
            let Ok(mut near) = near.try_borrow_mut() else {
                return false;
            };
            near.gather(self.receptor, centre, radius);
            each(&near);
            true
        })
    }
}

impl Field for Exact<'_> {
    fn atoms_energy(&self, xs: &[XsType], at: &[DVec3], out: &mut [f64]) {
        let done = self.with_near(at, |near| {
            for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
                let rows = self.table.fast_rows(t);
                let mut e = 0.0;
                near.visit(x, |p, u| {
                    e += rows[u as usize][index((p - x).length_squared())];
                });
                *o = e;
            }
        });
        if !done {
            for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
                *o = self.atom_energy(t, x);
            }
        }
    }

    fn atoms_energy_gradient(&self, xs: &[XsType], at: &[DVec3], out: &mut [(f64, DVec3)]) {
        let done = self.with_near(at, |near| {
            for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
                let rows = self.table.smooth_rows(t);
                let (mut e, mut g) = (0.0, DVec3::ZERO);
                near.visit(x, |p, u| {
                    let d = x - p;
                    let (v, dv) = smooth_at(rows[u as usize], d.length_squared());
                    e += v;
                    g += d * (2.0 * dv);
                });
                *o = (e, g);
            }
        });
        if !done {
            for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
                *o = self.atom_energy_gradient(t, x);
            }
        }
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

    /// The whole-drug path gives the one-atom path's values to the bit: for
    /// compact drugs (gathered), drugs spread too wide to gather, drugs of
    /// fewer than four atoms and atoms outside the receptor's box.
    #[test]
    fn whole_drug_path_gives_the_one_atom_values_exactly() {
        let r = receptor(21, 1500, 18.0);
        let exact = Exact::new(&r, Scoring::Vina);
        let mut rng = Rng(5);
        let types = [XsType::C_H, XsType::N_A, XsType::O_DA, XsType::C_P];
        let mut gathered = 0;
        for case in 0..60 {
            let n = [1, 3, 4, 7, 21, 40][case % 6];
            let spread = [2.0, 5.0, 30.0][case % 3];
            let centre = rng.in_box(DVec3::splat(14.0));
            let at: Vec<DVec3> = (0..n)
                .map(|_| centre + rng.in_box(DVec3::splat(spread)))
                .collect();
            let xs: Vec<XsType> = (0..n).map(|i| types[(i + case) % types.len()]).collect();
            if n >= 4 && exact.with_near(&at, |_| ()) {
                gathered += 1;
            }
            let mut e = vec![0.0; n];
            exact.atoms_energy(&xs, &at, &mut e);
            let mut eg = vec![(0.0, DVec3::ZERO); n];
            exact.atoms_energy_gradient(&xs, &at, &mut eg);
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
        assert!(gathered > 10 && gathered < 40, "{gathered} gathered");
    }
}
