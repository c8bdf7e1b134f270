//! Which atoms of a molecule are bonded, and the orders the file or a
//! residue template states.
//!
//! Sources, in order of trust:
//! 1. A file that states every bond with its order (an SDF bond block): its
//!    bonds and nothing else.
//! 2. Standard residues ([`super::templates`]): the template's bonds between
//!    the atoms present, with orders; the peptide C–N and phosphodiester
//!    O3'–P links to the next residue of the same chain when the two atoms
//!    are at most [`MAX_LINK`] apart (so chain breaks stay broken);
//!    disulfides between cysteine SG atoms at most [`MAX_DISULFIDE`] apart.
//! 3. Bonds the file states without orders (PDB `CONECT`, mmCIF
//!    `struct_conn`), except to metals.
//! 4. Distances, for every atom of a residue no template covers (ligands,
//!    cofactors, modified residues) and the template residues' atoms the
//!    template does not name: two atoms are bonded when they are between
//!    [`MIN_BOND_LENGTH`] and the sum of their covalent radii plus
//!    [`BOND_TOLERANCE`] apart. A spatial grid keeps this linear in the
//!    atom count. Metals get no perceived bonds (coordination is not a
//!    covalent bond, and it must not take a hydrogen's place in valence).
//!    An atom left with more perceived bonds than its element allows loses
//!    the longest.

use glam::Vec3;

use super::elements::{BOND_TOLERANCE, MIN_BOND_LENGTH, covalent_radius, is_metal};
use super::grid::NeighbourGrid;
use super::templates::{PolymerKind, Template, canonical_name, template};
use super::{Bond, Warnings};
use crate::model::{AtomInfo, BondOrder, Molecule};

/// Longest peptide or phosphodiester link accepted between consecutive
/// residues (Å); a real one is 1.33 or 1.61 Å.
pub const MAX_LINK: f32 = 2.0;

/// Longest disulfide accepted (Å); a real one is 2.05 Å.
pub const MAX_DISULFIDE: f32 = 2.5;

/// The bonds of a molecule with what is known of their orders.
#[derive(Debug, Clone)]
pub(crate) struct Connection {
    /// Bonds, each pair once with `a < b`, sorted. Orders are `Unspecified`
    /// where neither the file nor a template states them.
    pub bonds: Vec<Bond>,
    /// Per atom: its bonds' orders are stated (file or template), so
    /// geometry need not guess them.
    pub ordered: Vec<bool>,
    /// Per atom: in an aromatic ring of its residue template.
    pub template_aromatic: Vec<bool>,
    /// Per atom: the formal charge (file or template).
    pub charges: Vec<i8>,
    /// Per atom: its residue (index into `templates`).
    pub residue_of: Vec<u32>,
    /// Per residue: the template that covers it.
    pub templates: Vec<Option<&'static Template>>,
    /// Per atom: how many metal atoms an N or O is bonded to by distance
    /// (as Open Babel bonds them); bump keeps metals out of `bonds`, but a
    /// metal takes the place of a hydrogen and of a lone pair.
    pub metal_bonds: Vec<u8>,
}

/// Residues as ranges of consecutive atoms with the same chain, number,
/// insertion code and name.
pub(crate) fn residue_ranges(atoms: &[AtomInfo]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut start = 0usize;
    let same = |a: &AtomInfo, b: &AtomInfo| {
        a.seq == b.seq && a.chain == b.chain && a.insertion == b.insertion && a.residue == b.residue
    };
    for i in 1..=atoms.len() {
        if i == atoms.len() || !same(&atoms[i], &atoms[start]) {
            out.push((idx(start), idx(i)));
            start = i;
        }
    }
    out
}

/// An index as u32 (molecules hold far fewer than 2^32 atoms).
pub(crate) fn idx(i: usize) -> u32 {
    u32::try_from(i).unwrap_or(u32::MAX)
}

/// For a histidine with hydrogens in the file, the tautomer they show.
fn histidine_from_hydrogens(
    t: &'static Template,
    names: &[std::borrow::Cow<'_, str>],
    s: u32,
    explicit_h: &[Option<u8>],
) -> &'static Template {
    if !t.has_atom("NE2") || !t.aromatic.contains(&"ND1") {
        return t;
    }
    let h_on = |name: &str| {
        names
            .iter()
            .position(|nm| nm == name)
            .and_then(|k| explicit_h[s as usize + k])
            .is_some_and(|h| h > 0)
    };
    match (h_on("ND1"), h_on("NE2")) {
        (true, true) => template("HIP").unwrap_or(t),
        (false, true) => template("HIE").unwrap_or(t),
        (true, false) => template("HID").unwrap_or(t),
        (false, false) => t,
    }
}

/// Connects `mol`'s heavy atoms. `explicit_h[i]` is the number of the
/// file's hydrogens on atom `i` when its residue has any.
pub(crate) fn connect(
    mol: &Molecule,
    explicit_h: &[Option<u8>],
    warn: &mut Warnings,
) -> Connection {
    let n = mol.len();
    let atoms = &mol.atoms;
    let residues = residue_ranges(atoms);
    let mut residue_of = vec![0u32; n];
    for (r, &(s, e)) in residues.iter().enumerate() {
        for slot in &mut residue_of[s as usize..e as usize] {
            *slot = idx(r);
        }
    }
    let mut charges = if mol.formal_charges.len() == n {
        mol.formal_charges.clone()
    } else {
        vec![0; n]
    };
    let mut ordered = vec![false; n];
    let mut template_aromatic = vec![false; n];
    let mut templates: Vec<Option<&'static Template>> = vec![None; residues.len()];
    let mut bonds: Vec<Bond> = Vec::new();
    let metal_bonds = metal_bonds(mol);

    if mol.bonds_complete {
        bonds.extend(mol.file_bonds.iter().copied());
        ordered.iter_mut().for_each(|o| *o = true);
        return finish(
            bonds,
            metal_bonds,
            ordered,
            template_aromatic,
            charges,
            residue_of,
            templates,
        );
    }

    // Template residues; not in a PDBQT ligand, whose torsion tree orders
    // its atoms (a residue's atoms need not be together) and whose residue
    // names Open Babel gives to look-alikes (a phenylalaninol as PHE).
    let tree = mol.autodock.as_ref().is_some_and(|ad| ad.tree);
    let mut perceive = vec![true; n];
    for (r, &(s, e)) in residues.iter().enumerate() {
        let Some(t) = template(&atoms[s as usize].residue).filter(|_| !tree) else {
            continue;
        };
        let t: &'static Template = t;
        // Not for a hetero group that merely shares a name (a free "A"
        // ligand would be odd, but a residue with no backbone is not a
        // polymer residue): the template must name most of its atoms.
        let names: Vec<std::borrow::Cow<'_, str>> = (s..e)
            .map(|i| canonical_name(&atoms[i as usize].name))
            .collect();
        let named = names.iter().filter(|nm| t.has_atom(nm)).count();
        if named * 2 < names.len() || named == 0 {
            continue;
        }
        let t = histidine_from_hydrogens(t, &names, s, explicit_h);
        templates[r] = Some(t);
        for (k, nm) in names.iter().enumerate() {
            let i = s as usize + k;
            if t.has_atom(nm) {
                perceive[i] = false;
                ordered[i] = true;
                template_aromatic[i] = t.aromatic.contains(&nm.as_ref());
                if charges[i] == 0 {
                    charges[i] = t.charge(nm);
                }
            }
        }
        let first = bonds.len();
        for (x, y, order) in t.bonds {
            let find = |name: &str| names.iter().position(|nm| nm == name);
            if let (Some(p), Some(q)) = (find(x), find(y)) {
                bonds.push(Bond::new(s + idx(p), s + idx(q), order_of(*order)));
            }
        }
        for &(c, o1, o2) in acid_groups(t.kind, atoms[s as usize].residue.trim()) {
            let find = |name: &str| names.iter().position(|nm| nm == name).map(|k| s + idx(k));
            if let (Some(c), Some(o1), Some(o2)) = (find(c), find(o1), find(o2)) {
                place_acid_hydrogen(
                    mol,
                    explicit_h,
                    &charges,
                    &metal_bonds,
                    &mut bonds[first..],
                    (c, o1, o2),
                );
            }
        }
    }

    // Links between consecutive template residues of a chain.
    for r in 1..residues.len() {
        let (Some(prev), Some(next)) = (templates[r - 1], templates[r]) else {
            continue;
        };
        let (ps, pe) = residues[r - 1];
        let (ns, ne) = residues[r];
        if atoms[ps as usize].chain != atoms[ns as usize].chain || prev.kind != next.kind {
            continue;
        }
        let (from, to) = match prev.kind {
            PolymerKind::Peptide => ("C", "N"),
            PolymerKind::Nucleic => ("O3'", "P"),
        };
        let find = |s: u32, e: u32, name: &str| {
            (s..e).find(|&i| canonical_name(&atoms[i as usize].name) == name)
        };
        if let (Some(a), Some(b)) = (find(ps, pe, from), find(ns, ne, to))
            && mol.local[a as usize].distance(mol.local[b as usize]) <= MAX_LINK
        {
            bonds.push(Bond::new(a, b, BondOrder::Single));
        }
    }

    // Disulfides.
    let sulfurs: Vec<u32> = (0..n)
        .filter(|&i| {
            !perceive[i] && atoms[i].element == "S" && canonical_name(&atoms[i].name) == "SG"
        })
        .map(idx)
        .collect();
    if sulfurs.len() > 1 {
        let pts: Vec<Vec3> = sulfurs.iter().map(|&i| mol.local[i as usize]).collect();
        let grid = NeighbourGrid::new(&pts, MAX_DISULFIDE);
        for (k, &i) in sulfurs.iter().enumerate() {
            grid.for_each_near(pts[k], |j| {
                let j = j as usize;
                if j > k && pts[k].distance(pts[j]) <= MAX_DISULFIDE {
                    bonds.push(Bond::new(i, sulfurs[j], BondOrder::Single));
                }
            });
        }
    }

    // Bonds the file states (CONECT, struct_conn), except to metals.
    for b in &mol.file_bonds {
        let (a, c) = (b.a as usize, b.b as usize);
        if a < n && c < n && !is_metal(&atoms[a].element) && !is_metal(&atoms[c].element) {
            bonds.push(*b);
        }
    }

    // Distances, for atoms no template covers.
    perceive_by_distance(mol, &perceive, &mut bonds, warn);

    finish(
        bonds,
        metal_bonds,
        ordered,
        template_aromatic,
        charges,
        residue_of,
        templates,
    )
}

/// The acid groups (carbon or phosphorus, oxygen, oxygen) of a template
/// residue whose protonation the residue's name leaves open: Asp's and
/// Glu's side chains, every amino acid's C terminus and every nucleotide's
/// phosphate.
fn acid_groups(
    kind: PolymerKind,
    residue: &str,
) -> &'static [(&'static str, &'static str, &'static str)] {
    match (kind, residue) {
        (PolymerKind::Peptide, "ASP") => &[("CG", "OD1", "OD2"), ("C", "O", "OXT")],
        (PolymerKind::Peptide, "GLU") => &[("CD", "OE1", "OE2"), ("C", "O", "OXT")],
        (PolymerKind::Peptide, _) => &[("C", "O", "OXT")],
        (PolymerKind::Nucleic, _) => &[("P", "OP1", "OP2")],
    }
}

/// Chooses which oxygen of a neutral carboxylic or phosphoric acid carries
/// the hydrogen, by setting the orders of its two bonds to the central atom
/// among `bonds`.
///
/// An oxygen with a hydrogen in the file, bonded to a metal (which takes
/// the hydrogen's place) or given a negative charge by the file (an anion's
/// oxygen, which then has no hydrogen) takes the single bond. Otherwise the choice is
/// Open Babel's when it adds hydrogens to a PDB file (the preparation of
/// AutoDock Vina's usual receptors): its distance bonding adds each atom's
/// bonds in order of the partner's z coordinate and its functional-group
/// typer makes the first oxygen found the carbonyl, so the oxygen with the
/// larger z carries the hydrogen. In a crystal structure the two bonds are
/// the same within error, so geometry cannot choose better.
fn place_acid_hydrogen(
    mol: &Molecule,
    explicit_h: &[Option<u8>],
    charges: &[i8],
    metal_bonds: &[u8],
    bonds: &mut [Bond],
    (c, o1, o2): (u32, u32, u32),
) {
    // A hydrogen, a metal or a negative charge (a carboxylate written
    // `1-`) takes the single bond.
    let has_h = |o: u32| {
        explicit_h[o as usize].is_some_and(|h| h > 0)
            || metal_bonds[o as usize] > 0
            || charges[o as usize] < 0
    };
    let z = |o: u32| mol.file_position(o as usize).z;
    let hydroxyl = match (has_h(o1), has_h(o2)) {
        (true, false) => o1,
        (false, true) => o2,
        (true, true) => return,
        (false, false) if z(o1) > z(o2) => o1,
        (false, false) if z(o2) > z(o1) => o2,
        (false, false) => return,
    };
    for b in bonds.iter_mut() {
        let other = match (b.a == c, b.b == c) {
            (true, _) => b.b,
            (_, true) => b.a,
            _ => continue,
        };
        if other == o1 || other == o2 {
            b.order = if other == hydroxyl {
                BondOrder::Single
            } else {
                BondOrder::Double
            };
        }
    }
}

/// Sorts and deduplicates `bonds` (a pair stated twice keeps its stated
/// order over an unspecified one) and builds the [`Connection`].
fn finish(
    mut bonds: Vec<Bond>,
    metal_bonds: Vec<u8>,
    ordered: Vec<bool>,
    template_aromatic: Vec<bool>,
    charges: Vec<i8>,
    residue_of: Vec<u32>,
    templates: Vec<Option<&'static Template>>,
) -> Connection {
    bonds.retain(|b| b.a != b.b);
    bonds.sort_unstable_by_key(|b| (b.a, b.b, b.order == BondOrder::Unspecified));
    bonds.dedup_by_key(|b| (b.a, b.b));
    Connection {
        bonds,
        ordered,
        template_aromatic,
        charges,
        residue_of,
        templates,
        metal_bonds,
    }
}

/// Per atom, the metal atoms an N or O lies within bonding distance of
/// (covalent radii + [`BOND_TOLERANCE`]): a zinc's histidines and
/// carboxylates, a heme's nitrogens.
fn metal_bonds(mol: &Molecule) -> Vec<u8> {
    let atoms = &mol.atoms;
    let mut out = vec![0u8; atoms.len()];
    let metals: Vec<usize> = (0..atoms.len())
        .filter(|&i| is_metal(&atoms[i].element))
        .collect();
    if metals.is_empty() {
        return out;
    }
    let ligating = |i: usize| matches!(atoms[i].element.as_str(), "N" | "O");
    let candidates: Vec<usize> = (0..atoms.len()).filter(|&i| ligating(i)).collect();
    let points: Vec<Vec3> = candidates.iter().map(|&i| mol.local[i]).collect();
    let reach = 2.0 * MAX_COVALENT + BOND_TOLERANCE as f32;
    let grid = NeighbourGrid::new(&points, reach);
    for &m in &metals {
        // A metal without a tabulated radius (a lanthanide) as a large one.
        let rm = covalent_radius(&atoms[m].element).unwrap_or(1.8);
        grid.for_each_near(mol.local[m], |k| {
            let i = candidates[k as usize];
            let ri = covalent_radius(&atoms[i].element).unwrap_or(0.7);
            let d = mol.local[m].distance(mol.local[i]);
            if d >= MIN_BOND_LENGTH as f32 && d <= (rm + ri + BOND_TOLERANCE) as f32 {
                out[i] = out[i].saturating_add(1);
            }
        });
    }
    out
}

/// The largest covalent radius of a metal or a ligating atom (Å): the
/// metal bonds' search reach.
const MAX_COVALENT: f32 = 2.03;

/// The bond order of a template's digit.
fn order_of(order: u8) -> BondOrder {
    match order {
        2 => BondOrder::Double,
        3 => BondOrder::Triple,
        _ => BondOrder::Single,
    }
}

/// Most bonds an element takes (perceived bonds beyond it are dropped,
/// longest first).
fn max_bonds(element: &str) -> usize {
    match element {
        "H" | "D" | "F" | "Cl" | "Br" | "I" | "At" => 1,
        "O" => 2,
        "B" | "N" => 4,
        "C" | "Si" => 4,
        "P" | "As" => 5,
        _ => 6,
    }
}

/// Adds the bonds perceived from distances for every atom with
/// `perceive[i]` set, to any other atom of the molecule (a template atom
/// only across residues or to an atom its template does not name).
fn perceive_by_distance(
    mol: &Molecule,
    perceive: &[bool],
    bonds: &mut Vec<Bond>,
    warn: &mut Warnings,
) {
    let atoms = &mol.atoms;
    if !perceive.iter().any(|&p| p) {
        return;
    }
    let radius: Vec<Option<f32>> = atoms
        .iter()
        .map(|a| {
            if is_metal(&a.element) {
                None
            } else {
                covalent_radius(&a.element).map(|r| r as f32)
            }
        })
        .collect();
    let max_r = radius.iter().flatten().fold(0.0f32, |m, &r| m.max(r));
    let cutoff = 2.0 * max_r + BOND_TOLERANCE as f32;
    // Only the atoms that can bond go into the grid.
    let members: Vec<u32> = (0..atoms.len())
        .filter(|&i| radius[i].is_some())
        .map(idx)
        .collect();
    let pts: Vec<Vec3> = members.iter().map(|&i| mol.local[i as usize]).collect();
    let grid = NeighbourGrid::new(&pts, cutoff);
    let mut found: Vec<(u32, u32, f32)> = Vec::new();
    for (k, &i) in members.iter().enumerate() {
        if !perceive[i as usize] {
            continue;
        }
        let ri = radius[i as usize].unwrap_or(0.0);
        grid.for_each_near(pts[k], |m| {
            let j = members[m as usize];
            // Each perceived pair once: from its lower index, or from the
            // perceived side when only one side is.
            if j == i || (perceive[j as usize] && j < i) {
                return;
            }
            let rj = radius[j as usize].unwrap_or(0.0);
            let d = pts[k].distance(pts[m as usize]);
            if d >= MIN_BOND_LENGTH as f32 && d <= ri + rj + BOND_TOLERANCE as f32 {
                found.push((i.min(j), i.max(j), d));
            }
        });
    }
    if found.is_empty() {
        return;
    }
    // Cap valences: drop an over-bonded atom's longest perceived bonds. A
    // pair already bonded (by a template or the file's CONECT records) is
    // that bond, not another one.
    let mut known: Vec<(u32, u32)> = bonds.iter().map(|b| (b.a.min(b.b), b.a.max(b.b))).collect();
    known.sort_unstable();
    known.dedup();
    let mut count = vec![0usize; atoms.len()];
    for &(a, b) in &known {
        count[a as usize] += 1;
        count[b as usize] += 1;
    }
    found.retain(|&(a, b, _)| known.binary_search(&(a, b)).is_err());
    found.sort_by(|x, y| x.2.total_cmp(&y.2).then((x.0, x.1).cmp(&(y.0, y.1))));
    for (a, b, d) in found {
        let (ea, eb) = (&atoms[a as usize].element, &atoms[b as usize].element);
        if count[a as usize] >= max_bonds(ea) || count[b as usize] >= max_bonds(eb) {
            let (who, el) = if count[a as usize] >= max_bonds(ea) {
                (a, ea)
            } else {
                (b, eb)
            };
            warn.atom(
                mol,
                who as usize,
                format!(
                    "a {el} atom with more close neighbours than it can bond; \
                     the {d:.2} Å contact is not read as a bond"
                ),
            );
            continue;
        }
        count[a as usize] += 1;
        count[b as usize] += 1;
        bonds.push(Bond::new(a, b, BondOrder::Unspecified));
    }
}
