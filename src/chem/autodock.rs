//! AutoDock atom types, as a PDBQT file states them, and the X-Score types
//! AutoDock Vina derives from them.
//!
//! A PDBQT file gives each atom an AutoDock type from column 78 (`C`, `A`
//! for an aromatic carbon, `NA`/`OA`/`SA` for acceptors, `HD` for a polar
//! hydrogen, …) and a partial charge in columns 69–76. Vina reads only these:
//! it takes an atom's element from its type, bonds atoms by distance, and
//! types each atom (`model::assign_types` in AutoDock Vina 1.2): a carbon is
//! C_P when bonded to a heteroatom (any type but `C`, `A`, `H`, `HD`, or a
//! metal) and C_H otherwise; an N or O is an acceptor when typed `NA` or
//! `OA`, a donor when bonded to an `HD` hydrogen (or a metal, always a
//! donor); sulfur is S_P whatever its type, halogens hydrophobic. The names
//! Vina takes for metals it has no AutoDock type for (`Cu`, `Fe`, `Na`, `K`,
//! `Hg`, `Co`, `U`, `Cd`, `Ni`) are metals, donors; `Se` reads as `S`.
//!
//! [`xs_type`] applies that rule to one atom, given what it is bonded to, so
//! that a PDBQT scores in bump as it scores in Vina, whatever bump itself
//! would perceive from the atoms.

use serde::Serialize;

use super::gasteiger::Charges;
use super::{Adjacency, Bond, Warnings, XsType};
use crate::model::{AutoDockData, Molecule};

/// An AutoDock atom type (Vina 1.2's `atom_constants.h`), or one of the
/// metal names Vina accepts without one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum AdType {
    /// Aliphatic carbon (`C`).
    C,
    /// Aromatic carbon (`A`).
    A,
    /// Nitrogen, not an acceptor (`N`).
    N,
    /// Nitrogen acceptor (`NA`).
    NA,
    /// Oxygen, not an acceptor (`O`).
    O,
    /// Oxygen acceptor (`OA`).
    OA,
    /// Sulfur (`S`, and `Se`, which Vina reads as `S`).
    S,
    /// Sulfur acceptor (`SA`).
    SA,
    /// Phosphorus (`P`).
    P,
    /// Non-polar hydrogen (`H`).
    H,
    /// Polar hydrogen, a donor's (`HD`).
    HD,
    /// Fluorine (`F`).
    F,
    /// Chlorine (`Cl`).
    Cl,
    /// Bromine (`Br`).
    Br,
    /// Iodine (`I`).
    I,
    /// Silicon (`Si`).
    Si,
    /// Astatine (`At`).
    At,
    /// A carbon that closes a macrocycle (`CG0` … `CG3`, Meeko's), with its
    /// closure number.
    Cg(u8),
    /// A macrocycle closure's dummy atom (`G0` … `G3`): not an atom.
    G(u8),
    /// A water of hydrated docking (`W`): not scored by Vina's function.
    W,
    /// A metal (`Mg`, `Mn`, `Zn`, `Ca`, `Fe`, and `Cu`, `Na`, `K`, `Hg`,
    /// `Co`, `U`, `Cd`, `Ni`), with its element symbol.
    Metal(&'static str),
}

/// The metals Vina reads: AutoDock's types, then the names it adds.
const METALS: [&str; 13] = [
    "Mg", "Mn", "Zn", "Ca", "Fe", "Cu", "Na", "K", "Hg", "Co", "U", "Cd", "Ni",
];

/// The types with fixed names, as a PDBQT file spells them.
const NAMED: [(&str, AdType); 18] = [
    ("C", AdType::C),
    ("A", AdType::A),
    ("N", AdType::N),
    ("NA", AdType::NA),
    ("O", AdType::O),
    ("OA", AdType::OA),
    ("S", AdType::S),
    ("SA", AdType::SA),
    ("P", AdType::P),
    ("H", AdType::H),
    ("HD", AdType::HD),
    ("F", AdType::F),
    ("Cl", AdType::Cl),
    ("Br", AdType::Br),
    ("I", AdType::I),
    ("Si", AdType::Si),
    ("At", AdType::At),
    ("W", AdType::W),
];

impl AdType {
    /// The type a PDBQT file's type column names (case-sensitive, as Vina
    /// reads it); `None` for a name Vina does not accept.
    pub fn parse(name: &str) -> Option<Self> {
        if let Some(&(_, t)) = NAMED.iter().find(|(n, _)| *n == name) {
            return Some(t);
        }
        if name == "Se" {
            // Vina reads selenium as sulphur.
            return Some(Self::S);
        }
        if let Some(n) = closure_number(name, "CG") {
            Some(Self::Cg(n))
        } else if let Some(n) = closure_number(name, "G") {
            Some(Self::G(n))
        } else {
            Some(Self::Metal(METALS.iter().copied().find(|&m| m == name)?))
        }
    }

    /// The element symbol of an atom of this type; `None` for the pseudo
    /// atoms (`G0`–`G3`, `W`).
    pub fn element(self) -> Option<&'static str> {
        Some(match self {
            Self::C | Self::A | Self::Cg(_) => "C",
            Self::N | Self::NA => "N",
            Self::O | Self::OA => "O",
            Self::S | Self::SA => "S",
            Self::P => "P",
            Self::H | Self::HD => "H",
            Self::F => "F",
            Self::Cl => "Cl",
            Self::Br => "Br",
            Self::I => "I",
            Self::Si => "Si",
            Self::At => "At",
            Self::Metal(e) => e,
            Self::G(_) | Self::W => return None,
        })
    }

    /// The type's name as a PDBQT file writes it.
    pub fn name(self) -> &'static str {
        const CG: [&str; 4] = ["CG0", "CG1", "CG2", "CG3"];
        const G: [&str; 4] = ["G0", "G1", "G2", "G3"];
        match self {
            Self::Cg(n) => CG[usize::from(n.min(3))],
            Self::G(n) => G[usize::from(n.min(3))],
            Self::Metal(e) => e,
            _ => NAMED
                .iter()
                .find(|(_, t)| *t == self)
                .map_or("?", |(n, _)| n),
        }
    }

    /// True for `H` and `HD`.
    pub fn is_hydrogen(self) -> bool {
        matches!(self, Self::H | Self::HD)
    }

    /// Vina's heteroatom (`atom_type::is_heteroatom`): anything but carbon
    /// `C`/`A` and the hydrogens; metals included.
    pub fn is_heteroatom(self) -> bool {
        !matches!(self, Self::C | Self::A | Self::H | Self::HD)
    }
}

/// `n` in 0–3 when `name` is `prefix` followed by that digit.
fn closure_number(name: &str, prefix: &str) -> Option<u8> {
    let d = name.strip_prefix(prefix)?;
    match d.as_bytes() {
        [c @ b'0'..=b'3'] => Some(c - b'0'),
        _ => None,
    }
}

/// Vina's X-Score type of an atom of AutoDock type `t`: `hetero_neighbour`
/// says whether it is bonded to a heteroatom ([`AdType::is_heteroatom`]),
/// `hd_neighbour` whether it is bonded to an `HD` hydrogen. `None` for the
/// hydrogens and pseudo atoms, which Vina does not score.
pub fn xs_type(t: AdType, hetero_neighbour: bool, hd_neighbour: bool) -> Option<XsType> {
    let (acceptor, donor) = (matches!(t, AdType::NA | AdType::OA), hd_neighbour);
    Some(match t {
        AdType::C | AdType::A => {
            if hetero_neighbour {
                XsType::C_P
            } else {
                XsType::C_H
            }
        }
        // A closure carbon is bonded to its dummy partner, a heteroatom to
        // Vina.
        AdType::Cg(_) => XsType::C_P,
        AdType::N | AdType::NA => match (donor, acceptor) {
            (true, true) => XsType::N_DA,
            (false, true) => XsType::N_A,
            (true, false) => XsType::N_D,
            (false, false) => XsType::N_P,
        },
        AdType::O | AdType::OA => match (donor, acceptor) {
            (true, true) => XsType::O_DA,
            (false, true) => XsType::O_A,
            (true, false) => XsType::O_D,
            (false, false) => XsType::O_P,
        },
        AdType::S | AdType::SA => XsType::S_P,
        AdType::P => XsType::P_P,
        AdType::F => XsType::F_H,
        AdType::Cl => XsType::Cl_H,
        AdType::Br => XsType::Br_H,
        AdType::I => XsType::I_H,
        AdType::Si => XsType::Si,
        AdType::At => XsType::At,
        AdType::Metal(_) => XsType::Met_D,
        AdType::H | AdType::HD | AdType::G(_) | AdType::W => return None,
    })
}

/// Vina's X-Score types of `mol`'s atoms from the AutoDock types its file
/// states (`ad`), with the bonds perceived (`adj`) and the hydrogens kept
/// apart as the neighbours.
pub(crate) fn file_xs_types(
    mol: &Molecule,
    ad: &AutoDockData,
    adj: &Adjacency,
) -> Vec<Option<XsType>> {
    let mut hd = vec![false; mol.len()];
    for (k, &p) in mol.hydrogens.parent.iter().enumerate() {
        if ad.hydrogens.get(k).is_some_and(|h| h.ad == AdType::HD)
            && let Some(x) = hd.get_mut(p as usize)
        {
            *x = true;
        }
    }
    let type_of = |j: u32| ad.atoms.get(j as usize).map(|a| a.ad);
    (0..mol.len())
        .map(|i| {
            let t = ad.atoms.get(i)?.ad;
            let hetero = adj
                .of(i)
                .iter()
                .any(|&(j, _)| type_of(j).is_some_and(AdType::is_heteroatom));
            let donor = hd[i]
                || adj
                    .of(i)
                    .iter()
                    .any(|&(j, _)| type_of(j) == Some(AdType::HD));
            xs_type(t, hetero, donor)
        })
        .collect()
}

/// The rotatable bonds a file's torsion tree states.
pub(crate) struct FileTorsions {
    /// Per bond of the perceived bonds: turned by the tree.
    pub rotatable: Vec<bool>,
    /// Vina's torsion count of the branches bump holds (see
    /// [`file_rotatable`]), to add to the tree's.
    pub held_count: f64,
}

/// Per bond of `bonds` (sorted, `a < b`): rotatable when the file's torsion
/// tree turns it. `None` when the file has no tree.
///
/// A branch across a ring bond (a macrocycle Meeko opened, closing it with
/// `CG`/`G` pseudo-atoms) or between atoms bump does not bond is held, with
/// a warning; Vina turns it, and it counts in Vina's torsion count as it
/// does there (½ for each of its atoms whose partner has more than one heavy
/// neighbour), so the score stays Vina's.
pub(crate) fn file_rotatable(
    mol: &Molecule,
    ad: &AutoDockData,
    bonds: &[Bond],
    adj: &Adjacency,
    in_ring: &[bool],
    warn: &mut Warnings,
) -> Option<FileTorsions> {
    if !ad.tree {
        return None;
    }
    let mut rotatable = vec![false; bonds.len()];
    let mut held_count = 0.0;
    // (ring bonds, bonds bump does not perceive) held, named.
    let (mut ring, mut unbonded) = (Vec::new(), Vec::new());
    let name = |i: u32| {
        mol.atoms
            .get(i as usize)
            .map_or_else(String::new, |x| format!("{}", x.name))
    };
    for &[a, b] in &ad.branches {
        let key = (a.min(b), a.max(b));
        let held = match bonds.binary_search_by(|bd| (bd.a, bd.b).cmp(&key)) {
            Ok(k) if !in_ring[k] => {
                rotatable[k] = true;
                continue;
            }
            Ok(_) => &mut ring,
            Err(_) => &mut unbonded,
        };
        held.push(format!("{}–{}", name(key.0), name(key.1)));
        let side = |x: u32| {
            if super::torsions::heavy_neighbours(mol, adj, x as usize) > 1 {
                0.5
            } else {
                0.0
            }
        };
        held_count += side(key.0) + side(key.1);
    }
    let list = |v: &[String]| {
        let shown = v.iter().take(4).cloned().collect::<Vec<_>>().join(", ");
        if v.len() > 4 {
            format!("{shown} and {} more", v.len() - 4)
        } else {
            shown
        }
    };
    if !ring.is_empty() {
        warn.general(format!(
            "{}: the file's torsion tree turns {} ring bond(s) ({}: a macrocycle opened for \
             docking); bump holds the ring, and counts them in Vina's torsion count as Vina does",
            mol.name,
            ring.len(),
            list(&ring)
        ));
    }
    if !unbonded.is_empty() {
        warn.general(format!(
            "{}: the file's torsion tree turns {} bond(s) between atoms bump does not bond ({}); \
             bump holds them, and counts them in Vina's torsion count as Vina does",
            mol.name,
            unbonded.len(),
            list(&unbonded)
        ));
    }
    Some(FileTorsions {
        rotatable,
        held_count,
    })
}

/// The partial charges a PDBQT states, in the shape of Gasteiger's: per
/// heavy atom with its non-polar hydrogens (`H`) added, the sum of its polar
/// hydrogens (`HD`), and each kept hydrogen's (0 for a non-polar one).
pub(crate) fn file_charges(mol: &Molecule, ad: &AutoDockData) -> Charges {
    let mut heavy: Vec<f32> = (0..mol.len())
        .map(|i| ad.atoms.get(i).map_or(0.0, |a| a.charge))
        .collect();
    let mut polar_h = vec![0.0f32; mol.len()];
    let mut kept_h = vec![0.0f32; mol.hydrogens.len()];
    for (k, &p) in mol.hydrogens.parent.iter().enumerate() {
        let (Some(h), Some(slot)) = (ad.hydrogens.get(k), heavy.get_mut(p as usize)) else {
            continue;
        };
        if h.ad == AdType::HD {
            polar_h[p as usize] += h.charge;
            kept_h[k] = h.charge;
        } else {
            *slot += h.charge;
        }
    }
    Charges {
        heavy,
        polar_h,
        kept_h,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_as_vina_reads_them() {
        assert_eq!(AdType::parse("A"), Some(AdType::A));
        assert_eq!(AdType::parse("NA"), Some(AdType::NA));
        assert_eq!(AdType::parse("Se"), Some(AdType::S));
        assert_eq!(AdType::parse("CG1"), Some(AdType::Cg(1)));
        assert_eq!(AdType::parse("G3"), Some(AdType::G(3)));
        assert_eq!(AdType::parse("Zn"), Some(AdType::Metal("Zn")));
        assert_eq!(AdType::parse("Cu"), Some(AdType::Metal("Cu")));
        // Case matters, as in Vina; unknown names are refused.
        assert_eq!(AdType::parse("CL"), None);
        assert_eq!(AdType::parse("G4"), None);
        assert_eq!(AdType::parse("X"), None);
        assert_eq!(AdType::parse(""), None);
        assert_eq!(AdType::parse("Zn").and_then(AdType::element), Some("Zn"));
        assert_eq!(AdType::parse("W").and_then(AdType::element), None);
        // Every name reads back as the type it names.
        let names = NAMED.iter().map(|(n, _)| *n);
        let more = ["CG0", "CG3", "G0", "G2"].into_iter().chain(METALS);
        for name in names.chain(more) {
            let t = AdType::parse(name).expect(name);
            assert_eq!(t.name(), name);
        }
    }

    #[test]
    fn types_follow_vinas_assign_types() {
        assert_eq!(xs_type(AdType::A, false, false), Some(XsType::C_H));
        assert_eq!(xs_type(AdType::C, true, false), Some(XsType::C_P));
        assert_eq!(xs_type(AdType::NA, false, true), Some(XsType::N_DA));
        assert_eq!(xs_type(AdType::N, false, true), Some(XsType::N_D));
        assert_eq!(xs_type(AdType::N, false, false), Some(XsType::N_P));
        assert_eq!(xs_type(AdType::OA, false, false), Some(XsType::O_A));
        assert_eq!(xs_type(AdType::O, false, false), Some(XsType::O_P));
        assert_eq!(xs_type(AdType::SA, false, true), Some(XsType::S_P));
        assert_eq!(
            xs_type(AdType::Metal("Zn"), false, false),
            Some(XsType::Met_D)
        );
        assert_eq!(xs_type(AdType::HD, false, false), None);
        assert!(AdType::Metal("Fe").is_heteroatom());
        assert!(!AdType::A.is_heteroatom());
        assert!(AdType::G(0).is_heteroatom());
    }
}
