//! From molecules to the scoring's typed atoms, through their chemistry
//! ([`crate::model::Molecule::chemistry`]).
//!
//! Both come out in their molecule's own frame (relative to its centre, as
//! the molecule stores its atoms), so a drug's conformation is posed by
//! exactly the relative pose the collider is queried with
//! ([`crate::scene::Scene::relative`]). Charges are the chemistry's
//! Gasteiger charges with every hydrogen's charge merged into its heavy
//! atom (hydrogens are not scored).

use super::ligand::{Fragment, Ligand, LigandError};
use super::receptor::Receptor;
use crate::model::Molecule;

/// The drug as a ligand: heavy atoms with their X-Score types (atoms the
/// chemistry could not type move with their fragment but are not scored),
/// the torsion tree, Vina's intramolecular pairs and torsion count.
///
/// # Errors
/// Only if the chemistry's tree were inconsistent ([`LigandError`]).
pub fn ligand(drug: &Molecule) -> Result<Ligand, LigandError> {
    let chem = drug.chemistry();
    let tree = &chem.torsions;
    let fragments = tree
        .nodes
        .iter()
        .map(|n| Fragment {
            parent: n.parent,
            bond: n
                .bond
                .and_then(|b| tree.bonds.get(b as usize))
                .map(|b| [b.parent_atom, b.child_atom]),
            atoms: n.atoms.clone(),
        })
        .collect();
    let pairs: Vec<[u32; 2]> = tree
        .vina_pairs(&chem.adjacency, &chem.xs)
        .into_iter()
        .map(|(a, b)| [a, b])
        .collect();
    Ligand::from_parts(
        drug.local.iter().map(|v| v.as_dvec3()).collect(),
        fragments,
        &chem.xs,
        chem.united_charges().into_iter().map(f64::from).collect(),
        &pairs,
        tree.vina_count,
    )
}

/// The receptor's typed heavy atoms (untyped atoms are left out), relative
/// to its centre.
pub fn receptor(receptor: &Molecule) -> Receptor {
    let chem = receptor.chemistry();
    let positions: Vec<_> = receptor.local.iter().map(|v| v.as_dvec3()).collect();
    let charges: Vec<f64> = chem.united_charges().into_iter().map(f64::from).collect();
    Receptor::new(&positions, &chem.xs, &charges)
}
