//! The symmetries of a molecule's bond graph, and the RMSD that allows for
//! them.
//!
//! Two poses of a drug that differ only by swapping atoms its graph cannot
//! tell apart — benzamidine's ring turned over, the two oxygens of a
//! carboxylate, the methyls of a tert-butyl — are the same pose to a
//! chemist; docking benchmarks compare poses by the smallest RMSD over
//! those swaps (as spyrmsd and DockRMSD do). [`automorphisms`] lists the
//! swaps: the permutations of the atoms that keep every element and every
//! bond (bond orders aside, since a Kekulé form or a charged resonance
//! form does not change which atoms are equivalent). The search maps the
//! atoms in breadth-first order, each one's candidates the unused
//! neighbours of an already mapped neighbour's image, so it prunes at the
//! first broken bond; it stops at [`MAX_AUTOMORPHISMS`] permutations or
//! [`MAX_SEARCH`] trial mappings, whichever comes first (the identity is
//! always first, so the RMSD is never above the plain one). A molecule of
//! more than [`MAX_ATOMS`] atoms (no drug; the search recurses once per
//! atom) gets the identity alone.

use super::graph::Adjacency;
use crate::model::Molecule;
use crate::model::element::is_hydrogen;

/// Most permutations listed.
pub const MAX_AUTOMORPHISMS: usize = 1024;

/// Most trial mappings of an atom to an image, over a whole search.
pub const MAX_SEARCH: usize = 200_000;

/// Most atoms searched: larger molecules get the identity alone.
pub const MAX_ATOMS: usize = 1000;

/// The permutations `p` of the atoms (atom `i` goes to `p[i]`) that keep
/// `labels` (one per atom: atoms with different labels never swap) and
/// `adjacency`, the identity first, the rest in the search's order.
pub fn automorphisms<L: PartialEq>(labels: &[L], adjacency: &Adjacency) -> Vec<Vec<u32>> {
    let n = labels.len();
    let identity: Vec<u32> = (0..n as u32).collect();
    if n != adjacency.len() || n == 0 || n > MAX_ATOMS {
        return vec![identity];
    }
    let order = breadth_first(adjacency);
    let mut search = Search {
        labels,
        adjacency,
        order: &order,
        map: vec![u32::MAX; n],
        used: vec![false; n],
        found: vec![identity.clone()],
        trials: 0,
    };
    search.extend(0);
    search.found
}

/// The permutations of `mol`'s heavy atoms, as positions in the list of
/// its heavy atoms in atom order, that keep their elements and bonds
/// ([`automorphisms`] of its perceived chemistry).
pub fn heavy_swaps(mol: &Molecule) -> Vec<Vec<u32>> {
    let heavy: Vec<usize> = (0..mol.atoms.len())
        .filter(|&i| !is_hydrogen(&mol.atoms[i].element))
        .collect();
    let labels: Vec<String> = mol
        .atoms
        .iter()
        .map(|a| a.element.to_ascii_uppercase())
        .collect();
    let mut at = vec![u32::MAX; mol.atoms.len()];
    for (k, &i) in heavy.iter().enumerate() {
        at[i] = k as u32;
    }
    automorphisms(&labels, &mol.chemistry().adjacency)
        .into_iter()
        .map(|p| heavy.iter().map(|&i| at[p[i] as usize]).collect())
        .collect()
}

/// The smallest RMSD between `a` and `b` (the same atoms in the same
/// order) over `perms`, Å: `b`'s atom `p[i]` against `a`'s atom `i`.
pub fn rmsd_over(perms: &[Vec<u32>], a: &[glam::DVec3], b: &[glam::DVec3]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return 0.0;
    }
    let plain = || (0..n).map(|i| (a[i] - b[i]).length_squared()).sum::<f64>();
    let best = perms
        .iter()
        .filter(|p| p.len() == n)
        .map(|p| {
            (0..n)
                .map(|i| (a[i] - b[p[i] as usize]).length_squared())
                .sum::<f64>()
        })
        .fold(f64::INFINITY, f64::min);
    let sum = if best.is_finite() { best } else { plain() };
    (sum / n as f64).sqrt()
}

/// Every atom once, each connected part breadth first from its lowest atom.
fn breadth_first(adjacency: &Adjacency) -> Vec<u32> {
    let n = adjacency.len();
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for root in 0..n {
        if seen[root] {
            continue;
        }
        seen[root] = true;
        let mut head = order.len();
        order.push(root as u32);
        while head < order.len() {
            let i = order[head] as usize;
            head += 1;
            for &(j, _) in adjacency.of(i) {
                if !std::mem::replace(&mut seen[j as usize], true) {
                    order.push(j);
                }
            }
        }
    }
    order
}

/// The state of one automorphism search.
struct Search<'a, L> {
    labels: &'a [L],
    adjacency: &'a Adjacency,
    order: &'a [u32],
    /// Atom → its image so far (`u32::MAX`: not mapped yet).
    map: Vec<u32>,
    /// Image atoms taken.
    used: Vec<bool>,
    found: Vec<Vec<u32>>,
    trials: usize,
}

impl<L: PartialEq> Search<'_, L> {
    /// Maps the atoms from `order[k]` on in every way that keeps the graph.
    fn extend(&mut self, k: usize) {
        if self.found.len() >= MAX_AUTOMORPHISMS || self.trials >= MAX_SEARCH {
            return;
        }
        let Some(&i) = self.order.get(k) else {
            if self.map.iter().enumerate().any(|(a, &b)| a as u32 != b) {
                self.found.push(self.map.clone());
            }
            return;
        };
        let i = i as usize;
        // Candidates: beside the image of a mapped neighbour, or any atom
        // for the first atom of a connected part.
        let anchor = self
            .adjacency
            .of(i)
            .iter()
            .map(|&(j, _)| self.map[j as usize])
            .find(|&m| m != u32::MAX);
        let candidates: Vec<u32> = match anchor {
            Some(m) => self
                .adjacency
                .of(m as usize)
                .iter()
                .map(|&(c, _)| c)
                .collect(),
            None => (0..self.labels.len() as u32).collect(),
        };
        for c in candidates {
            self.trials += 1;
            if self.trials >= MAX_SEARCH {
                return;
            }
            if self.used[c as usize] || !self.fits(i, c as usize) {
                continue;
            }
            self.map[i] = c;
            self.used[c as usize] = true;
            self.extend(k + 1);
            self.map[i] = u32::MAX;
            self.used[c as usize] = false;
        }
    }

    /// Whether atom `i` may go to `c`: the same label and degree, and every
    /// mapped neighbour of `i` goes to a neighbour of `c` (with equal
    /// degrees and a bijection, that keeps every bond both ways).
    fn fits(&self, i: usize, c: usize) -> bool {
        if self.labels[i] != self.labels[c] || self.adjacency.degree(i) != self.adjacency.degree(c)
        {
            return false;
        }
        let images = self.adjacency.of(c);
        self.adjacency.of(i).iter().all(|&(j, _)| {
            let m = self.map[j as usize];
            m == u32::MAX || images.iter().any(|&(x, _)| x == m)
        }) && images.iter().all(|&(x, _)| {
            // An already taken neighbour of `c` must be the image of a
            // neighbour of `i`.
            !self.used[x as usize]
                || self
                    .adjacency
                    .of(i)
                    .iter()
                    .any(|&(j, _)| self.map[j as usize] == x)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chem::graph::Bond;
    use crate::model::BondOrder;
    use glam::DVec3;

    fn graph(n: usize, edges: &[(u32, u32)]) -> Adjacency {
        let bonds: Vec<Bond> = edges
            .iter()
            .map(|&(a, b)| Bond {
                a,
                b,
                order: BondOrder::Single,
            })
            .collect();
        Adjacency::new(n, &bonds)
    }

    /// Every listed permutation is a bijection that keeps labels and bonds.
    fn check(labels: &[&str], adj: &Adjacency, perms: &[Vec<u32>]) {
        for p in perms {
            let mut seen = vec![false; labels.len()];
            for (i, &x) in p.iter().enumerate() {
                assert!(!std::mem::replace(&mut seen[x as usize], true), "{p:?}");
                assert_eq!(labels[i], labels[x as usize]);
                for &(j, _) in adj.of(i) {
                    assert!(adj.of(x as usize).iter().any(|&(y, _)| y == p[j as usize]));
                }
            }
        }
        let mut sorted = perms.to_vec();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), perms.len(), "repeats");
    }

    #[test]
    fn benzamidine_turns_over_and_swaps_its_nitrogens() {
        // Ring C0..C5, C6 on C0, N7 and N8 on C6.
        let labels = ["C", "C", "C", "C", "C", "C", "C", "N", "N"];
        let adj = graph(
            9,
            &[
                (0, 1),
                (1, 2),
                (2, 3),
                (3, 4),
                (4, 5),
                (0, 5),
                (0, 6),
                (6, 7),
                (6, 8),
            ],
        );
        let perms = automorphisms(&labels, &adj);
        check(&labels, &adj, &perms);
        // The ring turned over (or not) times the nitrogens swapped (or not).
        assert_eq!(perms.len(), 4);
        assert_eq!(perms[0], (0..9).collect::<Vec<u32>>());
    }

    #[test]
    fn a_ring_of_six_has_twelve_and_labels_break_them() {
        let ring: Vec<(u32, u32)> = (0..6).map(|i| (i, (i + 1) % 6)).collect();
        let adj = graph(6, &ring);
        let perms = automorphisms(&["C"; 6], &adj);
        check(&["C"; 6], &adj, &perms);
        assert_eq!(perms.len(), 12);
        let labels = ["N", "C", "C", "C", "C", "C"];
        let perms = automorphisms(&labels, &adj);
        check(&labels, &adj, &perms);
        assert_eq!(perms.len(), 2, "pyridine: the mirror through N only");
    }

    #[test]
    fn separate_parts_and_the_cap() {
        // Two separate ethanes' worth of C–C: each flips, and they swap.
        let adj = graph(4, &[(0, 1), (2, 3)]);
        let perms = automorphisms(&["C"; 4], &adj);
        check(&["C"; 4], &adj, &perms);
        assert_eq!(perms.len(), 8);
        // Beyond the atom cap: the identity alone.
        let adj = graph(MAX_ATOMS + 1, &[]);
        assert_eq!(automorphisms(&vec!["C"; MAX_ATOMS + 1], &adj).len(), 1);
        // Twelve atoms with no bonds: 12! permutations, capped.
        let adj = graph(12, &[]);
        let perms = automorphisms(&["C"; 12], &adj);
        check(&["C"; 12], &adj, &perms);
        assert_eq!(perms.len(), MAX_AUTOMORPHISMS);
    }

    #[test]
    fn rmsd_over_the_swaps_is_the_least_and_never_above_the_plain() {
        // A carboxylate-like C with two O: the Os swapped in `b`.
        let labels = ["C", "O", "O"];
        let adj = graph(3, &[(0, 1), (0, 2)]);
        let perms = automorphisms(&labels, &adj);
        let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let b = [DVec3::ZERO, DVec3::Y, DVec3::X];
        let plain = rmsd_over(&perms[..1], &a, &b);
        assert!((plain - (4.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(rmsd_over(&perms, &a, &b), 0.0);
        let shifted: Vec<DVec3> = a.iter().map(|&x| x + DVec3::Z).collect();
        assert!((rmsd_over(&perms, &a, &shifted) - 1.0).abs() < 1e-12);
        assert_eq!(rmsd_over(&[], &a, &a), 0.0);
    }
}
