//! Gasteiger–Marsili partial charges as Open Babel 3.1 computes them
//! (`molchrg.cpp`), which is what AutoDock's preparation writes into a
//! PDBQT file.
//!
//! Every atom, hydrogens included (the file's, or those its valence
//! implies), gets (a, b, c) from its element and hybridisation (Open
//! Babel's table; the sp2 nitrogen's pair depends on whether Open Babel
//! types it `Npl`/`Nam` — amide, aniline — or otherwise — aromatic, imine,
//! amidinium); charges start at zero (formal charges are not used, as Open
//! Babel's `--partialcharge gasteiger` does not), and six rounds with
//! damping ½, ¼, … move charge along every bond from the less to the more
//! electronegative atom: `Δ = (χ_s − χ_t) / D`, D being the receiving-side
//! atom's a + b + c, or 20.02 for a hydrogen, with χ = a + b q + c q²
//! frozen for the round. Non-polar hydrogens (on carbon) are then merged
//! into their carbon, as AutoDock's PDBQT writer does.
//!
//! Open Babel gives up on a whole molecule when one atom has no parameters
//! (a metal, boron, selenium); here only that atom's connected piece gets
//! zero charges (a metal ion is a piece of its own), with a warning naming
//! the element.

use std::collections::BTreeMap;

use super::graph::Adjacency;
use super::typing::{Hybridisation, Hydro};
use super::{Bond, Warnings};
use crate::model::{BondOrder, Molecule};

/// Damping per round.
const DAMP: f64 = 0.5;
/// Rounds.
const ITERATIONS: usize = 6;
/// Denominator for a hydrogen.
const HYDROGEN_DENOM: f64 = 20.02;

/// The charges of a molecule.
#[derive(Debug, Clone)]
pub(crate) struct Charges {
    /// Per heavy atom, its non-polar hydrogens merged.
    pub heavy: Vec<f32>,
    /// Per heavy atom, the sum of its polar hydrogens' charges.
    pub polar_h: Vec<f32>,
    /// Per kept hydrogen (0 for a non-polar one: merged into its carbon).
    pub kept_h: Vec<f32>,
}

/// (v0, v1, v2) of Open Babel's table, or `None` without parameters.
fn table(
    mol: &Molecule,
    i: usize,
    hyb: Hybridisation,
    degree: usize,
    charge: i8,
    npl_or_nam: bool,
    free_oxygens: usize,
) -> Option<[f64; 3]> {
    use Hybridisation::{Sp, Sp2, Sp3};
    Some(match (mol.atoms[i].element.as_str(), hyb) {
        ("C", Sp3) => [0.68, 7.98, 19.04],
        ("C", Sp2) => [0.98, 8.79, 19.62],
        ("C", Sp) => [1.67, 10.39, 20.57],
        ("N", Sp3) if degree == 4 || charge != 0 => [0.0, 0.0, 23.72],
        ("N", Sp3) => [2.08, 11.54, 23.72],
        ("N", Sp2) if npl_or_nam => [2.46, 12.32, 24.86],
        ("N", Sp2) => [2.57, 12.87, 24.87],
        ("N", Sp) => [3.71, 15.68, 27.11],
        ("O", Sp3) => [2.65, 14.18, 28.49],
        ("O", Sp2) => [3.75, 17.07, 31.33],
        ("F", _) => [3.12, 14.66, 30.82],
        ("P", _) => [1.62, 8.90, 18.10],
        ("S", _) if free_oxygens > 1 => [2.39, 12.00, 24.00],
        ("S", _) => [2.39, 10.14, 20.65],
        ("Cl", _) => [2.66, 11.00, 22.04],
        ("Br", _) => [2.77, 10.08, 19.71],
        ("I", _) => [2.90, 9.90, 18.82],
        ("Al", _) => [1.06, 5.47, 11.65],
        ("H" | "D", _) => HYDROGEN,
        _ => return None,
    })
}

/// Hydrogen's (v0, v1, v2).
const HYDROGEN: [f64; 3] = [0.37, 7.17, 12.85];

/// (a, b, c) from (v0, v1, v2).
fn abc(v: [f64; 3]) -> [f64; 3] {
    [v[1], (v[2] - v[0]) / 2.0, (v[2] + v[0]) / 2.0 - v[1]]
}

/// True when Open Babel types sp2 nitrogen `i` `Npl` or `Nam` (not `Nar`,
/// `N2`, `Ng+`, `Nox` or `Ntr`).
fn npl_or_nam(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    aromatic: &[bool],
    in_ring_atom: &[bool],
    hydro: &Hydro,
    i: usize,
) -> bool {
    let elem = |j: usize| mol.atoms[j].element.as_str();
    let total_degree = |j: usize| adj.degree(j) + usize::from(hydro.count[j]);
    if aromatic[i] {
        return false;
    }
    let row = adj.of(i);
    let terminal_o = row
        .iter()
        .filter(|&&(j, _)| elem(j as usize) == "O" && total_degree(j as usize) == 1)
        .count();
    if terminal_o >= 2 {
        return false; // Ntr
    }
    let single = |k: u32| matches!(bonds[k as usize].order, BondOrder::Single);
    let amide = row.iter().any(|&(c, k)| {
        single(k)
            && elem(c as usize) == "C"
            && adj.of(c as usize).iter().any(|&(o, kk)| {
                bonds[kk as usize].order == BondOrder::Double
                    && matches!(elem(o as usize), "O" | "S")
            })
    });
    if amide {
        return true; // Nam (only Ntr and Nar come after it)
    }
    if row
        .iter()
        .any(|&(_, k)| bonds[k as usize].order == BondOrder::Double)
    {
        return false; // N2
    }
    // Ng+: a non-ring N on a C that is double bonded to another non-ring N
    // and single bonded to a third (guanidine); or, with no hydrogens, two
    // terminal N on one C (amidine).
    let ring_free_n = |j: usize| elem(j) == "N" && !in_ring_atom[j];
    if !in_ring_atom[i] {
        for &(c, k) in row {
            let c = c as usize;
            if !single(k) || elem(c) != "C" {
                continue;
            }
            let others = adj.of(c);
            let double_n = others.iter().any(|&(j, kk)| {
                j as usize != i
                    && bonds[kk as usize].order == BondOrder::Double
                    && ring_free_n(j as usize)
            });
            let single_n = others
                .iter()
                .any(|&(j, kk)| j as usize != i && single(kk) && ring_free_n(j as usize));
            if double_n && single_n {
                return false;
            }
            if total_degree(i) == 1
                && others.iter().any(|&(j, kk)| {
                    j as usize != i
                        && bonds[kk as usize].order == BondOrder::Double
                        && elem(j as usize) == "N"
                        && total_degree(j as usize) == 1
                })
            {
                return false;
            }
        }
    }
    // Nox: an N with an O neighbour and another neighbour.
    if row
        .iter()
        .any(|&(j, k)| single(k) && elem(j as usize) == "O")
        && total_degree(i) >= 2
    {
        return false;
    }
    true
}

/// Gasteiger charges of `mol`.
pub(crate) fn charges(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    aromatic: &[bool],
    hyb: &[Hybridisation],
    hydro: &Hydro,
    warn: &mut Warnings,
) -> Charges {
    let (params, h_parent) = parameters(mol, bonds, adj, aromatic, hyb, hydro);
    let (piece, bad_piece) = pieces_without_parameters(mol, adj, &params, warn);
    let q = equalise(mol.len(), bonds, &params, &h_parent, &piece, &bad_piece);
    gather(mol, hydro, &h_parent, &q)
}

/// The parameters of each atom (`None` where the table has none), the
/// heavy atoms' first, then the implicit hydrogens, hydro.count[i] of them
/// per atom, each with its parent in the second list.
fn parameters(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    aromatic: &[bool],
    hyb: &[Hybridisation],
    hydro: &Hydro,
) -> (Vec<Option<[f64; 3]>>, Vec<u32>) {
    let n = mol.len();
    let elem = |j: usize| mol.atoms[j].element.as_str();
    let total_degree = |j: usize| adj.degree(j) + usize::from(hydro.count[j]);
    let in_ring_bond = super::rings::ring_bonds(adj, bonds.len());
    let mut in_ring_atom = vec![false; n];
    for (k, b) in bonds.iter().enumerate() {
        if in_ring_bond[k] {
            in_ring_atom[b.a as usize] = true;
            in_ring_atom[b.b as usize] = true;
        }
    }
    let mut params: Vec<Option<[f64; 3]>> = Vec::with_capacity(n * 2);
    for (i, &h) in hyb.iter().enumerate().take(n) {
        let free_oxygens = adj
            .of(i)
            .iter()
            .filter(|&&(j, _)| elem(j as usize) == "O" && adj.degree(j as usize) == 1)
            .count();
        let nn = elem(i) == "N"
            && h == Hybridisation::Sp2
            && npl_or_nam(mol, bonds, adj, aromatic, &in_ring_atom, hydro, i);
        params.push(
            table(
                mol,
                i,
                h,
                total_degree(i),
                hydro.charges[i],
                nn,
                free_oxygens,
            )
            .map(abc),
        );
    }
    let mut h_parent: Vec<u32> = Vec::new();
    for i in 0..n {
        for _ in 0..hydro.count[i] {
            h_parent.push(i as u32);
            params.push(Some(abc(HYDROGEN)));
        }
    }
    (params, h_parent)
}

/// Each heavy atom's piece (connected part) and, per piece, whether an
/// atom of it lacks parameters: such pieces get no charges, with a warning
/// per element.
fn pieces_without_parameters(
    mol: &Molecule,
    adj: &Adjacency,
    params: &[Option<[f64; 3]>],
    warn: &mut Warnings,
) -> (Vec<u32>, Vec<bool>) {
    let n = mol.len();
    let elem = |j: usize| mol.atoms[j].element.as_str();
    let mut piece = vec![u32::MAX; n];
    let mut bad_piece: Vec<bool> = Vec::new();
    let mut missing: BTreeMap<String, usize> = BTreeMap::new();
    for s in 0..n {
        if piece[s] != u32::MAX {
            continue;
        }
        let id = bad_piece.len() as u32;
        let mut bad = false;
        let mut queue = vec![s as u32];
        piece[s] = id;
        while let Some(v) = queue.pop() {
            if params[v as usize].is_none() {
                bad = true;
                *missing.entry(elem(v as usize).to_string()).or_default() += 1;
            }
            for &(w, _) in adj.of(v as usize) {
                if piece[w as usize] == u32::MAX {
                    piece[w as usize] = id;
                    queue.push(w);
                }
            }
        }
        bad_piece.push(bad);
    }
    for (e, count) in &missing {
        warn.general(format!(
            "{}: no Gasteiger parameters for {e} ({count} atom{}); \
             the piece{} holding {} get{} zero charges",
            mol.name,
            if *count == 1 { "" } else { "s" },
            if *count == 1 { "" } else { "s" },
            if *count == 1 { "it" } else { "them" },
            if *count == 1 { "s" } else { "" },
        ));
    }
    (piece, bad_piece)
}

/// The damped iterations of partial equalisation of orbital
/// electronegativity over the bonds (heavy, then to the `n` heavy atoms'
/// implicit hydrogens) of the pieces with parameters: the charge of every
/// atom of `params`, heavy atoms first.
fn equalise(
    n: usize,
    bonds: &[Bond],
    params: &[Option<[f64; 3]>],
    h_parent: &[u32],
    piece: &[u32],
    bad_piece: &[bool],
) -> Vec<f64> {
    let total = params.len();
    let mut q = vec![0.0f64; total];
    let mut chi = vec![0.0f64; total];
    let p: Vec<[f64; 3]> = params.iter().map(|x| x.unwrap_or([0.0; 3])).collect();
    let denom: Vec<f64> = p.iter().map(|v| v[0] + v[1] + v[2]).collect();
    let ok = |i: usize| {
        let heavy = if i < n { i } else { h_parent[i - n] as usize };
        !bad_piece[piece[heavy] as usize]
    };
    // Bonds as index pairs, heavy then hydrogen.
    let mut pairs: Vec<(usize, usize)> =
        bonds.iter().map(|b| (b.a as usize, b.b as usize)).collect();
    pairs.extend(
        h_parent
            .iter()
            .enumerate()
            .map(|(h, &par)| (par as usize, n + h)),
    );
    pairs.retain(|&(s, t)| ok(s) && ok(t));
    let mut alpha = 1.0;
    for _ in 0..ITERATIONS {
        alpha *= DAMP;
        for i in 0..total {
            chi[i] = (p[i][2] * q[i] + p[i][1]) * q[i] + p[i][0];
        }
        for &(s, t) in &pairs {
            let d = if chi[s] >= chi[t] {
                if t >= n { HYDROGEN_DENOM } else { denom[t] }
            } else if s >= n {
                HYDROGEN_DENOM
            } else {
                denom[s]
            };
            let delta = (chi[s] - chi[t]) / d;
            q[s] -= alpha * delta;
            q[t] += alpha * delta;
        }
    }
    q
}

/// The charges as the atom types use them: a carbon's implicit hydrogens
/// merged into it, a polar atom's kept apart, and the molecule's kept
/// hydrogens given their parent's first implicit slots' charges.
fn gather(mol: &Molecule, hydro: &Hydro, h_parent: &[u32], q: &[f64]) -> Charges {
    let n = mol.len();
    let elem = |j: usize| mol.atoms[j].element.as_str();
    let mut heavy: Vec<f32> = q[..n].iter().map(|&x| x as f32).collect();
    let mut polar_h = vec![0.0f32; n];
    // Kept hydrogens take the charges of their parent's first slots.
    let mut slot_start = vec![0usize; n + 1];
    for i in 0..n {
        slot_start[i + 1] = slot_start[i] + usize::from(hydro.count[i]);
    }
    for (h, &par) in h_parent.iter().enumerate() {
        let par = par as usize;
        let qh = q[n + h] as f32;
        if elem(par) == "C" {
            heavy[par] += qh;
        } else {
            polar_h[par] += qh;
        }
    }
    let mut used = vec![0usize; n];
    let kept_h = mol
        .hydrogens
        .parent
        .iter()
        .map(|&par| {
            let par = par as usize;
            if par >= n || elem(par) == "C" {
                return 0.0;
            }
            let k = used[par];
            used[par] += 1;
            if k < usize::from(hydro.count[par]) {
                q[n + slot_start[par] + k] as f32
            } else {
                0.0
            }
        })
        .collect();
    Charges {
        heavy,
        polar_h,
        kept_h,
    }
}
