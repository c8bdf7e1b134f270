//! What the integration tests share: the helpers the benchmarks share too
//! (the `bump-testkit` dev-dependency: test data, seeded generator, random
//! molecules, exact f64 oracles), and the tests' own: a GPU and, for the
//! real-window tests, an X server ([`x11`]).
#![allow(dead_code)] // each test crate uses only some of them
#![allow(unused_imports)]

pub mod cli;
pub mod mol2;
pub mod x11;

pub use bump_testkit::oracle::{
    collides as collides_f64, contact, dense_screw_toi, max_speed, min_gap as min_gap_f64,
    translation_toi as exact_translation_toi,
};
pub use bump_testkit::{Rng, all_colliders, atom, random_molecule, shared_pdb, sphere_directions};

/// The GPU (lavapipe without one), or `None` (skip) outside CI; under
/// `CI=true` it must exist.
#[cfg(feature = "app")]
pub fn gpu() -> Option<bump::render::Gpu> {
    match bump::render::Gpu::headless() {
        Ok(g) => Some(g),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => panic!("CI must render: {e}"),
        Err(e) => {
            eprintln!("SKIP: no graphics adapter ({e})");
            None
        }
    }
}
