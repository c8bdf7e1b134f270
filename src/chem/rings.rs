//! Rings: which bonds lie in a ring (every bond that is not a bridge, by
//! Tarjan's low-link search, linear in the bonds) and the smallest ring
//! through each ring bond (a breadth-first search of bounded depth), for
//! aromaticity and for planarity in bond-order perception.

use std::collections::HashSet;

use glam::Vec3;

use super::graph::Adjacency;

/// Largest ring [`smallest_rings`] looks for.
pub const MAX_RING: usize = 8;

/// `in_ring[k]` for every bond `k`: the bond is not a bridge.
pub fn ring_bonds(adj: &Adjacency, n_bonds: usize) -> Vec<bool> {
    let n = adj.len();
    let mut in_ring = vec![true; n_bonds];
    let mut disc = vec![u32::MAX; n];
    let mut low = vec![0u32; n];
    let mut time = 0u32;
    // Iterative DFS: (atom, bond it was entered by, next neighbour slot).
    let mut stack: Vec<(u32, u32, usize)> = Vec::new();
    for root in 0..n {
        if disc[root] != u32::MAX {
            continue;
        }
        disc[root] = time;
        low[root] = time;
        time += 1;
        stack.push((root as u32, u32::MAX, 0));
        while let Some(top) = stack.last_mut() {
            let (v, via, slot) = *top;
            let row = adj.of(v as usize);
            if slot < row.len() {
                top.2 += 1;
                let (w, k) = row[slot];
                if k == via {
                    continue;
                }
                if disc[w as usize] == u32::MAX {
                    disc[w as usize] = time;
                    low[w as usize] = time;
                    time += 1;
                    stack.push((w, k, 0));
                } else {
                    low[v as usize] = low[v as usize].min(disc[w as usize]);
                }
            } else {
                stack.pop();
                if let Some(parent) = stack.last() {
                    let p = parent.0 as usize;
                    low[p] = low[p].min(low[v as usize]);
                    if low[v as usize] > disc[p] {
                        in_ring[via as usize] = false;
                    }
                }
            }
        }
    }
    in_ring
}

/// The smallest ring (up to [`MAX_RING`] atoms) through each ring bond one
/// of whose atoms `wanted` selects, each ring once, as atom lists in ring
/// order, sorted.
pub fn smallest_rings(
    adj: &Adjacency,
    bonds: &[super::Bond],
    in_ring: &[bool],
    wanted: &dyn Fn(usize) -> bool,
) -> Vec<Vec<u32>> {
    let mut seen: HashSet<Vec<u32>> = HashSet::new();
    let mut out = Vec::new();
    let mut prev: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
    for (k, b) in bonds.iter().enumerate() {
        if !in_ring[k] || !(wanted(b.a as usize) || wanted(b.b as usize)) {
            continue;
        }
        // Shortest path from a to b not using bond k.
        prev.clear();
        prev.insert(b.a, u32::MAX);
        let mut frontier = vec![b.a];
        let mut found = false;
        for _ in 0..MAX_RING - 1 {
            let mut next = Vec::new();
            for &v in &frontier {
                for &(w, kk) in adj.of(v as usize) {
                    if kk as usize == k || !in_ring[kk as usize] || prev.contains_key(&w) {
                        continue;
                    }
                    prev.insert(w, v);
                    if w == b.b {
                        found = true;
                        break;
                    }
                    next.push(w);
                }
                if found {
                    break;
                }
            }
            if found || next.is_empty() {
                break;
            }
            frontier = next;
        }
        if !found {
            continue;
        }
        let mut ring = vec![b.b];
        let mut v = b.b;
        while let Some(&p) = prev.get(&v) {
            if p == u32::MAX {
                break;
            }
            ring.push(p);
            v = p;
        }
        let mut key = ring.clone();
        key.sort_unstable();
        if seen.insert(key) {
            out.push(ring);
        }
    }
    out.sort();
    out
}

/// Largest distance (Å) of a ring's atoms from their best plane (the
/// plane through the centroid normal to the smallest spread).
pub fn ring_deviation(ring: &[u32], pos: &[Vec3]) -> f32 {
    let pts: Vec<Vec3> = ring.iter().map(|&i| pos[i as usize]).collect();
    let c = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
    // Normal from the sum of cross products of consecutive atoms (Newell),
    // exact for a planar polygon and a good estimate otherwise.
    let mut normal = Vec3::ZERO;
    for i in 0..pts.len() {
        let (p, q) = (pts[i] - c, pts[(i + 1) % pts.len()] - c);
        normal += p.cross(q);
    }
    let Some(nrm) = normal.try_normalize() else {
        return f32::INFINITY;
    };
    pts.iter()
        .map(|p| (*p - c).dot(nrm).abs())
        .fold(0.0, f32::max)
}

#[cfg(test)]
mod tests {
    use super::super::Bond;
    use super::*;
    use crate::model::BondOrder;

    #[test]
    fn bridges_and_rings() {
        // A six-ring (0..6) with a tail 5-6-7.
        let mut bonds: Vec<Bond> = (0..6)
            .map(|i| Bond::new(i, (i + 1) % 6, BondOrder::Single))
            .collect();
        bonds.push(Bond::new(5, 6, BondOrder::Single));
        bonds.push(Bond::new(6, 7, BondOrder::Single));
        let adj = Adjacency::new(8, &bonds);
        let r = ring_bonds(&adj, bonds.len());
        assert_eq!(r, vec![true, true, true, true, true, true, false, false]);
        let rings = smallest_rings(&adj, &bonds, &r, &|_| true);
        assert_eq!(rings.len(), 1);
        assert_eq!(rings[0].len(), 6);
    }
}
