//! Molecules: atoms, elements and radii, loading from PDB, mmCIF and SDF files,
//! splitting a complex into receptor and drug, and the built-in scene.
//!
//! Loading gives a [`Structure`]: every kept atom of the first model, with
//! alternate locations resolved and hydrogens dropped or kept as asked.
//! [`select`] turns a structure into the receptor and drug [`Molecule`]s.

pub mod builtin;
pub mod element;
pub mod error;
pub mod label;
pub mod molecule;
pub mod pdb;
pub mod sdf;
pub mod select;
pub mod write;

use std::path::Path;

use glam::DVec3;
use serde::Serialize;

pub use element::RadiiSet;
pub use error::LoadError;
pub use label::Label;
pub use molecule::{AtomInfo, Molecule};
pub use select::{
    LigandSpec, receptor_only, receptor_only_owned, split_complex, split_complex_owned,
};

/// Whether hydrogens are kept when loading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Hydrogens {
    /// Drop H and D atoms (the default: crystal structures rarely have them,
    /// and hydrogen-bond contacts would read as collisions).
    #[default]
    Drop,
    /// Keep them.
    Keep,
}

/// How to read a file.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Radius table.
    pub radii: RadiiSet,
    /// Keep or drop hydrogens.
    pub hydrogens: Hydrogens,
    /// For SDF files: which record (1-based); the first when `None`. Other
    /// formats have no records and refuse one ([`LoadError::NotRecords`]).
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

/// Reads a PDB, mmCIF (plain or gzipped) or SDF file, chosen by extension
/// (`.pdb`, `.ent`, `.cif`, `.mmcif`, `.sdf`, `.mol`, each optionally `.gz`).
///
/// # Errors
/// [`LoadError`] naming the file (and line, when known) for an unreadable file,
/// an unknown format, a parse failure or a file with no atoms.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let lower = path.to_string_lossy().to_ascii_lowercase();
    let stem = lower.strip_suffix(".gz").unwrap_or(&lower);
    let loaded = if stem.ends_with(".sdf") || stem.ends_with(".mol") || stem.ends_with(".sd") {
        sdf::load_sdf(path, opts)?
    } else if stem.ends_with(".pdb")
        || stem.ends_with(".ent")
        || stem.ends_with(".cif")
        || stem.ends_with(".mmcif")
    {
        if let Some(record) = opts.sdf_record {
            return Err(LoadError::NotRecords {
                path: path.display().to_string(),
                record,
            });
        }
        pdb::load_pdb_or_mmcif(path, opts)?
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
