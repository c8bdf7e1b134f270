//! Aromaticity: residue templates name their aromatic rings; elsewhere each
//! smallest ring of five to seven atoms (and each pair of such rings
//! sharing a bond, for fused systems) is aromatic when every atom takes part
//! in its π system and the π electrons number 4n + 2 (Hückel): an atom with
//! a double bond inside the ring gives one, a nitrogen without one (a
//! pyrrole nitrogen, an N with three neighbours), an oxygen or a sulfur
//! gives two, a carbon with an exocyclic double bond to O, N or S gives
//! none (as in pyridone and uracil, aromatic in the Daylight model Open
//! Babel follows). A ring with an sp3 atom is not aromatic.

use super::connect::Connection;
use super::graph::Adjacency;
use super::rings::smallest_rings;
use crate::model::{BondOrder, Molecule};

/// π electrons atom `i` gives ring `ring`, or `None` when it breaks the π system.
fn electrons(
    mol: &Molecule,
    conn: &Connection,
    adj: &Adjacency,
    explicit_h: &[Option<u8>],
    ring: &[u32],
    i: usize,
) -> Option<u32> {
    let bonds = &conn.bonds;
    let mut in_ring_double = false;
    let mut exo_double: Option<&str> = None;
    for &(j, k) in adj.of(i) {
        if bonds[k as usize].order == BondOrder::Double {
            if ring.contains(&j) {
                in_ring_double = true;
            } else {
                exo_double = Some(mol.atoms[j as usize].element.as_str());
            }
        } else if bonds[k as usize].order == BondOrder::Triple {
            return None;
        }
    }
    let e = mol.atoms[i].element.as_str();
    if in_ring_double {
        return Some(1);
    }
    let deg = adj.degree(i) as u32 + u32::from(explicit_h[i].unwrap_or(0));
    match e {
        "C" => match exo_double {
            Some("O" | "N" | "S") => Some(0),
            _ if conn.charges[i] < 0 => Some(2),
            _ => None,
        },
        "N" | "P" => {
            if conn.charges[i] > 0 && deg >= 4 {
                None
            } else if exo_double.is_some() {
                // N-oxide-like N=O out of the ring.
                Some(1)
            } else if deg <= 3 {
                Some(2)
            } else {
                None
            }
        }
        "O" | "S" | "Se" if deg == 2 && exo_double.is_none() => Some(2),
        "B" => Some(0),
        _ => None,
    }
}

/// Per atom and per bond: aromatic.
pub(crate) fn perceive(
    mol: &Molecule,
    conn: &Connection,
    adj: &Adjacency,
    in_ring: &[bool],
    explicit_h: &[Option<u8>],
) -> (Vec<bool>, Vec<bool>) {
    let n = mol.len();
    let bonds = &conn.bonds;
    let mut atom = vec![false; n];
    let mut bond = vec![false; bonds.len()];
    // Templates.
    for (k, b) in bonds.iter().enumerate() {
        let (a, c) = (b.a as usize, b.b as usize);
        if conn.template_aromatic[a]
            && conn.template_aromatic[c]
            && conn.residue_of[a] == conn.residue_of[c]
            && in_ring[k]
        {
            bond[k] = true;
            atom[a] = true;
            atom[c] = true;
        }
    }
    let covered =
        |i: usize| conn.templates[conn.residue_of[i] as usize].is_some() && conn.ordered[i];
    let rings: Vec<Vec<u32>> = smallest_rings(adj, bonds, in_ring, &|i| !covered(i))
        .into_iter()
        .filter(|r| (5..=7).contains(&r.len()))
        .collect();
    let count = |atoms: &[u32]| -> Option<u32> {
        atoms
            .iter()
            .map(|&i| electrons(mol, conn, adj, explicit_h, atoms, i as usize))
            .sum()
    };
    let mut aromatic_ring = vec![false; rings.len()];
    for (r, ring) in rings.iter().enumerate() {
        if let Some(e) = count(ring)
            && e % 4 == 2
        {
            aromatic_ring[r] = true;
        }
    }
    // Fused pairs: two rings sharing a bond, each with a closed π system.
    // Rings are paired through the atoms they share, so the cost stays
    // linear in the number of rings.
    let mut rings_of: std::collections::HashMap<u32, Vec<usize>> = std::collections::HashMap::new();
    for (r, ring) in rings.iter().enumerate() {
        for &a in ring {
            rings_of.entry(a).or_default().push(r);
        }
    }
    for r in 0..rings.len() {
        let mut partners: Vec<usize> = rings[r]
            .iter()
            .flat_map(|a| rings_of.get(a).into_iter().flatten().copied())
            .filter(|&s| s > r)
            .collect();
        partners.sort_unstable();
        partners.dedup();
        for s in partners {
            if aromatic_ring[r] && aromatic_ring[s] {
                continue;
            }
            let shared = rings[r].iter().filter(|a| rings[s].contains(a)).count();
            if shared != 2 {
                continue;
            }
            let mut union: Vec<u32> = rings[r].clone();
            union.extend(rings[s].iter().filter(|a| !rings[r].contains(a)));
            if let Some(e) = count(&union)
                && e % 4 == 2
            {
                aromatic_ring[r] = true;
                aromatic_ring[s] = true;
            }
        }
    }
    for (r, ring) in rings.iter().enumerate() {
        if !aromatic_ring[r] {
            continue;
        }
        for (x, &i) in ring.iter().enumerate() {
            atom[i as usize] = true;
            let j = ring[(x + 1) % ring.len()];
            if let Some(&(_, k)) = adj.of(i as usize).iter().find(|&&(w, _)| w == j) {
                bond[k as usize] = true;
            }
        }
    }
    (atom, bond)
}
