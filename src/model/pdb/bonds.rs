//! The bonds a PDB or mmCIF file states, between the atoms bump keeps.
//!
//! PDB `CONECT` records name atoms by serial number; mmCIF `struct_conn`
//! rows by chain, residue number, insertion code, atom name, residue name
//! and alternate location. Both are read as the file goes ([`Pending`]) and
//! resolved once the atoms are chosen ([`resolve`]): a bond to an atom that
//! was not kept (a dropped hydrogen, an alternate not chosen, another
//! model, a symmetry copy) is left out, as is a bond of an atom to itself.
//! The result has each pair once, the lower index first, sorted.

use std::collections::{HashMap, HashSet};

use crate::model::label::{AtomName, ChainId, InsertionCode, ResidueName};
use crate::model::{AtomInfo, BondOrder, FileBond};

/// One end of a bond named as mmCIF names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) struct AtomRef {
    /// Chain (the author's, as atoms keep it).
    pub chain: ChainId,
    /// Residue sequence number (the author's).
    pub seq: i64,
    /// Insertion code.
    pub insertion: InsertionCode,
    /// Atom name.
    pub name: AtomName,
    /// Residue name; empty when not given.
    pub residue: ResidueName,
    /// Alternate location; 0 when not given.
    pub alt: u8,
}

/// A bond between two atoms named as mmCIF names them.
#[derive(Debug, Clone, Copy)]
pub(super) struct NamedBond {
    /// One end.
    pub a: AtomRef,
    /// The other.
    pub b: AtomRef,
    /// Its order.
    pub order: BondOrder,
}

/// Bonds read, to be resolved to atom indices.
#[derive(Debug, Default)]
pub(super) struct Pending {
    /// `CONECT` pairs of serial numbers.
    pub serials: Vec<(i64, i64)>,
    /// `struct_conn` bonds.
    pub named: Vec<NamedBond>,
}

/// The bonds of `pending` between atoms kept (`keep`, by index into `atoms`
/// and `alt`), as indices into the kept atoms.
pub(super) fn resolve(
    pending: &Pending,
    atoms: &[AtomInfo],
    alt: &[u8],
    keep: &[bool],
) -> Vec<FileBond> {
    if pending.serials.is_empty() && pending.named.is_empty() {
        return Vec::new();
    }
    // Index among the kept atoms, by index among all.
    let mut kept_before = 0;
    let new_index: Vec<usize> = keep
        .iter()
        .map(|&k| {
            let index = kept_before;
            kept_before += usize::from(k);
            index
        })
        .collect();
    let mut out: Vec<FileBond> = Vec::new();
    let mut add = |i: usize, j: usize, order: BondOrder| {
        let (a, b) = (new_index[i], new_index[j]);
        if a != b {
            out.push(FileBond {
                a: a.min(b),
                b: a.max(b),
                order,
            });
        }
    };
    if !pending.serials.is_empty() {
        let wanted: HashSet<i64> = pending.serials.iter().flat_map(|&(a, b)| [a, b]).collect();
        let mut by_serial: HashMap<i64, usize> = HashMap::new();
        for (i, a) in atoms.iter().enumerate() {
            if keep[i] && wanted.contains(&a.serial) {
                by_serial.entry(a.serial).or_insert(i);
            }
        }
        for (a, b) in &pending.serials {
            if let (Some(&i), Some(&j)) = (by_serial.get(a), by_serial.get(b)) {
                add(i, j, BondOrder::Unspecified);
            }
        }
    }
    if !pending.named.is_empty() {
        type Key = (ChainId, i64, InsertionCode, AtomName);
        let key = |r: &AtomRef| -> Key { (r.chain, r.seq, r.insertion, r.name) };
        let wanted: HashSet<Key> = pending
            .named
            .iter()
            .flat_map(|b| [key(&b.a), key(&b.b)])
            .collect();
        let mut by_name: HashMap<Key, usize> = HashMap::new();
        for (i, a) in atoms.iter().enumerate() {
            let k = (a.chain, a.seq, a.insertion, a.name);
            if keep[i] && wanted.contains(&k) {
                by_name.entry(k).or_insert(i);
            }
        }
        let find = |r: &AtomRef| {
            let i = *by_name.get(&key(r))?;
            let residue_fits = r.residue.is_empty() || r.residue == atoms[i].residue;
            let alt_fits = r.alt == 0 || alt.get(i) == Some(&r.alt);
            (residue_fits && alt_fits).then_some(i)
        };
        for b in &pending.named {
            if let (Some(i), Some(j)) = (find(&b.a), find(&b.b)) {
                add(i, j, b.order);
            }
        }
    }
    out.sort_unstable();
    out.dedup_by_key(|b| (b.a, b.b));
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use crate::model::molecule::test_carbon;

    #[test]
    fn serial_bonds_skip_atoms_not_kept_and_come_once_sorted() {
        let atoms: Vec<AtomInfo> = (1..=4).map(test_carbon).collect();
        let keep = [true, false, true, true];
        let pending = Pending {
            serials: vec![(4, 1), (1, 4), (1, 2), (3, 3), (3, 1), (9, 1)],
            named: Vec::new(),
        };
        let bonds = resolve(&pending, &atoms, &[0; 4], &keep);
        let pairs: Vec<(usize, usize)> = bonds.iter().map(|b| (b.a, b.b)).collect();
        // Kept atoms 1, 3, 4 are indices 0, 1, 2.
        assert_eq!(pairs, [(0, 1), (0, 2)]);
        assert!(bonds.iter().all(|b| b.order == BondOrder::Unspecified));
    }

    #[test]
    fn named_bonds_match_residue_and_alternate() {
        let mut atoms: Vec<AtomInfo> = (1..=3).map(test_carbon).collect();
        atoms[0].name = "SG".into();
        atoms[1].name = "SG".into();
        atoms[1].seq = 2;
        atoms[2].name = "ZN".into();
        let r = |name: &str, seq: i64, alt: u8| AtomRef {
            chain: "A".into(),
            seq,
            insertion: InsertionCode::EMPTY,
            name: name.into(),
            residue: "X".into(),
            alt,
        };
        let pending = Pending {
            serials: Vec::new(),
            named: vec![
                NamedBond {
                    a: r("SG", 2, 0),
                    b: r("SG", 1, 0),
                    order: BondOrder::Single,
                },
                // The alternate named was not the one kept.
                NamedBond {
                    a: r("SG", 1, b'B'),
                    b: r("ZN", 1, 0),
                    order: BondOrder::Single,
                },
            ],
        };
        let bonds = resolve(&pending, &atoms, &[b'A', 0, 0], &[true; 3]);
        assert_eq!(
            bonds,
            [FileBond {
                a: 0,
                b: 1,
                order: BondOrder::Single
            }]
        );
    }
}
