//! Hydrogen counts, hybridisation and AutoDock Vina's atom types.
//!
//! Hydrogens: an atom gets the hydrogens its usual valence (after its
//! formal charge) leaves free, as Open Babel's
//! `AssignTypicalImplicitHydrogens` and RDKit do; where its residue has
//! hydrogens in the file, it has those, and more only where the valence
//! still wants them (as Open Babel's `-h` adds them: a carboxylate or a
//! histidine written without a hydrogen gets one). A nitrogen with four
//! bonds and no charge is read as a cation (+1); an atom beyond every
//! valence its element has is reported.
//!
//! Hybridisation follows Open Babel's `atomtyp.txt` (`INTHYB`): aromatic
//! or doubly bonded atoms are sp2, triply bonded (or cumulated) sp; a
//! nitrogen or oxygen singly bonded to a C, N or O that has a double,
//! triple or aromatic bond (an amide or aniline N, an ester or phenol O) is
//! sp2, as is a nitrogen on an aromatic atom.
//!
//! Vina's X-Score types (AutoDock Vina 1.2 `atom_constants.h`, and the
//! PDBQT types Open Babel writes): carbon is C_P when bonded to a heteroatom
//! (anything but C and H), else C_H; every oxygen is an acceptor; a
//! nitrogen is an acceptor unless it has four neighbours and is sp3, or
//! three and is sp2 (Open Babel's `IsHbondAcceptor`, neighbours counted
//! with its hydrogens); N and O are donors when they carry a hydrogen;
//! sulfur (and selenium, which Vina reads as sulfur) is S_P, phosphorus
//! P_P, halogens hydrophobic; metals are Met_D (always donors).

use serde::Serialize;

use super::connect::Connection;
use super::elements::{charged_valences, covalent_radius, is_metal, valences};
use super::graph::Adjacency;
use super::{Bond, Warnings};
use crate::model::{BondOrder, Molecule};

/// Vina's X-Score atom types (the first 19 of `atom_constants.h`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[allow(non_camel_case_types)]
pub enum XsType {
    /// Carbon bonded only to carbon and hydrogen (hydrophobic).
    C_H,
    /// Carbon bonded to a heteroatom.
    C_P,
    /// Nitrogen, neither donor nor acceptor.
    N_P,
    /// Nitrogen donor.
    N_D,
    /// Nitrogen acceptor.
    N_A,
    /// Nitrogen donor and acceptor.
    N_DA,
    /// Oxygen, neither donor nor acceptor.
    O_P,
    /// Oxygen donor.
    O_D,
    /// Oxygen acceptor.
    O_A,
    /// Oxygen donor and acceptor.
    O_DA,
    /// Sulfur.
    S_P,
    /// Phosphorus.
    P_P,
    /// Fluorine (hydrophobic).
    F_H,
    /// Chlorine (hydrophobic).
    Cl_H,
    /// Bromine (hydrophobic).
    Br_H,
    /// Iodine (hydrophobic).
    I_H,
    /// Silicon.
    Si,
    /// Astatine.
    At,
    /// Metal (a donor).
    Met_D,
}

impl XsType {
    /// Every type, in Vina's index order.
    pub const ALL: [XsType; 19] = [
        XsType::C_H,
        XsType::C_P,
        XsType::N_P,
        XsType::N_D,
        XsType::N_A,
        XsType::N_DA,
        XsType::O_P,
        XsType::O_D,
        XsType::O_A,
        XsType::O_DA,
        XsType::S_P,
        XsType::P_P,
        XsType::F_H,
        XsType::Cl_H,
        XsType::Br_H,
        XsType::I_H,
        XsType::Si,
        XsType::At,
        XsType::Met_D,
    ];

    /// Vina's index of the type (0 for C_H … 18 for Met_D).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The name Vina uses (`C_H`, `N_DA`, `Met_D`).
    pub fn name(self) -> &'static str {
        match self {
            XsType::C_H => "C_H",
            XsType::C_P => "C_P",
            XsType::N_P => "N_P",
            XsType::N_D => "N_D",
            XsType::N_A => "N_A",
            XsType::N_DA => "N_DA",
            XsType::O_P => "O_P",
            XsType::O_D => "O_D",
            XsType::O_A => "O_A",
            XsType::O_DA => "O_DA",
            XsType::S_P => "S_P",
            XsType::P_P => "P_P",
            XsType::F_H => "F_H",
            XsType::Cl_H => "Cl_H",
            XsType::Br_H => "Br_H",
            XsType::I_H => "I_H",
            XsType::Si => "Si",
            XsType::At => "At",
            XsType::Met_D => "Met_D",
        }
    }

    /// The type Vina names `name`.
    pub fn from_name(name: &str) -> Option<XsType> {
        XsType::ALL.into_iter().find(|t| t.name() == name)
    }

    /// True for hydrophobic types (C_H and the halogens).
    pub fn is_hydrophobic(self) -> bool {
        matches!(
            self,
            XsType::C_H | XsType::F_H | XsType::Cl_H | XsType::Br_H | XsType::I_H
        )
    }

    /// True for hydrogen-bond donors (N_D, N_DA, O_D, O_DA, Met_D).
    pub fn is_donor(self) -> bool {
        matches!(
            self,
            XsType::N_D | XsType::N_DA | XsType::O_D | XsType::O_DA | XsType::Met_D
        )
    }

    /// True for hydrogen-bond acceptors (N_A, N_DA, O_A, O_DA).
    pub fn is_acceptor(self) -> bool {
        matches!(
            self,
            XsType::N_A | XsType::N_DA | XsType::O_A | XsType::O_DA
        )
    }
}

/// Hybridisation as Open Babel assigns it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Hybridisation {
    /// Linear.
    Sp,
    /// Trigonal.
    Sp2,
    /// Tetrahedral (and anything else).
    Sp3,
}

/// Hydrogens and formal charges per heavy atom.
#[derive(Debug, Clone)]
pub(crate) struct Hydro {
    /// Hydrogens bonded to each atom that are not among the molecule's
    /// atoms (implicit, or the file's kept apart).
    pub count: Vec<u8>,
    /// Hydrogens bonded to each atom that are among the molecule's atoms
    /// (loaded with `--hydrogens keep`); its bonds already count them.
    pub atom_h: Vec<u8>,
    /// Formal charges (file, template or implied).
    pub charges: Vec<i8>,
    /// Metal atoms bonded to each N or O ([`Connection::metal_bonds`]).
    pub metal_bonds: Vec<u8>,
}

impl Hydro {
    /// Hydrogens of atom `i` that are polar (on N, O, S or P).
    pub fn polar(&self, mol: &Molecule, i: usize) -> u8 {
        if matches!(mol.atoms[i].element.as_str(), "N" | "O" | "S" | "P") {
            self.count[i]
        } else {
            0
        }
    }
}

/// Sum of bond orders of atom `i`, in halves.
fn valence_halves(adj: &Adjacency, bonds: &[Bond], i: usize) -> u32 {
    adj.of(i)
        .iter()
        .map(|&(_, k)| bonds[k as usize].valence_halves())
        .sum()
}

/// Hydrogen counts and formal charges.
pub(crate) fn hydrogens(
    mol: &Molecule,
    conn: &Connection,
    adj: &Adjacency,
    explicit_h: &[Option<u8>],
    warn: &mut Warnings,
) -> Hydro {
    let n = mol.len();
    let mut count = vec![0u8; n];
    let mut charges = conn.charges.clone();
    for i in 0..n {
        let e = mol.atoms[i].element.as_str();
        let used = valence_halves(adj, &conn.bonds, i) / 2;
        if !is_metal(e) && covalent_radius(e).is_none() {
            warn.atom(
                mol,
                i,
                format!("unknown element {e:?}: no valence, no Vina type"),
            );
            continue;
        }
        let imposed = conn.templates[conn.residue_of[i] as usize].and_then(|t| {
            t.hydrogen_override(&super::templates::canonical_name(&mol.atoms[i].name))
        });
        if let (Some(h), None) = (imposed, explicit_h[i]) {
            count[i] = h;
            continue;
        }
        if let Some(h) = explicit_h[i] {
            // Open Babel adds the hydrogens a valence still wants even to a
            // file that has some (a carboxylate written without its
            // hydrogen gets one), so an atom has at least those.
            // A metal bonded to the atom takes the place of one.
            let wanted = charged_valences(e, charges[i])
                .iter()
                .find(|&&v| u32::from(v) >= used)
                .map_or(0, |&v| u32::from(v) - used)
                .saturating_sub(u32::from(conn.metal_bonds[i]));
            let h = h.max(u8::try_from(wanted).unwrap_or(0));
            count[i] = h;
            let total = used + u32::from(h);
            let allowed = charged_valences(e, charges[i]);
            if let Some(&max) = allowed.last()
                && total > u32::from(max)
            {
                // An onium: NH4+-like N or P, H3O+-like O.
                let onium = charges[i] == 0
                    && ((matches!(e, "N" | "P") && total == 4) || (e == "O" && total == 3));
                if onium {
                    charges[i] = 1;
                } else {
                    warn.atom(
                        mol,
                        i,
                        format!("odd valence: {total} bonds and hydrogens on a {e}"),
                    );
                }
            }
            continue;
        }
        if valences(e).is_empty() {
            continue;
        }
        let allowed = charged_valences(e, charges[i]);
        match allowed.iter().find(|&&v| u32::from(v) >= used) {
            Some(&v) => count[i] = u8::try_from(u32::from(v) - used).unwrap_or(0),
            None if matches!(e, "N" | "P") && used == 4 && charges[i] == 0 => charges[i] = 1,
            None if e == "O" && used == 3 && charges[i] == 0 => charges[i] = 1,
            None => warn.atom(
                mol,
                i,
                format!(
                    "odd valence: bond orders sum to {used} on a {e} with charge {}",
                    charges[i]
                ),
            ),
        }
    }
    // A nitrogen charged by its four bonds (nitro, N-oxide, an azide's
    // middle N) read without charges: its singly bonded terminal oxygen, or
    // the azide's singly bonded N, is the anion, not a hydroxyl or an NH
    // (as Open Babel types them).
    for i in 0..n {
        if mol.atoms[i].element.as_str() != "N" || charges[i] != 1 || conn.charges[i] != 0 {
            continue;
        }
        let azide = adj
            .of(i)
            .iter()
            .any(|&(_, k)| conn.bonds[k as usize].order == BondOrder::Triple);
        let oxide = adj.of(i).iter().find(|&&(o, k)| {
            let o = o as usize;
            let anion = match mol.atoms[o].element.as_str() {
                "O" => adj.degree(o) == 1,
                "N" => azide && adj.degree(o) == 2,
                _ => false,
            };
            anion
                && conn.bonds[k as usize].order == BondOrder::Single
                && explicit_h[o].is_none()
                && charges[o] == 0
        });
        if let Some(&(o, _)) = oxide {
            charges[o as usize] = -1;
            count[o as usize] = 0;
        }
    }
    // A metal takes a hydrogen's place on the N or O it binds (a zinc's
    // carboxylate, a heme's pyrrole N), unless the file gives hydrogens.
    for i in 0..n {
        if explicit_h[i].is_none() {
            count[i] = count[i].saturating_sub(conn.metal_bonds[i]);
        }
    }
    // Hydrogens loaded as atoms count as their neighbours' hydrogens.
    let mut atom_h = vec![0u8; n];
    for i in 0..n {
        if matches!(mol.atoms[i].element.as_str(), "H" | "D") {
            for &(j, _) in adj.of(i) {
                atom_h[j as usize] = atom_h[j as usize].saturating_add(1);
            }
        }
    }
    Hydro {
        count,
        atom_h,
        charges,
        metal_bonds: conn.metal_bonds.clone(),
    }
}

/// Open Babel's hybridisation of every atom.
pub(crate) fn hybridisation(
    mol: &Molecule,
    bonds: &[Bond],
    adj: &Adjacency,
    aromatic: &[bool],
    bond_aromatic: &[bool],
    hydro: &Hydro,
) -> Vec<Hybridisation> {
    let n = mol.len();
    let elem = |i: usize| mol.atoms[i].element.as_str();
    // Atom has a double, triple or aromatic bond (other than to `except`).
    let unsaturated_except = |i: usize, except: usize| {
        adj.of(i).iter().any(|&(j, k)| {
            j as usize != except
                && (bond_aromatic[k as usize]
                    || matches!(
                        bonds[k as usize].order,
                        BondOrder::Double | BondOrder::Triple
                    ))
        })
    };
    (0..n)
        .map(|i| {
            let row = adj.of(i);
            let doubles = row
                .iter()
                .filter(|&&(_, k)| bonds[k as usize].order == BondOrder::Double)
                .count();
            let triple = row
                .iter()
                .any(|&(_, k)| bonds[k as usize].order == BondOrder::Triple);
            let total_degree = row.len() + usize::from(hydro.count[i]);
            match elem(i) {
                "C" => {
                    if aromatic[i] {
                        Hybridisation::Sp2
                    } else if triple || doubles >= 2 {
                        Hybridisation::Sp
                    } else if doubles == 1 {
                        Hybridisation::Sp2
                    } else {
                        Hybridisation::Sp3
                    }
                }
                "N" => {
                    if triple || (total_degree == 2 && doubles >= 2) {
                        Hybridisation::Sp
                    } else if aromatic[i]
                        || doubles > 0
                        || row.iter().any(|&(j, _)| {
                            let j = j as usize;
                            (matches!(elem(j), "C" | "N" | "O") && unsaturated_except(j, i))
                                || (aromatic[j] && total_degree <= 3)
                        })
                    {
                        Hybridisation::Sp2
                    } else {
                        Hybridisation::Sp3
                    }
                }
                "O" => {
                    let carboxylate = total_degree == 1
                        && row.iter().any(|&(j, _)| {
                            elem(j as usize) == "C"
                                && adj.of(j as usize).iter().any(|&(o, _)| {
                                    o as usize != i
                                        && elem(o as usize) == "O"
                                        && adj.degree(o as usize)
                                            + usize::from(hydro.count[o as usize])
                                            == 1
                                })
                        });
                    if triple {
                        Hybridisation::Sp
                    } else if aromatic[i]
                        || doubles > 0
                        || carboxylate
                        || row.iter().any(|&(j, _)| {
                            matches!(elem(j as usize), "C" | "N" | "O")
                                && unsaturated_except(j as usize, i)
                        })
                    {
                        Hybridisation::Sp2
                    } else {
                        Hybridisation::Sp3
                    }
                }
                "S" => {
                    if aromatic[i] || (total_degree == 1 && doubles == 1) {
                        Hybridisation::Sp2
                    } else {
                        Hybridisation::Sp3
                    }
                }
                "B" => Hybridisation::Sp2,
                _ => Hybridisation::Sp3,
            }
        })
        .collect()
}

/// Vina's X-Score type of every atom.
pub(crate) fn xs_types(
    mol: &Molecule,
    adj: &Adjacency,
    hyb: &[Hybridisation],
    hydro: &Hydro,
    warn: &mut Warnings,
) -> Vec<Option<XsType>> {
    (0..mol.len())
        .map(|i| {
            let e = mol.atoms[i].element.as_str();
            let h = hydro.count[i] + hydro.atom_h[i];
            // A metal bonded to an N holds its lone pair: counted as a
            // neighbour, as Open Babel bonds it.
            let degree =
                adj.degree(i) + usize::from(hydro.count[i]) + usize::from(hydro.metal_bonds[i]);
            let t = match e {
                "C" => {
                    let hetero = adj.of(i).iter().any(|&(j, _)| {
                        !matches!(mol.atoms[j as usize].element.as_str(), "C" | "H" | "D")
                    });
                    if hetero { XsType::C_P } else { XsType::C_H }
                }
                "N" => {
                    let acceptor = !((degree == 4 && hyb[i] == Hybridisation::Sp3)
                        || (degree == 3 && hyb[i] == Hybridisation::Sp2));
                    match (h > 0, acceptor) {
                        (true, true) => XsType::N_DA,
                        (true, false) => XsType::N_D,
                        (false, true) => XsType::N_A,
                        (false, false) => XsType::N_P,
                    }
                }
                "O" => {
                    if h > 0 {
                        XsType::O_DA
                    } else {
                        XsType::O_A
                    }
                }
                "S" | "Se" => XsType::S_P,
                // Hydrogens loaded as atoms (`--hydrogens keep`) have no
                // type; they count as their neighbour's hydrogens.
                "H" | "D" => return None,
                "P" => XsType::P_P,
                "F" => XsType::F_H,
                "Cl" => XsType::Cl_H,
                "Br" => XsType::Br_H,
                "I" => XsType::I_H,
                "Si" => XsType::Si,
                "At" => XsType::At,
                _ if is_metal(e) => XsType::Met_D,
                _ => {
                    if covalent_radius(e).is_some() {
                        warn.atom(
                            mol,
                            i,
                            format!("Vina has no atom type for {e}; it is not scored"),
                        );
                    }
                    return None;
                }
            };
            Some(t)
        })
        .collect()
}
