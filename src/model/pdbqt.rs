//! Reading PDBQT files (plain or gzipped): AutoDock's receptors and
//! ligands, and AutoDock Vina's docked poses.
//!
//! A PDBQT atom record is a PDB one up to column 66, then a partial charge
//! (columns 69–76) and an AutoDock type (column 78 to the line's end, as
//! Vina reads it: `A`, `NA`, `OA`, `HD`, Meeko's `CG0`, …, case-sensitive);
//! a ligand also has a torsion tree (`ROOT`, `BRANCH a b`, `ENDBRANCH`,
//! `TORSDOF`). A docking's output holds one pose per `MODEL`;
//! [`LoadOptions::sdf_record`] picks one (1-based, the first by default).
//!
//! The reader turns each atom record into a PDB record whose element is its
//! type's and reads those through the PDB reader (same checks, same
//! messages, line numbers unchanged). Beside the structure it keeps what
//! the file states for scoring ([`AutoDockData`]): each atom's type and
//! charge, the rotatable bonds of its tree (the `BRANCH` records), so that
//! the chemistry types atoms and counts torsions as Vina does from the same
//! file.
//!
//! - Macrocycle closure and water pseudo-atoms (`G0`–`G3`, `W`) are not
//!   atoms: they are left out with a warning.
//! - The side chains a flexible docking's output holds beside the ligand
//!   (`BEGIN_RES` … `END_RES`) are the receptor's: they are left out too,
//!   unless the file holds nothing else (a flexible-residue input file).
//! - A receptor's waters are kept (see [`super::select`]).
//! - An unknown type, a charge that is not a number, a `BRANCH` naming an
//!   atom the file does not have, or a model past the last is an error
//!   naming the file's line.
//!
//! [`super::write::pdbqt_text`] writes such a molecule back, with its tree.

use std::path::Path;

use glam::DVec3;

use super::label::AtomName;
use super::pdb::{self, Format, file_name, read_bytes};
use super::{Label, LoadError, LoadOptions, Loaded};
use crate::chem::autodock::AdType;
use crate::text::excerpt;

/// What a PDBQT file states about one atom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdAtom {
    /// Its AutoDock type.
    pub ad: AdType,
    /// Its partial charge (e), as the file gives it.
    pub charge: f32,
}

/// What a PDBQT file states beyond the atoms: in a
/// [`Structure`](super::Structure) indexed like its atoms and hydrogens, in
/// a [`Molecule`](super::Molecule) like the molecule's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AutoDockData {
    /// Per atom: type and charge.
    pub atoms: Vec<AdAtom>,
    /// Per hydrogen kept apart from the atoms: type and charge.
    pub hydrogens: Vec<AdAtom>,
    /// The torsion tree's rotatable bonds (its `BRANCH` records), as pairs
    /// of atom indices.
    pub branches: Vec<[u32; 2]>,
    /// True when the file has a torsion tree (`ROOT`): then its branches,
    /// and only they, are the rotatable bonds.
    pub tree: bool,
}

/// One atom record of the chosen model, as read here.
struct Record {
    serial: i64,
    name: AtomName,
    position: Option<DVec3>,
    atom: AdAtom,
    /// Where its PDB line lies in the text given to the PDB reader.
    line: std::ops::Range<usize>,
    /// Inside a `BEGIN_RES` … `END_RES` block (a flexible residue).
    flexible: bool,
}

/// Reads one model of a PDBQT file (plain, or gzipped `.pdbqt.gz`).
///
/// # Errors
/// [`LoadError::Io`] for an unreadable file; [`LoadError::Parse`] naming
/// the line for a malformed record or a model past the last; the PDB
/// reader's errors for the atom records.
pub fn load_pdbqt(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let bytes = read_bytes(path, opts.max_decompressed())?;
    let text = String::from_utf8_lossy(&bytes);
    parse_pdbqt(&text, &path.display().to_string(), &file_name(path), opts)
}

/// Parses PDBQT text already in memory. `label` names the source in
/// messages; `name` becomes [`Structure::name`](super::Structure::name).
///
/// # Errors
/// As [`load_pdbqt`], less the I/O error.
pub fn parse_pdbqt(
    text: &str,
    label: &str,
    name: &str,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    let want = opts.sdf_record.unwrap_or(1);
    let err = |line: usize, column: Option<usize>, reason: String| {
        LoadError::parse_at(label, Some(line), column, reason)
    };
    let mut pdb = String::with_capacity(text.len());
    let mut records: Vec<Record> = Vec::new();
    let mut branches: Vec<(i64, i64, usize)> = Vec::new();
    let mut tree = false;
    // (macrocycle closures, waters) left out.
    let mut pseudo = (0usize, 0usize);
    let (mut models, mut in_model) = (0usize, false);
    let mut in_residue = false;
    let mut notes = Vec::new();
    for (k, line) in crate::text::lines::split_str(text).enumerate() {
        let number = k + 1;
        let line = line.trim_end_matches(['\r', '\n']);
        let chosen = if in_model {
            models == want
        } else {
            models == 0
        };
        if line.starts_with("MODEL") {
            models += 1;
            in_model = true;
            pdb.push('\n');
            continue;
        }
        if line.starts_with("ENDMDL") {
            in_model = false;
            pdb.push('\n');
            continue;
        }
        if !chosen {
            pdb.push('\n');
            continue;
        }
        if line.starts_with("ATOM  ") || line.starts_with("HETATM") {
            let record = atom_record(line).map_err(|(c, r)| err(number, Some(c), r))?;
            if record.atom.ad.element().is_none() {
                if record.atom.ad == AdType::W {
                    pseudo.1 += 1;
                } else {
                    pseudo.0 += 1;
                }
                pdb.push('\n');
                continue;
            }
            let start = pdb.len();
            push_as_pdb(&mut pdb, line, record.atom.ad);
            records.push(Record {
                line: start..pdb.len() - 1,
                flexible: in_residue,
                ..record
            });
        } else if line.starts_with("BEGIN_RES") {
            in_residue = true;
            pdb.push('\n');
        } else if line.starts_with("END_RES") {
            in_residue = false;
            pdb.push('\n');
        } else if line.starts_with("ROOT") {
            tree = true;
            pdb.push('\n');
        } else if let Some(rest) = line.strip_prefix("BRANCH") {
            let (a, b) = two_serials(rest).ok_or_else(|| {
                err(
                    number,
                    None,
                    format!(
                        "a BRANCH record names two atom serial numbers: {}",
                        excerpt(line)
                    ),
                )
            })?;
            branches.push((a, b, number));
            pdb.push('\n');
        } else if line.starts_with("TER") {
            // Chains end as in a PDB file.
            pdb.push_str("TER\n");
        } else {
            // REMARK, TORSDOF, ENDROOT, ENDBRANCH: nothing the structure
            // needs.
            pdb.push('\n');
        }
    }
    // A flexible docking's output holds the moved side chains beside the
    // ligand, in BEGIN_RES blocks: they belong to the receptor, not the
    // drug. A file of nothing but such blocks (Vina's flex input) is read
    // whole.
    let flexible = records.iter().filter(|r| r.flexible).count();
    if flexible > 0 && flexible < records.len() {
        for r in records.iter().filter(|r| r.flexible) {
            // Spaces keep the line numbers; the PDB reader passes them by.
            pdb.replace_range(r.line.clone(), &" ".repeat(r.line.len()));
        }
        records.retain(|r| !r.flexible);
        let kept: std::collections::HashSet<i64> = records.iter().map(|r| r.serial).collect();
        branches.retain(|(a, b, _)| kept.contains(a) && kept.contains(b));
        notes.push(format!(
            "{label}: {flexible} atom(s) of flexible residues (BEGIN_RES blocks) are the \
             receptor's side chains, not the drug's; left out"
        ));
    }
    if want > models.max(1) {
        return Err(LoadError::parse_at(
            label,
            None,
            None,
            if models == 0 {
                format!("model {want} was asked for; the file has no MODEL records, only one model")
            } else {
                format!("model {want} was asked for; the file has {models}")
            },
        ));
    }
    let keep_h = LoadOptions {
        hydrogens: super::Hydrogens::Keep,
        sdf_record: None,
        ..opts.clone()
    };
    let mut loaded = pdb::parse_bytes(pdb.as_bytes(), Format::Pdb, label, name, &keep_h)?;
    let s = &mut loaded.structure;
    // The PDB reader keeps the records in order, less alternate locations.
    let mut index_of_record = vec![None; records.len()];
    let mut atoms = Vec::with_capacity(s.atoms.len());
    let mut r = 0;
    for (i, (a, p)) in s.atoms.iter().zip(&s.positions).enumerate() {
        while r < records.len() {
            let rec = &records[r];
            r += 1;
            if rec.serial == a.serial && rec.name == a.name && rec.position == Some(*p) {
                index_of_record[r - 1] = Some(i);
                atoms.push(rec.atom);
                break;
            }
        }
    }
    if atoms.len() != s.atoms.len() {
        return Err(LoadError::parse_at(
            label,
            None,
            None,
            "the atom records could not be matched with their AutoDock types",
        ));
    }
    // A BRANCH names an atom by serial: the first record with it, as Vina
    // takes it.
    let mut first_of: std::collections::HashMap<i64, usize> = std::collections::HashMap::new();
    for (k, r) in records.iter().enumerate() {
        first_of.entry(r.serial).or_insert(k);
    }
    let mut pairs = Vec::with_capacity(branches.len());
    for (a, b, line) in branches {
        let find = |serial: i64| {
            first_of.get(&serial).copied().ok_or_else(|| {
                err(
                    line,
                    None,
                    format!("BRANCH names atom {serial}, which the file does not have"),
                )
            })
        };
        let (ra, rb) = (find(a)?, find(b)?);
        if let (Some(i), Some(j)) = (index_of_record[ra], index_of_record[rb]) {
            let (i, j) = (u32::try_from(i), u32::try_from(j));
            if let (Ok(i), Ok(j)) = (i, j) {
                pairs.push([i, j]);
            }
        }
    }
    s.file_chem.autodock = Some(AutoDockData {
        atoms,
        hydrogens: Vec::new(),
        branches: pairs,
        tree,
    });
    loaded.warnings.extend(notes);
    let (closure, waters) = pseudo;
    if closure > 0 {
        loaded.warnings.push(format!(
            "{label}: {closure} macrocycle closure pseudo-atom(s) (G0-G3) are not atoms and are \
             left out; Vina's glue term that closes the ring is not computed"
        ));
    }
    if waters > 0 {
        loaded.warnings.push(format!(
            "{label}: {waters} hydrated-docking water(s) (W) are left out, as Vina's vina and \
             vinardo functions leave them out"
        ));
    }
    Ok(loaded)
}

/// Reads an atom record's serial, name, position (when it reads), charge
/// (columns 69–76; blank reads 0) and type (column 78 on). The error is the
/// column it points at and the message.
fn atom_record(line: &str) -> Result<Record, (usize, String)> {
    let field = |range: std::ops::Range<usize>| line.get(range).unwrap_or("").trim();
    // Vina reads the type from column 78 to the end of the line, so
    // Meeko's three-letter closure carbons (`CG0`) read whole.
    let ad_text = line.get(77..).map(str::trim).unwrap_or("");
    if ad_text.is_empty() {
        return Err((
            78,
            "no AutoDock atom type from column 78 on (is this a PDB file named .pdbqt?)".into(),
        ));
    }
    let ad = AdType::parse(ad_text).ok_or_else(|| {
        (
            78,
            format!(
                "{} (from column 78) is not an AutoDock type Vina reads \
                 (types are case-sensitive: C, A, N, NA, OA, SA, HD, Cl, Br, Zn, ...)",
                excerpt(ad_text)
            ),
        )
    })?;
    let charge_text = field(68..76);
    let charge = if charge_text.is_empty() {
        0.0
    } else {
        match charge_text.parse::<f32>() {
            Ok(q) if q.is_finite() => q,
            _ => {
                return Err((
                    69,
                    format!(
                        "the partial charge (columns 69-76) is not a number: {}",
                        excerpt(charge_text)
                    ),
                ));
            }
        }
    };
    let xyz = [30..38, 38..46, 46..54].map(|r| field(r).parse::<f64>().ok());
    let position = match xyz {
        [Some(x), Some(y), Some(z)] => Some(DVec3::new(x, y, z)),
        _ => None,
    };
    Ok(Record {
        serial: field(6..11).parse().unwrap_or(0),
        name: Label::truncated(field(12..16)),
        position,
        atom: AdAtom { ad, charge },
        line: 0..0,
        flexible: false,
    })
}

/// Appends `line` as a PDB atom record: columns 1–66 as they are, the
/// element of `ad` in columns 77–78.
fn push_as_pdb(out: &mut String, line: &str, ad: AdType) {
    let head = line.get(..line.len().min(66)).unwrap_or(line);
    out.push_str(head);
    for _ in head.len()..76 {
        out.push(' ');
    }
    let element = ad.element().unwrap_or("X");
    if element.len() == 1 {
        out.push(' ');
    }
    out.push_str(element);
    out.push('\n');
}

/// The two whole numbers after a `BRANCH` keyword.
fn two_serials(rest: &str) -> Option<(i64, i64)> {
    let mut words = rest.split_whitespace();
    let a = words.next()?.parse().ok()?;
    let b = words.next()?.parse().ok()?;
    Some((a, b))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use crate::model::Hydrogens;

    /// A small ligand in Meeko's layout: an acetamide-like root, one branch
    /// to a hydroxyl.
    const LIGAND: &str = "\
REMARK SMILES CC(=O)NCO
ROOT
ATOM      1  C   UNL     1       0.000   0.000   0.000  1.00  0.00     0.051 C 
ATOM      2  C   UNL     1       1.500   0.000   0.000  1.00  0.00     0.217 C 
ATOM      3  O   UNL     1       2.100   1.050   0.000  1.00  0.00    -0.274 OA
ATOM      4  N   UNL     1       2.170  -1.170   0.000  1.00  0.00    -0.338 N 
ATOM      5  H   UNL     1       1.680  -2.060   0.000  1.00  0.00     0.163 HD
ATOM      6  C   UNL     1       3.620  -1.200   0.000  1.00  0.00     0.210 C 
ENDROOT
BRANCH   6   7
ATOM      7  O   UNL     1       4.100  -2.520   0.000  1.00  0.00    -0.380 O 
ATOM      8  H   UNL     1       5.070  -2.520   0.000  1.00  0.00     0.210 HD
ENDBRANCH   6   7
TORSDOF 1
";

    fn opts() -> LoadOptions {
        LoadOptions {
            hydrogens: Hydrogens::Keep,
            ..Default::default()
        }
    }

    #[test]
    fn types_charges_and_branches_are_read() {
        let l = parse_pdbqt(LIGAND, "lig.pdbqt", "lig.pdbqt", &opts()).unwrap();
        let s = &l.structure;
        assert_eq!(s.atoms.len(), 8);
        let ad = s.file_chem.autodock.as_ref().unwrap();
        assert!(ad.tree);
        assert_eq!(ad.branches, vec![[5, 6]]);
        let types: Vec<AdType> = ad.atoms.iter().map(|a| a.ad).collect();
        use AdType::*;
        assert_eq!(types, vec![C, C, OA, N, HD, C, O, HD]);
        assert_eq!(ad.atoms[2].charge, -0.274);
        let elements: Vec<&str> = s.atoms.iter().map(|a| a.element.as_str()).collect();
        assert_eq!(elements, vec!["C", "C", "O", "N", "H", "C", "O", "H"]);
        assert_eq!(s.positions[6], DVec3::new(4.1, -2.52, 0.0));
    }

    #[test]
    fn the_chemistry_takes_the_files_types_tree_and_charges() {
        use crate::chem::XsType;
        let mut l = parse_pdbqt(LIGAND, "lig.pdbqt", "lig.pdbqt", &opts()).unwrap();
        crate::model::set_hydrogens_apart(&mut l.structure);
        let mol = crate::model::receptor_only(&l.structure).unwrap();
        assert_eq!(mol.len(), 6);
        let c = mol.chemistry();
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
        use XsType::*;
        let xs: Vec<XsType> = c.xs.iter().map(|t| t.unwrap()).collect();
        // N is typed N (not an acceptor) with an HD: a donor only. The
        // hydroxyl O is typed O, not OA: a donor only, where bump's own
        // perception would make it a donor and acceptor.
        assert_eq!(xs, vec![C_H, C_P, O_A, N_D, C_P, O_D]);
        // The tree turns only C6-O7, where bump's own rule would also turn
        // N4-C6; O7 is terminal, so it counts ½.
        assert_eq!(c.torsions.bonds.len(), 1);
        let b = c.bonds[c.torsions.bonds[0].bond as usize];
        assert_eq!((b.a, b.b), (4, 5));
        assert_eq!(c.vina_torsion_count(), 0.5);
        // The file's charges, polar hydrogens apart.
        assert_eq!(c.charges[2], -0.274);
        assert_eq!(c.polar_hydrogen_charge[3], 0.163);
        assert_eq!(c.polar_hydrogen_charge[5], 0.21);
    }

    /// A tree that turns a ring bond (a macrocycle Meeko opened, here a
    /// cyclohexane): bump holds the ring, with one warning, and counts the
    /// bond in Vina's torsion count as Vina does (both atoms have two
    /// heavy neighbours: 1).
    #[test]
    fn a_branch_across_a_ring_is_held_and_counted() {
        let text = "ROOT\nATOM      1  C1  UNL     1       1.500   0.000   0.000  1.00  0.00     0.000 C \nATOM      2  C2  UNL     1       0.750   1.299   0.000  1.00  0.00     0.000 C \nATOM      3  C3  UNL     1      -0.750   1.299   0.000  1.00  0.00     0.000 C \nENDROOT\nBRANCH   3   4\nATOM      4  C4  UNL     1      -1.500   0.000   0.000  1.00  0.00     0.000 C \nATOM      5  C5  UNL     1      -0.750  -1.299   0.000  1.00  0.00     0.000 C \nATOM      6  C6  UNL     1       0.750  -1.299   0.000  1.00  0.00     0.000 C \nENDBRANCH   3   4\nTORSDOF 1\n";
        let l = parse_pdbqt(text, "ring.pdbqt", "ring.pdbqt", &opts()).unwrap();
        let mol = crate::model::receptor_only(&l.structure).unwrap();
        let c = mol.chemistry();
        assert!(c.torsions.bonds.is_empty());
        assert_eq!(c.vina_torsion_count(), 1.0);
        assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
        assert!(c.warnings[0].contains("ring bond") && c.warnings[0].contains("C3–C4"));
    }

    /// With `--hydrogens keep` the hydrogens are atoms, bonded, but not
    /// heavy neighbours: the hydroxyl's C–O still counts ½, as in Vina.
    #[test]
    fn kept_hydrogens_do_not_count_as_heavy_neighbours() {
        let l = parse_pdbqt(LIGAND, "lig.pdbqt", "lig.pdbqt", &opts()).unwrap();
        let mol = crate::model::receptor_only(&l.structure).unwrap();
        assert_eq!(mol.len(), 8, "hydrogens kept as atoms");
        let c = mol.chemistry();
        assert_eq!(c.torsions.bonds.len(), 1);
        assert_eq!(c.vina_torsion_count(), 0.5);
        assert_eq!(c.xs[6], Some(crate::chem::XsType::O_D));
    }

    #[test]
    fn models_are_records() {
        let two = format!(
            "MODEL 1\n{LIGAND}ENDMDL\nMODEL 2\n{}ENDMDL\n",
            LIGAND.replace("   0.000  1.00", "   1.000  1.00")
        );
        let first = parse_pdbqt(&two, "out.pdbqt", "out.pdbqt", &opts()).unwrap();
        assert_eq!(first.structure.positions[0].z, 0.0);
        let o = LoadOptions {
            sdf_record: Some(2),
            ..opts()
        };
        let second = parse_pdbqt(&two, "out.pdbqt", "out.pdbqt", &o).unwrap();
        assert_eq!(second.structure.positions[0].z, 1.0);
        assert_eq!(second.structure.atoms.len(), 8);
        let o = LoadOptions {
            sdf_record: Some(3),
            ..opts()
        };
        let e = parse_pdbqt(&two, "out.pdbqt", "out.pdbqt", &o)
            .unwrap_err()
            .to_string();
        assert!(e.contains("model 3") && e.contains("has 2"), "{e}");
    }

    #[test]
    fn bad_records_name_their_line() {
        let bad_type = LIGAND.replace("0.217 C ", "0.217 CL");
        let e = parse_pdbqt(&bad_type, "x.pdbqt", "x.pdbqt", &opts())
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.pdbqt:4") && e.contains("CL"), "{e}");
        let bad_charge = LIGAND.replace("-0.274", "-0.2x4");
        let e = parse_pdbqt(&bad_charge, "x.pdbqt", "x.pdbqt", &opts())
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.pdbqt:5") && e.contains("charge"), "{e}");
        let no_type = "ATOM      1  C   UNL     1       0.000   0.000   0.000  1.00  0.00\n";
        let e = parse_pdbqt(no_type, "x.pdbqt", "x.pdbqt", &opts())
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.pdbqt:1") && e.contains("column 78"), "{e}");
        let bad_branch = LIGAND.replace("BRANCH   6   7", "BRANCH   6  17");
        let e = parse_pdbqt(&bad_branch, "x.pdbqt", "x.pdbqt", &opts())
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.pdbqt:10") && e.contains("17"), "{e}");
    }

    #[test]
    fn a_pdbqt_receptor_keeps_its_waters() {
        let text = "\
ATOM      1  N   GLY A   1       0.000   0.000   0.000  1.00  0.00    -0.350 N 
ATOM      2  CA  GLY A   1       1.450   0.000   0.000  1.00  0.00     0.220 C 
ATOM      3  O   HOH A 101       5.000   0.000   0.000  1.00  0.00    -0.410 OA
";
        let l = parse_pdbqt(text, "r.pdbqt", "r.pdbqt", &opts()).unwrap();
        let r = crate::model::receptor_only(&l.structure).unwrap();
        assert_eq!(r.len(), 3, "Vina scores a PDBQT's waters, and so does bump");
        let pdb = text.replace("-0.350 N ", "").replace(" 0.220 C ", "");
        let pdb = pdb.replace("-0.410 OA", "");
        let p =
            crate::model::pdb::parse_bytes(pdb.as_bytes(), Format::Pdb, "r.pdb", "r.pdb", &opts())
                .unwrap();
        assert_eq!(crate::model::receptor_only(&p.structure).unwrap().len(), 2);
    }

    #[test]
    fn a_flexible_dockings_side_chains_are_not_the_drugs() {
        let out = format!(
            "MODEL 1\n{LIGAND}BEGIN_RES SER A  70\nREMARK  residue\nROOT\n\
ATOM     20  CA  SER A  70       8.000   0.000   0.000  1.00  0.00     0.200 C \n\
ENDROOT\nBRANCH  20  21\n\
ATOM     21  CB  SER A  70       9.500   0.000   0.000  1.00  0.00     0.200 C \n\
ENDBRANCH  20  21\nEND_RES SER A  70\nENDMDL\n"
        );
        let l = parse_pdbqt(&out, "out.pdbqt", "out.pdbqt", &opts()).unwrap();
        assert_eq!(l.structure.atoms.len(), 8);
        assert_eq!(
            l.structure.file_chem.autodock.as_ref().unwrap().branches,
            vec![[5, 6]]
        );
        assert!(
            l.warnings.iter().any(|w| w.contains("flexible residues")),
            "{:?}",
            l.warnings
        );
        // A flex file alone (nothing but residues) is read whole.
        let flex = "BEGIN_RES SER A  70\nROOT\n\
ATOM     20  CA  SER A  70       8.000   0.000   0.000  1.00  0.00     0.200 C \n\
ENDROOT\nEND_RES SER A  70\n";
        let l = parse_pdbqt(flex, "flex.pdbqt", "flex.pdbqt", &opts()).unwrap();
        assert_eq!(l.structure.atoms.len(), 1);
    }

    #[test]
    fn pseudo_atoms_are_left_out_with_a_warning() {
        let g = LIGAND.replace(
            "ENDROOT",
            "ATOM      9  G0  UNL     1       9.000   0.000   0.000  1.00  0.00     0.000 G0\nENDROOT",
        );
        let l = parse_pdbqt(&g, "g.pdbqt", "g.pdbqt", &opts()).unwrap();
        assert_eq!(l.structure.atoms.len(), 8);
        assert!(
            l.warnings.iter().any(|w| w.contains("G0-G3")),
            "{:?}",
            l.warnings
        );
    }
}
