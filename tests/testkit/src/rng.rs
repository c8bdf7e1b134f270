//! The library's seeded generator and evenly spread directions
//! ([`bump::rng`]), so that tests, benchmarks and `bump steer` draw the same
//! numbers from the same seed.

pub use bump::rng::{Rng, sphere_directions};
