//! The headless docking session: modes, selection, collision responses,
//! contacts and their cues, undo/redo, screen and object space.

use bump::collide::Response;
use bump::model::{RadiiSet, builtin};
use bump::session::{Command, FrameInput, Mode, Motion6, Session, Settings, Space};
use glam::DVec3;

fn builtin_session() -> Session {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    Session::new(vec![rings, e], Settings::default()).expect("session")
}

fn push(v: DVec3) -> FrameInput {
    FrameInput::nudged(v, DVec3::ZERO)
}

#[test]
fn starts_in_view_mode_with_collision_off_and_the_drug_selected() {
    let s = builtin_session();
    assert_eq!(s.mode(), Mode::View);
    assert!(!s.settings().collision);
    assert_eq!(s.selected(), 1);
    assert!(Session::new(vec![], Settings::default()).is_err());
}

#[test]
fn view_mode_moves_the_camera_not_the_molecules() {
    let mut s = builtin_session();
    let poses: Vec<_> = s.bodies().iter().map(|b| b.pose).collect();
    let cam = *s.camera();
    let out = s.step(&push(DVec3::new(1.0, 0.0, 0.0)), 0.016);
    assert!(out.changed && !out.moved);
    assert_ne!(*s.camera(), cam);
    assert_eq!(s.bodies().iter().map(|b| b.pose).collect::<Vec<_>>(), poses);
    s.step(&FrameInput::with_commands(&[Command::ResetView]), 0.0);
    assert_eq!(*s.camera(), cam);
}

#[test]
fn collision_on_stops_the_e_at_the_rings_and_off_lets_it_through() {
    let mut s = builtin_session();
    s.step(&FrameInput::docking(), 0.0);
    assert_eq!(s.mode(), Mode::Object);
    // Misalign the prongs, then push 25 Å towards the rings (screen z is
    // world z with the initial camera): the E stops touching.
    s.step(&push(DVec3::new(0.0, 5.0, 0.0)), 0.0);
    let out = s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    assert!(out.moved && out.t < 1.0);
    assert!(!out.contacts.is_empty() && out.contacts.iter().all(|c| c.gap() > 0.0));
    assert!(out.new_contact, "the first contact beeps");
    assert!(!out.highlight_changes.is_empty());
    let (b, a) = out.contacts[0].moving;
    assert!(s.is_highlighted(b, a));
    // Pushing on: contacts stay, no new beep.
    let again = s.step(&push(DVec3::new(0.0, 0.0, 1.0)), 0.0);
    assert!(!again.new_contact);
    // Collision off: the push goes through, highlights clear.
    let off = s.step(&FrameInput::with_commands(&[Command::ToggleCollision]), 0.0);
    assert!(off.contacts.is_empty() && !s.is_highlighted(b, a));
    let through = s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    assert!(through.moved && through.t == 1.0 && through.collision_us.is_none());
}

#[test]
fn each_response_is_one_command_away() {
    let mut s = builtin_session();
    s.step(&FrameInput::docking(), 0.0);
    s.step(&push(DVec3::new(0.0, 5.0, 0.0)), 0.0);
    let start = s.bodies()[1].pose;
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(Response::Stop)]),
        0.0,
    );
    let out = s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    assert_eq!(s.bodies()[1].pose, start, "stop rejects the whole step");
    assert!(!out.moved);
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(Response::Pass)]),
        0.0,
    );
    let out = s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    assert!(
        out.moved && out.contacts.iter().any(|c| c.gap() <= 0.0),
        "pass reports overlaps"
    );
    s.step(&FrameInput::with_commands(&[Command::CycleResponse]), 0.0);
    assert_eq!(s.settings().response, Response::Stop);
}

#[test]
fn undo_redo_and_reset() {
    let mut s = builtin_session();
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    let loaded = s.bodies()[1].pose;
    // A held key over three frames is one gesture, one undo entry.
    let held = FrameInput {
        velocity: Motion6 {
            translate: DVec3::new(10.0, 0.0, 0.0),
            rotate: DVec3::ZERO,
        },
        ..FrameInput::default()
    };
    for _ in 0..3 {
        s.step(&held, 0.1);
    }
    s.step(&FrameInput::default(), 0.1); // released
    let moved = s.bodies()[1].pose;
    assert!((moved.translation - loaded.translation - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-9);
    assert_eq!(s.history().undo_len(), 1);
    s.step(
        &FrameInput::with_commands(&[Command::MoveBy {
            translate: DVec3::new(0.0, 1.0, 0.0),
            axis: DVec3::Z,
            degrees: 90.0,
        }]),
        0.0,
    );
    assert_eq!(s.history().undo_len(), 2);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert_eq!(s.bodies()[1].pose, moved);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert_eq!(s.bodies()[1].pose, loaded);
    s.step(&FrameInput::with_commands(&[Command::Redo]), 0.0);
    assert_eq!(s.bodies()[1].pose, moved);
    s.step(&FrameInput::with_commands(&[Command::ResetMolecule]), 0.0);
    assert_eq!(s.bodies()[1].pose, loaded);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert_eq!(s.bodies()[1].pose, moved, "reset is undoable");
    let none = s.step(
        &FrameInput::with_commands(&[Command::Redo, Command::Redo, Command::Redo]),
        0.0,
    );
    assert!(!none.messages.is_empty());
}

#[test]
fn screen_and_object_space() {
    let mut s = builtin_session();
    // Turn the view a quarter turn about screen y, then push along screen x.
    s.step(
        &FrameInput::nudged(DVec3::ZERO, DVec3::Y * std::f64::consts::FRAC_PI_2),
        0.0,
    );
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    let p0 = s.bodies()[1].pose.translation;
    s.step(&push(DVec3::X), 0.0);
    let d = s.bodies()[1].pose.translation - p0;
    // Screen x is now world +z (the scene turned −90° about y relative to the eye).
    assert!((d - s.camera().to_world(DVec3::X)).length() < 1e-9);
    assert!((d.length() - 1.0).abs() < 1e-9);
    // Object space: the molecule's own x, here world x (it has not turned).
    s.step(&FrameInput::with_commands(&[Command::ToggleSpace]), 0.0);
    assert_eq!(s.settings().space, Space::Object);
    let p1 = s.bodies()[1].pose.translation;
    s.step(&push(DVec3::X), 0.0);
    assert!((s.bodies()[1].pose.translation - p1 - DVec3::X).length() < 1e-9);
}

#[test]
fn selecting_the_receptor_moves_it_against_the_drug() {
    let mut s = builtin_session();
    s.step(
        &FrameInput::with_commands(&[
            Command::ToggleMode,
            Command::ToggleCollision,
            Command::NextMolecule,
        ]),
        0.0,
    );
    assert_eq!(s.selected(), 0);
    // Drag the rings towards the (misaligned) E: they stop touching it.
    s.step(&FrameInput::with_commands(&[Command::Select(1)]), 0.0);
    s.step(&push(DVec3::new(0.0, 5.0, 0.0)), 0.0);
    s.step(&FrameInput::with_commands(&[Command::Select(0)]), 0.0);
    let out = s.step(&push(DVec3::new(0.0, 0.0, -25.0)), 0.0);
    assert!(out.t < 1.0 && !out.contacts.is_empty());
    assert!(
        out.contacts
            .iter()
            .all(|c| c.moving.0 == 0 && c.other.0 == 1)
    );
    let bad = s.step(&FrameInput::with_commands(&[Command::Select(7)]), 0.0);
    assert!(!bad.messages.is_empty());
}

#[test]
fn nonsense_input_is_ignored_not_fatal() {
    let mut s = builtin_session();
    s.step(&FrameInput::docking(), 0.0);
    let p = s.bodies()[1].pose;
    let out = s.step(&push(DVec3::new(f64::NAN, 0.0, 0.0)), 0.0);
    assert!(!out.messages.is_empty());
    let out2 = s.step(
        &FrameInput {
            velocity: Motion6 {
                translate: DVec3::X,
                rotate: DVec3::ZERO,
            },
            ..FrameInput::default()
        },
        f64::INFINITY,
    );
    assert!(!out2.moved);
    assert_eq!(s.bodies()[1].pose, p);
    let q = s.step(&FrameInput::with_commands(&[Command::Quit]), 0.0);
    assert!(q.quit);
}

#[test]
fn three_molecules_collide_with_each_other() {
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let (_, e2) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e, e2], Settings::default()).expect("session");
    s.step(&FrameInput::docking(), 0.0);
    // The two Es start on top of each other: moving one away is allowed,
    // moving it deeper is not.
    let out = s.step(&push(DVec3::new(0.0, 0.0, 0.5)), 0.0);
    assert!(out.contacts.iter().any(|c| c.other.0 == 1));
    let p = s.bodies()[2].pose;
    let away = s.step(&push(DVec3::new(0.0, 30.0, 0.0)), 0.0);
    assert!(away.moved);
    assert!(s.bodies()[2].pose.translation.y > p.translation.y + 1.0);
}

#[test]
fn pose_in_the_receptor_frame_for_saving() {
    let mut s = builtin_session();
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    let rel = s.pose_in_frame_of(1, 0).expect("pose");
    let drug = &s.bodies()[1].molecule;
    // Docked: the E's atoms are where builtin::docked_offset puts them.
    let x = rel.transform_point(drug.local[0].as_dvec3());
    let expected = drug.file_position(0) + builtin::docked_offset();
    assert!((x - expected).length() < 1e-9);
}

#[test]
fn a_grab_moves_the_molecule_in_view_mode_and_files_can_be_added() {
    let mut s = builtin_session();
    assert_eq!(s.mode(), Mode::View);
    let p = s.bodies()[1].pose;
    let cam = *s.camera();
    s.step(
        &FrameInput {
            object_nudge: Motion6 {
                translate: DVec3::new(0.0, 2.0, 0.0),
                rotate: DVec3::ZERO,
            },
            ..FrameInput::default()
        },
        0.0,
    );
    assert!(
        (s.bodies()[1].pose.translation - p.translation - DVec3::new(0.0, 2.0, 0.0)).length()
            < 1e-9
    );
    assert_eq!(*s.camera(), cam, "a grab does not move the view");
    let (_, e) = builtin::scene(RadiiSet::Bondi);
    s.add_molecule(e);
    assert_eq!(s.bodies().len(), 3);
    assert_eq!(s.selected(), 2);
    s.step(&FrameInput::with_commands(&[Command::ToggleCollision]), 0.0);
    assert!(
        !s.contacts().is_empty(),
        "the new E overlaps the grabbed one's old place"
    );
}

#[test]
fn an_empty_session_waits_for_files_without_panicking() {
    let mut s = Session::empty(Settings::default());
    assert!(s.bodies().is_empty());
    for c in [
        Command::ToggleMode,
        Command::ToggleCollision,
        Command::NextMolecule,
        Command::Select(0),
        Command::Undo,
        Command::Redo,
        Command::ResetMolecule,
        Command::ResetView,
        Command::MoveBy {
            translate: DVec3::X,
            axis: DVec3::Z,
            degrees: 10.0,
        },
        Command::CycleResponse,
        Command::ToggleSpace,
    ] {
        s.step(&FrameInput::with_commands(&[c]), 0.0);
    }
    let out = s.step(&push(DVec3::X), 0.016);
    assert!(out.changed && !out.moved);
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    s.add_molecule(rings);
    s.add_molecule(e);
    s.frame_all();
    assert_eq!(s.selected(), 1);
    // Object mode and collision were switched on while empty.
    let moved = s.step(&push(DVec3::new(0.0, 5.0, 25.0)), 0.0);
    assert!(moved.moved && moved.t < 1.0, "collision is on from before");
}

#[test]
fn highlight_changes_are_exactly_the_atoms_that_changed() {
    let mut s = builtin_session();
    s.step(&FrameInput::docking(), 0.0);
    s.step(&push(DVec3::new(0.0, 5.0, 0.0)), 0.0);
    let hit = s.step(&push(DVec3::new(0.0, 0.0, 25.0)), 0.0);
    let mut lit: Vec<(usize, usize)> = hit
        .contacts
        .iter()
        .flat_map(|c| [c.moving, c.other])
        .collect();
    lit.sort_unstable();
    lit.dedup();
    let mut changed: Vec<(usize, usize)> = hit
        .highlight_changes
        .iter()
        .map(|&(k, i, level)| {
            assert_eq!(level, 1, "touching, not pressed");
            (k, i)
        })
        .collect();
    changed.sort_unstable();
    assert_eq!(changed, lit, "every lit atom reported once, nothing else");
    // Pulling back out clears exactly those atoms.
    let away = s.step(&push(DVec3::new(0.0, 0.0, -10.0)), 0.0);
    assert!(away.contacts.is_empty());
    let cleared: Vec<(usize, usize)> = away
        .highlight_changes
        .iter()
        .map(|&(k, i, level)| {
            assert_eq!(level, 0);
            (k, i)
        })
        .collect();
    assert_eq!(cleared, lit);
    assert!(lit.iter().all(|&(k, i)| !s.is_highlighted(k, i)));
}

/// World positions of body `b`'s atoms.
fn world(s: &Session, b: usize) -> Vec<DVec3> {
    let body = &s.bodies()[b];
    body.molecule
        .local
        .iter()
        .map(|x| body.pose.transform_point(x.as_dvec3()))
        .collect()
}

#[test]
fn a_turned_and_moved_receptor_stops_the_drug_at_contact_where_it_stands() {
    // The receptor's collider is built once, in its own frame; the drug is
    // queried in that frame wherever the receptor stands. Turn and move the
    // rings (collision off), then push the E at them in steps (collision
    // on): no pose may overlap, and the contacts must be every pair within
    // tolerance of contact by the rule applied to world coordinates.
    let mut s = builtin_session();
    s.step(
        &FrameInput::with_commands(&[Command::ToggleMode, Command::Select(0)]),
        0.0,
    );
    s.step(
        &FrameInput::with_commands(&[Command::MoveBy {
            translate: DVec3::new(3.0, -2.0, 1.0),
            axis: DVec3::new(1.0, 2.0, 0.5),
            degrees: 23.0,
        }]),
        0.0,
    );
    s.step(
        &FrameInput::with_commands(&[Command::Select(1), Command::ToggleCollision]),
        0.0,
    );
    let rule = s.settings().rule;
    let tol = s.settings().touch.tolerance as f32;
    let to_rings = s.bodies()[0].pose.translation - s.bodies()[1].pose.translation;
    let mut blocked = 0;
    for _ in 0..60 {
        let out = s.step(&push(to_rings.normalize() * 0.5), 0.0);
        blocked += usize::from(out.t < 1.0);
        let (rings, e) = (world(&s, 0), world(&s, 1));
        let (ra, ea) = (&s.bodies()[0].molecule.atoms, &s.bodies()[1].molecule.atoms);
        let mut want = Vec::new();
        for (i, x) in e.iter().enumerate() {
            for (j, q) in rings.iter().enumerate() {
                let c = rule.contact_distance(ea[i].radius, ea[i].polar, ra[j].radius, ra[j].polar);
                let d = (*x - *q).length() as f32;
                assert!(d > c - 1e-4, "E atom {i} overlaps ring atom {j}: {d} < {c}");
                // Pairs clearly inside or outside the band (f32 rounding
                // of the frames aside) must be reported as such.
                if d <= c + tol - 1e-4 {
                    want.push((i, j));
                }
            }
        }
        let got: Vec<(usize, usize)> = out
            .contacts
            .iter()
            .map(|c| (c.moving.1, c.other.1))
            .collect();
        for p in &want {
            assert!(
                got.contains(p),
                "pair {p:?} within tolerance but not reported"
            );
        }
        assert!(
            out.contacts
                .iter()
                .all(|c| c.moving.0 == 1 && c.other.0 == 0)
        );
        assert!(
            out.contacts
                .iter()
                .all(|c| c.distance <= c.contact + tol + 1e-4)
        );
    }
    assert!(blocked > 0, "the E never reached the turned rings");
}

/// Pushes the drug (molecule 1) of `s` along `dir` frame after frame
/// with `response`, as a held key does (a 0.2 Å tap, then 0.064 Å a frame);
/// checks that every frame shows exactly the pairs within tolerance of
/// contact at the pose shown, and returns how many each frame showed.
fn pressed(mut s: Session, response: Response, dir: DVec3) -> Vec<usize> {
    s.step(&FrameInput::docking(), 0.0);
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(response)]),
        0.0,
    );
    let rule = s.settings().rule;
    let tol = s.settings().touch.tolerance as f32;
    let mut seen = Vec::new();
    for k in 0..60 {
        let step = if k % 10 == 0 { 0.2 } else { 0.064 };
        let out = s.step(&push(dir.normalize() * step), 1.0 / 60.0);
        assert_eq!(s.contacts(), out.contacts.as_slice());
        let (rec, drug) = (world(&s, 0), world(&s, 1));
        let (ra, da) = (&s.bodies()[0].molecule.atoms, &s.bodies()[1].molecule.atoms);
        for (i, x) in drug.iter().enumerate() {
            for (j, q) in rec.iter().enumerate() {
                let c = rule.contact_distance(da[i].radius, da[i].polar, ra[j].radius, ra[j].polar);
                let d = (*x - *q).length() as f32;
                let shown = s
                    .contacts()
                    .iter()
                    .any(|p| p.moving.1 == i && p.other.1 == j);
                assert!(
                    shown || d > c + tol - 1e-4,
                    "{response:?} {dir} frame {k}: pair {i}-{j} within tolerance ({d} Å, contact {c}) not shown"
                );
                assert!(
                    !shown || d <= c + tol + 1e-4,
                    "{response:?} {dir} frame {k}: pair {i}-{j} shown but {d} Å apart (contact {c})"
                );
            }
        }
        seen.push(s.contacts().len());
    }
    seen
}

#[test]
fn contacts_shown_are_those_of_the_pose_shown_in_every_response() {
    for response in Response::ALL {
        let mut s = builtin_session();
        s.step(&push(DVec3::ZERO), 0.0);
        s.step(
            &FrameInput::with_commands(&[Command::MoveBy {
                translate: DVec3::new(0.0, 5.0, 0.0),
                axis: DVec3::Z,
                degrees: 0.0,
            }]),
            0.0,
        );
        pressed(s, response, DVec3::new(0.0, 0.0, 1.0));
    }
}

#[test]
fn a_drug_pressed_into_its_pocket_with_slide_shows_its_contacts_every_frame() {
    // Trimethoprim in DHFR (issue 42: "Contacts: 3" for one frame, then 0,
    // while the drug could not move): the slide's tangent legs ended just
    // clear of the atoms they slid along.
    let dir = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    let file = dir.join("6xg5_tmp_prepared.pdb");
    if !file.is_file() {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must have {}",
            file.display()
        );
        eprintln!("SKIP: {} not found", file.display());
        return;
    }
    let loaded = bump::model::load(&file, &bump::model::LoadOptions::default()).expect("load");
    let spec = bump::model::LigandSpec::parse("TOP").expect("spec");
    let (r, d) = bump::model::split_complex(&loaded.structure, &spec).expect("split");
    for push_dir in [DVec3::Z, DVec3::X, -DVec3::Y, DVec3::new(0.3, 0.5, -1.0)] {
        let s = Session::new(vec![r.clone(), d.clone()], Settings::default()).expect("session");
        let seen = pressed(s, Response::Slide, push_dir);
        // From the first contact on, the drug stays pressed against the pocket.
        let first = seen
            .iter()
            .position(|&n| n > 0)
            .expect("the drug met the pocket");
        assert!(
            seen[first..].iter().all(|&n| n > 0),
            "{push_dir}: frames without contacts while pressed: {seen:?}"
        );
    }
}

#[test]
fn moves_since_the_last_save_are_unsaved_and_ask_before_quitting() {
    let mut s = builtin_session();
    assert!(s.unsaved().is_empty(), "nothing moved yet");
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(&push(DVec3::new(1.0, 0.0, 0.0)), 0.0);
    assert_eq!(s.unsaved(), [1]);
    s.mark_saved(1);
    assert!(s.unsaved().is_empty());
    s.step(&FrameInput::default(), 0.0); // the gesture ends
    s.step(&push(DVec3::new(0.0, 1.0, 0.0)), 0.0);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert!(s.unsaved().is_empty(), "back where it was saved");
    // The view is not a pose: turning it leaves nothing unsaved.
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(&FrameInput::nudged(DVec3::ZERO, DVec3::Y), 0.0);
    assert!(s.unsaved().is_empty());
}

#[test]
fn the_view_commands_centre_on_the_drug_and_fit_everything() {
    let mut s = builtin_session();
    let home = *s.camera();
    s.step(&FrameInput::with_commands(&[Command::CentreOnDrug]), 0.0);
    let drug = s.bodies()[1].pose.translation;
    assert!((s.camera().centre - drug).length() < 1e-12);
    assert!(s.camera().distance < home.distance, "closer on the drug");
    s.step(&FrameInput::with_commands(&[Command::FitAll]), 0.0);
    assert!((s.camera().centre - home.centre).length() < 1e-9);
    // The load view: the drug at the centre, every molecule in view; V
    // comes back to it.
    s.step(&FrameInput::with_commands(&[Command::ViewDrug]), 0.0);
    let view = *s.camera();
    assert!((view.centre - drug).length() < 1e-12);
    s.step(&FrameInput::nudged(DVec3::X, DVec3::Y), 0.0);
    s.step(&FrameInput::with_commands(&[Command::ResetView]), 0.0);
    assert_eq!(*s.camera(), view);
    // Files that arrive later re-home the view, but move it only while
    // the user has not moved it.
    s.step(&FrameInput::nudged(DVec3::X, DVec3::ZERO), 0.0);
    let moved = *s.camera();
    s.step(&FrameInput::with_commands(&[Command::ViewDrug]), 0.0);
    assert_eq!(*s.camera(), moved);
    // The rings are one residue, like a drug, but the larger of two small
    // molecules is the receptor.
    assert_eq!(s.role(0), Some(bump::session::Role::Receptor));
    assert_eq!(s.role(1), Some(bump::session::Role::Drug));
    assert_eq!(s.drug(), Some(1));
}
