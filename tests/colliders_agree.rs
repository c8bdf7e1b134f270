//! Every collider returns exactly brute force's sorted pair list: on random
//! sphere sets (property tests) and on real structures. Move-to-touch, which
//! asks the grids' clearance maps which drug atoms it may skip, returns
//! brute force's answer bit for bit, and its contacts are the static rule's
//! at the pose it returns.

mod common;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, TouchOptions, check, move_to_touch,
    pairs_within,
};
use bump::motion::Pose;
use bump_testkit::surface;
use common::{Rng, all_colliders, random_molecule};
use glam::{DQuat, DVec3};
use proptest::prelude::*;

/// Brute force (the reference), then the full grid and the hashed grid.
fn colliders(receptor: &bump::model::Molecule) -> Vec<Collider> {
    all_colliders(receptor, &ContactRule::default())
}

fn agree(receptor: &bump::model::Molecule, drug: &bump::model::Molecule, rel: &Pose, extra: f32) {
    agree_with(&colliders(receptor), drug, rel, extra);
}

fn agree_with(cols: &[Collider], drug: &bump::model::Molecule, rel: &Pose, extra: f32) {
    let rule = ContactRule::default();
    let d = DrugAtoms::new(drug, &rule, cols[0].max_radius());
    let reference = pairs_within(&cols[0], &d, rel, extra);
    for c in &cols[1..] {
        assert_eq!(
            pairs_within(c, &d, rel, extra),
            reference,
            "{:?} disagrees with brute force",
            c.kind()
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn random_sets_agree(seed in any::<u64>(), n in 1usize..400, m in 1usize..40,
                         size in 5.0f64..60.0, ax in -1.0f64..1.0, ay in -1.0f64..1.0,
                         ang in -3.2f64..3.2, ox in -30.0f64..30.0, extra in 0.0f32..2.0) {
        let mut rng = Rng(seed | 1);
        let receptor = random_molecule(&mut rng, n, size, DVec3::new(1e5, -3.0, 7.0), true);
        let drug = random_molecule(&mut rng, m, 8.0, DVec3::ZERO, true);
        let axis = DVec3::new(ax, ay, 0.5).normalize();
        let rel = Pose::new(DQuat::from_axis_angle(axis, ang), DVec3::new(ox, 0.3 * ox, -0.2 * ox));
        agree(&receptor, &drug, &rel, 0.0);
        agree(&receptor, &drug, &rel, extra);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]
    #[test]
    fn move_to_touch_matches_brute_force_bit_for_bit(
        seed in any::<u64>(), n in 1usize..400, m in 1usize..30, size in 5.0f64..40.0,
        sx in -20.0f64..20.0, dx in -6.0f64..6.0, dy in -6.0f64..6.0, deg in -40.0f64..40.0,
        tol in 1e-5f64..1e-1,
    ) {
        let mut rng = Rng(seed | 1);
        let receptor = random_molecule(&mut rng, n, size, DVec3::new(-4e4, 2.0, 9.0), true);
        let drug = random_molecule(&mut rng, m, 6.0, DVec3::ZERO, true);
        let cols = colliders(&receptor);
        let rule = ContactRule::default();
        let d = DrugAtoms::new(&drug, &rule, cols[0].max_radius());
        let start = Pose::new(
            DQuat::from_axis_angle(DVec3::new(0.3, -0.5, 0.8).normalize(), 0.1 * sx),
            DVec3::new(sx, 0.5 * sx, -0.3 * sx),
        );
        // A third of the motions are pure translations, which place atoms
        // (and cull groups of them) by another path than screws.
        let deg = if deg.abs() < 13.0 { 0.0 } else { deg };
        let end = start.moved(DVec3::new(dx, dy, -dx), DVec3::new(dy, 1.0, 0.2), deg.to_radians());
        let opts = TouchOptions { tolerance: tol, ..TouchOptions::default() };
        let reference = move_to_touch(&cols[0], &d, &start, &end, &opts);
        for c in &cols {
            // What the search skipped (groups outside the receptor's box,
            // atoms the map proves clear) held no pair: the contacts and the
            // start's collisions are the static rule's, at those poses.
            let r = move_to_touch(c, &d, &start, &end, &opts);
            prop_assert_eq!(
                &r.contacts,
                &pairs_within(c, &d, &r.pose, opts.tolerance as f32),
                "{:?} contacts at the stop",
                c.kind()
            );
            prop_assert_eq!(&r.start_colliding, &check(c, &d, &start), "{:?} start", c.kind());
            prop_assert_eq!(r.t.to_bits(), reference.t.to_bits(), "{:?} t", c.kind());
            prop_assert_eq!(r.pose, reference.pose, "{:?} pose", c.kind());
            prop_assert_eq!(&r.contacts, &reference.contacts, "{:?} contacts", c.kind());
            prop_assert_eq!(
                &r.start_colliding,
                &reference.start_colliding,
                "{:?} start",
                c.kind()
            );
        }
    }
}

#[test]
fn colliding_pairs_are_found_and_sorted() {
    let mut rng = Rng(7);
    let receptor = random_molecule(&mut rng, 500, 30.0, DVec3::ZERO, true);
    let drug = random_molecule(&mut rng, 30, 8.0, DVec3::ZERO, true);
    let rule = ContactRule::default();
    let c = Collider::build(&receptor, &rule, ColliderKind::Hashed);
    let d = DrugAtoms::new(&drug, &rule, c.max_radius());
    let pairs = check(&c, &d, &Pose::IDENTITY);
    assert!(!pairs.is_empty());
    assert!(
        pairs
            .windows(2)
            .all(|w| (w[0].receptor, w[0].drug) < (w[1].receptor, w[1].drug))
    );
    assert!(pairs.iter().all(|p| p.collides()));
}

#[test]
fn real_structures_agree() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let opts = bump::model::LoadOptions::default();
    for (file, lig) in [
        ("6xg5_tmp_prepared.pdb", "TOP"),
        ("4dfr.pdb", "MTX"),
        ("3ptb.pdb", "BEN"),
        ("1hvr.pdb", "XK2"),
    ] {
        let loaded = bump::model::load(&dir.join(file), &opts).expect(file);
        let spec = bump::model::LigandSpec::parse(lig).expect("spec");
        let (receptor, drug) = bump::model::split_complex(&loaded.structure, &spec).expect(file);
        let cols = colliders(&receptor);
        let mut rng = Rng(11);
        // The crystal pose, poses pushed into the receptor, and random turns.
        for k in 0..25 {
            let off = if k == 0 {
                DVec3::ZERO
            } else {
                rng.unit() * rng.range(0.0, 4.0)
            };
            let rot =
                DQuat::from_axis_angle(rng.unit(), rng.range(-0.5, 0.5) * (k as f64).min(1.0));
            let rel = Pose::new(rot, drug.centre - receptor.centre + off);
            agree_with(&cols, &drug, &rel, 0.0);
            agree_with(&cols, &drug, &rel, 0.5);
        }
    }
}

/// The large receptors of the scaling benchmark, whose clearance maps have
/// more than 2²⁴ vertices (up to 2²⁶): move-to-touch onto each of 16
/// surface patches (a 1.5 Å step in, the same with a 15° turn, and a 6 Å
/// step that goes deeper) returns brute force's answer bit for bit, and the
/// static check at the end poses finds brute force's pairs. A map vertex's
/// index once went through f32, which past 2²⁴ reads a neighbour's value:
/// the maps of all four receptors then proved some atoms clear that were
/// not, and a 1aon patch stopped 0.24 Å deep in a carbon pair.
#[test]
fn large_receptors_agree_on_surface_approaches() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let rule = ContactRule::default();
    let strict = ContactRule::new(rule.overlap, 0.0).expect("rule");
    let opts = TouchOptions::default();
    for file in [
        "4kya.pdb.gz",
        "2btv.pdb.gz",
        "1aon.pdb.gz",
        "1f2n_assembly1.cif.gz",
    ] {
        let loaded =
            bump::model::load(&dir.join(file), &bump::model::LoadOptions::default()).expect(file);
        let receptor = bump::model::receptor_only(&loaded.structure).expect(file);
        let cols = colliders(&receptor);
        let vertices = cols[1].clearance().map_or(0, |m| m.bytes());
        assert!(vertices > 1 << 24, "{file}: {vertices} vertices");
        let patches = surface::surface_drugs(&receptor, &strict, 30, 16);
        assert_eq!(patches.len(), 16, "{file}");
        let mut rng = Rng(17);
        let mut touched = 0;
        for (k, patch) in patches.iter().enumerate() {
            let d = DrugAtoms::new(&patch.drug, &rule, cols[0].max_radius());
            let turned = patch
                .step_in(1.5)
                .moved(DVec3::ZERO, rng.unit(), 15f64.to_radians());
            for end in [patch.step_in(1.5), turned, patch.step_in(6.0)] {
                let reference = move_to_touch(&cols[0], &d, &patch.start, &end, &opts);
                assert!(reference.colliding.is_empty(), "{file} patch {k}");
                touched += usize::from(reference.t < 1.0);
                for c in &cols[1..] {
                    let r = move_to_touch(c, &d, &patch.start, &end, &opts);
                    let what = format!("{file} patch {k}, {:?}", c.kind());
                    assert_eq!(r.t.to_bits(), reference.t.to_bits(), "{what}: t");
                    assert_eq!(r.contacts, reference.contacts, "{what}: contacts");
                    assert!(check(c, &d, &r.pose).is_empty(), "{what}: overlap");
                }
                agree_with(&cols, &patch.drug, &end, 0.0);
                agree_with(&cols, &patch.drug, &end, 0.5);
            }
        }
        // The steps in meet the surface, so the comparison is not vacuous.
        assert!(touched >= 40, "{file}: {touched} of 48 steps touched");
    }
}
