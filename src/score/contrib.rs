//! Each receptor atom's share of a pose's intermolecular energy: the sum of
//! its pair energies with the drug's atoms within 8 Å (the same table values
//! the drug atoms' sums in [`super::report`] are made of), for colouring the
//! pocket by contribution.
//!
//! A pair's energy is counted on both sides (once in the drug atom's sum,
//! once in the receptor atom's), so each side shows which of its atoms
//! help and which hurt. The curl that damps a drug atom's positive sum is
//! not applied: it belongs to the drug atom's total, not to one pair.
//!
//! [`receptor_contributions`] walks the pairs on its own;
//! [`super::report::score_with_contributions`] collects the same pairs in
//! the same order during a score's own walk, so the lists are equal to the
//! bit (a unit test there checks it).

use glam::DVec3;

use super::exact::Exact;
use super::ligand::Ligand;
use super::table::{Table, index};

/// `(receptor atom, energy)` for every receptor atom within 8 Å of a
/// scored drug atom, in receptor-atom order; receptor atoms are numbered
/// as in the molecule the receptor was built from
/// ([`super::Receptor::source`]); `x` are the drug's heavy-atom positions
/// in the receptor's frame ([`Ligand::place`]).
pub fn receptor_contributions(exact: &Exact<'_>, lig: &Ligand, x: &[DVec3]) -> Vec<(u32, f64)> {
    let table = Table::of(exact.scoring());
    let receptor = exact.receptor();
    let mut sums: Vec<(u32, f64)> = Vec::new();
    for (&i, &t) in lig.scored.iter().zip(&lig.xs) {
        let Some(&xi) = x.get(i as usize) else {
            continue;
        };
        let rows = table.fast_rows(t);
        exact.neighbours(xi, |j, r2| {
            let e = rows[receptor.xs[j].index()][index(r2)];
            sums.push((receptor.source[j], e));
        });
    }
    merge(sums)
}

/// The pair energies `(receptor atom, energy)` summed per receptor atom, in
/// receptor-atom order; each atom's pairs are added in the order given.
pub(super) fn merge(mut sums: Vec<(u32, f64)>) -> Vec<(u32, f64)> {
    sums.sort_by_key(|s| s.0);
    let mut out: Vec<(u32, f64)> = Vec::new();
    for (a, e) in sums {
        match out.last_mut() {
            Some(last) if last.0 == a => last.1 += e,
            _ => out.push((a, e)),
        }
    }
    out
}
