//! Shared helpers for the integration tests: test data location, random
//! molecules and the exact (f64) oracles of `bump::collide::oracle`.
#![allow(dead_code)]

pub mod x11;

use std::path::PathBuf;

use bump::collide::{Collider, ContactRule, DrugAtoms};
use bump::model::{AtomInfo, Molecule};
use bump::motion::{Pose, Screw};
use glam::DVec3;

/// `../shared/pdb`, or `None` (with a message) when it is absent outside CI.
/// Under `CI=true` a missing folder fails the test.
pub fn shared_pdb() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if dir.join("MANIFEST.md").is_file() {
        return Some(dir);
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("{} is missing: CI must have ../shared/pdb", dir.display());
    }
    eprintln!(
        "SKIP: {} not found; tests on real structures skipped",
        dir.display()
    );
    None
}

pub use bump::rng::Rng;

/// A test atom: element `element`, radius `radius`, N and O polar.
pub fn atom(serial: i64, element: &str, radius: f32) -> AtomInfo {
    AtomInfo {
        serial,
        name: format!("{element}{serial}").into(),
        residue: "RND".into(),
        seq: 1,
        insertion: Default::default(),
        chain: "A".into(),
        element: element.into(),
        radius,
        polar: matches!(element, "N" | "O"),
        hetero: false,
    }
}

/// `n` random atoms (C/N/O/S radii) in a cube of edge `size` centred at `centre`.
pub fn random_molecule(rng: &mut Rng, n: usize, size: f64, centre: DVec3, polar: bool) -> Molecule {
    let kinds: &[(&str, f32)] = if polar {
        &[("C", 1.7), ("N", 1.55), ("O", 1.52), ("S", 1.8)]
    } else {
        &[("C", 1.7), ("S", 1.8), ("C", 1.5)]
    };
    let mut atoms = Vec::new();
    let mut pos = Vec::new();
    for i in 0..n {
        let (e, r) = kinds[(rng.next_u64() % kinds.len() as u64) as usize];
        atoms.push(atom(i as i64 + 1, e, r));
        pos.push(
            centre
                + DVec3::new(
                    rng.range(-0.5, 0.5),
                    rng.range(-0.5, 0.5),
                    rng.range(-0.5, 0.5),
                ) * size,
        );
    }
    Molecule::new("random", atoms, &pos)
}

/// Contact distance of a receptor/drug atom pair in f64.
pub fn contact(rule: &ContactRule, a: &AtomInfo, b: &AtomInfo) -> f64 {
    f64::from(rule.contact_distance(a.radius, a.polar, b.radius, b.polar))
}

/// The f64 oracles live in the library ([`bump::collide::oracle`]): exact
/// time of impact for a pure translation, smallest gap, dense screw search.
#[allow(unused_imports)] // each test crate uses only some of them
pub use bump::collide::oracle::{
    dense_screw_toi, min_gap as min_gap_f64, translation_toi as exact_translation_toi,
};

/// True when any pair collides (f64) at `pose`.
pub fn collides_f64(rule: &ContactRule, receptor: &Molecule, drug: &Molecule, pose: &Pose) -> bool {
    min_gap_f64(rule, receptor, drug, pose) <= 0.0
}

/// Largest atom speed of a screw (Å per unit t) for the drug at its start.
pub fn max_speed(drug: &DrugAtoms, screw: &Screw) -> f64 {
    drug.rotated(screw.start())
        .iter()
        .map(|y| screw.speed(*y))
        .fold(0.0, f64::max)
}

/// Brute-force reference collider plus the other two for `receptor`, each
/// once its clearance map is built (a grid's map is built on its own
/// thread), so the tests exercise the queries that skip atoms with it.
pub fn all_colliders(receptor: &Molecule, rule: &ContactRule) -> Vec<Collider> {
    use bump::collide::ColliderKind;
    ColliderKind::ALL
        .iter()
        .map(|k| {
            let c = Collider::build(receptor, rule, *k);
            let map = c.wait_for_clearance().is_some();
            assert_eq!(map, *k != ColliderKind::Brute, "{k:?}: clearance map");
            assert_eq!(
                c.has_padded_rows(),
                *k != ColliderKind::Brute,
                "{k:?}: padded rows"
            );
            c
        })
        .collect()
}

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
