//! Collision detection between a receptor and a drug made of spheres.
//!
//! [`rule`] says when two atoms collide; [`collider`] indexes the receptor
//! (brute force, full grid or hashed grid; the grids also in
//! [`padded_rows`]) and keeps a [`clearance`] map of the space around it;
//! [`drug`] prepares a drug's atoms for queries, four at a time in
//! compact groups ([`grouping`]); [`mod@check`] answers static queries;
//! [`sweep`] moves the drug to touch without tunnelling; [`response`]
//! turns a proposed step into the session's answer (stop, touch, slide,
//! soft, pass), [`soft`] with the loosened index it needs and
//! [`body_shape`] with the receptor's body-scale shape for its glide;
//! [`torsion`] turns one side of a rotatable bond without collisions;
//! [`stats`] measures grid occupancy (the thesis's Table 1); [`layers`] names the
//! optional layers that make queries fast, each of which can be turned off
//! to measure what it saves. The exact f64 answers that tests and
//! benchmarks measure these against live with them, in the dev-only crate
//! `bump-testkit`.

pub mod body_shape;
pub mod check;
pub mod clearance;
pub mod collider;
pub mod drug;
pub mod grouping;
pub mod layers;
pub mod padded_rows;
pub mod response;
pub mod rule;
pub mod soft;
pub mod stats;
pub mod sweep;
pub mod torsion;

pub use check::{Pair, any_collision, check, min_gap, pairs_within};
pub use collider::{Collider, ColliderKind};
pub use drug::DrugAtoms;
pub use layers::Layers;
pub use response::{Response, StepResult, respond};
pub use rule::ContactRule;
pub use soft::{SoftIndex, respond_soft};
pub use sweep::{Method, TouchOptions, TouchResult, move_to_touch, move_to_touch_into};
