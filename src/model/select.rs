//! Splitting a loaded complex into a receptor and a drug.
//!
//! A residue copy is identified by chain, sequence number, insertion code and
//! residue name; atoms are grouped into copies in file order. The drug is one
//! copy, chosen by a [`LigandSpec`]:
//! - `RESNAME[:CHAIN[:SEQ[ICODE]]]`: the first copy in file order with that
//!   name (any case) and, when given, that chain (exact, chain ids are
//!   case-sensitive), sequence number and insertion code (`52A`; without a
//!   code any copy with that number matches);
//! - `auto`: the copy with the most atoms (ties to the first) among hetero
//!   residues that are not water ([`super::is_water`]) and not in the skip list:
//!   single-atom residues, the small ions and additives in [`AUTO_SKIPPED`]
//!   (sulphate, phosphate, glycerol, ...), common modified amino acids
//!   (`MSE`, `CSO`, ...) and any hetero residue numbered between two polymer
//!   residues of its chain (a modified residue, such as a tRNA's modified
//!   nucleotides), which are part of the polymer.
//!
//! The receptor is every other atom except waters (a PDBQT keeps its
//! waters: it was prepared for docking, and Vina scores them). Errors name the file and
//! list the hetero residues that are present, so the user can name one.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt;
use std::str::FromStr;

use glam::DVec3;

use super::{
    AtomInfo, AutoDockData, FileBond, FileChemistry, LoadError, Molecule, Structure, is_water,
};
use crate::chem::Bond;

/// Hetero residue names `auto` never picks: ions and small inorganic groups,
/// crystallisation and buffer additives, and modified amino acids that belong
/// to the polymer. Residues with a single atom are skipped as well.
pub const AUTO_SKIPPED: &[&str] = &[
    // ions and small inorganic groups
    "SO4", "PO4", "NO3", "CO3", "NH4", "SCN", "AZI", "IOD", "PI", "2HP", "BCT", "CYN",
    // additives: cryoprotectants, precipitants, buffers, solvents
    "GOL", "EDO", "PEG", "PGE", "PG4", "1PE", "P6G", "MPD", "ACT", "ACY", "FMT", "DMS", "EOH",
    "IPA", "MOH", "BME", "TRS", "MES", "EPE", "IMD", "CIT", "FLC", "TAR", "MLI",
    // modified amino acids
    "MSE", "CSO", "CSD", "CSX", "OCS", "CME", "CAS", "SEP", "TPO", "PTR", "HYP", "MLY", "M3L",
    "KCX", "LLP", "PCA", "ALY",
];

/// Which residue of a complex is the drug.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LigandSpec {
    /// The largest hetero residue that is not water, an ion, an additive or a
    /// modified amino acid.
    Auto,
    /// A residue by name, optionally narrowed by chain and sequence number.
    Residue {
        /// Residue name, upper case (`MTX`).
        name: String,
        /// Chain identifier, exact.
        chain: Option<String>,
        /// Residue sequence number.
        seq: Option<i64>,
        /// Insertion code (`A` of `52A`), exact; only with a number.
        insertion: Option<String>,
    },
}

impl LigandSpec {
    /// Parses `auto` (any case), `RESNAME`, `RESNAME:CHAIN` or
    /// `RESNAME:CHAIN:SEQ`, where SEQ may end in an insertion code (`52A`).
    /// The name is matched in any case; an empty chain (`MTX::162`) means
    /// any chain.
    ///
    /// # Errors
    /// A message saying what is wrong with `s`.
    pub fn parse(s: &str) -> Result<LigandSpec, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("auto") {
            return Ok(LigandSpec::Auto);
        }
        let parts: Vec<&str> = s.split(':').map(str::trim).collect();
        if parts.len() > 3 {
            return Err(format!(
                "ligand {s:?}: expected auto, RESNAME, RESNAME:CHAIN or RESNAME:CHAIN:SEQ"
            ));
        }
        let name = parts[0];
        if name.is_empty() || name.contains(char::is_whitespace) {
            return Err(format!(
                "ligand {s:?}: the residue name must be non-empty with no spaces \
                 (expected auto, RESNAME, RESNAME:CHAIN or RESNAME:CHAIN:SEQ)"
            ));
        }
        let chain = parts
            .get(1)
            .filter(|c| !c.is_empty())
            .map(|c| (*c).to_string());
        let (seq, insertion) = match parts.get(2).filter(|q| !q.is_empty()) {
            Some(q) => {
                // An insertion code is the letters after the number.
                let digits = q.trim_end_matches(|c: char| c.is_ascii_alphabetic());
                let code = &q[digits.len()..];
                let seq = digits.parse::<i64>().map_err(|_| {
                    format!(
                        "ligand {s:?}: residue number {q:?} is not an integer \
                         (with an optional insertion code, as in 52A)"
                    )
                })?;
                (Some(seq), (!code.is_empty()).then(|| code.to_string()))
            }
            None => (None, None),
        };
        Ok(LigandSpec::Residue {
            name: name.to_ascii_uppercase(),
            chain,
            seq,
            insertion,
        })
    }
}

impl FromStr for LigandSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

impl fmt::Display for LigandSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LigandSpec::Auto => write!(f, "auto"),
            LigandSpec::Residue {
                name,
                chain,
                seq,
                insertion,
            } => {
                write!(f, "{name}")?;
                match (chain, seq) {
                    (None, None) => Ok(()),
                    (Some(c), None) => write!(f, ":{c}"),
                    (c, Some(q)) => write!(
                        f,
                        ":{}:{q}{}",
                        c.as_deref().unwrap_or(""),
                        insertion.as_deref().unwrap_or("")
                    ),
                }
            }
        }
    }
}

/// One residue copy: its identity and the indices of its atoms.
#[derive(Clone)]
struct Group<'a> {
    chain: &'a str,
    seq: i64,
    insertion: &'a str,
    name: &'a str,
    hetero: bool,
    atoms: Vec<usize>,
}

impl Group<'_> {
    /// `TOP X/0`, or `TOP 0` without a chain.
    fn label(&self) -> String {
        if self.chain.is_empty() {
            format!("{} {}{}", self.name, self.seq, self.insertion)
        } else {
            format!(
                "{} {}/{}{}",
                self.name, self.chain, self.seq, self.insertion
            )
        }
    }
}

/// Residue copies in order of first atom.
fn residue_groups(s: &Structure) -> Vec<Group<'_>> {
    let mut groups: Vec<Group<'_>> = Vec::new();
    let mut index: HashMap<(&str, i64, &str, &str), usize> = HashMap::new();
    for (i, a) in s.atoms.iter().enumerate() {
        let key = (
            a.chain.as_str(),
            a.seq,
            a.insertion.as_str(),
            a.residue.as_str(),
        );
        // Consecutive atoms of one residue are the common case.
        if let Some(last) = groups.last_mut()
            && (last.chain, last.seq, last.insertion, last.name) == key
        {
            last.atoms.push(i);
            last.hetero |= a.hetero;
            continue;
        }
        match index.get(&key) {
            Some(&g) => {
                groups[g].atoms.push(i);
                groups[g].hetero |= a.hetero;
            }
            None => {
                index.insert(key, groups.len());
                groups.push(Group {
                    chain: key.0,
                    seq: key.1,
                    insertion: key.2,
                    name: key.3,
                    hetero: a.hetero,
                    atoms: vec![i],
                });
            }
        }
    }
    groups
}

/// The places (chain, sequence number) that lie within a polymer chain:
/// on each side, the numbers next to it in its chain, one after another,
/// reach a polymer (non-hetero) residue before a gap in the numbering.
/// Waters are left out. One pass each way over the sorted numbers, so a
/// chain of thousands of hetero residues (a membrane's lipids) costs no
/// more than a protein.
type WithinPolymer<'a> = HashSet<(&'a str, i64)>;

/// [`WithinPolymer`] of `groups`.
fn within_polymer<'a>(groups: &[Group<'a>]) -> WithinPolymer<'a> {
    // Each number used, and whether a polymer residue has it, in order.
    let mut numbers: BTreeMap<(&str, i64), bool> = BTreeMap::new();
    for g in groups.iter().filter(|g| !is_water(g.name)) {
        *numbers.entry((g.chain, g.seq)).or_default() |= !g.hetero;
    }
    let places: Vec<((&str, i64), bool)> = numbers.into_iter().collect();
    let n = places.len();
    // Places `a` and `b` are consecutive numbers of one chain.
    let next = |a: usize, b: usize| {
        let ((ca, sa), (cb, sb)) = (places[a].0, places[b].0);
        ca == cb && sa.checked_add(1) == Some(sb)
    };
    // Walking down (up) from each place reaches a polymer residue.
    let mut below = vec![false; n];
    for i in 1..n {
        below[i] = next(i - 1, i) && (places[i - 1].1 || below[i - 1]);
    }
    let mut above = vec![false; n];
    for i in (0..n.saturating_sub(1)).rev() {
        above[i] = next(i, i + 1) && (places[i + 1].1 || above[i + 1]);
    }
    (0..n)
        .filter(|&i| below[i] && above[i])
        .map(|i| places[i].0)
        .collect()
}

/// Why `auto` passes over a hetero residue, or `None` when it is a candidate.
/// A hetero residue [`within_polymer`] is a modified residue of the polymer
/// (a tRNA's modified nucleotides, a modified amino acid not in
/// [`AUTO_SKIPPED`]).
fn auto_skip_reason(g: &Group<'_>, within: &WithinPolymer<'_>) -> Option<&'static str> {
    if is_water(g.name) {
        Some("water")
    } else if g.atoms.len() == 1 {
        Some("single atom")
    } else if AUTO_SKIPPED.contains(&g.name.to_ascii_uppercase().as_str()) {
        Some("ion, additive or modified amino acid")
    } else if within.contains(&(g.chain, g.seq)) {
        Some("modified residue within a polymer chain")
    } else {
        None
    }
}

/// `MTX ×2, CA, CL ×2`: the non-water hetero residue names present, with copy
/// counts, in file order; `None` when there are none.
fn hetero_summary(groups: &[Group<'_>]) -> Option<String> {
    let mut names: Vec<(&str, usize)> = Vec::new();
    for g in groups.iter().filter(|g| g.hetero && !is_water(g.name)) {
        match names.iter_mut().find(|(n, _)| *n == g.name) {
            Some(entry) => entry.1 += 1,
            None => names.push((g.name, 1)),
        }
    }
    if names.is_empty() {
        return None;
    }
    Some(
        names
            .iter()
            .map(|(n, c)| {
                if *c == 1 {
                    (*n).to_string()
                } else {
                    format!("{n} ×{c}")
                }
            })
            .collect::<Vec<_>>()
            .join(", "),
    )
}

/// Picks the drug's residue copy.
fn pick(s: &Structure, groups: &[Group<'_>], spec: &LigandSpec) -> Result<usize, LoadError> {
    let fail = |reason: String| LoadError::Ligand {
        path: s.name.clone(),
        reason,
    };
    let present = || {
        hetero_summary(groups).map_or_else(
            || "the file has no hetero residues other than water".to_string(),
            |h| format!("hetero residues present: {h}"),
        )
    };
    match spec {
        LigandSpec::Auto => {
            let within = within_polymer(groups);
            let mut best: Option<usize> = None;
            for (i, g) in groups.iter().enumerate() {
                if !g.hetero || auto_skip_reason(g, &within).is_some() {
                    continue;
                }
                if best.is_none_or(|b| g.atoms.len() > groups[b].atoms.len()) {
                    best = Some(i);
                }
            }
            best.ok_or_else(|| {
                // Names by reason, each in first-seen order: `MG, MN (single atom)`.
                let mut by_reason: Vec<(&str, Vec<&str>)> = Vec::new();
                for g in groups.iter().filter(|g| g.hetero && !is_water(g.name)) {
                    let Some(r) = auto_skip_reason(g, &within) else {
                        continue;
                    };
                    match by_reason.iter_mut().find(|(q, _)| *q == r) {
                        Some((_, names)) if names.contains(&g.name) => {}
                        Some((_, names)) => names.push(g.name),
                        None => by_reason.push((r, vec![g.name])),
                    }
                }
                let skipped: Vec<String> = by_reason
                    .iter()
                    .map(|(r, names)| format!("{} ({r})", names.join(", ")))
                    .collect();
                if skipped.is_empty() {
                    fail(format!(
                        "no ligand found automatically: {}; give the drug as a separate file",
                        present()
                    ))
                } else {
                    fail(format!(
                        "no ligand found automatically: the only hetero residues are {}, \
                         which auto skips; name one (e.g. {}) or give the drug as a separate file",
                        skipped.join("; "),
                        groups
                            .iter()
                            .find(|g| g.hetero && !is_water(g.name))
                            .map_or("RESNAME", |g| g.name)
                    ))
                }
            })
        }
        LigandSpec::Residue {
            name,
            chain,
            seq,
            insertion,
        } => {
            let same_name = |g: &&Group<'_>| g.name.eq_ignore_ascii_case(name);
            if let Some(i) = groups.iter().position(|g| {
                same_name(&g)
                    && chain.as_deref().is_none_or(|c| g.chain == c)
                    && seq.is_none_or(|q| g.seq == q)
                    && insertion.as_deref().is_none_or(|c| g.insertion == c)
            }) {
                return Ok(i);
            }
            let copies: Vec<String> = groups.iter().filter(same_name).map(Group::label).collect();
            if copies.is_empty() {
                let hydrogen_only: Vec<&str> = s
                    .hydrogen_only
                    .iter()
                    .filter(|(n, _)| n.eq_ignore_ascii_case(name))
                    .map(|(_, at)| at.as_str())
                    .collect();
                if hydrogen_only.is_empty() {
                    Err(fail(format!("no residue named {name}; {}", present())))
                } else {
                    Err(fail(format!(
                        "residue {name} ({}) has only hydrogen atoms, which are dropped by \
                         default (--hydrogens keep keeps them)",
                        hydrogen_only.join(", ")
                    )))
                }
            } else {
                Err(fail(format!(
                    "no residue {spec}; copies of {name} present: {}",
                    copies.join(", ")
                )))
            }
        }
    }
}

/// Splits a complex into `(receptor, drug)`.
///
/// The drug is one residue copy chosen by `spec` (see the module docs); the
/// receptor is every other atom except waters. They are named
/// `"<file> receptor"` and `"<file> <RES> <chain>/<seq>"` (e.g.
/// `"4dfr.pdb MTX A/161"`).
///
/// # Errors
/// [`LoadError::Ligand`] when no residue matches (the message lists the hetero
/// residues present) or when nothing is left for the receptor.
pub fn split_complex(s: &Structure, spec: &LigandSpec) -> Result<(Molecule, Molecule), LoadError> {
    let groups = residue_groups(s);
    let chosen = &groups[pick(s, &groups, spec)?];
    let mut in_drug = vec![false; s.atoms.len()];
    for &i in &chosen.atoms {
        in_drug[i] = true;
    }
    let receptor_atoms: Vec<usize> = (0..s.atoms.len())
        .filter(|&i| !in_drug[i] && !left_out(s, i))
        .collect();
    if receptor_atoms.is_empty() {
        return Err(LoadError::Ligand {
            path: s.name.clone(),
            reason: format!(
                "nothing is left for the receptor after taking {} as the drug and removing waters",
                chosen.label()
            ),
        });
    }
    let receptor = molecule_from(s, &receptor_atoms, format!("{} receptor", s.name));
    let drug = molecule_from(s, &chosen.atoms, format!("{} {}", s.name, chosen.label()));
    Ok((receptor, drug))
}

/// The molecule made of `s`'s atoms `indices` (ascending), with the file's
/// hydrogens bonded to them, the bonds among them and their formal charges.
pub fn molecule_from(s: &Structure, indices: &[usize], name: String) -> Molecule {
    let atoms: Vec<AtomInfo> = indices.iter().map(|&i| s.atoms[i].clone()).collect();
    let positions: Vec<DVec3> = indices.iter().map(|&i| s.positions[i]).collect();
    let mut mol = Molecule::new(name, atoms, &positions);
    attach_file_chemistry(&mut mol, &s.bonds, &s.file_chem, s.atoms.len(), indices);
    mol
}

/// Gives `mol`, made of the atoms `indices` (ascending) of a structure of
/// `total` atoms, the structure's `bonds` among them, their formal charges
/// and the hydrogens bonded to them.
fn attach_file_chemistry(
    mol: &mut Molecule,
    bonds: &[FileBond],
    fc: &FileChemistry,
    total: usize,
    indices: &[usize],
) {
    let mut new_index = vec![u32::MAX; total];
    for (k, &i) in indices.iter().enumerate() {
        new_index[i] = u32::try_from(k).unwrap_or(u32::MAX);
    }
    mol.file_bonds = bonds
        .iter()
        .filter(|b| new_index[b.a] != u32::MAX && new_index[b.b] != u32::MAX)
        .map(|b| Bond::new(new_index[b.a], new_index[b.b], b.order))
        .collect();
    if fc.formal_charges.len() == total && indices.iter().any(|&i| fc.formal_charges[i] != 0) {
        mol.formal_charges = indices.iter().map(|&i| fc.formal_charges[i]).collect();
    }
    mol.bonds_complete = fc.bonds_complete && indices.len() == total;
    mol.from_sdf = fc.from_sdf;
    let file_ad = fc
        .autodock
        .as_ref()
        .filter(|ad| ad.atoms.len() == total && ad.hydrogens.len() == fc.hydrogens.len());
    let mut ad = file_ad.map(|ad| AutoDockData {
        atoms: indices.iter().map(|&i| ad.atoms[i]).collect(),
        hydrogens: Vec::new(),
        branches: ad
            .branches
            .iter()
            .map(|&[a, b]| [new_index[a as usize], new_index[b as usize]])
            .filter(|[a, b]| *a != u32::MAX && *b != u32::MAX)
            .collect(),
        tree: ad.tree,
    });
    for (k, h) in fc.hydrogens.iter().enumerate() {
        let Some(p) = h.parent.filter(|&p| new_index[p] != u32::MAX) else {
            continue;
        };
        if let (Some(ad), Some(file)) = (ad.as_mut(), file_ad) {
            ad.hydrogens.push(file.hydrogens[k]);
        }
        // Written before the first kept atom at or after its place.
        let before = indices.partition_point(|&i| i < h.before);
        mol.hydrogens.push(
            new_index[p],
            (h.position - mol.centre).as_vec3(),
            h.atom.serial,
            u32::try_from(before).unwrap_or(u32::MAX),
            &h.atom.name,
        );
    }
    mol.autodock = ad;
}

/// True when atom `i` of `s` is left out of a receptor: a water, unless the
/// file is a PDBQT, prepared for docking, whose waters Vina scores.
fn left_out(s: &Structure, i: usize) -> bool {
    s.file_chem.autodock.is_none() && is_water(&s.atoms[i].residue)
}

/// The whole structure as a receptor: every atom except waters, named
/// `"<file> receptor"`.
///
/// # Errors
/// [`LoadError::OnlyWaters`] when only waters remain, [`LoadError::NoAtoms`]
/// when nothing does.
pub fn receptor_only(s: &Structure) -> Result<Molecule, LoadError> {
    let indices: Vec<usize> = (0..s.atoms.len()).filter(|&i| !left_out(s, i)).collect();
    if indices.is_empty() {
        return Err(if s.atoms.is_empty() {
            LoadError::NoAtoms {
                path: s.name.clone(),
                dropped_hydrogens: 0,
            }
        } else {
            LoadError::OnlyWaters {
                path: s.name.clone(),
                waters: s.atoms.len(),
            }
        });
    }
    Ok(molecule_from(s, &indices, format!("{} receptor", s.name)))
}

/// [`split_complex`] taking the structure: its atoms move into the two
/// molecules rather than being copied (the receptor's in place), so that a
/// large structure is not held twice while it is split.
///
/// # Errors
/// As [`split_complex`].
pub fn split_complex_owned(
    s: Structure,
    spec: &LigandSpec,
) -> Result<(Molecule, Molecule), LoadError> {
    let (chosen, label) = {
        let groups = residue_groups(&s);
        let g = &groups[pick(&s, &groups, spec)?];
        (g.atoms.clone(), g.label())
    };
    let mut in_drug = vec![false; s.atoms.len()];
    for &i in &chosen {
        in_drug[i] = true;
    }
    let receptor_indices: Vec<usize> = (0..s.atoms.len())
        .filter(|&i| !in_drug[i] && !left_out(&s, i))
        .collect();
    drop(in_drug);
    if receptor_indices.is_empty() {
        return Err(LoadError::Ligand {
            path: s.name,
            reason: format!(
                "nothing is left for the receptor after taking {label} as the drug and removing waters"
            ),
        });
    }
    let drug = molecule_from(&s, &chosen, format!("{} {label}", s.name));
    let receptor = molecule_moved(s, &receptor_indices, |name| format!("{name} receptor"));
    Ok((receptor, drug))
}

/// [`molecule_from`] taking the structure: the atoms `indices` (ascending)
/// move into the molecule in place rather than being copied.
fn molecule_moved(s: Structure, indices: &[usize], name: impl Fn(&str) -> String) -> Molecule {
    let Structure {
        name: file,
        mut atoms,
        mut positions,
        bonds,
        file_chem,
        ..
    } = s;
    let total = atoms.len();
    let mut keep = vec![false; total];
    for &i in indices {
        keep[i] = true;
    }
    let mut k = 0;
    atoms.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    let mut k = 0;
    positions.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    drop(keep);
    let mut mol = Molecule::new(name(&file), atoms, &positions);
    drop(positions);
    attach_file_chemistry(&mut mol, &bonds, &file_chem, total, indices);
    mol
}

/// [`receptor_only`] taking the structure: its atoms move into the
/// molecule in place rather than being copied.
///
/// # Errors
/// As [`receptor_only`].
pub fn receptor_only_owned(s: Structure) -> Result<Molecule, LoadError> {
    let indices: Vec<usize> = (0..s.atoms.len()).filter(|&i| !left_out(&s, i)).collect();
    if indices.is_empty() {
        return Err(if s.atoms.is_empty() {
            LoadError::NoAtoms {
                path: s.name,
                dropped_hydrogens: 0,
            }
        } else {
            LoadError::OnlyWaters {
                waters: s.atoms.len(),
                path: s.name,
            }
        });
    }
    Ok(molecule_moved(s, &indices, |name| {
        format!("{name} receptor")
    }))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use crate::model::{Hydrogens, LoadOptions, load};

    /// The shared test-data folder, or `None` (after saying so) when it is
    /// missing outside CI. In CI a missing folder fails the test.
    use crate::model::test_data_dir as data_dir;

    fn structure(file: &str, hydrogens: Hydrogens) -> Option<Structure> {
        let dir = data_dir()?;
        let opts = LoadOptions {
            hydrogens,
            ..LoadOptions::default()
        };
        Some(
            load(&dir.join(file), &opts)
                .unwrap_or_else(|e| panic!("{file}: {e}"))
                .structure,
        )
    }

    fn spec(s: &str) -> LigandSpec {
        LigandSpec::parse(s).unwrap()
    }

    #[test]
    fn parse_specs() {
        assert_eq!(spec("AUTO"), LigandSpec::Auto);
        assert_eq!(
            spec("mtx"),
            LigandSpec::Residue {
                name: "MTX".into(),
                chain: None,
                seq: None,
                insertion: None
            }
        );
        assert_eq!(
            spec("MTX:B:162"),
            LigandSpec::Residue {
                name: "MTX".into(),
                chain: Some("B".into()),
                seq: Some(162),
                insertion: None
            }
        );
        assert_eq!(
            spec("MTX::-3"),
            LigandSpec::Residue {
                name: "MTX".into(),
                chain: None,
                seq: Some(-3),
                insertion: None
            }
        );
        assert_eq!(
            spec("MTX:A:52a"),
            LigandSpec::Residue {
                name: "MTX".into(),
                chain: Some("A".into()),
                seq: Some(52),
                insertion: Some("a".into())
            }
        );
        assert_eq!(spec("MTX:A:-52B").to_string(), "MTX:A:-52B");
        assert_eq!(spec("MTX:B:162").to_string(), "MTX:B:162");
        assert_eq!(spec("MTX::7").to_string(), "MTX::7");
        assert_eq!(spec("MTX:b").to_string(), "MTX:b");
        for bad in [
            "",
            ":A",
            "MTX:A:x",
            "MTX:A:5x2",
            "MTX:A:B52",
            "A:B:C:D",
            "M X",
        ] {
            assert!(LigandSpec::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn six_xg5_top_heavy_and_with_hydrogens() {
        let Some(s) = structure("6xg5_tmp_prepared.pdb", Hydrogens::Drop) else {
            return;
        };
        let (rec, drug) = split_complex(&s, &spec("TOP")).unwrap();
        assert_eq!(drug.len(), 21);
        assert_eq!(rec.len(), 1268);
        assert_eq!(drug.name, "6xg5_tmp_prepared.pdb TOP X/0");
        assert_eq!(rec.name, "6xg5_tmp_prepared.pdb receptor");
        let (_, auto) = split_complex(&s, &LigandSpec::Auto).unwrap();
        assert_eq!(auto.len(), 21);

        let h = structure("6xg5_tmp_prepared.pdb", Hydrogens::Keep).unwrap();
        let (rec_h, drug_h) = split_complex(&h, &spec("top")).unwrap();
        assert_eq!(drug_h.len(), 39);
        assert_eq!(rec_h.len(), 2491);
    }

    #[test]
    fn trimethoprim_sdf_matches_the_pdb_residue() {
        let Some(s) = structure("6xg5_tmp_prepared.pdb", Hydrogens::Drop) else {
            return;
        };
        let (_, drug) = split_complex(&s, &spec("TOP")).unwrap();
        let dir = data_dir().unwrap();
        let sdf = load(
            &dir.join("trimethoprim_top_6xg5pose.sdf"),
            &LoadOptions::default(),
        )
        .unwrap()
        .structure;
        let from_pdb = drug.file_positions();
        assert_eq!(sdf.positions.len(), from_pdb.len());
        for (i, (a, b)) in sdf.positions.iter().zip(&from_pdb).enumerate() {
            assert!((*a - *b).length() < 1e-3, "atom {i}: {a} vs {b}");
            assert_eq!(sdf.atoms[i].element, drug.atoms[i].element, "atom {i}");
        }
    }

    #[test]
    fn four_dfr_copies() {
        let Some(s) = structure("4dfr.pdb", Hydrogens::Drop) else {
            return;
        };
        let (rec, first) = split_complex(&s, &spec("MTX")).unwrap();
        assert_eq!(first.len(), 33);
        assert!(first.atoms.iter().all(|a| a.chain == "A" && a.seq == 161));
        assert_eq!(first.name, "4dfr.pdb MTX A/161");
        let waters = s.atoms.iter().filter(|a| is_water(&a.residue)).count();
        assert_eq!(rec.len(), s.atoms.len() - 33 - waters);

        let (_, second) = split_complex(&s, &spec("MTX:B:162")).unwrap();
        assert_eq!(second.len(), 33);
        assert!(second.atoms.iter().all(|a| a.chain == "B" && a.seq == 162));
        let (_, by_chain) = split_complex(&s, &spec("mtx:B")).unwrap();
        assert_eq!(by_chain.centre, second.centre);

        let err = split_complex(&s, &spec("MTX:C")).unwrap_err().to_string();
        assert!(
            err.contains("4dfr.pdb") && err.contains("MTX B/162"),
            "{err}"
        );
        let err = split_complex(&s, &spec("XYZ")).unwrap_err().to_string();
        assert!(err.contains("MTX ×2") && err.contains("CL ×2"), "{err}");

        // The second copy given an insertion code: picked by it, and by its
        // number alone; another code is refused with the copies listed.
        let mut coded = s.clone();
        for a in &mut coded.atoms {
            if a.residue == "MTX" && a.chain == "B" {
                a.insertion = "A".into();
            }
        }
        let (_, by_code) = split_complex(&coded, &spec("MTX:B:162A")).unwrap();
        assert_eq!(by_code.centre, second.centre);
        assert_eq!(by_code.name, "4dfr.pdb MTX B/162A");
        let (_, by_number) = split_complex(&coded, &spec("MTX:B:162")).unwrap();
        assert_eq!(by_number.centre, second.centre);
        let err = split_complex(&coded, &spec("MTX::162B"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("MTX B/162A"), "{err}");
    }

    #[test]
    fn auto_picks() {
        for (file, name, n) in [
            ("3ptb.pdb", "BEN", 9),
            ("1hvr.pdb", "XK2", 46),
            ("1u72.pdb", "NDP", 48),
            ("1dt6.pdb", "HEM", 43),
        ] {
            let Some(s) = structure(file, Hydrogens::Drop) else {
                return;
            };
            let (_, drug) = split_complex(&s, &LigandSpec::Auto).unwrap();
            assert_eq!(drug.atoms[0].residue, name, "{file}");
            assert_eq!(drug.len(), n, "{file}");
        }
        let s = structure("1u72.pdb", Hydrogens::Drop).unwrap();
        let (_, mtx) = split_complex(&s, &spec("MTX")).unwrap();
        assert_eq!(mtx.len(), 33);
    }

    /// Why `auto` finds no ligand in `s`.
    fn auto_error(s: &Structure) -> String {
        split_complex(s, &LigandSpec::Auto).unwrap_err().to_string()
    }

    #[test]
    fn auto_errors_list_what_is_there() {
        let Some(s) = structure("1ubq.pdb", Hydrogens::Drop) else {
            return;
        };
        let err = auto_error(&s);
        assert!(
            err.contains("1ubq.pdb") && err.contains("no hetero"),
            "{err}"
        );
        let err = auto_error(&structure("1azv.pdb", Hydrogens::Drop).unwrap());
        assert!(err.contains("CU") && err.contains("single atom"), "{err}");
    }

    #[test]
    fn auto_passes_over_modified_residues_within_a_chain() {
        // tRNA-Phe: eleven kinds of modified nucleotide, runs of them
        // (PSU 39, 5MC 40) included, and magnesium and manganese ions.
        let Some(s) = structure("1ehz.cif", Hydrogens::Drop) else {
            return;
        };
        let err = auto_error(&s);
        assert!(
            err.contains("YYG") && err.contains("5MC") && err.contains("within a polymer chain"),
            "{err}"
        );
        // Named, one is still taken.
        let (_, yyg) = split_complex(&s, &spec("YYG")).unwrap();
        assert!(yyg.len() > 20);
        // A hetero residue numbered right after the chain's last residue (a
        // ligand) is not within it: the rule needs a polymer residue on
        // both sides.
        let mut groups = residue_groups(&s);
        let last = groups
            .iter()
            .filter(|g| !g.hetero && g.chain == "A")
            .map(|g| g.seq)
            .max()
            .unwrap();
        let ligand = Group {
            chain: "A",
            seq: last + 1,
            insertion: "",
            name: "LIG",
            hetero: true,
            atoms: vec![0, 1],
        };
        groups.push(ligand.clone());
        let within = within_polymer(&groups);
        assert_eq!(auto_skip_reason(&ligand, &within), None);
        let yyg = groups.iter().find(|g| g.name == "YYG").unwrap();
        assert!(within.contains(&(yyg.chain, yyg.seq)));
        // ... and numbered as the chain's next residue, the same ligand is.
        groups.push(Group {
            seq: last + 2,
            name: "ALA",
            hetero: false,
            ..ligand.clone()
        });
        assert!(within_polymer(&groups).contains(&("A", last + 1)));
    }

    /// A chain of hetero residues alone (no polymer in it) has none within
    /// a polymer, at either end of the numbers `i64` holds.
    #[test]
    fn hetero_chains_are_not_within_a_polymer() {
        let group = |seq: i64, hetero: bool| Group {
            chain: "A",
            seq,
            insertion: "",
            name: if hetero { "LIG" } else { "ALA" },
            hetero,
            atoms: vec![0, 1],
        };
        let run: Vec<Group<'_>> = (0..5)
            .map(|k| group(i64::MAX - k, true))
            .chain((0..5).map(|k| group(i64::MIN + k, true)))
            .collect();
        assert!(within_polymer(&run).is_empty());
        // Polymer at both ends: everything between is within.
        let mut run: Vec<Group<'_>> = (1..=20).map(|k| group(k, true)).collect();
        run.extend([group(0, false), group(21, false)]);
        assert_eq!(within_polymer(&run).len(), 20);
    }

    #[test]
    fn receptor_only_drops_waters() {
        let Some(s) = structure("1ubq.pdb", Hydrogens::Drop) else {
            return;
        };
        let r = receptor_only(&s).unwrap();
        assert_eq!(r.len(), 602);
        assert_eq!(r.name, "1ubq.pdb receptor");
        let waters = Structure {
            name: "w.pdb".into(),
            atoms: s
                .atoms
                .iter()
                .filter(|a| is_water(&a.residue))
                .cloned()
                .collect(),
            positions: vec![glam::DVec3::ZERO; 58],
            hydrogen_only: Vec::new(),
            bonds: Vec::new(),
            file_chem: Default::default(),
        };
        let err = receptor_only(&waters).unwrap_err();
        assert!(matches!(err, LoadError::OnlyWaters { waters: 58, .. }));
        assert_eq!(
            err.to_string(),
            "w.pdb: only waters (58 atoms), which are never part of a receptor or a drug"
        );
    }
}
