//! Move-to-touch against exact answers: the closed-form time of impact for
//! translations, a dense f64 search for screw motions, and parry3d's shape
//! casts on the same queries. Plus the thin wall, the 1000 Å step and the
//! numerical stress cases. Worst errors are printed (`--nocapture`).

mod common;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, TouchOptions, TouchResult,
    move_to_touch, move_to_touch_into,
};
use bump::model::Molecule;
use bump::motion::{Pose, Screw};
use bump_testkit::parry;
use common::*;
use glam::{DQuat, DVec3};

const TOL: f64 = 1e-3;

struct Setup {
    rule: ContactRule,
    receptor: Molecule,
    drug: Molecule,
    cols: Vec<Collider>,
    atoms: DrugAtoms,
}

fn setup(rng: &mut Rng, n: usize, m: usize, polar: bool, rule: ContactRule) -> Setup {
    let receptor = random_molecule(rng, n, 30.0, DVec3::new(-4e4, 2.0, 1e5), polar);
    let drug = random_molecule(rng, m, 7.0, DVec3::new(3.0, 1e5, 0.0), polar);
    let cols = all_colliders(&receptor, &rule);
    let atoms = DrugAtoms::new(&drug, &rule, cols[0].max_radius());
    Setup {
        rule,
        receptor,
        drug,
        cols,
        atoms,
    }
}

/// A collision-free start pose outside the receptor, and an approach motion.
fn random_query(rng: &mut Rng, s: &Setup, rotate: bool) -> (Pose, Pose) {
    loop {
        let dir = rng.unit();
        let start = Pose::new(
            DQuat::from_axis_angle(rng.unit(), rng.range(0.0, 3.0)),
            dir * rng.range(14.0, 30.0),
        );
        if collides_f64(&s.rule, &s.receptor, &s.drug, &start)
            || min_gap_f64(&s.rule, &s.receptor, &s.drug, &start) < 0.01
        {
            continue;
        }
        let travel = -dir * rng.range(1.0, 30.0) + rng.unit() * rng.range(0.0, 5.0);
        let (axis, ang) = if rotate {
            (rng.unit(), rng.range(-1.2, 1.2))
        } else {
            (DVec3::X, 0.0)
        };
        return (start, start.moved(travel, axis, ang));
    }
}

#[test]
fn translations_match_the_closed_form() {
    let mut rng = Rng(0x5eed);
    let mut worst_travel: f64 = 0.0;
    let mut worst_gap: f64 = 0.0;
    let mut hits = 0;
    let (mut thesis_overlaps, mut thesis_passed) = (0, 0);
    let thesis = TouchOptions {
        method: Method::Thesis,
        ..TouchOptions::default()
    };
    for case in 0..300 {
        let s = setup(&mut rng, 300, 15, case % 2 == 0, ContactRule::default());
        let (start, end) = random_query(&mut rng, &s, false);
        let d = end.translation - start.translation;
        let exact = exact_translation_toi(&s.rule, &s.receptor, &s.drug, &start, d);
        // The thesis's method on the same query: how often it fails.
        let rt = move_to_touch(&s.cols[2], &s.atoms, &start, &end, &thesis);
        if min_gap_f64(&s.rule, &s.receptor, &s.drug, &rt.pose) <= 0.0 {
            thesis_overlaps += 1;
        }
        if exact.is_some_and(|te| rt.t > te) {
            thesis_passed += 1;
        }
        for c in &s.cols {
            let r = move_to_touch(c, &s.atoms, &start, &end, &TouchOptions::default());
            let g = min_gap_f64(&s.rule, &s.receptor, &s.drug, &r.pose);
            assert!(g > 0.0, "overlap {g} ({:?}, case {case})", c.kind());
            assert!(r.t.is_finite() && (0.0..=1.0).contains(&r.t));
            match exact {
                None => assert_eq!(r.t, 1.0, "case {case}: free path not taken"),
                Some(te) => {
                    hits += 1;
                    assert!(r.t <= te, "case {case}: passed contact {} > {te}", r.t);
                    assert!(
                        g <= TOL + 1e-6,
                        "case {case}: stopped {g} Å short of contact"
                    );
                    worst_travel = worst_travel.max((te - r.t) * d.length());
                    worst_gap = worst_gap.max(g);
                    assert!(!r.contacts.is_empty());
                }
            }
        }
    }
    println!(
        "closed form: {hits} hits, worst gap at stop {worst_gap:.2e} Å, worst travel short of exact contact {worst_travel:.2e} Å"
    );
    println!(
        "thesis method on the same 300 queries: {thesis_overlaps} overlapping results, {thesis_passed} past the first contact"
    );
    assert!(hits > 100);
}

#[test]
fn screw_motions_match_a_dense_search() {
    let mut rng = Rng(0xfeed);
    let mut worst_gap: f64 = 0.0;
    let mut worst_t: f64 = 0.0;
    let mut hits = 0;
    for case in 0..80 {
        let s = setup(&mut rng, 150, 8, case % 2 == 1, ContactRule::default());
        let (start, end) = random_query(&mut rng, &s, true);
        let screw = Screw::between(start, end);
        let dense = dense_screw_toi(&s.rule, &s.receptor, &s.drug, &screw, 4000);
        let smax = max_speed(&s.drug, &screw);
        for c in &s.cols {
            let r = move_to_touch(c, &s.atoms, &start, &end, &TouchOptions::default());
            let g = min_gap_f64(&s.rule, &s.receptor, &s.drug, &r.pose);
            assert!(g > 0.0, "overlap {g} at case {case}");
            match dense {
                None => assert_eq!(r.t, 1.0, "case {case}"),
                Some(td) => {
                    hits += 1;
                    assert!(r.t <= td + 1e-9, "case {case}: {} beyond {td}", r.t);
                    assert!(g <= TOL + 1e-6, "case {case}: gap {g}");
                    worst_gap = worst_gap.max(g);
                    worst_t = worst_t.max((td - r.t) * smax);
                }
            }
        }
    }
    println!(
        "dense screw search: {hits} hits, worst gap at stop {worst_gap:.2e} Å, worst travel short {worst_t:.2e} Å"
    );
    assert!(hits > 20);
}

#[test]
fn agrees_with_parry3d_shape_casts() {
    use parry3d::math::Pose as PPose;
    use parry3d::query::{self, NonlinearRigidMotion};

    // parry's balls of radius r − 0.3 touch exactly where the rule's
    // non-polar contact is (overlap 0.6); polar atoms are left out. The
    // model and the casts are the benchmarks' own (`parry::Spheres`).
    let rule = ContactRule::default();
    let mut rng = Rng(0xabc);
    let (mut worst_lin, mut worst_rot, mut n_lin, mut n_rot) = (0.0f64, 0.0f64, 0, 0);
    let (mut same_contacts, mut with_contacts) = (0, 0);
    for case in 0..60 {
        let s = setup(&mut rng, 200, 10, false, rule);
        let rec = parry::Spheres::new(&s.receptor, &rule);
        let dr = parry::Spheres::new(&s.drug, &rule);
        let rotate = case % 2 == 1;
        let (start, end) = random_query(&mut rng, &s, rotate);
        let r = move_to_touch(&s.cols[2], &s.atoms, &start, &end, &TouchOptions::default());
        let screw = Screw::between(start, end);
        let smax = max_speed(&s.drug, &screw);
        // The baseline's contact list, at bump's stop, is bump's own.
        let ours_pairs: Vec<(u32, u32)> = r.contacts.iter().map(|p| (p.receptor, p.drug)).collect();
        if !ours_pairs.is_empty() {
            with_contacts += 1;
            if parry::contacts(&rec, &dr, &r.pose, 1e-3) == ours_pairs {
                same_contacts += 1;
            }
        }
        let parry_t = if !rotate {
            let t = parry::touch(&rec, &dr, &start, &end, 1e-3, &mut Vec::new());
            (t < 1.0).then_some(t)
        } else {
            // A screw is parry's nonlinear motion about a point on the screw axis.
            let a = screw.axis_point().expect("rotating");
            let local_a = start.inverse().transform_point(a).as_vec3();
            let motion = NonlinearRigidMotion::new(
                parry::pose(&start),
                local_a,
                screw.slide().as_vec3(),
                (screw.axis() * screw.angle()).as_vec3(),
            );
            let still = NonlinearRigidMotion::constant_position(PPose::IDENTITY);
            query::cast_shapes_nonlinear(
                &still,
                &rec.compound,
                &motion,
                &dr.compound,
                0.0,
                1.0,
                true,
            )
            .expect("supported")
            .map(|h| f64::from(h.time_of_impact))
        };
        let ours = (r.t < 1.0).then_some(r.t);
        match (ours, parry_t) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                let err = (a - b).abs() * smax;
                if rotate {
                    worst_rot = worst_rot.max(err);
                    n_rot += 1;
                } else {
                    worst_lin = worst_lin.max(err);
                    n_lin += 1;
                }
            }
            (a, b) => {
                // Only acceptable when the contact is within f32/tolerance noise of t = 1.
                let t = a.or(b).unwrap_or(1.0);
                assert!(
                    (1.0 - t) * smax < 1e-2,
                    "case {case}: ours {a:?}, parry {b:?}"
                );
            }
        }
    }
    println!(
        "parry3d: {n_lin} translations, worst |Δt|·speed {worst_lin:.2e} Å; {n_rot} screws, worst {worst_rot:.2e} Å; same contacts at bump's stop {same_contacts}/{with_contacts}"
    );
    assert!(worst_lin < 0.05 && worst_rot < 0.05);
    assert!(n_lin + n_rot > 20);
    assert!(with_contacts > 20);
    assert_eq!(same_contacts, with_contacts);
}

/// A one-atom-thick wall of carbon at z = 0, 40 × 40 Å.
fn wall() -> Molecule {
    let mut atoms = Vec::new();
    let mut pos = Vec::new();
    for i in 0..27 {
        for j in 0..27 {
            atoms.push(atom((i * 27 + j) as i64 + 1, "C", 1.7));
            pos.push(DVec3::new(
                i as f64 * 1.5 - 20.0,
                j as f64 * 1.5 - 20.0,
                0.0,
            ));
        }
    }
    Molecule::new("wall", atoms, &pos)
}

/// The default rule, the wall and a random 12-atom drug (seeded).
fn wall_and_drug(seed: u64) -> (ContactRule, Molecule, Molecule) {
    let mut rng = Rng(seed);
    let drug = random_molecule(&mut rng, 12, 5.0, DVec3::ZERO, true);
    (ContactRule::default(), wall(), drug)
}

#[test]
fn a_1000_angstrom_step_never_passes_a_thin_wall() {
    let (rule, w, drug) = wall_and_drug(3);
    for c in all_colliders(&w, &rule) {
        let (kind, d) = (c.kind(), DrugAtoms::new(&drug, &rule, c.max_radius()));
        let start = Pose::from_translation(DVec3::new(0.3, -0.2, -500.0));
        let end = start.moved(DVec3::new(0.0, 0.0, 1000.0), DVec3::X, 0.0);
        let r = move_to_touch(&c, &d, &start, &end, &TouchOptions::default());
        assert!(r.t < 0.5 && r.t > 0.49, "{kind:?}: t = {}", r.t);
        assert!(r.pose.translation.z < 0.0);
        assert!(min_gap_f64(&rule, &w, &drug, &r.pose) > 0.0);
        assert!(!r.contacts.is_empty());
        // With a spin about the direction of travel (a helix through the wall).
        let end2 = start.moved(DVec3::new(0.0, 0.0, 1000.0), DVec3::Z, 2.5);
        let r2 = move_to_touch(&c, &d, &start, &end2, &TouchOptions::default());
        assert!(r2.pose.translation.z < 0.0 && r2.t < 0.5, "{kind:?}");
        assert!(min_gap_f64(&rule, &w, &drug, &r2.pose) > 0.0);
        // A spin about y makes the screw an arc about a distant axis: wherever
        // it stops, no sampled pose on the way overlaps the wall.
        let end3 = start.moved(DVec3::new(0.0, 0.0, 1000.0), DVec3::Y, 2.5);
        let r3 = move_to_touch(&c, &d, &start, &end3, &TouchOptions::default());
        let screw = Screw::between(start, end3);
        for k in 0..=20_000 {
            let t = r3.t * k as f64 / 20_000.0;
            assert!(
                !collides_f64(&rule, &w, &drug, &screw.pose_at(t)),
                "{kind:?} at {t}"
            );
        }
        // The thesis's method looks only at the end pose: it tunnels.
        let thesis = TouchOptions {
            method: Method::Thesis,
            ..TouchOptions::default()
        };
        let rt = move_to_touch(&c, &d, &start, &end, &thesis);
        assert_eq!(rt.t, 1.0, "the thesis method should tunnel here");
    }
}

/// Steps of 10⁸ Å (10⁸ intervals of 1 Å, were each one visited) through,
/// past and along the wall: only the intervals near the wall are searched,
/// and the drug still stops at it, or passes it untouched.
#[test]
fn a_1e8_angstrom_step_searches_only_near_the_wall() {
    let (rule, w, drug) = wall_and_drug(4);
    let opts = TouchOptions::default();
    for c in all_colliders(&w, &rule) {
        let (kind, d) = (c.kind(), DrugAtoms::new(&drug, &rule, c.max_radius()));
        // Straight through: it stops just short of the wall, half way.
        let start = Pose::from_translation(DVec3::new(0.3, -0.2, -5e7));
        let end = start.moved(DVec3::new(0.0, 0.0, 1e8), DVec3::X, 0.0);
        let r = move_to_touch(&c, &d, &start, &end, &opts);
        assert!(r.t < 0.5 && r.t > 0.4999999, "{kind:?}: t = {}", r.t);
        assert!(r.pose.translation.z < 0.0 && r.pose.translation.z > -10.0);
        assert!(min_gap_f64(&rule, &w, &drug, &r.pose) > 0.0);
        assert!(!r.contacts.is_empty());
        // Spinning about the direction of travel: a helix through the wall.
        let spun = start.moved(DVec3::new(0.0, 0.0, 1e8), DVec3::Z, 2.5);
        let r = move_to_touch(&c, &d, &start, &spun, &opts);
        assert!(r.t < 0.5 && r.pose.translation.z < 0.0, "{kind:?}");
        assert!(min_gap_f64(&rule, &w, &drug, &r.pose) > 0.0);
        // Turning 2.5 rad about y: an arc about an axis 5·10⁷ Å away, which
        // bulges 3.6·10⁷ Å to the side of the straight path and misses the
        // wall (10⁸ intervals, were each one visited).
        let arc = start.moved(DVec3::new(0.0, 0.0, 1e8), DVec3::Y, 2.5);
        let r = move_to_touch(&c, &d, &start, &arc, &opts);
        assert_eq!(r.t, 1.0, "{kind:?}");
        assert!(r.contacts.is_empty() && r.start_colliding.is_empty());
        // The same arc moved sideways so that its middle runs into the
        // wall's centre (where it travels along z): it stops just short.
        let mid = Screw::between(start, arc).centre_at(0.5) - DVec3::new(0.3, -0.2, 0.0);
        let (start_m, arc_m) = (
            start.moved(-mid, DVec3::X, 0.0),
            arc.moved(-mid, DVec3::X, 0.0),
        );
        let r = move_to_touch(&c, &d, &start_m, &arc_m, &opts);
        assert!(r.t < 0.5 && r.t > 0.49999, "{kind:?}: t = {}", r.t);
        assert!(r.pose.translation.z < 0.0 && r.pose.translation.z > -10.0);
        assert!(min_gap_f64(&rule, &w, &drug, &r.pose) > 0.0);
        assert!(!r.contacts.is_empty(), "{kind:?}");
        // Beside the wall, from far before it to far past it: free.
        let beside = Pose::from_translation(DVec3::new(100.0, 0.0, -5e7));
        let past = beside.moved(DVec3::new(0.0, 0.0, 1e8), DVec3::X, 0.0);
        let r = move_to_touch(&c, &d, &beside, &past, &opts);
        assert_eq!(r.t, 1.0, "{kind:?}");
        assert!(r.contacts.is_empty() && r.start_colliding.is_empty());
        // The long way to a pose in contact: its contacts are reported.
        let r = move_to_touch(&c, &d, &start, &end, &opts);
        let r = move_to_touch(&c, &d, &start, &r.pose, &opts);
        assert!(!r.contacts.is_empty(), "{kind:?}");
        assert!(min_gap_f64(&rule, &w, &drug, &r.pose) > 0.0);
    }
}

#[test]
fn stress_cases_never_overlap_nan_or_panic() {
    let rule = ContactRule::default();
    let far = DVec3::new(1e5, -1e5, 1e5);
    let two = |d: f64| {
        let r = Molecule::new("r", vec![atom(1, "C", 1.7)], &[far]);
        let m = Molecule::new(
            "d",
            vec![atom(1, "C", 1.7)],
            &[far + DVec3::new(d, 0.0, 0.0)],
        );
        (r, m)
    };
    for kind in ColliderKind::ALL {
        let (r, m) = two(5.0);
        let c = Collider::build(&r, &rule, kind);
        let d = DrugAtoms::new(&m, &rule, c.max_radius());
        let start = Pose::from_translation(m.centre - r.centre);
        let opts = TouchOptions::default();
        // Tiny and huge steps towards the receptor atom.
        for step in [1e-9, 1e-3, 1.0, 1e3] {
            let end = start.moved(DVec3::new(-step, 0.0, 0.0), DVec3::Z, 0.0);
            let res = move_to_touch(&c, &d, &start, &end, &opts);
            let x = res.pose.translation.x;
            assert!(res.t.is_finite() && x.is_finite());
            assert!(x > 2.8, "{kind:?} step {step}: overlap at {x}");
            if step < 2.0 {
                assert_eq!(res.t, 1.0);
            } else {
                assert!(x < 2.8 + TOL + 1e-6, "{kind:?}: stopped at {x}");
            }
        }
        // Zero-length motion.
        let res = move_to_touch(&c, &d, &start, &start, &opts);
        assert_eq!(res.t, 1.0);
        assert_eq!(res.pose, start);
        // Exactly touching (d = c = 2.8 Å) collides by the rule: it may move away, not closer.
        let touching = Pose::from_translation(DVec3::new(2.8, 0.0, 0.0));
        let away = touching.moved(DVec3::new(1.0, 0.0, 0.0), DVec3::Z, 0.0);
        let closer = touching.moved(DVec3::new(-1.0, 0.0, 0.0), DVec3::Z, 0.0);
        let ra = move_to_touch(&c, &d, &touching, &away, &opts);
        assert!(ra.start_collides() && ra.t == 1.0, "{kind:?}: {}", ra.t);
        let rc = move_to_touch(&c, &d, &touching, &closer, &opts);
        assert!(rc.t == 0.0 && rc.pose.translation.x >= 2.8 - 1e-6);
        // Coincident atoms: frozen against deepening, free to leave.
        let same = Pose::IDENTITY;
        let leave = same.moved(DVec3::new(0.0, 4.0, 0.0), DVec3::Z, 0.0);
        let rl = move_to_touch(&c, &d, &same, &leave, &opts);
        assert!(rl.start_collides() && rl.t.is_finite() && !rl.pose.translation.is_nan());
        // A spin about a coincident atom neither deepens nor separates: allowed.
        let spin = same.moved(DVec3::ZERO, DVec3::Z, 1.0);
        let rs = move_to_touch(&c, &d, &same, &spin, &opts);
        assert!(rs.t.is_finite());
        // In contact within tolerance, then moving away and sideways.
        let near = Pose::from_translation(DVec3::new(2.8005, 0.0, 0.0));
        let side = near.moved(DVec3::new(0.0, 3.0, 0.0), DVec3::Z, 0.0);
        let rn = move_to_touch(&c, &d, &near, &side, &opts);
        assert_eq!(rn.t, 1.0, "{kind:?}: sliding off a contact is free");
        let rin = move_to_touch(&c, &d, &near, &closer, &opts);
        assert!(rin.t < 1e-3 && rin.pose.translation.x > 2.8);
        // Non-finite input never panics.
        let bad = Pose::from_translation(DVec3::new(f64::NAN, 0.0, 0.0));
        let rb = move_to_touch(&c, &d, &start, &bad, &opts);
        assert_eq!(rb.t, 0.0);
    }
}

/// One result passed to `move_to_touch_into` query after query (stops with
/// contacts, free steps, colliding starts, both methods, a pose out of
/// reach) holds exactly what a fresh `move_to_touch` answers each time:
/// nothing of an earlier answer is left in it.
#[test]
fn a_reused_result_answers_as_a_fresh_one() {
    let rule = ContactRule::default();
    let mut rng = Rng(2024);
    let s = setup(&mut rng, 300, 12, true, rule);
    let mut reused = TouchResult::default();
    let (mut stopped, mut free, mut colliding) = (0, 0, 0);
    for k in 0..240 {
        let (start, end) = match k % 6 {
            // Buried in the receptor: the start collides.
            4 => (
                Pose::IDENTITY,
                Pose::IDENTITY.moved(rng.unit() * 2.0, rng.unit(), 0.3),
            ),
            5 if k % 12 == 5 => (
                Pose::IDENTITY,
                Pose::from_translation(DVec3::splat(f64::NAN)),
            ),
            _ => random_query(&mut rng, &s, k % 3 == 1),
        };
        let method = if k % 7 == 3 {
            Method::Thesis
        } else {
            Method::Swept
        };
        let opts = TouchOptions {
            method,
            ..TouchOptions::default()
        };
        for col in &s.cols {
            let fresh = move_to_touch(col, &s.atoms, &start, &end, &opts);
            move_to_touch_into(col, &s.atoms, &start, &end, &opts, &mut reused);
            assert_eq!(fresh.t.to_bits(), reused.t.to_bits(), "query {k}");
            assert_eq!(fresh.pose, reused.pose, "query {k}");
            assert_eq!(fresh.contacts, reused.contacts, "query {k}");
            assert_eq!(fresh.colliding, reused.colliding, "query {k}");
            assert_eq!(fresh.start_colliding, reused.start_colliding, "query {k}");
            stopped += usize::from(fresh.t < 1.0 && !fresh.contacts.is_empty());
            free += usize::from(fresh.contacts.is_empty());
            colliding += usize::from(fresh.start_collides());
        }
    }
    assert!(
        stopped > 100 && free > 20 && colliding > 20,
        "{stopped} {free} {colliding}"
    );
}

#[test]
fn a_colliding_start_allows_only_motions_that_do_not_deepen() {
    let rule = ContactRule::default();
    let mut rng = Rng(99);
    let receptor = random_molecule(&mut rng, 300, 25.0, DVec3::ZERO, true);
    let drug = random_molecule(&mut rng, 10, 6.0, DVec3::ZERO, true);
    let c = Collider::build(&receptor, &rule, ColliderKind::Hashed);
    let d = DrugAtoms::new(&drug, &rule, c.max_radius());
    let start = Pose::IDENTITY; // buried in the random receptor: collides
    let r0 = move_to_touch(
        &c,
        &d,
        &start,
        &start.moved(DVec3::X * 3.0, DVec3::Z, 0.4),
        &TouchOptions::default(),
    );
    assert!(r0.start_collides());
    // Every pair colliding at the start is no closer at the result.
    let before = bump::collide::check(&c, &d, &start);
    let after = bump::collide::check(&c, &d, &r0.pose);
    for p in &after {
        let b = before
            .iter()
            .find(|b| (b.receptor, b.drug) == (p.receptor, p.drug));
        let b = b.expect("no new collisions");
        assert!(p.distance >= b.distance - 1e-4);
    }
}

/// Pushes from a colliding start, each from where the last stopped, long
/// enough that a colliding pair would pass by and end no deeper (so its
/// target allows a rounding-size dip on the way): no stop short of the end
/// may leave any pair that collided at that step's start closer (f64) than
/// it was, so repeated pushes cannot sink the drug.
#[test]
fn pushes_from_a_colliding_start_never_sink_the_drug() {
    let rule = ContactRule::default();
    let mut rng = Rng(41);
    let mut checked = 0;
    for round in 0..40 {
        let receptor = random_molecule(&mut rng, 200, 20.0, DVec3::ZERO, true);
        let drug = random_molecule(&mut rng, 8, 5.0, DVec3::ZERO, true);
        let c = Collider::build(&receptor, &rule, ColliderKind::Grid);
        let d = DrugAtoms::new(&drug, &rule, c.max_radius());
        let at = |p: &Pose, i: usize| p.rotation * drug.local[i].as_dvec3() + p.translation;
        let gap2 = |p: &Pose, r: u32, i: u32| {
            (at(p, i as usize) - receptor.local[r as usize].as_dvec3()).length_squared()
        };
        let dir = rng.unit();
        let mut pose = Pose::from_translation(rng.unit() * 2.0);
        for _ in 0..30 {
            let end = pose.moved(dir * 6.0, DVec3::Z, 0.0);
            let r = move_to_touch(&c, &d, &pose, &end, &TouchOptions::default());
            if r.t < 1.0 {
                for p in &r.start_colliding {
                    let (before, after) = (
                        gap2(&pose, p.receptor, p.drug),
                        gap2(&r.pose, p.receptor, p.drug),
                    );
                    assert!(
                        after >= before,
                        "round {round}: pair {}/{} sank from {} to {} Å at t = {}",
                        p.receptor,
                        p.drug,
                        before.sqrt(),
                        after.sqrt(),
                        r.t
                    );
                }
                checked += usize::from(r.start_collides());
            }
            pose = r.pose;
        }
    }
    // Many stops from a colliding start were checked.
    assert!(checked > 100, "{checked}");
}

#[test]
fn overlapping_copies_can_be_pulled_apart_but_never_pushed_in() {
    use bump::model::{RadiiSet, builtin};
    let rule = ContactRule::default();
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    // The E and rings merged into one receptor whose centre differs from the
    // E's, so the drug copy's atoms coincide with the receptor's only up to
    // f32 rounding (~1e-6 Å), in random directions.
    let mut atoms = rings.atoms.clone();
    atoms.extend(e.atoms.clone());
    let mut pos = rings.file_positions();
    pos.extend(e.file_positions());
    let env = Molecule::new("env", atoms, &pos);
    let c = Collider::build(&env, &rule, ColliderKind::Hashed);
    let d = DrugAtoms::new(&e, &rule, c.max_radius());
    let start = Pose::from_translation(e.centre - env.centre);
    let mut rng = Rng(5);
    for k in 0..20 {
        // Straight out of the E's plane (±y), with in-plane wobble of rounding
        // size: the copy separates at once. (Any real in-plane component
        // would push spine neighbours deeper into each other, and is refused.)
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let dir = (DVec3::new(0.0, sign, 0.0) + rng.unit() * 1e-7).normalize();
        let r = move_to_touch(
            &c,
            &d,
            &start,
            &start.moved(dir * 30.0, DVec3::Z, 0.0),
            &TouchOptions::default(),
        );
        assert!(r.start_collides());
        assert!(r.t > 0.9, "stuck leaving along {dir}: t = {}", r.t);
    }
    // Pushing along the E's own spine (x) deepens every neighbour overlap: it
    // must not creep, however many frames it is repeated.
    let depth = |p: &Pose| {
        bump::collide::check(&c, &d, p)
            .iter()
            .map(|q| q.distance)
            .fold(f32::INFINITY, f32::min)
    };
    let first = depth(&start);
    let mut pose = start;
    for _ in 0..2000 {
        let r = move_to_touch(
            &c,
            &d,
            &pose,
            &pose.moved(DVec3::new(0.01, 0.0, 0.0), DVec3::Z, 0.0),
            &TouchOptions::default(),
        );
        pose = r.pose;
    }
    assert!(
        (pose.translation - start.translation).length() < 1e-3,
        "crept {}",
        (pose.translation - start.translation).length()
    );
    assert!(depth(&pose) >= first - 1e-4);
}
