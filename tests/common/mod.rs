//! Shared helpers for the integration tests: test data location, random
//! molecules and the exact (f64) oracles of `bump::collide::oracle`.
#![allow(dead_code)]

pub mod x11;

use std::path::PathBuf;

use bump::collide::{Collider, ContactRule, DrugAtoms, oracle};
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

/// A tiny deterministic generator (xorshift64*), so tests need no seed crate.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

pub fn atom(serial: i64, element: &str, radius: f32) -> AtomInfo {
    AtomInfo {
        serial,
        name: format!("{element}{serial}"),
        residue: "RND".into(),
        seq: 1,
        insertion: String::new(),
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

/// Exact time of impact for a pure translation `d` of the drug from relative
/// pose `start` ([`bump::collide::oracle::translation_toi`]).
pub fn exact_translation_toi(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    start: &Pose,
    d: DVec3,
) -> Option<f64> {
    oracle::translation_toi(rule, receptor, drug, start, d)
}

/// True when any pair collides (f64) at `pose`.
pub fn collides_f64(rule: &ContactRule, receptor: &Molecule, drug: &Molecule, pose: &Pose) -> bool {
    min_gap_f64(rule, receptor, drug, pose) <= 0.0
}

/// Smallest `d − c` over all pairs (f64).
pub fn min_gap_f64(rule: &ContactRule, receptor: &Molecule, drug: &Molecule, pose: &Pose) -> f64 {
    oracle::min_gap(rule, receptor, drug, pose)
}

/// First contact time along the screw by dense f64 sampling then bisection.
pub fn dense_screw_toi(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    screw: &Screw,
    samples: usize,
) -> Option<f64> {
    oracle::dense_screw_toi(rule, receptor, drug, screw, samples)
}

/// Largest atom speed of a screw (Å per unit t) for the drug at its start.
pub fn max_speed(drug: &DrugAtoms, screw: &Screw) -> f64 {
    drug.rotated(screw.start())
        .iter()
        .map(|y| screw.speed(*y))
        .fold(0.0, f64::max)
}

/// Brute-force reference collider plus the other two for `receptor`.
pub fn all_colliders(receptor: &Molecule, rule: &ContactRule) -> Vec<Collider> {
    bump::collide::ColliderKind::ALL
        .iter()
        .map(|k| Collider::build(receptor, rule, *k))
        .collect()
}
