//! Numerical stress: many seeded random move-to-touch queries checked against
//! exact answers, scenes far from the origin, long sessions, extreme steps.
//!
//! Bounded for CI: 10⁵ random queries by default; `BUMP_STRESS=full` runs
//! 10⁷ (and a number, e.g. `BUMP_STRESS=2000000`, runs that many).
//!
//! References (`bump_testkit::oracle`, all f64 over every pair): the
//! closed-form time of impact for translations, and for screw motions a
//! Lipschitz certificate that no pose on the allowed part of the path
//! overlaps (it cannot miss a thin wall). Counts and worst cases are printed
//! (`--nocapture`).

mod common;

use bump::collide::{Collider, ColliderKind, ContactRule, DrugAtoms, TouchOptions, move_to_touch};
use bump::model::{Molecule, RadiiSet, builtin};
use bump::motion::{Pose, Screw};
use bump::session::{Command, FrameInput, Session, Settings};
use bump_testkit::oracle::{certify_free_path, min_gap, translation_toi};
use common::*;
use glam::{DMat3, DQuat, DVec3};

const TOL: f64 = 1e-3;

/// How many random queries: 10⁵, or what `BUMP_STRESS` asks for.
fn query_count() -> usize {
    match std::env::var("BUMP_STRESS").as_deref() {
        Ok("full") => 10_000_000,
        Ok(n) => n.parse().unwrap_or(100_000),
        Err(_) => 100_000,
    }
}

/// A random start outside the receptor (gap ≥ 0.01 Å) and a motion towards it.
/// Also says whether the motion is a pure translation.
fn random_query(
    rng: &mut Rng,
    rule: &ContactRule,
    r: &Molecule,
    d: &Molecule,
) -> (Pose, Pose, bool) {
    loop {
        let dir = rng.unit();
        let start = Pose::new(
            DQuat::from_axis_angle(rng.unit(), rng.range(0.0, 3.1)),
            dir * rng.range(6.0, 16.0),
        );
        if min_gap(rule, r, d, &start) < 0.01 {
            continue;
        }
        // Step lengths from 10⁻³ to 10² Å (log-uniform), aimed at the receptor
        // with some scatter; every other query also turns (up to ±2 rad).
        let len = 10f64.powf(rng.range(-3.0, 2.0));
        let travel = (-dir + rng.unit() * 0.4).normalize() * len;
        if rng.next_u64().is_multiple_of(2) {
            return (
                start,
                start.moved(travel, rng.unit(), rng.range(-2.0, 2.0)),
                false,
            );
        }
        // A pure translation (built directly: `moved` renormalises the rotation).
        let end = Pose {
            rotation: start.rotation,
            translation: start.translation + travel,
        };
        return (start, end, true);
    }
}

#[test]
fn random_queries_never_overlap_tunnel_or_give_nan() {
    let n = query_count();
    let rule = ContactRule::default();
    let mut rng = Rng(0x57e55);
    let per_scene = 250;
    let (mut hits, mut screws, mut evals) = (0usize, 0usize, 0usize);
    let (mut worst_gap, mut min_stop_gap, mut worst_short) = (0.0f64, f64::INFINITY, 0.0f64);
    let mut done = 0;
    let mut scene = 0usize;
    let mut edge_without_contact = 0usize;
    while done < n {
        // A fresh small scene: 60 receptor atoms in a 14 Å cube, 5 drug atoms.
        let polar = scene.is_multiple_of(2);
        let receptor = random_molecule(&mut rng, 60, 14.0, DVec3::ZERO, polar);
        let drug = random_molecule(&mut rng, 5, 4.0, DVec3::ZERO, polar);
        let kind = ColliderKind::ALL[scene % 3];
        scene += 1;
        let col = Collider::build(&receptor, &rule, kind);
        let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
        for _ in 0..per_scene.min(n - done) {
            done += 1;
            let (start, end, translation) = random_query(&mut rng, &rule, &receptor, &drug);
            let r = move_to_touch(&col, &atoms, &start, &end, &TouchOptions::default());
            let ctx = || format!("query {done} ({kind:?}): {start:?} -> {end:?}, t = {}", r.t);
            assert!(r.t.is_finite() && (0.0..=1.0).contains(&r.t), "{}", ctx());
            assert!(r.pose.is_finite(), "{}", ctx());
            let g = min_gap(&rule, &receptor, &drug, &r.pose);
            assert!(g > 0.0, "overlap {g} Å: {}", ctx());
            let screw = Screw::between(start, end);
            if translation {
                // Never past the exact first contact, never short of it by
                // more than the tolerance allows.
                let d = end.translation - start.translation;
                match translation_toi(&rule, &receptor, &drug, &start, d) {
                    // No contact on the way: the whole step, unless it ends
                    // within the tolerance of one (checked below).
                    None => {}
                    Some(te) => {
                        assert!(r.t <= te, "tunnelled past t = {te}: {}", ctx());
                        worst_short = worst_short.max((te - r.t) * d.length());
                    }
                }
            } else {
                screws += 1;
                match certify_free_path(&rule, &receptor, &drug, &screw, r.t) {
                    Ok(e) => evals += e,
                    Err(f) => panic!("tunnelled: gap {} at t = {}: {}", f.gap, f.t, ctx()),
                }
            }
            if r.t < 1.0 {
                hits += 1;
                assert!(g <= TOL + 1e-6, "stopped {g} Å short of contact: {}", ctx());
                // The stop is decided in f64, the contact list by the f32 rule:
                // a stop within f32 rounding of the tolerance's edge may list
                // no contact (counted and printed; anything else fails).
                if r.contacts.is_empty() {
                    assert!(
                        (g - TOL).abs() < 1e-5,
                        "stopped with no contact reported (gap {g} Å): {}",
                        ctx()
                    );
                    edge_without_contact += 1;
                }
                worst_gap = worst_gap.max(g);
                min_stop_gap = min_stop_gap.min(g);
            }
        }
    }
    println!(
        "{n} random queries ({screws} screws, {hits} stopped at a contact, {scene} scenes): \
         none overlapped, tunnelled or gave NaN; gap at the stop in [{min_stop_gap:.2e}, {worst_gap:.2e}] Å; \
         worst travel short of the exact contact (translations) {worst_short:.2e} Å; \
         {:.1} certificate evaluations per screw; {edge_without_contact} stops within 10⁻⁵ Å \
         of the tolerance's edge listed no contact",
        evals as f64 / screws.max(1) as f64
    );
    assert!(hits > n / 5 && screws > n / 3);
}

/// The angle between two rotations, accurate for tiny angles (unlike
/// `acos` of the dot product).
fn angle(a: DQuat, b: DQuat) -> f64 {
    let r = a * b.conjugate();
    let v = DVec3::new(r.x, r.y, r.z).length();
    2.0 * v.atan2(r.w.abs())
}

/// `m` with every position moved by `offset`.
fn shifted(m: &Molecule, offset: DVec3) -> Molecule {
    let pos: Vec<DVec3> = m.file_positions().iter().map(|p| *p + offset).collect();
    Molecule::new(m.name.clone(), m.atoms.clone(), &pos)
}

/// The built-in scene (rings, E) moved by `offset`, object mode, collision on.
fn builtin_session(offset: DVec3) -> Session {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(
        vec![shifted(&rings, offset), shifted(&e, offset)],
        Settings::default(),
    )
    .expect("session");
    s.step(&FrameInput::docking(), 0.0);
    s
}

/// Smallest f64 gap between the E (body 1) and the rings (body 0).
fn e_gap(s: &Session) -> f64 {
    let b = s.bodies();
    let rel = b[0].pose.inverse().compose(&b[1].pose);
    min_gap(&s.settings().rule, &b[0].molecule, &b[1].molecule, &rel)
}

fn move_by(translate: DVec3, axis: DVec3, degrees: f64) -> FrameInput {
    FrameInput::with_commands(&[Command::MoveBy {
        translate,
        axis,
        degrees,
    }])
}

/// Answers far from the origin must match those at the origin to this, Å
/// (every atom of the moved molecule). A far offset rounds the f64 poses
/// (10⁻⁹ Å at 10⁷ Å) and can flip the f32 rounding of a local coordinate
/// (10⁻⁶ Å); a touch or slide turns such differences into differences of
/// its stop, amplified where a contact is grazing.
const FAR_TOLERANCE: f64 = 1e-4;

/// One docking query in the built-in scene moved by `offset`: the E placed
/// at `start` (offset from its file pose, a turn in degrees), then `step`
/// with collision on under `response`. Returns the E's atoms relative to the
/// offset, the allowed fraction and the contacts not within FAR_TOLERANCE of
/// the tolerance's edge — or `None` when the start overlaps.
fn far_query(
    offset: DVec3,
    start: (DVec3, DVec3, f64),
    step: (DVec3, DVec3, f64),
    response: bump::collide::Response,
) -> Option<(Vec<DVec3>, f64, usize)> {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(
        vec![shifted(&rings, offset), shifted(&e, offset)],
        Settings::default(),
    )
    .expect("session");
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(&move_by(start.0, start.1, start.2), 0.0);
    if e_gap(&s) < 0.01 {
        return None;
    }
    s.step(
        &FrameInput::with_commands(&[Command::ToggleCollision, Command::SetResponse(response)]),
        0.0,
    );
    let o = s.step(&move_by(step.0, step.1, step.2), 0.0);
    assert!(e_gap(&s) > 0.0, "overlap at offset {offset}");
    let e = &s.bodies()[1];
    let centre = e.pose.translation - offset;
    let atoms = e
        .molecule
        .local
        .iter()
        .map(|l| centre + e.pose.rotation * l.as_dvec3())
        .collect();
    let robust = o
        .contacts
        .iter()
        .filter(|c| (f64::from(c.gap()) - TOL).abs() > FAR_TOLERANCE)
        .count();
    Some((atoms, o.t, robust))
}

#[test]
fn a_scene_far_from_the_origin_gives_the_same_answers() {
    use bump::collide::Response;
    // Queries around the docked pose: starts within a few Å (and degrees) of
    // it, steps of up to 4 Å and 20°, under touch and slide.
    let mut rng = Rng(0xfa5);
    let mut queries = Vec::new();
    while queries.len() < 300 {
        let start = (
            DVec3::new(0.0, 0.0, 25.0) + rng.unit() * rng.range(0.0, 3.0),
            rng.unit(),
            rng.range(-10.0, 10.0),
        );
        let step = (
            rng.unit() * rng.range(0.0, 4.0),
            rng.unit(),
            rng.range(-20.0, 20.0),
        );
        let response = if queries.len().is_multiple_of(2) {
            Response::Touch
        } else {
            Response::Slide
        };
        if let Some(base) = far_query(DVec3::ZERO, start, step, response) {
            queries.push((start, step, response, base));
        }
    }
    let touched = queries.iter().filter(|q| q.3.1 < 1.0).count();
    assert!(touched > 100, "the queries should touch often ({touched})");
    for scale in [1e3, 1e5, 1e7] {
        let offset = DVec3::new(1.0, -1.0, 1.0) * scale;
        let mut dp = 0.0f64;
        for (k, (start, step, response, base)) in queries.iter().enumerate() {
            let far = far_query(offset, *start, *step, *response).expect("same start");
            for (x, y) in base.0.iter().zip(&far.0) {
                dp = dp.max((*x - *y).length());
            }
            assert_eq!(
                base.2, far.2,
                "offset {scale:e}, query {k}: contacts differ"
            );
        }
        println!(
            "offset {scale:e} Å: {} queries ({touched} touch), worst atom position difference {dp:.2e} Å",
            queries.len()
        );
        assert!(
            dp < FAR_TOLERANCE,
            "offset {scale:e}: atoms differ by {dp} Å"
        );
    }
}

#[test]
fn moves_beyond_the_supported_range_are_refused() {
    let edge = bump::motion::MAX_COORDINATE;
    let mut s = builtin_session(DVec3::new(edge - 1e3, 0.0, 0.0));
    let before = s.bodies()[1].pose;
    // Within range, even out here: docking works and stops at the rings.
    let o = s.step(&move_by(DVec3::new(0.0, 5.0, 0.0), DVec3::Z, 0.0), 0.0);
    assert!(o.moved && o.messages.is_empty());
    let o = s.step(&move_by(DVec3::new(0.0, 0.0, 30.0), DVec3::Z, 0.0), 0.0);
    assert!(o.t < 1.0 && e_gap(&s) > 0.0);
    // A step past the edge is refused, with a message, and nothing moves.
    let here = s.bodies()[1].pose;
    let o = s.step(&move_by(DVec3::new(2e3, 0.0, 0.0), DVec3::Z, 0.0), 0.0);
    assert!(!o.moved && o.messages.iter().any(|m| m.contains("refused")));
    assert_eq!(s.bodies()[1].pose, here);
    assert_ne!(here, before);
}

/// Steps as long as two molecules in range can be apart (2·10⁹ Å) stop at
/// the receptor; longer ones, where a step's length in Å is no longer an
/// exact count in f64 (and at 10¹⁵⁵ Å its square overflows), are refused
/// at the start: they neither tunnel nor hang.
#[test]
fn steps_beyond_the_relative_range_are_refused_not_tunnelled() {
    use bump::collide::sweep::MAX_RELATIVE_COORDINATE;
    let rule = ContactRule::default();
    let r = Molecule::new("r", vec![atom(1, "C", 1.7)], &[DVec3::ZERO]);
    let m = Molecule::new("d", vec![atom(1, "C", 1.7)], &[DVec3::X * 5.0]);
    for kind in ColliderKind::ALL {
        let c = Collider::build(&r, &rule, kind);
        let d = DrugAtoms::new(&m, &rule, c.max_radius());
        let opts = TouchOptions::default();
        for (x0, turn) in [(5.0, 0.0), (5.0, 0.5), (-1.9e9, 0.0), (-1.9e9, 0.5)] {
            let start = Pose::from_translation(DVec3::new(x0, 0.0, 0.0));
            // Through the receptor atom to the far end of the range.
            // A turn about the path (a helix): an arc would miss the atom.
            let end = Pose::from_translation(DVec3::new(-x0.signum() * 1.9e9, 0.0, 0.0)).moved(
                DVec3::ZERO,
                DVec3::X,
                turn,
            );
            let res = move_to_touch(&c, &d, &start, &end, &opts);
            let x = res.pose.translation;
            assert!(
                res.t > 0.0 && res.t < 1.0,
                "{kind:?} {x0} {turn}: t = {}",
                res.t
            );
            assert!(
                x.length() > 2.8 && x.x.signum() == x0.signum(),
                "{kind:?}: {x}"
            );
            assert!(!res.contacts.is_empty(), "{kind:?} {x0} {turn}");
            // Beyond the range: refused, whatever the rest of the step.
            for far in [2.0 * MAX_RELATIVE_COORDINATE, 1e155, 1e308, f64::MAX] {
                let end = start.moved(DVec3::new(-far, 0.0, 0.0), DVec3::Z, turn);
                let res = move_to_touch(&c, &d, &start, &end, &opts);
                assert_eq!((res.t, res.pose), (0.0, start), "{kind:?} {far:e}");
            }
        }
    }
}

#[test]
fn a_million_small_turns_keep_the_drug_rigid() {
    let mut s = builtin_session(DVec3::ZERO);
    // Far from the rings, so every turn is free (but still a collision query).
    s.step(&move_by(DVec3::new(0.0, 0.0, -100.0), DVec3::Z, 0.0), 0.0);
    let q0 = s.bodies()[1].pose;
    let axis = DVec3::new(1.0, 2.0, 3.0).normalize();
    let step = 1e-3; // rad per frame
    let frame = FrameInput::nudged(DVec3::ZERO, axis * step);
    let n = 1_000_000;
    let mut queries = 0;
    for _ in 0..n {
        let o = s.step(&frame, 0.016);
        queries += usize::from(o.collision_us.is_some());
        assert!(o.t == 1.0);
    }
    let p = s.bodies()[1].pose;
    let local = &s.bodies()[1].molecule.local;
    // Unit quaternion, orthonormal matrix.
    assert!((p.rotation.length() - 1.0).abs() < 1e-12);
    let m = DMat3::from_quat(p.rotation);
    let err = (m.transpose() * m - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(err < 1e-12, "RᵀR − I = {err}");
    // The centre did not move; the total turn is n·step about the axis.
    assert_eq!(p.translation, q0.translation);
    let expected = (DQuat::from_axis_angle(axis, n as f64 * step) * q0.rotation).normalize();
    let drift = angle(p.rotation, expected);
    // Internal distances, from world positions, unchanged to 1e-9 relative.
    let mut worst = 0.0f64;
    for i in 0..local.len() {
        for j in (i + 1)..local.len() {
            let d0 = (local[i].as_dvec3() - local[j].as_dvec3()).length();
            let xi = p.transform_point(local[i].as_dvec3());
            let xj = p.transform_point(local[j].as_dvec3());
            worst = worst.max(((xi - xj).length() - d0).abs() / d0);
        }
    }
    println!(
        "{n} turns of {step} rad: |RᵀR − I| {err:.1e}, angle drift {drift:.1e} rad, \
         internal distances {worst:.1e} relative, {queries} collision queries"
    );
    assert!(worst < 1e-9, "distances changed by {worst} relative");
    assert!(drift < 1e-9, "rotation drifted {drift} rad from n·step");
    assert_eq!(queries, n);
}

/// Pushes the docked E sideways into the rings for `frames` frames and checks
/// that once it touches it neither moves (jitter, creep) nor leaves.
fn push_into_contact(rotate: DVec3, frames: usize) {
    let mut s = builtin_session(DVec3::ZERO);
    s.step(&move_by(DVec3::new(0.0, 0.0, 25.0), DVec3::Z, 0.0), 0.0);
    let push = FrameInput::nudged(DVec3::new(0.05, 0.02, 0.0), rotate);
    let mut first: Option<Pose> = None;
    let (mut max_step, mut lo, mut hi) = (0.0f64, f64::INFINITY, 0.0f64);
    let mut prev = s.bodies()[1].pose;
    for k in 0..frames {
        let o = s.step(&push, 0.016);
        let p = s.bodies()[1].pose;
        if first.is_none() && o.t < 1.0 {
            first = Some(p); // the frame that reached the contact
        } else if first.is_some() {
            max_step = max_step.max((p.translation - prev.translation).length());
            if k % 100 == 0 || k < 1000 {
                let g = e_gap(&s);
                lo = lo.min(g);
                hi = hi.max(g);
            }
            assert!(!o.contacts.is_empty(), "frame {k}: lost contact");
        }
        prev = p;
    }
    let first = first.expect("the push reaches the rings");
    let last = s.bodies()[1].pose;
    let drift = (last.translation - first.translation).length();
    let turn = angle(last.rotation, first.rotation);
    println!(
        "{frames} frames pushing (turn {rotate}): gap in [{lo:.2e}, {hi:.2e}] Å, \
         largest step after contact {max_step:.1e} Å, drift {drift:.1e} Å, {turn:.1e} rad"
    );
    assert!(lo > 0.0, "crept into the rings: gap {lo}");
    assert!(hi <= TOL + 1e-6, "drifted away: gap {hi}");
    assert!(drift < 1e-9 && turn < 1e-12, "crept {drift} Å, {turn} rad");
    assert!(
        max_step < 1e-9,
        "jitter: a step of {max_step} Å while blocked"
    );
}

#[test]
fn pushing_into_a_contact_for_1e5_frames_neither_jitters_creeps_nor_drifts() {
    push_into_contact(DVec3::ZERO, 100_000);
    push_into_contact(DVec3::new(0.0, 0.0, 2e-3), 20_000);
}

#[test]
fn extreme_steps_and_turns() {
    // Steps of 10⁻¹² Å in free space are all taken.
    let mut s = builtin_session(DVec3::ZERO);
    let p0 = s.bodies()[1].pose;
    for _ in 0..1000 {
        let o = s.step(&move_by(DVec3::new(1e-12, 0.0, 0.0), DVec3::Z, 0.0), 0.0);
        assert_eq!(o.t, 1.0);
    }
    let moved = s.bodies()[1].pose.translation.x - p0.translation.x;
    assert!((moved - 1e-9).abs() < 1e-11, "1000 × 1e-12 Å moved {moved}");
    // 10⁻¹² Å steps into a contact: never in, never NaN.
    let mut s = builtin_session(DVec3::ZERO);
    s.step(&move_by(DVec3::new(0.0, 5.0, 0.0), DVec3::Z, 0.0), 0.0);
    let o = s.step(&move_by(DVec3::new(0.0, 0.0, 30.0), DVec3::Z, 0.0), 0.0);
    assert!(o.t < 1.0 && e_gap(&s) > 0.0);
    for _ in 0..1000 {
        s.step(&move_by(DVec3::new(0.0, 0.0, 1e-12), DVec3::Z, 0.0), 0.0);
        assert!(e_gap(&s) > 0.0 && s.bodies()[1].pose.is_finite());
    }
    // A 10⁴ Å step through the rings stops at them; one away is taken whole.
    let mut s = builtin_session(DVec3::ZERO);
    s.step(&move_by(DVec3::new(0.0, 5.0, 0.0), DVec3::Z, 0.0), 0.0);
    let z0 = s.bodies()[1].pose.translation.z;
    let o = s.step(&move_by(DVec3::new(0.0, 0.0, 1e4), DVec3::Z, 0.0), 0.0);
    let z1 = s.bodies()[1].pose.translation.z;
    assert!(
        o.t < 1e-2 && z1 < 0.0 && e_gap(&s) > 0.0,
        "t {} z {z1}",
        o.t
    );
    assert!(e_gap(&s) <= TOL + 1e-6);
    let o = s.step(&move_by(DVec3::new(0.0, 0.0, -1e4), DVec3::Z, 0.0), 0.0);
    assert_eq!(o.t, 1.0);
    let z2 = s.bodies()[1].pose.translation.z;
    assert!((z2 - (z1 - 1e4)).abs() < 1e-9 && z0 > z2);
    // Turns of 10⁻⁹ degrees are all taken, not rounded away.
    let mut s = builtin_session(DVec3::ZERO);
    let q0 = s.bodies()[1].pose.rotation;
    for _ in 0..1000 {
        let o = s.step(&move_by(DVec3::ZERO, DVec3::Y, 1e-9), 0.0);
        assert_eq!(o.t, 1.0);
    }
    let turned = angle(s.bodies()[1].pose.rotation, q0);
    let want = 1e-6f64.to_radians();
    assert!(
        (turned - want).abs() < 1e-3 * want,
        "turned {turned}, want {want}"
    );
    // A turn of 10³ degrees: free, it lands on 1000° mod 360°; docked in the
    // rings it stops at a contact without entering them.
    let mut s = builtin_session(DVec3::ZERO);
    s.step(&move_by(DVec3::new(0.0, 0.0, -100.0), DVec3::Z, 0.0), 0.0);
    let q0 = s.bodies()[1].pose.rotation;
    let axis = DVec3::new(0.3, 1.0, -0.2).normalize();
    let o = s.step(&move_by(DVec3::ZERO, axis, 1e3), 0.0);
    assert_eq!(o.t, 1.0);
    let want = DQuat::from_axis_angle(axis, 1e3f64.to_radians()) * q0;
    assert!(angle(s.bodies()[1].pose.rotation, want) < 1e-9);
    let mut s = builtin_session(DVec3::ZERO);
    s.step(&move_by(DVec3::new(0.0, 0.0, 25.0), DVec3::Z, 0.0), 0.0);
    for k in 0..20 {
        let o = s.step(&move_by(DVec3::ZERO, axis, 1e3 * (k as f64 - 9.5)), 0.0);
        let p = s.bodies()[1].pose;
        assert!(p.is_finite() && o.t.is_finite());
        assert!(e_gap(&s) > 0.0, "turn {k}: overlap");
    }
}

/// A pair's reported distance and contact distance say what the rule says,
/// to the last bit: `distance ≤ contact` exactly when the static check
/// lists the pair (the rule compares squares, d² ≤ c², and √d² rounded to
/// f32 can land on `c` from a d² one unit above c², so a pair within
/// tolerance once read as colliding where the check found it clear), and
/// a zero-length move-to-touch reports no collision where the check finds
/// none. Poses a few units in the last place either side of contact, in
/// many directions, for a C–C pair and an N–O pair.
#[test]
fn reported_distances_agree_with_the_rule_to_the_last_bit() {
    let rule = ContactRule::default();
    let mut rng = Rng(0x5eed);
    let mut straddled = 0;
    for (a, b) in [(("C", 1.7), ("C", 1.7)), (("N", 1.55), ("O", 1.52))] {
        let receptor = Molecule::new("one", vec![atom(1, a.0, a.1)], &[DVec3::ZERO]);
        let drug = Molecule::new("other", vec![atom(1, b.0, b.1)], &[DVec3::ZERO]);
        let c = rule.contact_distance(a.1, a.0 != "C", b.1, b.0 != "C");
        let cc = c * c;
        for col in all_colliders(&receptor, &rule) {
            let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
            for _ in 0..2_000 {
                let dir = rng.unit();
                for k in -6..=6 {
                    let d = f64::from(c) * (1.0 + f64::from(k) * 1e-7);
                    let pose = Pose::from_translation(dir * d);
                    let x = pose.translation.as_vec3();
                    let d2 = x.length_squared();
                    if d2 > cc && d2.sqrt() <= c {
                        straddled += 1;
                    }
                    let clashes = bump::collide::check(&col, &atoms, &pose);
                    let near = bump::collide::pairs_within(&col, &atoms, &pose, 0.1);
                    assert_eq!(near.len(), 1, "{pose:?}");
                    assert_eq!(
                        near[0].collides(),
                        !clashes.is_empty(),
                        "{:?} {pose:?}",
                        near[0]
                    );
                    assert_eq!(near[0].gap() <= 0.0, !clashes.is_empty());
                    let r = move_to_touch(&col, &atoms, &pose, &pose, &TouchOptions::default());
                    assert_eq!(r.colliding, clashes, "{pose:?}");
                    assert_eq!(r.start_colliding, clashes, "{pose:?}");
                }
            }
        }
    }
    // The poses reach the one-unit window this test is about.
    assert!(straddled > 100, "{straddled}");
}
