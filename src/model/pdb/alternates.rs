//! Alternate locations: one atom per site.
//!
//! In a residue where any atom has an alternate-location code, the atoms
//! sharing a name compete: the one with the highest occupancy is kept, ties
//! going to the one that appears first in the file. Atoms without a code
//! have no rival and stay; alternates with different residue names
//! (microheterogeneity) compete as one residue. A residue is its chain,
//! sequence number and insertion code.

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};

use crate::model::AtomInfo;
use crate::model::label::{AtomName, ChainId, InsertionCode};

/// A residue: chain, sequence number, insertion code.
type Residue = (ChainId, i64, InsertionCode);

/// Which of `atoms` to keep (`occupancy` and `alt`, the alternate-location
/// code or 0, by atom): all of them unless some have alternates, then one
/// per name in each residue that does.
pub(super) fn one_per_site(atoms: &[AtomInfo], occupancy: &[f32], alt: &[u8]) -> Vec<bool> {
    let mut keep = vec![true; atoms.len()];
    let residue = |a: &AtomInfo| -> Residue { (a.chain, a.seq, a.insertion) };
    let with_alternates: HashSet<Residue> = atoms
        .iter()
        .zip(alt)
        .filter(|(_, code)| **code != 0)
        .map(|(a, _)| residue(a))
        .collect();
    if with_alternates.is_empty() {
        return keep;
    }
    let mut best: HashMap<(Residue, AtomName), usize> = HashMap::new();
    for (i, a) in atoms.iter().enumerate() {
        let r = residue(a);
        if !with_alternates.contains(&r) {
            continue;
        }
        match best.entry((r, a.name)) {
            Entry::Vacant(e) => {
                e.insert(i);
            }
            Entry::Occupied(mut e) => {
                let j = *e.get();
                if occupancy.get(i) > occupancy.get(j) {
                    keep[j] = false;
                    e.insert(i);
                } else {
                    keep[i] = false;
                }
            }
        }
    }
    keep
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use crate::model::molecule::test_carbon;

    fn atom(name: &str, seq: i64) -> AtomInfo {
        AtomInfo {
            name: name.into(),
            seq,
            ..test_carbon(1)
        }
    }

    #[test]
    fn the_highest_occupancy_wins_ties_to_the_first() {
        let atoms = [
            atom("N", 1),
            atom("CB", 1),
            atom("CB", 1),
            atom("OG", 1),
            atom("OG", 1),
            atom("CB", 2),
            atom("CB", 2),
        ];
        let occupancy = [1.0, 0.3, 0.7, 0.5, 0.5, 1.0, 1.0];
        let alt = [0, b'A', b'B', b'A', b'B', 0, 0];
        // Residue 2 has no alternates: its two CBs both stay.
        assert_eq!(
            one_per_site(&atoms, &occupancy, &alt),
            [true, false, true, true, false, true, true]
        );
        assert!(one_per_site(&atoms, &occupancy, &[0; 7]).iter().all(|k| *k));
    }
}
