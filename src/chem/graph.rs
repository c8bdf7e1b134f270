//! Bonds and the adjacency of a molecule's heavy atoms, in compressed rows.

use serde::Serialize;

use crate::model::BondOrder;

/// A bond between two heavy atoms of a molecule (indices into its atoms).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct Bond {
    /// The first atom (the lower index).
    pub a: u32,
    /// The second atom.
    pub b: u32,
    /// The order: Single, Double or Triple (a Kekulé structure) once
    /// perceived; `Aromatic` only where no Kekulé structure was found;
    /// `Unspecified` only before perception.
    pub order: BondOrder,
}

impl Bond {
    /// A bond with its atoms put in order.
    pub fn new(a: u32, b: u32, order: BondOrder) -> Self {
        Self {
            a: a.min(b),
            b: a.max(b),
            order,
        }
    }

    /// The other atom of the bond.
    pub fn other(&self, atom: u32) -> u32 {
        if self.a == atom { self.b } else { self.a }
    }

    /// The bond's contribution to valence (aromatic counts 1.5, rounded
    /// down by the callers that sum it in halves).
    pub fn valence_halves(&self) -> u32 {
        match self.order {
            BondOrder::Double => 4,
            BondOrder::Triple => 6,
            BondOrder::Aromatic => 3,
            BondOrder::Single | BondOrder::Unspecified => 2,
        }
    }
}

/// Neighbours of every atom: `(neighbour, bond index)` rows.
#[derive(Debug, Clone, Default)]
pub struct Adjacency {
    start: Vec<u32>,
    entries: Vec<(u32, u32)>,
}

impl Adjacency {
    /// The adjacency of `n` atoms joined by `bonds`.
    pub fn new(n: usize, bonds: &[Bond]) -> Self {
        let mut deg = vec![0u32; n + 1];
        for b in bonds {
            deg[b.a as usize + 1] += 1;
            deg[b.b as usize + 1] += 1;
        }
        for i in 0..n {
            deg[i + 1] += deg[i];
        }
        let mut fill = deg.clone();
        let mut entries = vec![(0, 0); bonds.len() * 2];
        for (k, b) in bonds.iter().enumerate() {
            let k = u32::try_from(k).unwrap_or(u32::MAX);
            entries[fill[b.a as usize] as usize] = (b.b, k);
            fill[b.a as usize] += 1;
            entries[fill[b.b as usize] as usize] = (b.a, k);
            fill[b.b as usize] += 1;
        }
        Self {
            start: deg,
            entries,
        }
    }

    /// `(neighbour, bond index)` of atom `i`, in bond order.
    pub fn of(&self, i: usize) -> &[(u32, u32)] {
        &self.entries[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Number of bonds of atom `i`.
    pub fn degree(&self, i: usize) -> usize {
        (self.start[i + 1] - self.start[i]) as usize
    }

    /// Number of atoms.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// True when there are no atoms.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
