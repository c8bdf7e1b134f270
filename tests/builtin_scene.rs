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
    // Slide: a push that is mostly along z but also skewed in y goes further
    // along z than touch alone, and never overlaps.
    let skew = start.moved(DVec3::new(0.0, 0.0, 25.0), DVec3::Z, 0.0);
    let slide = s.respond(&start, &skew, Response::Slide, &opts);
    assert!(slide.colliding.is_empty());
    assert!(slide.pose.translation.z >= touch.pose.translation.z - 1e-9);
    assert!(s.check(&slide.pose).is_empty());
}

#[test]
fn slide_goes_around_a_glancing_contact() {
    let s = scene(RadiiSet::Bondi, ColliderKind::Hashed);
    // Aligned with the rings but pushed diagonally: the prongs meet the ring
    // wall at a slant, and sliding carries them on along z.
    let start = s.file_relative(DVec3::new(0.0, 2.0, 0.0));
    let end = start.moved(DVec3::new(0.0, 4.0, 25.0), DVec3::Z, 0.0);
    let opts = TouchOptions::default();
    let touch = s.respond(&start, &end, Response::Touch, &opts);
    let slide = s.respond(&start, &end, Response::Slide, &opts);
    assert!(touch.t < 1.0);
    assert!(slide.legs > 1);
    assert!(
        slide.pose.translation.z > touch.pose.translation.z + 1.0,
        "slide {} vs touch {}",
        slide.pose.translation.z,
        touch.pose.translation.z
    );
    assert!(s.check(&slide.pose).is_empty());
}
