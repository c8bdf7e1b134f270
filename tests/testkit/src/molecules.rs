//! Test atoms, random molecules, and the three colliders of a receptor.

use bump::collide::{Collider, ColliderKind, ContactRule};
use bump::model::{AtomInfo, Molecule};
use glam::DVec3;

use crate::rng::Rng;

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

/// `n` random atoms (C/N/O/S radii, or only C/S when not `polar`) in a
/// cube of edge `size` centred at `centre`.
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

/// Brute force (the reference), then the full grid and the hashed grid
/// for `receptor`, each once its clearance map and padded rows are built
/// (on the collider's own thread), so the tests exercise the queries that
/// use them.
///
/// # Panics
/// When a grid has no map or no rows, or brute force has either.
pub fn all_colliders(receptor: &Molecule, rule: &ContactRule) -> Vec<Collider> {
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
