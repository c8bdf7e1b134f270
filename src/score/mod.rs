//! AutoDock Vina 1.2's scoring, exactly, with gradients, grid maps, a
//! Coulomb term beside it, and a local optimiser that never collides.
//!
//! - [`function`]: Vina's and Vinardo's terms, weights, curl and divisor.
//! - [`table`]: Vina's pair-energy table, which even its exact score reads.
//! - [`ligand`]: the drug as typed atoms in a torsion tree; conformations
//!   and gradients (force, torque, torsion torques).
//! - [`receptor`]: the receptor's typed atoms in a cell list.
//! - [`field`]: what an evaluator provides; a conformation's energy and
//!   gradient on top of one, and a conformation held while the drug moves
//!   rigidly (its whole gradient without placing atoms through the tree).
//! - [`exact`]: the exact evaluator (pairs within 8 Å), reading per-cell
//!   candidate lists (`candidates`).
//! - [`maps`]: grid maps per type, built on a background thread, read by
//!   trilinear interpolation; the exact evaluator covers what they do not.
//! - [`coulomb`]: Coulomb energy with AutoDock 4's dielectric, exact and
//!   from a map, reported beside the score.
//! - [`report`]: a pose's score term by term, per atom, with its hydrogen
//!   bonds.
//! - [`contrib`]: each receptor atom's share of a pose's energy.
//! - [`settle`](mod@settle): local minimisation over position, orientation and
//!   torsions (Vina's BFGS) whose steps never collide or tunnel.
//!
//! The scoring takes typed atoms (positions and X-Score types, and for the
//! drug its torsion tree), so it does not depend on how they were typed:
//! [`prepare`] builds them from a molecule's chemistry ([`crate::chem`]),
//! the tests also from the types Vina itself recorded.
//! Everything is in the receptor's frame: receptor atoms relative to the
//! receptor's centre, the drug placed by its pose relative to the receptor
//! (as [`crate::scene::Scene::relative`] gives it).

mod candidates;
pub mod contrib;
pub mod coulomb;
pub mod exact;
pub mod field;
pub mod function;
pub mod ligand;
pub mod maps;
pub mod prepare;
pub mod receptor;
pub mod report;
pub mod settle;
pub mod table;

pub use crate::chem::XsType;
pub use exact::Exact;
pub use field::{Energies, Field, PerAtom, RigidDrug, Workspace, energies, energy_gradient};
pub use function::{Scoring, curl, torsion_divisor};
pub use ligand::{Conformation, Fragment, Gradient, Ligand, LigandError};
pub use maps::{MapBox, MapField, Maps, MapsError, MapsJob};
pub use receptor::Receptor;
pub use report::{Donor, Evaluator, HBond, Score, score, score_with_contributions};
pub use settle::{Contacts, SettleOptions, Settled, settle};
