//! What the small-molecule readers (SDF, MOL2) share once a record is
//! parsed: the [`Structure`] of the one molecule read, its hydrogens set
//! apart when they are dropped, its name (with the record's number when the
//! file holds several) and the warnings.

use std::path::Path;

use glam::DVec3;

use super::pdb::{RadiusLookup, file_name};
use super::{
    AtomInfo, FileBond, FileChemistry, Hydrogens, LoadError, LoadOptions, Loaded, Structure,
    set_hydrogens_apart,
};

/// One molecule as a small-molecule reader parsed it.
pub(super) struct Record {
    /// Its atoms, hydrogens included.
    pub atoms: Vec<AtomInfo>,
    /// Their file coordinates.
    pub positions: Vec<DVec3>,
    /// Its bonds, each pair once with the lower index first, sorted.
    pub bonds: Vec<FileBond>,
    /// Formal charges per atom.
    pub charges: Vec<i8>,
    /// True when the file had a bond section (so `bonds` is complete).
    pub bonds_stated: bool,
}

/// Which of a file's molecules was read, for messages.
pub(super) struct Which<'a> {
    /// The file, as messages name it.
    pub path_label: &'a str,
    /// How many molecules the file holds.
    pub count: usize,
    /// The one read (1-based).
    pub wanted: usize,
    /// What the format calls one ("record", "molecule").
    pub noun: &'a str,
}

/// The loaded structure of `record`.
///
/// # Errors
/// [`LoadError::NoAtoms`] when no atom is left once hydrogens are dropped.
pub(super) fn loaded(
    record: Record,
    which: &Which<'_>,
    opts: &LoadOptions,
    lookup: &RadiusLookup,
    mut warnings: Vec<String>,
) -> Result<Loaded, LoadError> {
    let n_atoms = record.atoms.len();
    let mut structure = Structure {
        name: String::new(),
        atoms: record.atoms,
        positions: record.positions,
        hydrogen_only: Vec::new(),
        bonds: record.bonds,
        file_chem: FileChemistry {
            hydrogens: Vec::new(),
            formal_charges: if record.charges.iter().any(|&q| q != 0) {
                record.charges
            } else {
                Vec::new()
            },
            bonds_complete: record.bonds_stated || n_atoms == 1,
            from_sdf: true,
            autodock: None,
        },
    };
    let dropped = if opts.hydrogens == Hydrogens::Drop {
        set_hydrogens_apart(&mut structure)
    } else {
        0
    };
    // A small molecule's residue is never "hydrogen only" in a useful sense.
    structure.hydrogen_only.clear();
    let path_label = which.path_label;
    if structure.atoms.is_empty() {
        return Err(LoadError::NoAtoms {
            path: path_label.to_string(),
            dropped_hydrogens: dropped,
        });
    }
    if which.count > 1 {
        warnings.push(format!(
            "{path_label}: file holds {} {}s; using {} {}",
            which.count, which.noun, which.noun, which.wanted
        ));
    }
    warnings.extend(lookup.warnings(path_label));
    // A record of several is named with its number, in every message and
    // report that names the molecule.
    structure.name = match which.count {
        1 => file_name(Path::new(path_label)),
        _ => format!(
            "{} record {}",
            file_name(Path::new(path_label)),
            which.wanted
        ),
    };
    Ok(Loaded {
        structure,
        warnings,
    })
}
