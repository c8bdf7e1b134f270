//! The exact evaluator: every receptor atom within 8 Å of a drug atom, from
//! the receptor's cell list, each pair read from Vina's table — what
//! `Vina::score()` computes (`non_cache::eval`).
//!
//! Its cost depends on the drug's size and the atom density around it, not
//! on the receptor's size. The continuous energy it gives the optimiser
//! interpolates the table's samples linearly in r² ([`super::table`]).

use glam::DVec3;

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

impl Field for Exact<'_> {
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
