//! What bump's tests (`tests/*.rs`) and benchmarks (`benches/*.rs`) share,
//! so both run the same queries against the same references:
//!
//! - [`data`]: where the real structures are (`../shared/pdb`), and what a
//!   missing folder means (a skip, or a failure under `CI=true`).
//! - [`rng`]: a seeded generator and evenly spread directions, so the same
//!   seed gives the same queries on every machine.
//! - [`molecules`]: test atoms and random molecules.
//! - [`oracle`]: exact f64 answers to measure move-to-touch against.
//! - [`surface`]: patches of a receptor's own surface, the drugs of the
//!   scaling benchmarks.
//! - [`parry`]: parry3d doing move-to-touch, the independent baseline.
//! - [`score_bench`]: the scoring's benchmark setups and report section.
//! - [`vina_reference`]: the Vina reference's complexes and how to load
//!   them.
//! - [`settle_rates`]: settle from perturbed crystal poses on the Vina
//!   reference's complexes, checked by a test and printed by the report.
//!
//! A dev-dependency of bump only: the product does not link parry3d.

pub mod data;
pub mod molecules;
pub mod oracle;
pub mod parry;
pub mod rng;
pub mod score_bench;
pub mod settle_rates;
pub mod surface;
pub mod vina_reference;

pub use data::shared_pdb;
pub use molecules::{all_colliders, atom, random_molecule};
pub use rng::{Rng, sphere_directions};
