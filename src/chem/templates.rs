//! Standard residue templates: the heavy atoms and bonds, with orders, of
//! the amino acids and nucleotides, so that a crystal structure's polymer
//! is bonded and typed without guessing from distances.
//!
//! Bond orders are Kekulé structures, and the protonation they imply is the
//! one Open Babel gives a PDB file's residues when it adds hydrogens without
//! a pH model (its residue table, `resdata.txt`, then its bond-order
//! perception) — the inputs AutoDock Vina's reference receptors are made
//! from: neutral amines (Lys NZ and the N terminus get two hydrogens),
//! carboxylic acids (Asp OD1 and Glu OE2 carry a hydrogen; CG=OD2, CD=OE1),
//! Arg with NE=CZ (NH1 and NH2 each get two hydrogens), His with ND1–H and
//! NE2=CE1, and tryptophan's NE1 without a hydrogen (Open Babel's bond-order
//! perception leaves it so in 22 of the 23 reference tryptophans, which
//! makes it an acceptor). Residue names that state a protonation override
//! it: HIE (NE2–H), HIP (both), ASH (OD2–H), GLH (OE2–H), LYN, CYX/CYM (no
//! SG hydrogen); so do a residue's own hydrogens in the file. The
//! peptide C–N and phosphodiester O3'–P links between consecutive residues
//! are made by [`super::connect`], which checks their length.

/// A residue template: heavy atom names, bonds with orders, the atoms of
/// aromatic rings and formal charges.
#[derive(Debug)]
pub struct Template {
    /// Residue kind: amino acid or nucleotide (which inter-residue link it makes).
    pub kind: PolymerKind,
    /// Bonds between the template's atom names, with the order (1, 2, 3).
    pub bonds: &'static [(&'static str, &'static str, u8)],
    /// Names of the atoms in aromatic rings.
    pub aromatic: &'static [&'static str],
    /// Formal charges on named atoms.
    pub charges: &'static [(&'static str, i8)],
    /// Hydrogen counts that override the valence rule (Open Babel leaves
    /// tryptophan's NE1 without one when it reads a PDB file).
    pub hydrogens: &'static [(&'static str, u8)],
}

/// Which polymer a template's residue belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolymerKind {
    /// Amino acids: linked C–N (peptide bond).
    Peptide,
    /// Nucleotides: linked O3'–P (phosphodiester).
    Nucleic,
}

use PolymerKind::{Nucleic, Peptide};

macro_rules! aa {
    ($($b:expr),* $(;)? ) => {
        &[("N", "CA", 1), ("CA", "C", 1), ("C", "O", 2), ("C", "OXT", 1), $($b),*]
    };
}

const ALA: &[(&str, &str, u8)] = aa![("CA", "CB", 1)];
const GLY: &[(&str, &str, u8)] = aa![];
const SER: &[(&str, &str, u8)] = aa![("CA", "CB", 1), ("CB", "OG", 1)];
const CYS: &[(&str, &str, u8)] = aa![("CA", "CB", 1), ("CB", "SG", 1)];
const THR: &[(&str, &str, u8)] = aa![("CA", "CB", 1), ("CB", "OG1", 1), ("CB", "CG2", 1)];
const VAL: &[(&str, &str, u8)] = aa![("CA", "CB", 1), ("CB", "CG1", 1), ("CB", "CG2", 1)];
const LEU: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD1", 1),
    ("CG", "CD2", 1)
];
const ILE: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG1", 1),
    ("CB", "CG2", 1),
    ("CG1", "CD1", 1)
];
const MET: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "SD", 1),
    ("SD", "CE", 1)
];
const MSE: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "SE", 1),
    ("SE", "CE", 1)
];
const PRO: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD", 1),
    ("CD", "N", 1)
];
const ASP: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "OD1", 1),
    ("CG", "OD2", 2)
];
const ASH: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "OD1", 2),
    ("CG", "OD2", 1)
];
const ASN: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "OD1", 2),
    ("CG", "ND2", 1)
];
const GLU: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD", 1),
    ("CD", "OE1", 2),
    ("CD", "OE2", 1)
];
const GLN: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD", 1),
    ("CD", "OE1", 2),
    ("CD", "NE2", 1)
];
const LYS: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD", 1),
    ("CD", "CE", 1),
    ("CE", "NZ", 1)
];
const ARG: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD", 1),
    ("CD", "NE", 1),
    ("NE", "CZ", 2),
    ("CZ", "NH1", 1),
    ("CZ", "NH2", 1)
];
/// Histidine with ND1–H (HID, and Open Babel's HIS).
const HID: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "ND1", 1),
    ("CG", "CD2", 2),
    ("ND1", "CE1", 1),
    ("CE1", "NE2", 2),
    ("NE2", "CD2", 1)
];
/// Histidine with NE2–H.
const HIE: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "ND1", 1),
    ("CG", "CD2", 2),
    ("ND1", "CE1", 2),
    ("CE1", "NE2", 1),
    ("NE2", "CD2", 1)
];
const PHE: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD1", 1),
    ("CG", "CD2", 2),
    ("CD1", "CE1", 2),
    ("CD2", "CE2", 1),
    ("CE1", "CZ", 1),
    ("CE2", "CZ", 2)
];
const TYR: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD1", 2),
    ("CG", "CD2", 1),
    ("CD1", "CE1", 1),
    ("CD2", "CE2", 2),
    ("CE1", "CZ", 2),
    ("CE2", "CZ", 1),
    ("CZ", "OH", 1)
];
const TRP: &[(&str, &str, u8)] = aa![
    ("CA", "CB", 1),
    ("CB", "CG", 1),
    ("CG", "CD1", 2),
    ("CG", "CD2", 1),
    ("CD1", "NE1", 1),
    ("NE1", "CE2", 1),
    ("CE2", "CD2", 1),
    ("CE2", "CZ2", 2),
    ("CD2", "CE3", 2),
    ("CE3", "CZ3", 1),
    ("CZ3", "CH2", 2),
    ("CH2", "CZ2", 1)
];

const PHE_RING: &[&str] = &["CG", "CD1", "CD2", "CE1", "CE2", "CZ"];
const HIS_RING: &[&str] = &["CG", "ND1", "CD2", "CE1", "NE2"];
const TRP_RING: &[&str] = &["CG", "CD1", "CD2", "NE1", "CE2", "CE3", "CZ2", "CZ3", "CH2"];

macro_rules! nt {
    ($($b:expr),* $(;)? ) => {
        &[
            ("P", "OP1", 2), ("P", "OP2", 1), ("P", "OP3", 1), ("P", "O5'", 1), ("O5'", "C5'", 1),
            ("C5'", "C4'", 1), ("C4'", "O4'", 1), ("C4'", "C3'", 1), ("C3'", "O3'", 1),
            ("C3'", "C2'", 1), ("C2'", "C1'", 1), ("C1'", "O4'", 1), ("C2'", "O2'", 1),
            $($b),*
        ]
    };
}

const ADENINE: &[(&str, &str, u8)] = nt![
    ("C1'", "N9", 1),
    ("N9", "C8", 1),
    ("C8", "N7", 2),
    ("N7", "C5", 1),
    ("C5", "C4", 2),
    ("C4", "N9", 1),
    ("C5", "C6", 1),
    ("C6", "N1", 2),
    ("N1", "C2", 1),
    ("C2", "N3", 2),
    ("N3", "C4", 1),
    ("C6", "N6", 1)
];
const GUANINE: &[(&str, &str, u8)] = nt![
    ("C1'", "N9", 1),
    ("N9", "C8", 1),
    ("C8", "N7", 2),
    ("N7", "C5", 1),
    ("C5", "C4", 2),
    ("C4", "N9", 1),
    ("C4", "N3", 1),
    ("N3", "C2", 2),
    ("C2", "N2", 1),
    ("C2", "N1", 1),
    ("N1", "C6", 1),
    ("C6", "O6", 2),
    ("C6", "C5", 1)
];
const INOSINE: &[(&str, &str, u8)] = nt![
    ("C1'", "N9", 1),
    ("N9", "C8", 1),
    ("C8", "N7", 2),
    ("N7", "C5", 1),
    ("C5", "C4", 2),
    ("C4", "N9", 1),
    ("C4", "N3", 1),
    ("N3", "C2", 2),
    ("C2", "N1", 1),
    ("N1", "C6", 1),
    ("C6", "O6", 2),
    ("C6", "C5", 1)
];
const CYTOSINE: &[(&str, &str, u8)] = nt![
    ("C1'", "N1", 1),
    ("N1", "C2", 1),
    ("C2", "O2", 2),
    ("C2", "N3", 1),
    ("N3", "C4", 2),
    ("C4", "N4", 1),
    ("C4", "C5", 1),
    ("C5", "C6", 2),
    ("C6", "N1", 1)
];
const URACIL: &[(&str, &str, u8)] = nt![
    ("C1'", "N1", 1),
    ("N1", "C2", 1),
    ("C2", "O2", 2),
    ("C2", "N3", 1),
    ("N3", "C4", 1),
    ("C4", "O4", 2),
    ("C4", "C5", 1),
    ("C5", "C6", 2),
    ("C6", "N1", 1)
];
const THYMINE: &[(&str, &str, u8)] = nt![
    ("C1'", "N1", 1),
    ("N1", "C2", 1),
    ("C2", "O2", 2),
    ("C2", "N3", 1),
    ("N3", "C4", 1),
    ("C4", "O4", 2),
    ("C4", "C5", 1),
    ("C5", "C6", 2),
    ("C6", "N1", 1),
    ("C5", "C7", 1)
];

const PURINE_RING: &[&str] = &["N9", "C8", "N7", "C5", "C4", "C6", "N1", "C2", "N3"];
const PYRIMIDINE_RING: &[&str] = &["N1", "C2", "N3", "C4", "C5", "C6"];

const fn t(
    kind: PolymerKind,
    bonds: &'static [(&'static str, &'static str, u8)],
    aromatic: &'static [&'static str],
    charges: &'static [(&'static str, i8)],
) -> Template {
    Template {
        kind,
        bonds,
        aromatic,
        charges,
        hydrogens: &[],
    }
}

static T_ALA: Template = t(Peptide, ALA, &[], &[]);
static T_GLY: Template = t(Peptide, GLY, &[], &[]);
static T_SER: Template = t(Peptide, SER, &[], &[]);
static T_CYS: Template = t(Peptide, CYS, &[], &[]);
static T_CYM: Template = t(Peptide, CYS, &[], &[("SG", -1)]);
static T_THR: Template = t(Peptide, THR, &[], &[]);
static T_VAL: Template = t(Peptide, VAL, &[], &[]);
static T_LEU: Template = t(Peptide, LEU, &[], &[]);
static T_ILE: Template = t(Peptide, ILE, &[], &[]);
static T_MET: Template = t(Peptide, MET, &[], &[]);
static T_MSE: Template = t(Peptide, MSE, &[], &[]);
static T_PRO: Template = t(Peptide, PRO, &[], &[]);
static T_ASP: Template = t(Peptide, ASP, &[], &[]);
static T_ASH: Template = t(Peptide, ASH, &[], &[]);
static T_ASN: Template = t(Peptide, ASN, &[], &[]);
static T_GLU: Template = t(Peptide, GLU, &[], &[]);
static T_GLN: Template = t(Peptide, GLN, &[], &[]);
static T_LYS: Template = t(Peptide, LYS, &[], &[]);
static T_ARG: Template = t(Peptide, ARG, &[], &[]);
static T_HID: Template = t(Peptide, HID, HIS_RING, &[]);
static T_HIE: Template = t(Peptide, HIE, HIS_RING, &[]);
static T_HIP: Template = t(Peptide, HID, HIS_RING, &[("NE2", 1)]);
static T_PHE: Template = t(Peptide, PHE, PHE_RING, &[]);
static T_TYR: Template = t(Peptide, TYR, PHE_RING, &[]);
static T_TRP: Template = Template {
    hydrogens: &[("NE1", 0)],
    ..t(Peptide, TRP, TRP_RING, &[])
};
static T_A: Template = t(Nucleic, ADENINE, PURINE_RING, &[]);
static T_G: Template = t(Nucleic, GUANINE, PURINE_RING, &[]);
static T_I: Template = t(Nucleic, INOSINE, PURINE_RING, &[]);
static T_C: Template = t(Nucleic, CYTOSINE, PYRIMIDINE_RING, &[]);
static T_U: Template = t(Nucleic, URACIL, PYRIMIDINE_RING, &[]);
static T_T: Template = t(Nucleic, THYMINE, PYRIMIDINE_RING, &[]);

/// The template of a residue name (any case), with the usual variants.
pub fn template(residue: &str) -> Option<&'static Template> {
    let name = residue.trim();
    let mut buf = [0u8; 4];
    if name.len() > 4 {
        return None;
    }
    for (b, c) in buf.iter_mut().zip(name.bytes()) {
        *b = c.to_ascii_uppercase();
    }
    Some(match &buf[..name.len()] {
        b"ALA" => &T_ALA,
        b"GLY" => &T_GLY,
        b"SER" => &T_SER,
        b"CYS" | b"CYX" => &T_CYS,
        b"CYM" => &T_CYM,
        b"THR" => &T_THR,
        b"VAL" => &T_VAL,
        b"LEU" => &T_LEU,
        b"ILE" => &T_ILE,
        b"MET" => &T_MET,
        b"MSE" => &T_MSE,
        b"PRO" => &T_PRO,
        b"ASP" => &T_ASP,
        b"ASH" => &T_ASH,
        b"ASN" => &T_ASN,
        b"GLU" | b"GLH" => &T_GLU,
        b"GLN" => &T_GLN,
        b"LYS" | b"LYN" => &T_LYS,
        b"ARG" => &T_ARG,
        b"HIS" | b"HID" | b"HSD" => &T_HID,
        b"HIE" | b"HSE" => &T_HIE,
        b"HIP" | b"HSP" => &T_HIP,
        b"PHE" => &T_PHE,
        b"TYR" => &T_TYR,
        b"TRP" => &T_TRP,
        b"A" | b"DA" | b"RA" => &T_A,
        b"G" | b"DG" | b"RG" => &T_G,
        b"I" | b"DI" => &T_I,
        b"C" | b"DC" | b"RC" => &T_C,
        b"U" | b"DU" | b"RU" => &T_U,
        b"T" | b"DT" => &T_T,
        _ => return None,
    })
}

/// An atom name as the templates spell it: `*` read as `'` (old nucleic
/// acid names), and the old phosphate, thymine methyl and CHARMM C-terminal
/// names (`OT1`, `OT2`) mapped to the current ones.
pub fn canonical_name(name: &str) -> std::borrow::Cow<'_, str> {
    let n = name.trim();
    match n {
        "O1P" => "OP1".into(),
        "O2P" => "OP2".into(),
        "O3P" => "OP3".into(),
        "OT1" => "O".into(),
        "OT2" => "OXT".into(),
        "C5M" => "C7".into(),
        _ if n.contains('*') => n.replace('*', "'").into(),
        _ => n.into(),
    }
}

impl Template {
    /// True when the template names `atom` (a canonical name).
    pub fn has_atom(&self, atom: &str) -> bool {
        self.bonds.iter().any(|(a, b, _)| *a == atom || *b == atom)
    }

    /// The hydrogen count the template imposes on `atom`, if any.
    pub fn hydrogen_override(&self, atom: &str) -> Option<u8> {
        self.hydrogens
            .iter()
            .find(|(n, _)| *n == atom)
            .map(|(_, h)| *h)
    }

    /// The formal charge the template gives `atom`.
    pub fn charge(&self, atom: &str) -> i8 {
        self.charges
            .iter()
            .find(|(n, _)| *n == atom)
            .map_or(0, |(_, q)| *q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_and_names() {
        assert!(template("his").is_some_and(|t| t.has_atom("NE2")));
        assert!(template("HOH").is_none());
        assert_eq!(canonical_name("O5*"), "O5'");
        assert_eq!(canonical_name("O1P"), "OP1");
        assert_eq!(template("HIP").map(|t| t.charge("NE2")), Some(1));
        assert_eq!(template("DT").map(|t| t.kind), Some(PolymerKind::Nucleic));
    }
}
