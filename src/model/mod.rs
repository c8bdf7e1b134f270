//! Molecules: atoms, elements and radii, loading from PDB, mmCIF, PDBQT, SDF and
//! MOL2 files, splitting a complex into receptor and drug, and the built-in scene.
//!
//! Loading gives a [`Structure`]: every kept atom of the first model, with
//! alternate locations resolved and hydrogens dropped or kept as asked.
//! Dropped hydrogens are not lost: they are kept apart
//! ([`FileChemistry::hydrogens`]), each with its heavy atom, for the
//! chemistry ([`crate::chem`]) and the writer, never for collision.
//! [`select`] turns a structure into the receptor and drug [`Molecule`]s.

pub mod builtin;
pub mod element;
pub mod error;
pub mod label;
pub mod mol2;
pub mod molecule;
pub mod pdb;
pub mod pdbqt;
pub mod sdf;
pub mod select;
mod small;
pub mod write;

use std::path::Path;

use glam::DVec3;
use serde::Serialize;

pub use element::RadiiSet;
pub use error::LoadError;
pub use label::Label;
pub use molecule::{AtomInfo, AttachedHydrogens, Molecule};
pub use pdbqt::{AdAtom, AutoDockData};
pub use select::{
    LigandSpec, receptor_only, receptor_only_owned, split_complex, split_complex_owned,
};

/// Whether hydrogens are kept when loading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Hydrogens {
    /// Drop H and D atoms from the atoms (the default: crystal structures
    /// rarely have them, and hydrogen-bond contacts would read as
    /// collisions); they are kept apart for the chemistry and the writer.
    #[default]
    Drop,
    /// Keep them as atoms (collided and drawn; the chemistry counts them as
    /// their neighbours' hydrogens).
    Keep,
}

/// How to read a file.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Radius table.
    pub radii: RadiiSet,
    /// Keep or drop hydrogens.
    pub hydrogens: Hydrogens,
    /// For SDF and MOL2 files: which record (molecule, 1-based); for PDBQT
    /// which model (a docking's pose); the first when `None`. PDB and mmCIF
    /// have no records and refuse one ([`LoadError::NotRecords`]).
    pub sdf_record: Option<usize>,
    /// Most bytes a gzipped file may decompress to; past it the file is
    /// refused ([`LoadError::TooLarge`]). `None`: the environment variable
    /// [`DECOMPRESSED_LIMIT_VAR`] when it holds a size, else
    /// [`crate::text::DEFAULT_DECOMPRESSED_LIMIT`].
    pub decompressed_limit: Option<u64>,
}

/// The environment variable that sets the decompressed-size limit of
/// [`LoadOptions`] left at `None` (a size: `4GiB`, `500M`, `1000000`).
pub const DECOMPRESSED_LIMIT_VAR: &str = "BUMP_MAX_DECOMPRESSED";

impl LoadOptions {
    /// The decompressed-size limit in force (see
    /// [`field@LoadOptions::decompressed_limit`]); a variable that does not
    /// hold a size is passed over (the command line refuses it first).
    pub fn max_decompressed(&self) -> u64 {
        self.decompressed_limit
            .or_else(|| {
                let v = std::env::var(DECOMPRESSED_LIMIT_VAR).ok()?;
                crate::text::parse_byte_size(&v).ok()
            })
            .unwrap_or(crate::text::DEFAULT_DECOMPRESSED_LIMIT)
    }
}

/// Every kept atom of a file's first model, in file order.
#[derive(Debug, Clone)]
pub struct Structure {
    /// The file name, for messages and labels.
    pub name: String,
    /// Atom identities.
    pub atoms: Vec<AtomInfo>,
    /// File coordinates, same order as `atoms`.
    pub positions: Vec<DVec3>,
    /// Residues none of whose atoms were kept because all were hydrogens
    /// (dropped by default), as (name, `chain/seq`), in file order: so that
    /// asking for one as the ligand can say why it is not there.
    pub hydrogen_only: Vec<(String, String)>,
    /// Bonds the file states (an SDF bond block, PDB `CONECT` records, mmCIF
    /// `struct_conn`), between indices into `atoms`, each pair once with the
    /// lower index first, sorted. Bonds to atoms that were not kept (dropped
    /// hydrogens, other models) are left out.
    pub bonds: Vec<FileBond>,
    /// What else the file says about the chemistry: the hydrogens kept
    /// apart from `atoms`, formal charges, whether `bonds` is complete.
    pub file_chem: FileChemistry,
}

/// A hydrogen of the file kept apart from a structure's atoms (when
/// hydrogens are dropped): it takes no part in collision, but tells the
/// chemistry which atoms carry hydrogens, and the writer writes it.
#[derive(Debug, Clone)]
pub struct FileHydrogen {
    /// Its identity as the file gives it.
    pub atom: AtomInfo,
    /// File coordinates.
    pub position: DVec3,
    /// The heavy atom it is bonded to (index into [`Structure::atoms`]):
    /// the one the file's bonds give, else the nearest within
    /// [`HYDROGEN_BOND_REACH`]; `None` for a hydrogen bonded to nothing.
    pub parent: Option<usize>,
    /// How many of the structure's atoms precede it in the file (it is
    /// written before atom `before`).
    pub before: usize,
}

/// Farthest a hydrogen may be from the heavy atom it is given to (Å): an
/// S–H bond is 1.34 Å, and files written at low precision stretch it.
pub const HYDROGEN_BOND_REACH: f64 = 1.6;

/// The chemistry a file states beyond atoms and bonds.
#[derive(Debug, Clone, Default)]
pub struct FileChemistry {
    /// Hydrogens kept apart from the atoms, in file order.
    pub hydrogens: Vec<FileHydrogen>,
    /// Formal charges per atom (an SDF's charge field or `M  CHG`, MOL2's
    /// `UNITY_ATOM_ATTR`, PDB columns 79–80, mmCIF `pdbx_formal_charge`);
    /// empty when the file gives none.
    pub formal_charges: Vec<i8>,
    /// True when `bonds` holds every bond of the atoms with its order (an
    /// SDF bond block), so nothing need be perceived.
    pub bonds_complete: bool,
    /// True for a small-molecule file (SDF/MOL, MOL2).
    pub from_sdf: bool,
    /// What a PDBQT file states for scoring: AutoDock types, charges and
    /// the torsion tree's rotatable bonds; `None` for other formats.
    pub autodock: Option<AutoDockData>,
}

/// The order of a bond as a file gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BondOrder {
    /// A single bond.
    Single,
    /// A double bond.
    Double,
    /// A triple bond.
    Triple,
    /// An aromatic bond (SDF type 4).
    Aromatic,
    /// A bond whose order the file does not say (PDB `CONECT`, mmCIF
    /// `struct_conn` without `pdbx_value_order`).
    Unspecified,
}

/// A bond read from a file, between two atoms of a [`Structure`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct FileBond {
    /// The first atom (the lower index).
    pub a: usize,
    /// The second atom.
    pub b: usize,
    /// The order, when the file gives one.
    pub order: BondOrder,
}

/// A loaded structure with the reader's warnings (messages for the user,
/// already naming the file).
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The atoms.
    pub structure: Structure,
    /// Warnings: the parser's, unknown elements given a default radius, skipped records.
    pub warnings: Vec<String>,
}

/// Reads a PDB, mmCIF, PDBQT, SDF or MOL2 file (plain or gzipped), chosen
/// by extension (`.pdb`, `.ent`, `.cif`, `.mmcif`, `.pdbqt`, `.sdf`, `.mol`,
/// `.mol2`, each optionally `.gz`).
///
/// # Errors
/// [`LoadError`] naming the file (and line, when known) for an unreadable file,
/// an unknown format, a parse failure or a file with no atoms.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let lower = path.to_string_lossy().to_ascii_lowercase();
    let stem = lower.strip_suffix(".gz").unwrap_or(&lower);
    let loaded = if stem.ends_with(".sdf") || stem.ends_with(".mol") || stem.ends_with(".sd") {
        sdf::load_sdf(path, opts)?
    } else if stem.ends_with(".mol2") {
        mol2::load_mol2(path, opts)?
    } else if stem.ends_with(".pdb")
        || stem.ends_with(".ent")
        || stem.ends_with(".cif")
        || stem.ends_with(".mmcif")
        || stem.ends_with(".pdbqt")
    {
        let pdbqt = stem.ends_with(".pdbqt");
        if let (Some(record), false) = (opts.sdf_record, pdbqt) {
            return Err(LoadError::NotRecords {
                path: path.display().to_string(),
                record,
            });
        }
        // Hydrogens are read and then kept apart here, so that the
        // chemistry knows them even when they are dropped.
        let keep = LoadOptions {
            hydrogens: Hydrogens::Keep,
            ..opts.clone()
        };
        let mut loaded = if pdbqt {
            pdbqt::load_pdbqt(path, &keep)?
        } else {
            pdb::load_pdb_or_mmcif(path, &keep)?
        };
        if opts.hydrogens == Hydrogens::Drop {
            let dropped = set_hydrogens_apart(&mut loaded.structure);
            if loaded.structure.atoms.is_empty() {
                return Err(LoadError::NoAtoms {
                    path: path.display().to_string(),
                    dropped_hydrogens: dropped,
                });
            }
        }
        loaded
    } else {
        return Err(LoadError::UnknownFormat {
            path: path.display().to_string(),
        });
    };
    if loaded.structure.atoms.is_empty() {
        return Err(LoadError::NoAtoms {
            path: path.display().to_string(),
            dropped_hydrogens: 0,
        });
    }
    Ok(loaded)
}

/// Moves the hydrogens (and deuteriums) of `s.atoms` into
/// `s.file_chem.hydrogens`, each given its heavy atom (by the file's bonds,
/// else the nearest heavy atom within [`HYDROGEN_BOND_REACH`], found through
/// a grid so the cost is linear), and renumbers the bonds and charges.
/// Residues left without atoms are listed in `hydrogen_only`. Returns the
/// number of hydrogens moved.
pub fn set_hydrogens_apart(s: &mut Structure) -> usize {
    let is_h: Vec<bool> = s
        .atoms
        .iter()
        .map(|a| element::is_hydrogen(&a.element))
        .collect();
    let moved = is_h.iter().filter(|&&h| h).count();
    if moved == 0 {
        return 0;
    }
    let n = s.atoms.len();
    let mut new_index = vec![usize::MAX; n];
    let mut kept = 0;
    let mut before = vec![0usize; n];
    for i in 0..n {
        before[i] = kept;
        if !is_h[i] {
            new_index[i] = kept;
            kept += 1;
        }
    }
    // Parents from the file's bonds.
    let mut parent: Vec<Option<usize>> = vec![None; n];
    let mut bonds = Vec::with_capacity(s.bonds.len());
    for b in &s.bonds {
        match (is_h[b.a], is_h[b.b]) {
            (false, false) => bonds.push(FileBond {
                a: new_index[b.a],
                b: new_index[b.b],
                order: b.order,
            }),
            (true, false) => parent[b.a] = parent[b.a].or(Some(new_index[b.b])),
            (false, true) => parent[b.b] = parent[b.b].or(Some(new_index[b.a])),
            (true, true) => {}
        }
    }
    // The rest by distance.
    let heavy: Vec<usize> = (0..n).filter(|&i| !is_h[i]).collect();
    let centre = s.positions.first().copied().unwrap_or(DVec3::ZERO);
    let pts: Vec<glam::Vec3> = heavy
        .iter()
        .map(|&i| (s.positions[i] - centre).as_vec3())
        .collect();
    let grid = crate::chem::grid::NeighbourGrid::new(&pts, HYDROGEN_BOND_REACH as f32);
    let mut hydrogens = Vec::with_capacity(moved);
    let mut hydrogen_keys = Vec::new();
    for i in 0..n {
        if !is_h[i] {
            continue;
        }
        let p = parent[i].or_else(|| {
            let here = (s.positions[i] - centre).as_vec3();
            let mut best: Option<(f32, usize)> = None;
            grid.for_each_near(here, |k| {
                let j = heavy[k as usize];
                if crate::chem::elements::is_metal(&s.atoms[j].element) {
                    return;
                }
                let d = here.distance(pts[k as usize]);
                if d <= HYDROGEN_BOND_REACH as f32 && best.is_none_or(|(bd, bj)| (d, j) < (bd, bj))
                {
                    best = Some((d, j));
                }
            });
            best.map(|(_, j)| new_index[j])
        });
        hydrogen_keys.push(i);
        hydrogens.push(FileHydrogen {
            atom: s.atoms[i].clone(),
            position: s.positions[i],
            parent: p,
            before: before[i],
        });
    }
    // Residues that had only hydrogens.
    let kept_residues: std::collections::HashSet<(&str, i64, &str, &str)> = s
        .atoms
        .iter()
        .zip(&is_h)
        .filter(|(_, h)| !**h)
        .map(|(a, _)| {
            (
                a.chain.as_str(),
                a.seq,
                a.insertion.as_str(),
                a.residue.as_str(),
            )
        })
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut hydrogen_only = Vec::new();
    for &i in &hydrogen_keys {
        let a = &s.atoms[i];
        let key = (
            a.chain.as_str(),
            a.seq,
            a.insertion.as_str(),
            a.residue.as_str(),
        );
        if !kept_residues.contains(&key) && seen.insert(key) {
            hydrogen_only.push((
                a.residue.to_string(),
                format!("{}/{}{}", a.chain, a.seq, a.insertion),
            ));
        }
    }
    let charges = if s.file_chem.formal_charges.len() == n {
        (0..n)
            .filter(|&i| !is_h[i])
            .map(|i| s.file_chem.formal_charges[i])
            .collect()
    } else {
        Vec::new()
    };
    if let Some(ad) = s.file_chem.autodock.as_mut() {
        split_autodock(ad, &is_h, &new_index);
    }
    let mut k = 0;
    s.atoms.retain(|_| {
        k += 1;
        !is_h[k - 1]
    });
    let mut k = 0;
    s.positions.retain(|_| {
        k += 1;
        !is_h[k - 1]
    });
    bonds.sort_unstable();
    bonds.dedup();
    s.bonds = bonds;
    s.hydrogen_only.extend(hydrogen_only);
    s.file_chem.formal_charges = charges;
    s.file_chem.hydrogens.extend(hydrogens);
    moved
}

/// Splits a structure's AutoDock data as its atoms are split into heavy
/// atoms and hydrogens kept apart (`is_h`; heavy atom `i` becomes
/// `new_index[i]`): hydrogens in file order, as
/// [`set_hydrogens_apart`] lists them, and branches between heavy atoms.
fn split_autodock(ad: &mut AutoDockData, is_h: &[bool], new_index: &[usize]) {
    if ad.atoms.len() != is_h.len() {
        return;
    }
    let all = std::mem::take(&mut ad.atoms);
    for (a, &h) in all.into_iter().zip(is_h) {
        if h {
            ad.hydrogens.push(a);
        } else {
            ad.atoms.push(a);
        }
    }
    ad.branches = ad
        .branches
        .iter()
        .filter(|[a, b]| !is_h[*a as usize] && !is_h[*b as usize])
        .filter_map(|[a, b]| {
            Some([
                u32::try_from(new_index[*a as usize]).ok()?,
                u32::try_from(new_index[*b as usize]).ok()?,
            ])
        })
        .collect();
}

/// Largest coordinate magnitude, in Å, accepted from a file. Atoms are
/// kept in f32 relative to their molecule's centre, so one absurd outlier
/// (a typo, an overflow in the program that wrote the file) would move the
/// centre far away and take the precision of every other atom with it.
/// Real structures lie within a few thousand Å of their origin.
pub const MAX_FILE_COORDINATE: f64 = 1e6;

/// Residue names treated as water.
pub const WATER_NAMES: &[&str] = &["HOH", "WAT", "H2O", "DOD", "TIP", "TIP3", "SOL", "D2O"];

/// True when `residue` names a water.
pub fn is_water(residue: &str) -> bool {
    // No allocation: it runs once an atom when a structure is split.
    let r = residue.trim();
    WATER_NAMES.iter().any(|w| w.eq_ignore_ascii_case(r))
}

/// `../shared/pdb` for unit tests, or `None` with a skip message when it is
/// absent; under `CI=true` its absence fails the test.
#[cfg(test)]
pub(crate) fn test_data_dir() -> Option<std::path::PathBuf> {
    let dir = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if dir.join("MANIFEST.md").is_file() {
        return Some(dir);
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "test data folder {} is missing (CI must have ../shared/pdb)",
        dir.display()
    );
    eprintln!("SKIP: test data folder {} not found", dir.display());
    None
}
