//! A rigid molecule: atoms with identities and radii, and coordinates stored
//! relative to the molecule's own centre.
//!
//! Coordinates come from files in f64. The centre is the centroid of the kept
//! atoms; each atom's position relative to it is stored in f32 (`local`), which
//! keeps full precision however far from the origin the file places the
//! molecule. A [`crate::motion::Pose`] (f64) places the molecule in the world.
//!
//! A molecule also keeps what its chemistry needs: the file's hydrogens
//! ([`AttachedHydrogens`], apart from the atoms: they are neither collided
//! nor drawn), the bonds and formal charges the file states, and, computed
//! when first asked for ([`Molecule::chemistry`]), its perceived
//! [`Chemistry`].

use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};
use serde::Serialize;

use super::label::{AtomName, ChainId, ElementSymbol, InsertionCode, ResidueName};
use crate::chem::{Bond, Chemistry};

/// One atom's identity, as the file gave it, plus its radius.
///
/// The labels are [`Label`](super::Label)s, kept inline (48 bytes an atom in all): they
/// read as `&str` (deref, `Display`, comparison with `str`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AtomInfo {
    /// The file's atom serial number (PDB/mmCIF), or the 1-based record order (SDF).
    pub serial: i64,
    /// Atom name (`CA`, `N1`, ...); for SDF, element plus index (`C3`).
    pub name: AtomName,
    /// Residue name (`TOP`, `ALA`); for SDF, the molecule's name (cut to
    /// 8 bytes) or `LIG`.
    pub residue: ResidueName,
    /// Residue sequence number (0 for SDF).
    pub seq: i64,
    /// Insertion code, empty when none.
    pub insertion: InsertionCode,
    /// Chain identifier, empty when none.
    pub chain: ChainId,
    /// Element symbol, normalised (`C`, `Cl`).
    pub element: ElementSymbol,
    /// Van der Waals radius in Å.
    pub radius: f32,
    /// True for N and O (possible hydrogen-bond partners).
    pub polar: bool,
    /// True when the file marked the atom HETATM.
    pub hetero: bool,
}

impl AtomInfo {
    /// The residue number as files and viewers write it: the sequence number
    /// followed by the insertion code, if any (`221A`).
    pub fn residue_number(&self) -> String {
        format!("{}{}", self.seq, self.insertion)
    }
}

/// A molecule's hydrogens from the file, kept apart from its atoms: each
/// with its heavy atom, name, serial and place in the file's order, and
/// its position relative to the molecule's centre (so the molecule's pose
/// places it as it places the atoms). Compact arrays, one entry per
/// hydrogen; names share one string.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AttachedHydrogens {
    /// The heavy atom (index into [`Molecule::atoms`]) each is bonded to.
    pub parent: Vec<u32>,
    /// Positions relative to [`Molecule::centre`].
    pub local: Vec<Vec3>,
    /// Serial numbers as the file gives them.
    pub serial: Vec<i64>,
    /// Place in the file's order: written before heavy atom `before[i]`
    /// (after all of them when it equals the atom count).
    pub before: Vec<u32>,
    names: String,
    name_ends: Vec<u32>,
}

impl AttachedHydrogens {
    /// Number of hydrogens.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// Adds a hydrogen.
    pub fn push(&mut self, parent: u32, local: Vec3, serial: i64, before: u32, name: &str) {
        self.parent.push(parent);
        self.local.push(local);
        self.serial.push(serial);
        self.before.push(before);
        self.names.push_str(name);
        self.name_ends
            .push(u32::try_from(self.names.len()).unwrap_or(u32::MAX));
    }

    /// The name of hydrogen `i` as the file gives it.
    pub fn name(&self, i: usize) -> &str {
        let start = if i == 0 {
            0
        } else {
            self.name_ends[i - 1] as usize
        };
        self.names
            .get(start..self.name_ends[i] as usize)
            .unwrap_or("")
    }
}

/// A rigid molecule ready for collision detection.
#[derive(Debug, Clone)]
pub struct Molecule {
    /// A label for messages: the file name and, for a split complex, the part.
    pub name: String,
    /// Atom identities, in file order.
    pub atoms: Vec<AtomInfo>,
    /// Centroid of the atoms in file coordinates (f64).
    pub centre: DVec3,
    /// Atom positions relative to `centre`, same order as `atoms`.
    pub local: Vec<Vec3>,
    /// The file's hydrogens, apart from `atoms`.
    pub hydrogens: AttachedHydrogens,
    /// Bonds between atoms that the file states (SDF bond block, `CONECT`,
    /// `struct_conn`), indices into `atoms`.
    pub file_bonds: Vec<Bond>,
    /// Formal charges per atom from the file; empty when none.
    pub formal_charges: Vec<i8>,
    /// True when `file_bonds` holds every bond with its order (an SDF).
    pub bonds_complete: bool,
    /// True when the molecule came from a small-molecule file (SDF/MOL, MOL2).
    pub from_sdf: bool,
    /// What a PDBQT file states for scoring (AutoDock types and charges per
    /// atom and kept hydrogen, the torsion tree's rotatable bonds), indexed
    /// like `atoms` and `hydrogens`; `None` for other formats.
    pub autodock: Option<super::AutoDockData>,
    /// The perceived chemistry, computed when first asked for. Set the
    /// fields above before that.
    chemistry: OnceLock<Arc<Chemistry>>,
}

impl Molecule {
    /// Builds a molecule from atoms and their file coordinates. The centre is
    /// the centroid (the origin when there are no atoms).
    pub fn new(name: impl Into<String>, atoms: Vec<AtomInfo>, positions: &[DVec3]) -> Self {
        debug_assert_eq!(atoms.len(), positions.len());
        let centre = if positions.is_empty() {
            DVec3::ZERO
        } else {
            positions.iter().copied().sum::<DVec3>() / positions.len() as f64
        };
        let local = positions.iter().map(|p| (*p - centre).as_vec3()).collect();
        Self {
            name: name.into(),
            atoms,
            centre,
            local,
            hydrogens: AttachedHydrogens::default(),
            file_bonds: Vec::new(),
            formal_charges: Vec::new(),
            bonds_complete: false,
            from_sdf: false,
            autodock: None,
            chemistry: OnceLock::new(),
        }
    }

    /// The molecule's chemistry ([`crate::chem::perceive`]): computed on the
    /// first call (linear in the atom count), then kept.
    pub fn chemistry(&self) -> &Chemistry {
        self.chemistry
            .get_or_init(|| Arc::new(crate::chem::perceive(self)))
    }

    /// True once [`Molecule::chemistry`] has been computed.
    pub fn has_chemistry(&self) -> bool {
        self.chemistry.get().is_some()
    }

    /// Position of hydrogen `i` in file coordinates (f64).
    pub fn hydrogen_file_position(&self, i: usize) -> DVec3 {
        self.centre + self.hydrogens.local[i].as_dvec3()
    }

    /// Number of atoms.
    pub fn len(&self) -> usize {
        self.atoms.len()
    }

    /// True when the molecule has no atoms.
    pub fn is_empty(&self) -> bool {
        self.atoms.is_empty()
    }

    /// Position of atom `i` in file coordinates (f64).
    pub fn file_position(&self, i: usize) -> DVec3 {
        self.centre + self.local[i].as_dvec3()
    }

    /// All positions in file coordinates.
    pub fn file_positions(&self) -> Vec<DVec3> {
        (0..self.len()).map(|i| self.file_position(i)).collect()
    }

    /// The largest atom radius (0 for an empty molecule).
    pub fn max_radius(&self) -> f32 {
        self.atoms.iter().map(|a| a.radius).fold(0.0, f32::max)
    }

    /// Distance from the centre to the farthest atom surface.
    pub fn bounding_radius(&self) -> f64 {
        self.local
            .iter()
            .zip(&self.atoms)
            .map(|(p, a)| f64::from(p.length()) + f64::from(a.radius))
            .fold(0.0, f64::max)
    }
}

/// A carbon atom (Bondi radius, chain A) for unit tests that build molecules
/// by hand.
#[cfg(test)]
pub(crate) fn test_carbon(serial: i64) -> AtomInfo {
    AtomInfo {
        serial,
        name: format!("C{serial}").into(),
        residue: "X".into(),
        seq: 1,
        insertion: InsertionCode::EMPTY,
        chain: "A".into(),
        element: "C".into(),
        radius: 1.7,
        polar: false,
        hetero: false,
    }
}

/// A bumpy wall of carbons for unit tests: two square layers, 3 Å between
/// neighbours and 48 Å wide, at z = 0 and z = −1.5 Å, the lower one under
/// the upper one's hollows.
#[cfg(test)]
pub(crate) fn test_wall() -> Molecule {
    let mut pos = Vec::new();
    for (z, shift) in [(0.0, 0.0), (-1.5, 1.5)] {
        for i in -8..=8 {
            for j in -8..=8 {
                pos.push(glam::DVec3::new(
                    3.0 * f64::from(i) + shift,
                    3.0 * f64::from(j) + shift,
                    z,
                ));
            }
        }
    }
    let atoms = (1..=pos.len() as i64).map(test_carbon).collect();
    Molecule::new("wall", atoms, &pos)
}
