//! Chemistry of a molecule: bonds, bond orders and aromaticity, hydrogen
//! counts, AutoDock Vina's atom types, rotatable bonds and the torsion
//! tree, and Gasteiger partial charges.
//!
//! [`perceive`] computes a [`Chemistry`] from a [`Molecule`] in one pass
//! that is linear in the atom count:
//! 1. bonds ([`connect`]): the file's complete bond block (SDF), residue
//!    templates ([`templates`]) with their peptide and phosphodiester links,
//!    the file's `CONECT`/`struct_conn`, and distances for everything else;
//! 2. bond orders for bonds that have none ([`orders`]), from hydrogen
//!    counts or geometry, and aromatic rings ([`aromatic`]);
//! 3. hydrogens per heavy atom: the file's, when the residue has any, else
//!    implicit from valence and formal charge;
//! 4. Vina's X-Score atom types ([`typing`]);
//! 5. rotatable bonds, the torsion tree, Vina's torsion count and the
//!    intramolecular pairs ([`torsions`]);
//! 6. Gasteiger–Marsili charges as Open Babel computes them ([`gasteiger`]).
//!
//! A molecule computes its chemistry when first asked
//! ([`Molecule::chemistry`]), not when it is loaded. Nothing here panics on
//! odd input: an atom whose chemistry cannot be perceived is reported in
//! [`Chemistry::warnings`], naming it by file, serial and name.

pub mod aromatic;
pub mod connect;
pub mod elements;
pub mod gasteiger;
pub mod graph;
pub mod grid;
pub mod orders;
pub mod rings;
pub mod templates;
pub mod torsions;
pub mod typing;

use std::collections::BTreeMap;

pub use graph::{Adjacency, Bond};
pub use torsions::{RotatableBond, TorsionNode, TorsionTree};
pub use typing::{Hybridisation, XsType};

use crate::model::Molecule;

/// Everything perceived about a molecule's chemistry. Per-atom arrays are
/// indexed like [`Molecule::atoms`] (heavy atoms); per-hydrogen arrays like
/// [`Molecule::hydrogens`].
#[derive(Debug, Clone)]
pub struct Chemistry {
    /// Bonds between heavy atoms, each pair once with `a < b`, sorted, with
    /// Kekulé orders.
    pub bonds: Vec<Bond>,
    /// Neighbours of each heavy atom (through `bonds`).
    pub adjacency: Adjacency,
    /// Per bond: in a ring.
    pub bond_in_ring: Vec<bool>,
    /// Per bond: in an aromatic ring.
    pub bond_aromatic: Vec<bool>,
    /// Per atom: in an aromatic ring.
    pub aromatic: Vec<bool>,
    /// Per atom: formal charge (the file's, a template's, or implied by a
    /// valence beyond the neutral one, as in a quaternary nitrogen).
    pub formal_charges: Vec<i8>,
    /// Per atom: hydrogens bonded to it (the file's, or implicit).
    pub hydrogen_count: Vec<u8>,
    /// Per atom: true when its hydrogens are implicit (the file had none
    /// for its residue).
    pub implicit_hydrogens: Vec<bool>,
    /// Per atom: hybridisation as Open Babel assigns it.
    pub hybridisation: Vec<Hybridisation>,
    /// Per atom: Vina's X-Score type; `None` for an element Vina has no
    /// type for (reported in `warnings`).
    pub xs: Vec<Option<XsType>>,
    /// Per atom: Gasteiger partial charge (e) with its non-polar
    /// hydrogens' charges added, as AutoDock's PDBQT has them.
    pub charges: Vec<f32>,
    /// Per atom: the summed charge of its polar hydrogens (bonded to N, O,
    /// S or P). They are separate atoms in a PDBQT file; where the molecule
    /// keeps them, their charges are also in `hydrogen_charges`.
    pub polar_hydrogen_charge: Vec<f32>,
    /// Per kept hydrogen ([`Molecule::hydrogens`]): its Gasteiger charge
    /// (non-polar ones are already merged into their carbon's `charges`).
    pub hydrogen_charges: Vec<f32>,
    /// Rotatable bonds and the torsion tree.
    pub torsions: TorsionTree,
    /// What could not be perceived, naming the atom (file, serial, name).
    pub warnings: Vec<String>,
}

impl Chemistry {
    /// Vina's torsion count `N_tors` (each rotatable bond counts ½ per
    /// side whose other atom has more than one heavy neighbour); the score's
    /// divisor is `1 + 0.05846 · N_tors`.
    pub fn vina_torsion_count(&self) -> f64 {
        self.torsions.vina_count
    }

    /// Gasteiger charge per heavy atom with all its hydrogens' charges
    /// added (a united-atom charge, for a molecule whose hydrogens are not
    /// kept).
    pub fn united_charges(&self) -> Vec<f32> {
        self.charges
            .iter()
            .zip(&self.polar_hydrogen_charge)
            .map(|(q, h)| q + h)
            .collect()
    }
}

/// Collects warnings, one per atom and kind, in atom order.
#[derive(Debug, Default)]
pub(crate) struct Warnings {
    by_atom: BTreeMap<(usize, String), ()>,
    general: Vec<String>,
}

impl Warnings {
    /// A warning about atom `i` of `mol`.
    pub(crate) fn atom(&mut self, mol: &Molecule, i: usize, what: String) {
        let a = &mol.atoms[i];
        let chain = if a.chain.is_empty() {
            String::new()
        } else {
            format!("{}/", a.chain)
        };
        let text = format!(
            "{}: atom {} ({} {} {}{}): {what}",
            mol.name,
            a.serial,
            a.name,
            a.residue,
            chain,
            a.residue_number()
        );
        self.by_atom.insert((i, text), ());
    }

    /// A warning about the molecule.
    pub(crate) fn general(&mut self, what: String) {
        self.general.push(what);
    }

    fn into_vec(self) -> Vec<String> {
        self.general
            .into_iter()
            .chain(self.by_atom.into_keys().map(|(_, t)| t))
            .collect()
    }
}

/// Perceives `mol`'s chemistry (see the module docs). Linear in the atom
/// count; never panics.
pub fn perceive(mol: &Molecule) -> Chemistry {
    let mut warn = Warnings::default();
    let n = mol.len();
    // Explicit hydrogens per atom, for residues that have any.
    let residues = connect::residue_ranges(&mol.atoms);
    let mut residue_of = vec![0u32; n];
    for (r, &(s, e)) in residues.iter().enumerate() {
        residue_of[s as usize..e as usize].fill(connect::idx(r));
    }
    let mut h_of = vec![0u8; n];
    let mut residue_has_h = vec![false; residues.len()];
    for &p in &mol.hydrogens.parent {
        if let Some(slot) = h_of.get_mut(p as usize) {
            *slot = slot.saturating_add(1);
            residue_has_h[residue_of[p as usize] as usize] = true;
        }
    }
    let explicit_h: Vec<Option<u8>> = (0..n)
        .map(|i| residue_has_h[residue_of[i] as usize].then_some(h_of[i]))
        .collect();

    let mut conn = connect::connect(mol, &explicit_h, &mut warn);
    if !mol.bonds_complete && mol.file_bonds.is_empty() && mol.from_sdf && n > 1 {
        warn.general(format!(
            "{}: the file has no bonds; bonds and orders are perceived from distances",
            mol.name
        ));
    }
    let adjacency = Adjacency::new(n, &conn.bonds);
    let bond_in_ring = rings::ring_bonds(&adjacency, conn.bonds.len());

    orders::assign_orders(
        mol,
        &mut conn,
        &adjacency,
        &bond_in_ring,
        &explicit_h,
        &mut warn,
    );
    let (aromatic, bond_aromatic) =
        aromatic::perceive(mol, &conn, &adjacency, &bond_in_ring, &explicit_h);

    let hydro = typing::hydrogens(mol, &conn, &adjacency, &explicit_h, &mut warn);
    let hybridisation = typing::hybridisation(
        mol,
        &conn.bonds,
        &adjacency,
        &aromatic,
        &bond_aromatic,
        &hydro,
    );
    let xs = typing::xs_types(mol, &adjacency, &hybridisation, &hydro, &mut warn);
    let torsions = torsions::build(
        mol,
        &conn.bonds,
        &adjacency,
        &bond_in_ring,
        &bond_aromatic,
        &hydro,
    );
    let charges = gasteiger::charges(
        mol,
        &conn.bonds,
        &adjacency,
        &aromatic,
        &hybridisation,
        &hydro,
        &mut warn,
    );

    Chemistry {
        bonds: conn.bonds,
        adjacency,
        bond_in_ring,
        bond_aromatic,
        aromatic,
        formal_charges: hydro.charges.clone(),
        hydrogen_count: hydro.count.clone(),
        implicit_hydrogens: explicit_h.iter().map(Option::is_none).collect(),
        hybridisation,
        xs,
        charges: charges.heavy,
        polar_hydrogen_charge: charges.polar_h,
        hydrogen_charges: charges.kept_h,
        torsions,
        warnings: warn.into_vec(),
    }
}
