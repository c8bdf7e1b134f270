//! The built-in scene: the objects of Turk's user study (thesis, chapter 6).
//!
//! A "triple ring" — three parallel rings of spheres whose centres lie on one
//! axis (x), each ring in a plane normal to z — and an "E": a spine along x
//! with three prongs along z, spaced like the rings so that each prong passes
//! through one ring. All spheres are carbon atoms, so their radius follows the
//! chosen radius table (1.70 Å Bondi, 1.74 Å thesis).
//!
//! The E's file pose is the study's start pose: [`START_OFFSET`] away from its
//! docked pose, behind the rings. In the docked pose ([`docked_offset`] from
//! the start: +25 Å along z) each prong pierces its ring's centre, its tip
//! [`PRONG_OUT`] Å beyond the ring plane, the spine [`SPINE_DEPTH`] Å behind
//! it. The straight path from start to docked is collision-free (tests prove
//! it): `bump touch builtin --move 0,0,25` docks it with t = 1.

use glam::DVec3;

use super::{AtomInfo, Label, Molecule, RadiiSet, element::is_polar};

/// Ring radius (centre of ring to centre of its spheres), Å.
pub const RING_RADIUS: f64 = 5.0;
/// Spheres per ring.
pub const RING_SPHERES: usize = 18;
/// Distance between ring centres along x, Å.
pub const RING_SPACING: f64 = 12.0;
/// Spacing of spheres along the E's spine and prongs, Å.
pub const E_SPACING: f64 = 1.5;
/// How far the prong tips reach beyond the ring plane when docked, Å.
pub const PRONG_OUT: f64 = 6.0;
/// Depth of the spine behind the ring plane when docked, Å.
pub const SPINE_DEPTH: f64 = 8.0;
/// Offset of the E's start (file) pose from its docked pose, Å.
pub const START_OFFSET: DVec3 = DVec3::new(0.0, 0.0, -25.0);

fn carbon(serial: i64, name: String, residue: &str, chain: &str, radii: RadiiSet) -> AtomInfo {
    AtomInfo {
        serial,
        name: name.into(),
        residue: residue.into(),
        seq: 1,
        insertion: Label::EMPTY,
        chain: chain.into(),
        element: "C".into(),
        radius: radii.radius("C").unwrap_or(1.7),
        polar: is_polar("C"),
        hetero: false,
    }
}

/// The triple ring (the receptor of the built-in scene), in its file frame.
pub fn triple_ring(radii: RadiiSet) -> Molecule {
    let mut atoms = Vec::new();
    let mut pos = Vec::new();
    for ring in 0..3 {
        let cx = (ring as f64 - 1.0) * RING_SPACING;
        for k in 0..RING_SPHERES {
            let a = std::f64::consts::TAU * k as f64 / RING_SPHERES as f64;
            pos.push(DVec3::new(
                cx + RING_RADIUS * a.cos(),
                RING_RADIUS * a.sin(),
                0.0,
            ));
            let serial = atoms.len() as i64 + 1;
            atoms.push(carbon(serial, format!("R{ring}{k}"), "RNG", "R", radii));
        }
    }
    Molecule::new("built-in triple ring", atoms, &pos)
}

/// The E (the drug of the built-in scene) at its start pose.
pub fn e_shape(radii: RadiiSet) -> Molecule {
    let mut atoms = Vec::new();
    let mut pos = Vec::new();
    let mut push = |p: DVec3, name: String| {
        let serial = atoms.len() as i64 + 1;
        atoms.push(carbon(serial, name, "E", "E", radii));
        pos.push(p + START_OFFSET);
    };
    let spine_len = 2.0 * RING_SPACING;
    let n_spine = (spine_len / E_SPACING).round() as usize;
    for k in 0..=n_spine {
        let x = -RING_SPACING + spine_len * k as f64 / n_spine as f64;
        push(DVec3::new(x, 0.0, -SPINE_DEPTH), format!("S{k}"));
    }
    let prong_len = SPINE_DEPTH + PRONG_OUT;
    let n_prong = (prong_len / E_SPACING).round() as usize;
    for p in 0..3 {
        let x = (p as f64 - 1.0) * RING_SPACING;
        for k in 1..=n_prong {
            let z = -SPINE_DEPTH + prong_len * k as f64 / n_prong as f64;
            push(DVec3::new(x, 0.0, z), format!("P{p}{k}"));
        }
    }
    Molecule::new("built-in E", atoms, &pos)
}

/// The translation from the E's file (start) pose to its docked pose.
pub fn docked_offset() -> DVec3 {
    -START_OFFSET
}

/// The built-in scene: (receptor, drug) = (triple ring, E at its start pose).
pub fn scene(radii: RadiiSet) -> (Molecule, Molecule) {
    (triple_ring(radii), e_shape(radii))
}
