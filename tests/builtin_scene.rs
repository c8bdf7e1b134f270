//! The built-in scene (thesis chapter 6): a triple ring and an E whose docked
//! pose is collision-free and reachable by a straight push from the start.

use bump::collide::{ColliderKind, ContactRule, Response, TouchOptions};
use bump::model::{RadiiSet, builtin};
use bump::scene::Scene;
use glam::DVec3;

fn scene(radii: RadiiSet, kind: ColliderKind) -> Scene {
    let (r, d) = builtin::scene(radii);
    Scene::new(r, d, ContactRule::default(), kind)
}

#[test]
fn shapes_are_as_documented() {
    let (ring, e) = builtin::scene(RadiiSet::Bondi);
    assert_eq!(ring.len(), 3 * builtin::RING_SPHERES);
    assert!(e.len() > 30);
    assert!(ring.atoms.iter().chain(&e.atoms).all(|a| a.radius == 1.7));
    let (_, e_thesis) = builtin::scene(RadiiSet::Thesis);
    assert!(e_thesis.atoms.iter().all(|a| a.radius == 1.74));
}

#[test]
fn start_and_docked_poses_are_free_and_the_push_docks() {
    for radii in [RadiiSet::Bondi, RadiiSet::Thesis] {
        for kind in ColliderKind::ALL {
            let s = scene(radii, kind);
            let start = s.file_relative(DVec3::ZERO);
            let docked = s.file_relative(builtin::docked_offset());
            assert!(s.check(&start).is_empty());
            assert!(s.check(&docked).is_empty());
            let r = s.move_to_touch(&start, &docked, &TouchOptions::default());
            assert_eq!(r.t, 1.0, "{radii:?} {kind:?}");
            assert_eq!(r.pose, docked);
            // Docked really means threaded: each prong is inside its ring.
            let prongs_through = s
                .drug
                .atoms
                .iter()
                .zip(&s.drug.local)
                .filter(|(a, p)| {
                    a.name.starts_with('P')
                        && (docked.transform_point(p.as_dvec3()) + s.receptor.centre)
                            .z
                            .abs()
                            < 0.8
                })
                .count();
            assert_eq!(prongs_through, 3);
        }
    }
}

#[test]
fn a_misaligned_push_touches_and_each_response_behaves() {
    let s = scene(RadiiSet::Bondi, ColliderKind::Hashed);
    let start = s.file_relative(DVec3::new(0.0, 5.0, 0.0)); // prongs hit the rings
    let end = start.moved(DVec3::new(0.0, 0.0, 25.0), DVec3::Z, 0.0);
    let opts = TouchOptions::default();
    let touch = s.respond(&start, &end, Response::Touch, &opts);
    assert!(touch.t > 0.0 && touch.t < 1.0);
    assert!(!touch.contacts.is_empty() && touch.colliding.is_empty());
    let stop = s.respond(&start, &end, Response::Stop, &opts);
    assert_eq!(stop.t, 0.0);
    assert_eq!(stop.pose, start);
    assert!(!stop.contacts.is_empty(), "stop reports what it ran into");
    let pass = s.respond(&start, &end, Response::Pass, &opts);
    assert_eq!(pass.pose, end);
    assert!(!pass.colliding.is_empty(), "pass reports the overlaps");
    // Slide: never overlaps, and never moves against the push.
    let slide = s.respond(&start, &end, Response::Slide, &opts);
    assert!(slide.colliding.is_empty());
    assert!(s.check(&slide.pose).is_empty());
    let push = end.translation - start.translation;
    assert!((slide.pose.translation - touch.pose.translation).dot(push) >= -1e-9);
}

#[test]
fn slide_carries_on_along_a_flat_wall() {
    // A one-atom-thick wall of carbon at z = 0 and a small drug pushed into it
    // at a slant: touch stops at the wall, slide keeps the along-wall motion.
    let mut atoms = Vec::new();
    let mut pos = Vec::new();
    for i in 0..31 {
        for j in 0..31 {
            let mut a = builtin::triple_ring(RadiiSet::Bondi).atoms[0].clone();
            a.serial = (i * 31 + j) as i64 + 1;
            atoms.push(a);
            pos.push(DVec3::new(
                i as f64 * 1.2 - 18.0,
                j as f64 * 1.2 - 18.0,
                0.0,
            ));
        }
    }
    let wall = bump::model::Molecule::new("wall", atoms, &pos);
    let (_, e) = builtin::scene(RadiiSet::Bondi);
    let probe = bump::model::Molecule::new("probe", vec![e.atoms[0].clone()], &[DVec3::ZERO]);
    let s = Scene::new(wall, probe, ContactRule::default(), ColliderKind::Grid);
    let start = bump::motion::Pose::from_translation(DVec3::new(-6.0, 0.3, -6.0));
    // With a turn too (radians): the push still slides.
    for turn in [0.0, 1e-7, 0.2] {
        let end = start.moved(DVec3::new(10.0, 0.0, 8.0), DVec3::Z, turn);
        let opts = TouchOptions::default();
        let touch = s.respond(&start, &end, Response::Touch, &opts);
        let slide = s.respond(&start, &end, Response::Slide, &opts);
        assert!(touch.t < 1.0);
        assert!(slide.legs > 1);
        assert!(s.check(&slide.pose).is_empty());
        assert!(slide.pose.translation.z < 0.0, "slid through the wall");
        assert!(
            slide.pose.translation.x > touch.pose.translation.x + 2.0,
            "turn {turn}: slide {} vs touch {}",
            slide.pose.translation.x,
            touch.pose.translation.x
        );
    }
}

/// The E pushed into the rings off-centre, with a small turn (which once
/// left every slide leg stuck at the touch pose): it slides on past it.
#[test]
fn a_turning_push_slides_past_the_rings() {
    let s = scene(RadiiSet::Bondi, ColliderKind::Grid);
    let start = s.file_relative(DVec3::new(0.0, 2.5, 0.0));
    for degrees in [0.0f64, 0.001, 1.0] {
        let end = start.moved(DVec3::new(0.0, 0.0, 25.0), DVec3::Z, degrees.to_radians());
        let opts = TouchOptions::default();
        let touch = s.respond(&start, &end, Response::Touch, &opts);
        let slide = s.respond(&start, &end, Response::Slide, &opts);
        assert!(touch.t < 1.0, "{degrees}°");
        assert!(s.check(&slide.pose).is_empty());
        let (zt, zs) = (touch.pose.translation.z, slide.pose.translation.z);
        assert!(zs > zt + 2.0, "{degrees}°: slide z {zs} vs touch z {zt}");
    }
}

/// Slides never carry the drug back against the push: from the first touch
/// on, every push in random directions from random free starts only gains
/// ground along the push (legs that turned the motion round used to).
#[test]
fn slides_never_go_against_the_push() {
    let s = scene(RadiiSet::Bondi, ColliderKind::Hashed);
    let mut rng = bump_testkit::Rng(0x51de);
    let opts = TouchOptions::default();
    let (mut slid, mut worst) = (0, f64::INFINITY);
    for _ in 0..400 {
        let offset = DVec3::new(
            rng.range(-8.0, 8.0),
            rng.range(-8.0, 8.0),
            rng.range(-4.0, 30.0),
        );
        let start = s.file_relative(offset);
        if !s.check(&start).is_empty() {
            continue;
        }
        let push = rng.unit() * rng.range(2.0, 20.0);
        let end = start.moved(push, DVec3::Z, 0.0);
        let touch = s.respond(&start, &end, Response::Touch, &opts);
        let slide = s.respond(&start, &end, Response::Slide, &opts);
        assert!(s.check(&slide.pose).is_empty());
        let gained = (slide.pose.translation - touch.pose.translation).dot(push.normalize());
        worst = worst.min(gained);
        slid += usize::from(slide.legs > 1);
    }
    assert!(slid > 50, "only {slid} pushes slid");
    assert!(worst >= -1e-9, "a slide lost {worst} Å along its push");
}
