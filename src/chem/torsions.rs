//! Rotatable bonds, the torsion tree, Vina's torsion count and the atom
//! pairs Vina scores within a molecule.
//!
//! A bond is rotatable as Open Babel's PDBQT writer decides
//! (`IsRotBond_PDBQT`), which is what AutoDock Vina's inputs hold: a single
//! bond, not aromatic, not in a ring, not an amide C–N (the N with three
//! neighbours counting hydrogens, the C bonded to =O) or amidine C–N (the C
//! bonded to =N), and each of its atoms has another neighbour once non-polar
//! hydrogens are removed (so –OH and –NH2 rotate, a methyl does not).
//!
//! Cutting the rotatable bonds splits the molecule into rigid fragments,
//! the nodes of the tree. The root is the fragment of the atom whose
//! removal leaves the smallest largest piece (Open Babel's choice, found in
//! linear time from a depth-first search's articulation points); children
//! hang from their parent by one rotatable bond each, in depth-first order.
//! Fragments of other disconnected pieces are roots of their own.
//!
//! Vina's torsion count gives each rotatable bond ½ for each of its atoms
//! whose partner has more than one heavy neighbour (`atom_rotors`): 1 for a
//! bond between two inner atoms, ½ for one to a terminal –OH or –NH2.

use serde::Serialize;

use super::Bond;
use super::graph::Adjacency;
use super::typing::Hydro;
use crate::model::{BondOrder, Molecule};

/// A rotatable bond of the torsion tree.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RotatableBond {
    /// Index of the bond in [`super::Chemistry::bonds`].
    pub bond: u32,
    /// The axis atom in the parent fragment.
    pub parent_atom: u32,
    /// The axis atom in the child fragment (it stays on the axis).
    pub child_atom: u32,
    /// The parent node.
    pub parent_node: u32,
    /// The child node (it and its descendants move when the bond turns).
    pub child_node: u32,
    /// The bond's share of Vina's torsion count: 0, ½ or 1.
    pub vina_weight: f64,
}

/// A rigid fragment: a node of the torsion tree.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TorsionNode {
    /// Heavy atoms, ascending.
    pub atoms: Vec<u32>,
    /// Kept hydrogens ([`Molecule::hydrogens`] indices), ascending.
    pub hydrogens: Vec<u32>,
    /// The parent node; `None` for a root.
    pub parent: Option<u32>,
    /// The rotatable bond ([`TorsionTree::bonds`] index) joining this node
    /// to its parent.
    pub bond: Option<u32>,
    /// Child nodes in depth-first order.
    pub children: Vec<u32>,
}

/// The torsion tree of a molecule.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct TorsionTree {
    /// Nodes: `nodes[0]` is the root (when the molecule has atoms), then
    /// depth first; a disconnected piece starts a new root.
    pub nodes: Vec<TorsionNode>,
    /// Rotatable bonds, in the order their child nodes were made.
    pub bonds: Vec<RotatableBond>,
    /// Per heavy atom: its node.
    pub node_of_atom: Vec<u32>,
    /// Per kept hydrogen: its node.
    pub node_of_hydrogen: Vec<u32>,
    /// The atom Open Babel would pick as the root.
    pub root_atom: u32,
    /// Vina's torsion count `N_tors`.
    pub vina_count: f64,
}

/// True when bond `k` is rotatable (see the module docs).
fn rotatable(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    in_ring: &[bool],
    aromatic: &[bool],
    hydro: &Hydro,
    k: usize,
) -> bool {
    let b = bonds[k];
    if b.order != BondOrder::Single || in_ring[k] || aromatic[k] {
        return false;
    }
    let elem = |i: u32| mol.atoms[i as usize].element.as_str();
    // Heavy neighbours and polar hydrogens, whether the hydrogens are kept
    // apart or loaded as atoms: a methyl's kept hydrogens do not count.
    let explicit_degree = |i: u32| {
        let i = i as usize;
        let polar_atoms = if matches!(mol.atoms[i].element.as_str(), "N" | "O" | "S" | "P") {
            usize::from(hydro.atom_h[i])
        } else {
            0
        };
        heavy_neighbours(mol, adj, i) + usize::from(hydro.polar(mol, i)) + polar_atoms
    };
    if explicit_degree(b.a) <= 1 || explicit_degree(b.b) <= 1 {
        return false;
    }
    // Amide and amidine C–N.
    let (c, n) = match (elem(b.a), elem(b.b)) {
        ("C", "N") => (b.a, b.b),
        ("N", "C") => (b.b, b.a),
        _ => return true,
    };
    let total_degree = adj.degree(n as usize) + usize::from(hydro.count[n as usize]);
    if total_degree != 3 {
        return true;
    }
    let conjugated = adj.of(c as usize).iter().any(|&(j, kk)| {
        bonds[kk as usize].order == BondOrder::Double && matches!(elem(j), "O" | "N")
    });
    !conjugated
}

/// The neighbours of atom `i` that are not hydrogens.
pub(crate) fn heavy_neighbours(mol: &Molecule, adj: &Adjacency, i: usize) -> usize {
    adj.of(i)
        .iter()
        .filter(|&&(j, _)| {
            mol.atoms
                .get(j as usize)
                .is_some_and(|a| !crate::model::element::is_hydrogen(&a.element))
        })
        .count()
}

/// Builds the torsion tree: the rotatable bonds are `given` (per bond, as a
/// PDBQT's tree states them) or perceived by the rule of the module docs.
pub(crate) fn build(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    in_ring: &[bool],
    aromatic: &[bool],
    hydro: &Hydro,
    given: Option<Vec<bool>>,
) -> TorsionTree {
    let n = mol.len();
    let rot: Vec<bool> = given.unwrap_or_else(|| {
        (0..bonds.len())
            .map(|k| rotatable(mol, bonds, adj, in_ring, aromatic, hydro, k))
            .collect()
    });
    // Fragments: components without the rotatable bonds.
    let mut frag = vec![u32::MAX; n];
    let mut frags: Vec<Vec<u32>> = Vec::new();
    for s in 0..n {
        if frag[s] != u32::MAX {
            continue;
        }
        let id = frags.len() as u32;
        let mut atoms = vec![s as u32];
        frag[s] = id;
        let mut head = 0;
        while head < atoms.len() {
            let v = atoms[head];
            head += 1;
            for &(w, k) in adj.of(v as usize) {
                if !rot[k as usize] && frag[w as usize] == u32::MAX {
                    frag[w as usize] = id;
                    atoms.push(w);
                }
            }
        }
        atoms.sort_unstable();
        frags.push(atoms);
    }
    let weight: Vec<u32> = (0..n).map(|i| 1 + u32::from(hydro.polar(mol, i))).collect();
    let root_atom = best_root(adj, &weight);

    // Depth-first over fragments from the root's, then from each piece left.
    let mut node_of_frag = vec![u32::MAX; frags.len()];
    let mut nodes: Vec<TorsionNode> = Vec::new();
    let mut tbonds: Vec<RotatableBond> = Vec::new();
    // Hydrogens loaded as atoms (`--hydrogens keep`) are not heavy
    // neighbours: Vina counts a hydroxyl's C–O as ½ either way.
    let heavy_degree = |i: u32| heavy_neighbours(mol, adj, i as usize);
    let mut starts: Vec<u32> = Vec::new();
    if n > 0 {
        starts.push(frag[root_atom as usize]);
    }
    starts.extend(0..frags.len() as u32);
    for start in starts {
        if node_of_frag[start as usize] != u32::MAX {
            continue;
        }
        node_of_frag[start as usize] = nodes.len() as u32;
        nodes.push(TorsionNode {
            atoms: frags[start as usize].clone(),
            hydrogens: Vec::new(),
            parent: None,
            bond: None,
            children: Vec::new(),
        });
        let mut stack = vec![nodes.len() as u32 - 1];
        while let Some(&cur) = stack.last() {
            // The first unvisited fragment bonded to this node, by lowest atom.
            let mut next: Option<(u32, u32, u32, u32)> = None; // (frag, parent atom, child atom, bond)
            for &a in &nodes[cur as usize].atoms {
                for &(w, k) in adj.of(a as usize) {
                    let f = frag[w as usize];
                    if rot[k as usize] && node_of_frag[f as usize] == u32::MAX {
                        let cand = (f, a, w, k);
                        if next.is_none_or(|x| frags[f as usize][0] < frags[x.0 as usize][0]) {
                            next = Some(cand);
                        }
                    }
                }
            }
            let Some((f, a, w, k)) = next else {
                stack.pop();
                continue;
            };
            let child = nodes.len() as u32;
            node_of_frag[f as usize] = child;
            let weight_of = |x: u32, y: u32| if heavy_degree(y) > 1 { 0.5 } else { 0.0 } + if heavy_degree(x) > 1 { 0.5 } else { 0.0 };
            tbonds.push(RotatableBond {
                bond: k,
                parent_atom: a,
                child_atom: w,
                parent_node: cur,
                child_node: child,
                vina_weight: weight_of(a, w),
            });
            nodes[cur as usize].children.push(child);
            nodes.push(TorsionNode {
                atoms: frags[f as usize].clone(),
                hydrogens: Vec::new(),
                parent: Some(cur),
                bond: Some(tbonds.len() as u32 - 1),
                children: Vec::new(),
            });
            stack.push(child);
        }
    }
    let node_of_atom: Vec<u32> = frag.iter().map(|&f| node_of_frag[f as usize]).collect();
    let node_of_hydrogen: Vec<u32> = mol
        .hydrogens
        .parent
        .iter()
        .map(|&p| node_of_atom.get(p as usize).copied().unwrap_or(0))
        .collect();
    for (h, &nd) in node_of_hydrogen.iter().enumerate() {
        if let Some(node) = nodes.get_mut(nd as usize) {
            node.hydrogens.push(h as u32);
        }
    }
    let vina_count = tbonds.iter().map(|b| b.vina_weight).sum();
    TorsionTree {
        nodes,
        bonds: tbonds,
        node_of_atom,
        node_of_hydrogen,
        root_atom,
        vina_count,
    }
}

/// The atom whose removal leaves the smallest largest piece (the first such
/// in atom order), weights counting each atom with its polar hydrogens.
/// Linear: one depth-first search per connected piece, with subtree
/// weights and low links.
fn best_root(adj: &Adjacency, weight: &[u32]) -> u32 {
    let n = adj.len();
    if n == 0 {
        return 0;
    }
    let mut disc = vec![u32::MAX; n];
    let mut low = vec![0u32; n];
    let mut sub = vec![0u64; n];
    // For each atom: total of pieces cut off by its removal, and the largest.
    let mut cut = vec![0u64; n];
    let mut largest = vec![0u64; n];
    let mut comp_of = vec![0u32; n];
    let mut comp_weight: Vec<u64> = Vec::new();
    let mut time = 0u32;
    for root in 0..n {
        if disc[root] != u32::MAX {
            continue;
        }
        let comp = comp_weight.len() as u32;
        let mut stack: Vec<(u32, usize)> = vec![(root as u32, 0)];
        disc[root] = time;
        low[root] = time;
        time += 1;
        sub[root] = u64::from(weight[root]);
        comp_of[root] = comp;
        let mut total = 0u64;
        while let Some(top) = stack.last_mut() {
            let (v, slot) = *top;
            let row = adj.of(v as usize);
            if slot < row.len() {
                top.1 += 1;
                let w = row[slot].0 as usize;
                if disc[w] == u32::MAX {
                    disc[w] = time;
                    low[w] = time;
                    time += 1;
                    sub[w] = u64::from(weight[w]);
                    comp_of[w] = comp;
                    stack.push((w as u32, 0));
                } else {
                    low[v as usize] = low[v as usize].min(disc[w]);
                }
            } else {
                stack.pop();
                total += u64::from(weight[v as usize]);
                if let Some(&(p, _)) = stack.last() {
                    let (p, v) = (p as usize, v as usize);
                    low[p] = low[p].min(low[v]);
                    sub[p] += sub[v];
                    if low[v] >= disc[p] {
                        cut[p] += sub[v];
                        largest[p] = largest[p].max(sub[v]);
                    }
                }
            }
        }
        comp_weight.push(total);
    }
    // Largest other piece for each component.
    let mut top2 = [(0u64, u32::MAX), (0u64, u32::MAX)];
    for (c, &w) in comp_weight.iter().enumerate() {
        if w > top2[0].0 {
            top2[1] = top2[0];
            top2[0] = (w, c as u32);
        } else if w > top2[1].0 {
            top2[1] = (w, c as u32);
        }
    }
    let mut best = (u64::MAX, 0u32);
    for v in 0..n {
        let c = comp_of[v];
        let rest = comp_weight[c as usize] - u64::from(weight[v]) - cut[v];
        let other = if top2[0].1 == c { top2[1].0 } else { top2[0].0 };
        let worst = largest[v].max(rest).max(other);
        if worst < best.0 {
            best = (worst, v as u32);
        }
    }
    best.1
}

impl TorsionTree {
    /// The rotatable bonds' count (branches of the tree).
    pub fn len(&self) -> usize {
        self.bonds.len()
    }

    /// True when nothing rotates.
    pub fn is_empty(&self) -> bool {
        self.bonds.is_empty()
    }

    /// The nodes that move when rotatable bond `k` turns with its parent
    /// side held: its child node and all that node's descendants.
    pub fn moving_nodes(&self, k: usize) -> Vec<u32> {
        let Some(b) = self.bonds.get(k) else {
            return Vec::new();
        };
        let mut out = vec![b.child_node];
        let mut head = 0;
        while head < out.len() {
            let nd = out[head] as usize;
            head += 1;
            out.extend(self.nodes[nd].children.iter().copied());
        }
        out.sort_unstable();
        out
    }

    /// The heavy atoms and kept hydrogens on each side of rotatable bond
    /// `k`: `(parent side, child side)`, each as (atoms, hydrogens),
    /// ascending. The child side is what moves with the parent side held.
    #[allow(clippy::type_complexity)]
    pub fn sides(&self, k: usize) -> ((Vec<u32>, Vec<u32>), (Vec<u32>, Vec<u32>)) {
        let moving = self.moving_nodes(k);
        let mut child = (Vec::new(), Vec::new());
        let mut parent = (Vec::new(), Vec::new());
        let moves = |nd: u32| moving.binary_search(&nd).is_ok();
        for (i, &nd) in self.node_of_atom.iter().enumerate() {
            if moves(nd) {
                child.0.push(i as u32)
            } else {
                parent.0.push(i as u32)
            }
        }
        for (h, &nd) in self.node_of_hydrogen.iter().enumerate() {
            if moves(nd) {
                child.1.push(h as u32)
            } else {
                parent.1.push(h as u32)
            }
        }
        (parent, child)
    }

    /// The smaller side of rotatable bond `k` (fewer heavy atoms; the
    /// child side on a tie): `(atoms, hydrogens, true when it is the child side)`.
    pub fn smaller_side(&self, k: usize) -> (Vec<u32>, Vec<u32>, bool) {
        let (parent, child) = self.sides(k);
        if parent.0.len() < child.0.len() {
            (parent.0, parent.1, false)
        } else {
            (child.0, child.1, true)
        }
    }

    /// Pairs of heavy atoms AutoDock Vina scores within the molecule
    /// (`model::initialize_pairs`): atoms that can move relative to each
    /// other — not in one fragment, and neither is an axis atom of a
    /// rotatable bond whose other side holds the other atom — and more than
    /// three bonds apart, each with a Vina type (`types[i].is_some()`).
    /// `(i, j)` with `i < j`, sorted. Quadratic in the atom count: for
    /// drugs.
    pub fn vina_pairs<T>(&self, adj: &Adjacency, types: &[Option<T>]) -> Vec<(u32, u32)> {
        self.pairs_apart(adj, types, |node| node)
    }

    /// The pairs of heavy atoms more than three bonds apart whose distance
    /// the torsions change: Vina's pairs ([`Self::vina_pairs`]) with every
    /// root taken as one rigid piece. Pieces of the molecule that no bond
    /// joins (a metal among its ligand atoms, as heme's iron) are roots of
    /// their own, and the roots move only with the pose, all together: no
    /// turn changes the distance between two of their atoms, while one of
    /// a root and one of a turned branch move relative to each other.
    /// `(i, j)` with `i < j`, sorted.
    pub fn movable_pairs(&self, adj: &Adjacency) -> Vec<(u32, u32)> {
        // Roots are 0 and the nodes without a parent: all become node 0.
        let root = |node: u32| {
            if self.nodes[node as usize].parent.is_none() {
                0
            } else {
                node
            }
        };
        let all = vec![Some(()); self.node_of_atom.len()];
        self.pairs_apart(adj, &all, root)
    }

    /// The pairs more than three bonds apart, each with a type, that share
    /// no fixed set (see [`Self::vina_pairs`]), nodes named by `node`.
    fn pairs_apart<T>(
        &self,
        adj: &Adjacency,
        types: &[Option<T>],
        node: impl Fn(u32) -> u32,
    ) -> Vec<(u32, u32)> {
        let n = self.node_of_atom.len();
        // Each atom's fixed sets: its node, and for each rotatable bond at
        // it the node across the bond.
        let mut across: Vec<Vec<u32>> = vec![Vec::new(); n];
        for b in &self.bonds {
            across[b.parent_atom as usize].push(node(b.child_node));
            across[b.child_atom as usize].push(node(b.parent_node));
        }
        let sets: Vec<Vec<u32>> = (0..n)
            .map(|i| {
                let mut s = vec![node(self.node_of_atom[i])];
                s.extend(&across[i]);
                s
            })
            .collect();
        let near = within_three_bonds(adj);
        let mut out = Vec::new();
        for i in 0..n {
            if types.get(i).is_none_or(Option::is_none) {
                continue;
            }
            for j in i + 1..n {
                if types.get(j).is_none_or(Option::is_none) {
                    continue;
                }
                if sets[i].iter().any(|s| sets[j].contains(s)) {
                    continue;
                }
                if near[i].binary_search(&(j as u32)).is_ok() {
                    continue;
                }
                out.push((i as u32, j as u32));
            }
        }
        out
    }
}

/// For each atom, the atoms within three bonds of it (itself excluded),
/// ascending.
pub fn within_three_bonds(adj: &Adjacency) -> Vec<Vec<u32>> {
    (0..adj.len())
        .map(|i| {
            let mut seen = vec![i as u32];
            let mut frontier = vec![i as u32];
            for _ in 0..3 {
                let mut next = Vec::new();
                for &v in &frontier {
                    for &(w, _) in adj.of(v as usize) {
                        if !seen.contains(&w) {
                            seen.push(w);
                            next.push(w);
                        }
                    }
                }
                frontier = next;
            }
            seen.retain(|&w| w != i as u32);
            seen.sort_unstable();
            seen
        })
        .collect()
}

/// Pairs of heavy atoms more than three bonds apart (or in different
/// pieces), `(i, j)` with `i < j`, sorted: the pairs an internal collision
/// check of a flexible drug tests. Quadratic in the atom count.
pub fn pairs_beyond_three_bonds(adj: &Adjacency) -> Vec<(u32, u32)> {
    let near = within_three_bonds(adj);
    let n = adj.len();
    let mut out = Vec::new();
    for (i, close) in near.iter().enumerate() {
        for j in i + 1..n {
            if close.binary_search(&(j as u32)).is_err() {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}
