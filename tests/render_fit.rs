//! Image tests of the views of the fit, on whatever adapter there is
//! (Mesa's CPU Vulkan in CI): colour by contribution shows a known
//! favourable atom blue and a known unfavourable one red where they
//! project, and recolouring uploads only the atoms whose colour changed;
//! turned bonds and a settle's frames are drawn as a session there would
//! draw them; the ghost keeps the reference's conformation.

mod common;

use common::gpu;

use bump::model::{LigandSpec, LoadOptions};
use bump::render::colors::{CONTRIBUTION_LEVELS, level_color};
use bump::render::contrib::ContributionColors;
use bump::render::ghost::Ghost;
use bump::render::offscreen::Offscreen;
use bump::render::view::{depth_range, model_views, projection};
use bump::render::{Cues, ViewParams};
use bump::session::framing::drug_view;
use bump::session::{Command, FrameInput, LiveScore, Session, Settings};
use glam::{DVec3, Vec3};

fn dhfr_trimethoprim() -> Option<Session> {
    let dir = common::shared_pdb()?;
    let loaded = bump::model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default())
        .expect("load");
    let spec = LigandSpec::parse("TOP").expect("spec");
    let (r, d) = bump::model::split_complex(&loaded.structure, &spec).expect("split");
    let mut s = Session::new(vec![r, d], Settings::default()).expect("session");
    s.enable_score();
    Some(s)
}

fn move_drug(s: &mut Session, translate: DVec3) -> Option<std::sync::Arc<LiveScore>> {
    s.step(
        &FrameInput::with_commands(&[Command::MoveBy {
            translate,
            axis: DVec3::Z,
            degrees: 0.0,
        }]),
        0.0,
    )
    .score
}

/// A drug atom at least a quarter of the scale from neutral (blue side or
/// red side) whose centre
/// no other drug atom hides, nearest the eye: (atom, its step).
fn visible_atom(s: &Session, score: &LiveScore, favourable: bool) -> Option<(usize, i8)> {
    let mv = model_views(s)[1];
    let m = &s.bodies()[1].molecule;
    let view: Vec<Vec3> = m.local.iter().map(|p| mv.transform_point3(*p)).collect();
    let levels = ContributionColors::levels_of(score);
    let want = CONTRIBUTION_LEVELS / 4;
    let mut best: Option<(usize, i8)> = None;
    for (&(b, a), &l) in &levels {
        let strong = if favourable { l <= -want } else { l >= want };
        if b != 1 || !strong {
            continue;
        }
        let hidden = view.iter().enumerate().any(|(j, v)| {
            j != a
                && v.z > view[a].z
                && (v.truncate() - view[a].truncate()).length() < m.atoms[j].radius * 1.05
        });
        if !hidden && best.is_none_or(|(k, _)| view[a].z > view[k].z) {
            best = Some((a, l));
        }
    }
    best
}

fn project(s: &Session, body: usize, local: Vec3, w: u32, h: u32) -> (u32, u32) {
    let mv = model_views(s)[body];
    let clip = projection(s, f64::from(w) / f64::from(h)) * (mv * local.extend(1.0));
    let ndc = clip / clip.w;
    let x = (ndc.x + 1.0) * 0.5 * w as f32;
    let y = (1.0 - ndc.y) * 0.5 * h as f32;
    (x as u32, y as u32)
}

#[test]
fn favourable_atoms_are_blue_and_unfavourable_ones_red() {
    let Some(gpu) = gpu() else { return };
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    let crystal = s.step(&FrameInput::default(), 0.0).score.expect("scored");
    // Pushed 1.6 Å into the pocket's wall, some atoms clash: unfavourable.
    let mut clash = None;
    for d in [
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        -DVec3::X,
        -DVec3::Y,
        -DVec3::Z,
    ] {
        let sc = move_drug(&mut s, d * 1.6).expect("moved");
        move_drug(&mut s, -d * 1.6);
        if sc.score.atoms.iter().any(|a| a.inter > 0.4) {
            clash = Some((d * 1.6, sc));
            break;
        }
    }
    let (push, clashing) = clash.expect("some push makes an atom clash");
    for (favourable, score, at) in [(true, crystal, DVec3::ZERO), (false, clashing, push)] {
        move_drug(&mut s, at);
        let (w, h) = (400u32, 300u32);
        let mut off = Offscreen::new(&gpu, &s, w, h).expect("target");
        let changes = ContributionColors::default().update(Some(&score));
        let before = off.spheres.upload_stats().color_bytes;
        let n = off.spheres.set_colors(&gpu.queue, &changes);
        assert_eq!(n, changes.len());
        assert!(off.spheres.upload_stats().color_bytes - before <= 32 * n as u64);
        // The same colours again upload nothing.
        assert_eq!(off.spheres.set_colors(&gpu.queue, &changes), 0);
        // Pull the drug 30 Å towards the eye (keeping its colours) so that
        // no receptor atom hides it.
        s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
        s.step(
            &FrameInput::nudged(DVec3::new(0.0, 0.0, 30.0), DVec3::ZERO),
            0.0,
        );
        s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
        // If the atoms sought face away, turn the drug half a turn about
        // the screen's vertical (its colours stay).
        if visible_atom(&s, &score, favourable).is_none() {
            let up = s.camera().rotation.conjugate() * DVec3::Y;
            s.step(
                &FrameInput::with_commands(&[Command::MoveBy {
                    translate: DVec3::ZERO,
                    axis: up,
                    degrees: 180.0,
                }]),
                0.0,
            );
        }
        let Some((atom, level)) = visible_atom(&s, &score, favourable) else {
            let l: Vec<_> = score.drug_atoms().collect();
            panic!("no visible atom (favourable {favourable}): {l:?}");
        };
        assert_eq!(off.spheres.color_of(1, atom), Some(level_color(level)));
        let params = ViewParams {
            cues: Cues::parse("none").expect("cues"),
            ..ViewParams::default()
        };
        let img = off.render(&gpu, &s, &params).expect("render");
        let local = s.bodies()[1].molecule.local[atom];
        let (x, y) = project(&s, 1, local, w, h);
        let px = img.pixel(x, y).expect("in the image");
        let (r, g, b) = (i32::from(px[0]), i32::from(px[1]), i32::from(px[2]));
        if favourable {
            assert!(
                b >= r + 20 && g >= r,
                "atom {atom} (step {level}) at ({x},{y}) is {px:?}, not blue"
            );
        } else {
            // Red blended with white: green and blue equal, red above.
            assert!(
                r >= b + 20 && (g - b).abs() <= 8,
                "atom {atom} (step {level}) at ({x},{y}) is {px:?}, not red"
            );
        }
        // Back to the crystal pose for the next case.
        let home = s.bodies()[1].loaded;
        let now = s.bodies()[1].pose;
        move_drug(&mut s, home.translation - now.translation);
    }
}

/// A turned torsion reaches the GPU as the moved atoms' positions alone:
/// the picture after the upload equals a renderer built afresh on the
/// turned drug, and differs from the picture before the turn.
#[test]
fn a_turned_torsion_uploads_only_the_moved_atoms() {
    let Some(gpu) = gpu() else { return };
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    let (w, h) = (320u32, 240u32);
    let params = ViewParams {
        cues: Cues::parse("none").expect("cues"),
        ..ViewParams::default()
    };
    // The drug 30 Å towards the eye, so that no receptor atom hides it.
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(
        &FrameInput::nudged(DVec3::new(0.0, 0.0, 30.0), DVec3::ZERO),
        0.0,
    );
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    let mut off = Offscreen::new(&gpu, &s, w, h).expect("target");
    let before = off.render(&gpu, &s, &params).expect("render");
    let out = s.step(
        &FrameInput::with_commands(&[
            Command::SelectTorsion(Some(0)),
            Command::TurnTorsion { degrees: 120.0 },
        ]),
        0.0,
    );
    let moved: usize = out.reshaped.iter().map(|r| r.atoms.len()).sum();
    assert!(moved > 0, "the turn moved no atom");
    let bytes = off.spheres.upload_stats().position_bytes;
    let n = off.spheres.set_positions(&gpu.queue, &s, &out.reshaped);
    assert_eq!(n, moved);
    assert_eq!(
        off.spheres.upload_stats().position_bytes - bytes,
        32 * moved as u64
    );
    let after = off.render(&gpu, &s, &params).expect("render");
    let fresh = Offscreen::new(&gpu, &s, w, h)
        .expect("target")
        .render(&gpu, &s, &params)
        .expect("render");
    assert!(
        after == fresh,
        "the uploaded turn differs from a fresh renderer's picture"
    );
    assert!(after != before, "the turn changed nothing on screen");
}

/// A settle's animation (issue 44) draws the drug at poses and shapes the
/// session is not at: `show_pose` and `set_local_positions` must draw it
/// exactly as a renderer of a session standing there would, and putting
/// the session's own pose and positions back must restore its picture.
#[test]
fn a_settles_frames_draw_the_drug_where_a_session_there_would() {
    let Some(gpu) = gpu() else { return };
    let (Some(mut here), Some(mut there)) = (dhfr_trimethoprim(), dhfr_trimethoprim()) else {
        return;
    };
    let (w, h) = (320u32, 240u32);
    let params = ViewParams {
        cues: Cues::parse("none").expect("cues"),
        ..ViewParams::default()
    };
    // Both drugs 30 Å towards the eye; the second 2 Å further right, turned
    // 20° and with its first bond turned 90°.
    for s in [&mut here, &mut there] {
        s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
        s.step(
            &FrameInput::nudged(DVec3::new(0.0, 0.0, 30.0), DVec3::ZERO),
            0.0,
        );
    }
    there.step(
        &FrameInput::with_commands(&[
            Command::MoveBy {
                translate: DVec3::new(2.0, 0.0, 0.0),
                axis: DVec3::Z,
                degrees: 20.0,
            },
            Command::SelectTorsion(Some(0)),
            Command::TurnTorsion { degrees: 90.0 },
        ]),
        0.0,
    );
    let d = here.drug().expect("a drug");
    let pose = there.bodies()[d].pose;
    assert!(
        pose != here.bodies()[d].pose,
        "the second drug did not move"
    );
    let mut off = Offscreen::new(&gpu, &here, w, h).expect("target");
    let before = off.render(&gpu, &here, &params).expect("render");
    off.spheres.show_pose(Some((d, pose)));
    let n = off
        .spheres
        .set_local_positions(&gpu.queue, d, &there.bodies()[d].molecule.local);
    assert_eq!(n, there.bodies()[d].molecule.local.len());
    let shown = off.render(&gpu, &here, &params).expect("render");
    let fresh = Offscreen::new(&gpu, &there, w, h)
        .expect("target")
        .render(&gpu, &there, &params)
        .expect("render");
    assert!(
        shown == fresh,
        "the shown pose differs from a session's there"
    );
    assert!(shown != before, "showing another pose changed nothing");
    // A count that does not fit writes nothing.
    assert_eq!(off.spheres.set_local_positions(&gpu.queue, d, &[]), 0);
    off.spheres.show_pose(None);
    off.spheres
        .set_local_positions(&gpu.queue, d, &here.bodies()[d].molecule.local);
    let back = off.render(&gpu, &here, &params).expect("render");
    assert!(back == before, "the session's own pose did not come back");
}

/// The ghost keeps the reference's conformation while the drug's bonds
/// turn (the drug itself is moved out of the picture, sideways, so the
/// depth range stays and only the ghost and the receptor are drawn): with
/// a bond turned, the ghost is drawn exactly as with the drug at its file
/// torsions; after pinning a turned drug, it keeps the pinned shape when
/// the drug turns back. Its own atoms are written once per reference.
#[test]
fn the_ghost_keeps_the_reference_conformation_while_bonds_turn() {
    let Some(gpu) = gpu() else { return };
    let (w, h) = (240, 180);
    let ghost = ViewParams {
        cues: Cues::NONE,
        ghost: Some(Ghost {
            opacity: 1.0,
            ..Ghost::default()
        }),
        ..ViewParams::default()
    };
    let plain = ViewParams {
        ghost: None,
        ..ghost
    };
    // A session whose drug is set to `first` (and pinned there when asked),
    // moved out of view, then set to `then`.
    let session = |first: &[f64], pin: bool, then: &[f64]| -> Option<Session> {
        let mut s = dhfr_trimethoprim()?;
        let d = s.drug().expect("a drug");
        // Looking at the drug from the pocket's open side.
        *s.camera_mut() = drug_view(s.bodies(), d).expect("a view");
        s.set_torsions(d, first).expect("torsions");
        s.step(&FrameInput::default(), 0.0);
        if pin {
            assert!(s.pin_reference(), "nothing to pin");
        }
        let right = s
            .view_camera()
            .view_matrix()
            .inverse()
            .transform_vector3(DVec3::X);
        move_drug(&mut s, right * 400.0);
        s.set_torsions(d, then).expect("torsions");
        Some(s)
    };
    let Some(probe) = dhfr_trimethoprim() else {
        return;
    };
    let n = probe.torsion_angles(probe.drug().expect("a drug")).len();
    assert!(n > 0, "trimethoprim has rotatable bonds");
    let file = vec![0.0; n];
    let turned: Vec<f64> = (0..n).map(|k| 1.0 + 0.5 * k as f64).collect();
    let draw = |s: &Session, params: &ViewParams| {
        let mut off = Offscreen::new(&gpu, s, w, h).expect("target");
        let image = off.render(&gpu, s, params).expect("render");
        let again = off.render(&gpu, s, params).expect("render");
        assert!(image == again);
        (image, off.spheres.upload_stats().ghost_bytes)
    };
    let (Some(at_file), Some(bent)) = (
        session(&turned, false, &file),
        session(&file, false, &turned),
    ) else {
        return;
    };
    assert_eq!(depth_range(&at_file), depth_range(&bent));
    let (want, bytes) = draw(&at_file, &ghost);
    assert_eq!(bytes, 0, "the drug's own atoms show the file shape");
    assert!(want != draw(&at_file, &plain).0, "the ghost is not drawn");
    let (got, bytes) = draw(&bent, &ghost);
    let once = 32 * probe.bodies()[1].molecule.len() as u64;
    assert_eq!(
        bytes, once,
        "the ghost's own atoms, written once for two frames"
    );
    assert!(got == want, "the ghost turned with the drug");

    let (Some(pinned_here), Some(pinned_back)) = (
        session(&turned, true, &turned),
        session(&turned, true, &file),
    ) else {
        return;
    };
    let (want, bytes) = draw(&pinned_here, &ghost);
    assert_eq!(bytes, 0);
    let (got, bytes) = draw(&pinned_back, &ghost);
    assert_eq!(bytes, once);
    assert!(got == want, "the ghost left the pinned shape");
    assert!(got != draw(&at_file, &ghost).0, "pinning changed nothing");
}
