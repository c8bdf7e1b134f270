//! What molecules and atoms are called on screen, in a chemist's words:
//! `drug: TOP X 201 (trimethoprim.sdf)`, `atom: N1 of TOP X 201`,
//! `receptor: 6xg5_tmp_prepared.pdb (1,302 atoms, 159 residues)`.
//!
//! A molecule's role is read from what it is, not from the order the files
//! came in: one residue (a ligand file, a drug split from a complex) is a
//! drug; more than one is a receptor.

use crate::model::{AtomInfo, Molecule};

/// What a molecule is in the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A polymer: more than one residue.
    Receptor,
    /// A small molecule: one residue.
    Drug,
}

impl Role {
    /// The role of `m`.
    pub fn of(m: &Molecule) -> Self {
        let Some(first) = m.atoms.first() else {
            return Self::Receptor;
        };
        if m.atoms.iter().all(|a| same_residue(a, first)) {
            Self::Drug
        } else {
            Self::Receptor
        }
    }

    /// The word shown: `drug` or `receptor`.
    pub fn word(self) -> &'static str {
        match self {
            Self::Receptor => "receptor",
            Self::Drug => "drug",
        }
    }
}

fn same_residue(a: &AtomInfo, b: &AtomInfo) -> bool {
    a.residue == b.residue && a.chain == b.chain && a.seq == b.seq && a.insertion == b.insertion
}

/// A residue as written in papers and by ChimeraX: `TOP X 201`, `PHE A 31`
/// (a blank chain is left out).
pub fn residue(a: &AtomInfo) -> String {
    let chain = a.chain.trim();
    if chain.is_empty() {
        format!("{} {}", a.residue, a.residue_number())
    } else {
        format!("{} {} {}", a.residue, chain, a.residue_number())
    }
}

/// The file a molecule came from, as its name gives it: the name without
/// the ` receptor` a whole file gets or the ` RES chain/seq` a drug split
/// from a complex gets.
pub fn file_label(m: &Molecule) -> &str {
    let name = m.name.as_str();
    if let Some(f) = name.strip_suffix(" receptor") {
        return f;
    }
    if let Some(a) = m.atoms.first() {
        let part = format!(" {} {}/{}", a.residue, a.chain, a.residue_number());
        if let Some(f) = name.strip_suffix(part.as_str()) {
            return f;
        }
    }
    name
}

/// A molecule in words: `drug: TOP X 201 (trimethoprim.sdf)`, or
/// `receptor: 6xg5.pdb (1,302 atoms)`.
pub fn molecule(m: &Molecule) -> String {
    describe(m, Role::of(m))
}

/// A molecule in words, in the role the scene gives it.
pub fn describe(m: &Molecule, role: Role) -> String {
    match (role, m.atoms.first()) {
        (Role::Drug, Some(a)) => format!("drug: {} ({})", residue(a), file_label(m)),
        _ => format!(
            "{}: {} ({} atoms)",
            role.word(),
            file_label(m),
            thousands(m.len())
        ),
    }
}

/// An atom in words: `atom: N1 of TOP X 201`.
pub fn atom(m: &Molecule, i: usize) -> Option<String> {
    let a = m.atoms.get(i)?;
    Some(format!("atom: {} of {}", a.name.trim(), residue(a)))
}

/// `1302` as `1,302`.
pub fn thousands(n: usize) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (k, c) in s.chars().enumerate() {
        if k > 0 && (s.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn atom_of(name: &str, res: &str, chain: &str, seq: i64) -> AtomInfo {
        AtomInfo {
            serial: 1,
            name: name.into(),
            residue: res.into(),
            seq,
            insertion: Default::default(),
            chain: chain.into(),
            element: "N".into(),
            radius: 1.55,
            polar: true,
            hetero: true,
        }
    }

    #[test]
    fn a_drug_and_a_receptor_in_words() {
        let drug = Molecule::new(
            "6xg5.pdb TOP X/201",
            vec![
                atom_of("N1", "TOP", "X", 201),
                atom_of("C2", "TOP", "X", 201),
            ],
            &[DVec3::ZERO, DVec3::X],
        );
        assert_eq!(Role::of(&drug), Role::Drug);
        assert_eq!(molecule(&drug), "drug: TOP X 201 (6xg5.pdb)");
        assert_eq!(atom(&drug, 0).as_deref(), Some("atom: N1 of TOP X 201"));
        assert_eq!(atom(&drug, 2), None);
        // A ligand file loaded on its own is a drug, not a receptor.
        let sdf = Molecule::new(
            "trimethoprim.sdf receptor",
            vec![atom_of("N1", "UNL", "", 1)],
            &[DVec3::ZERO],
        );
        assert_eq!(molecule(&sdf), "drug: UNL 1 (trimethoprim.sdf)");
        let protein = Molecule::new(
            "dhfr.pdb receptor",
            (0..1302)
                .map(|k| atom_of("CA", "ALA", "A", k / 8))
                .collect(),
            &vec![DVec3::ZERO; 1302],
        );
        assert_eq!(molecule(&protein), "receptor: dhfr.pdb (1,302 atoms)");
        assert_eq!(thousands(272_000), "272,000");
        assert_eq!(thousands(12), "12");
    }
}
