//! Image tests on whatever adapter there is (Mesa's CPU Vulkan in CI):
//! silhouettes against the exact perspective projection, depth order,
//! contact highlights, what moving a molecule uploads, and that each depth
//! cue changes the pixels it should (and costs no pass when off).

mod common;

use common::gpu;

use bump::model::{LigandSpec, LoadOptions, Molecule, RadiiSet, builtin};
use bump::render::offscreen::{Image, Offscreen, render_image};
use bump::render::view::{model_views, projection};
use bump::render::{Cues, ViewParams};
use bump::session::{Command, FrameInput, Session, Settings};
use glam::DVec3;

fn one_atom(element: &str, radius: f32, at: DVec3) -> Molecule {
    Molecule::new("atom", vec![common::atom(1, element, radius)], &[at])
}

/// Pixel where world point `p` of molecule `body` (local coordinates) lands.
fn project(s: &Session, body: usize, local: DVec3, w: u32, h: u32) -> (u32, u32) {
    let mv = model_views(s)[body];
    let clip = projection(s, f64::from(w) / f64::from(h)) * (mv * local.as_vec3().extend(1.0));
    let ndc = clip / clip.w;
    let x = (ndc.x + 1.0) * 0.5 * w as f32;
    let y = (1.0 - ndc.y) * 0.5 * h as f32;
    (x as u32, y as u32)
}

fn is_background(img: &Image, px: [u8; 4]) -> bool {
    px == img.pixel(0, 0).expect("corner")
}

fn is_green(px: [u8; 4]) -> bool {
    let [r, g, b, _] = px.map(i32::from);
    g > r + 40 && g > b + 40
}

fn is_magenta(px: [u8; 4]) -> bool {
    let [r, g, b, _] = px.map(i32::from);
    r > 140 && b > 120 && g < r - 60
}

fn count(img: &Image, f: impl Fn([u8; 4]) -> bool) -> usize {
    img.rgba
        .chunks(4)
        .filter(|p| f([p[0], p[1], p[2], p[3]]))
        .count()
}

#[test]
fn a_sphere_has_its_exact_perspective_silhouette() {
    let Some(gpu) = gpu() else { return };
    let r = 1.7;
    let s = Session::new(
        vec![one_atom("C", r, DVec3::new(3.0, -2.0, 1e5))],
        Settings::default(),
    )
    .expect("session");
    let (w, h) = (400u32, 400u32);
    let img = render_image(&gpu, &s, w, h, &ViewParams::default()).expect("render");
    // On the view axis at distance d the silhouette is a circle of NDC radius
    // f·r/√(d²−r²), f = 1/tan(fov/2).
    let d = s.camera().distance;
    let f = 1.0 / (0.5 * s.camera().fov_y).tan();
    let expected = f * f64::from(r) / (d * d - f64::from(r * r)).sqrt() * f64::from(h) / 2.0;
    let row = h / 2;
    let lit: Vec<u32> = (0..w)
        .filter(|&x| !is_background(&img, img.pixel(x, row).expect("px")))
        .collect();
    let width = f64::from(lit.len() as u32);
    assert!(
        (width / 2.0 - expected).abs() < 1.5,
        "silhouette radius {} px, expected {expected:.2} px",
        width / 2.0
    );
    let col: usize = (0..h)
        .filter(|&y| !is_background(&img, img.pixel(w / 2, y).expect("px")))
        .count();
    assert!((col as f64 / 2.0 - expected).abs() < 1.5);
}

#[test]
fn nearer_spheres_hide_farther_ones() {
    let Some(gpu) = gpu() else { return };
    for (z_green, green_in_front) in [(1.5, true), (-1.5, false)] {
        // Body 0 has grey carbons, body 1 green: same x, y; one nearer the eye.
        let grey = one_atom("C", 1.7, DVec3::ZERO);
        let green = one_atom("C", 1.7, DVec3::new(0.0, 0.0, z_green));
        let s = Session::new(vec![grey, green], Settings::default()).expect("session");
        let img = render_image(&gpu, &s, 200, 200, &ViewParams::default()).expect("render");
        let (x, y) = project(&s, 0, DVec3::ZERO, 200, 200);
        let px = img.pixel(x, y).expect("centre");
        assert_eq!(is_green(px), green_in_front, "z {z_green}: {px:?}");
    }
}

#[test]
fn builtin_scene_draws_rings_and_e_where_they_project() {
    let Some(gpu) = gpu() else { return };
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let s = Session::new(vec![rings, e], Settings::default()).expect("session");
    let (w, h) = (480u32, 320u32);
    let img = render_image(&gpu, &s, w, h, &ViewParams::default()).expect("render");
    let ring = &s.bodies()[0].molecule;
    for i in [0, 5, 20, 40] {
        let (x, y) = project(&s, 0, ring.local[i].as_dvec3(), w, h);
        let px = img.pixel(x, y).expect("in view");
        assert!(
            !is_background(&img, px) && !is_green(px),
            "ring atom {i} at ({x},{y}): {px:?}"
        );
    }
    // The corners are empty, and most of the picture is background.
    let bg = count(&img, |p| p == img.pixel(0, 0).expect("corner"));
    assert!(bg > (w * h) as usize / 2);
    assert_eq!(count(&img, is_magenta), 0, "no contacts, no highlight");
}

#[test]
fn colliding_atoms_are_highlighted_where_they_are() {
    let Some(gpu) = gpu() else { return };
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
    // Misaligned by 5 Å and pushed through with collision off, then checked.
    s.step(
        &FrameInput::with_commands(&[
            Command::MoveBy {
                translate: DVec3::new(0.0, 5.0, 25.0),
                axis: DVec3::Z,
                degrees: 0.0,
            },
            Command::ToggleCollision,
        ]),
        0.0,
    );
    assert!(!s.contacts().is_empty());
    let (w, h) = (480u32, 320u32);
    let img = render_image(&gpu, &s, w, h, &ViewParams::default()).expect("render");
    assert!(count(&img, is_magenta) > 50);
    // Highlighted atoms facing the eye show magenta at their projected centre.
    let mut seen = 0;
    for c in s.contacts() {
        let (b, a) = c.other;
        let (x, y) = project(&s, b, s.bodies()[b].molecule.local[a].as_dvec3(), w, h);
        if img.pixel(x, y).is_some_and(is_magenta) {
            seen += 1;
        }
    }
    assert!(seen > 0, "no highlighted atom visible at its projection");
}

/// Orange to yellow: the soft band's deeper levels (magenta has little green).
fn is_pressed(px: [u8; 4]) -> bool {
    let [r, g, b, _] = px.map(i32::from);
    r > 140 && g > b + 40
}

/// Under `soft`, atoms pressed into the band are drawn in the graded
/// colours and nothing else changes; under another response the same
/// contacts are magenta.
#[test]
fn pressed_atoms_are_graded_in_colour_by_depth() {
    let Some(gpu) = gpu() else { return };
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
    s.step(&FrameInput::docking(), 0.0);
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(bump::collide::Response::Soft)]),
        0.0,
    );
    let towards = s.bodies()[0].pose.translation - s.bodies()[1].pose.translation;
    for _ in 0..300 {
        s.step(
            &FrameInput::nudged(towards.normalize() * 0.25, DVec3::ZERO),
            0.0,
        );
    }
    assert!(s.contacts().iter().any(|c| c.depth() > 0.5));
    let (w, h) = (480u32, 320u32);
    let view = ViewParams::default();
    let soft = render_image(&gpu, &s, w, h, &view).expect("render");
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(bump::collide::Response::Slide)]),
        0.0,
    );
    let slide = render_image(&gpu, &s, w, h, &view).expect("render");
    // (The scene has orange atoms of its own: the counts are compared.)
    let (graded, plain) = (count(&soft, is_pressed), count(&slide, is_pressed));
    assert!(graded > plain + 30, "graded {graded} against {plain}");
    assert!(count(&slide, is_magenta) > count(&soft, is_magenta) + 30);
    // Only the highlighted atoms' pixels differ.
    let mut differ = 0;
    for (a, b) in soft.rgba.chunks(4).zip(slide.rgba.chunks(4)) {
        if a != b {
            differ += 1;
            let (a, b) = ([a[0], a[1], a[2], a[3]], [b[0], b[1], b[2], b[3]]);
            assert!(b[0] > b[1] && b[2] > b[1], "{a:?} against {b:?}");
        }
    }
    assert!(differ > 30);
}

#[test]
fn dhfr_with_trimethoprim_renders_and_the_drug_shows_when_pulled_out() {
    let Some(gpu) = gpu() else { return };
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let loaded = bump::model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default())
        .expect("load");
    let spec = LigandSpec::parse("TOP").expect("spec");
    let (r, d) = bump::model::split_complex(&loaded.structure, &spec).expect("split");
    let mut s = Session::new(vec![r, d], Settings::default()).expect("session");
    let (w, h) = (320u32, 240u32);
    let img = render_image(&gpu, &s, w, h, &ViewParams::default()).expect("render");
    let covered = count(&img, |p| p != img.pixel(0, 0).expect("corner"));
    assert!(covered > (w * h) as usize / 10 && covered < (w * h) as usize * 9 / 10);
    // Pull the drug 25 Å towards the eye: it is drawn, green, in front.
    s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
    s.step(
        &FrameInput::nudged(DVec3::new(0.0, 0.0, 25.0), DVec3::ZERO),
        0.0,
    );
    let img = render_image(&gpu, &s, w, h, &ViewParams::default()).expect("render");
    let (x, y) = project(&s, 1, DVec3::ZERO, w, h);
    let greens = (x.saturating_sub(6)..x + 6)
        .flat_map(|x| (y.saturating_sub(6)..y + 6).map(move |y| (x, y)))
        .filter(|&(x, y)| img.pixel(x, y).is_some_and(is_green))
        .count();
    assert!(greens > 5, "drug not visible near ({x},{y})");
}

#[test]
fn moving_a_molecule_uploads_matrices_only_and_highlights_only_changed_words() {
    let Some(gpu) = gpu() else { return };
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
    let mut off = Offscreen::new(&gpu, &s, 64, 64).expect("target");
    let atoms = off.spheres.upload_stats().atom_bytes;
    assert_eq!(atoms, 98 * 32);
    off.render(&gpu, &s, &ViewParams::default())
        .expect("render");
    let before = off.spheres.upload_stats();
    s.step(&FrameInput::docking(), 0.0);
    let out = s.step(
        &FrameInput::nudged(DVec3::new(0.0, 5.0, 25.0), DVec3::ZERO),
        0.0,
    );
    assert!(!out.highlight_changes.is_empty());
    off.spheres
        .apply_highlights(&gpu.queue, &out.highlight_changes);
    off.render(&gpu, &s, &ViewParams::default())
        .expect("render");
    let after = off.spheres.upload_stats();
    assert_eq!(
        after.atom_bytes, before.atom_bytes,
        "no atom data after a move"
    );
    // One eye's uniform (272 bytes) and two model-view matrices.
    assert_eq!(after.matrix_bytes - before.matrix_bytes, 272 + 2 * 64);
    // 98 atoms span 13 words of eight four-bit levels: at most those are
    // rewritten, and fewer when the contacts touch only some of them.
    let written = after.highlight_bytes - before.highlight_bytes;
    assert!(written > 0 && written < 13 * 4, "{written} bytes");
}

fn with_cues(cues: Cues) -> ViewParams {
    ViewParams {
        cues,
        ..ViewParams::default()
    }
}

fn luma(px: [u8; 4]) -> f64 {
    0.2126 * f64::from(px[0]) + 0.7152 * f64::from(px[1]) + 0.0722 * f64::from(px[2])
}

fn atoms(list: &[(f32, DVec3)]) -> Vec<Molecule> {
    list.iter().map(|&(r, at)| one_atom("C", r, at)).collect()
}

#[test]
fn cues_that_are_off_cost_no_pass_draw_or_texture() {
    let Some(gpu) = gpu() else { return };
    let (rings, e) = builtin::scene(RadiiSet::Bondi);
    let s = Session::new(vec![rings, e], Settings::default()).expect("session");
    let mut off = Offscreen::new(&gpu, &s, 96, 64).expect("target");
    for cues in [Cues::NONE, Cues::default()] {
        off.render(&gpu, &s, &with_cues(cues)).expect("render");
        let st = off.spheres.frame_stats();
        assert_eq!((st.eyes, st.passes, st.draws), (1, 1, 1), "{cues:?}");
    }
    assert_eq!(
        off.spheres.resources(),
        bump::render::spheres::Resources::default(),
        "no shadow map, screen-space pass or eye texture was made"
    );
    let one = |f: fn(&mut Cues)| {
        let mut c = Cues::NONE;
        f(&mut c);
        c
    };
    // Each cue adds exactly its own work.
    for (cues, passes, draws) in [
        (one(|c| c.shadow = true), 2, 2),
        (one(|c| c.outline = true), 2, 2),
        (one(|c| c.ao = true), 2, 2),
        (one(|c| c.translucent = true), 1, 3),
    ] {
        off.render(&gpu, &s, &with_cues(cues)).expect("render");
        let st = off.spheres.frame_stats();
        assert_eq!((st.passes, st.draws), (passes, draws), "{cues:?}");
    }
}

#[test]
fn depth_cueing_fades_far_atoms_more_than_near_ones() {
    let Some(gpu) = gpu() else { return };
    let near = DVec3::new(-3.0, 0.0, 6.0);
    let far = DVec3::new(3.0, 0.0, -6.0);
    let s = Session::new(atoms(&[(1.7, near), (1.7, far)]), Settings::default()).expect("session");
    let (w, h) = (240u32, 160u32);
    let plain = render_image(&gpu, &s, w, h, &with_cues(Cues::NONE)).expect("render");
    let cued = render_image(
        &gpu,
        &s,
        w,
        h,
        &with_cues(Cues::parse("depth").expect("cue")),
    )
    .expect("render");
    let at = |img: &Image, body| {
        let (x, y) = project(&s, body, DVec3::ZERO, w, h);
        luma(img.pixel(x, y).expect("px"))
    };
    let near_loss = at(&plain, 0) - at(&cued, 0);
    let far_loss = at(&plain, 1) - at(&cued, 1);
    // Far atoms fade by tens of percent (sRGB), near ones by a few.
    assert!(
        near_loss >= 0.0 && near_loss < 0.08 * at(&plain, 0),
        "near {near_loss}"
    );
    assert!(far_loss > 0.15 * at(&plain, 1), "far {far_loss}");
    assert!(far_loss > 3.0 * near_loss);
}

#[test]
fn outlines_darken_the_silhouette_and_leave_the_inside() {
    let Some(gpu) = gpu() else { return };
    let s = Session::new(atoms(&[(1.7, DVec3::ZERO)]), Settings::default()).expect("session");
    let (w, h) = (200u32, 200u32);
    let plain = render_image(&gpu, &s, w, h, &with_cues(Cues::NONE)).expect("render");
    let lined = render_image(
        &gpu,
        &s,
        w,
        h,
        &with_cues(Cues::parse("outline").expect("cue")),
    )
    .expect("render");
    let bg = plain.pixel(0, 0).expect("corner");
    // The rim: the lit pixels of the centre row nearest the background.
    let row = h / 2;
    let lit: Vec<u32> = (0..w)
        .filter(|&x| plain.pixel(x, row).expect("px") != bg)
        .collect();
    let (first, last) = (lit[0], *lit.last().expect("lit"));
    for x in [first, first + 1, last - 1, last] {
        let (a, b) = (
            plain.pixel(x, row).expect("px"),
            lined.pixel(x, row).expect("px"),
        );
        assert!(luma(b) < 0.5 * luma(a), "rim x {x}: {a:?} -> {b:?}");
    }
    assert_eq!(
        plain.pixel(w / 2, row),
        lined.pixel(w / 2, row),
        "inside unchanged"
    );
    assert_eq!(lined.pixel(0, 0), Some(bg), "background unchanged");
}

#[test]
fn ambient_occlusion_darkens_an_atom_in_a_crevice_only() {
    let Some(gpu) = gpu() else { return };
    // Body 0 sits at the bottom of a crevice of four nearer atoms; body 5
    // stands alone.
    let mut list = vec![(1.7, DVec3::ZERO)];
    for (dx, dy) in [(3.6, 0.0), (-3.6, 0.0), (0.0, 3.6), (0.0, -3.6)] {
        list.push((1.7, DVec3::new(dx, dy, 2.5)));
    }
    list.push((1.7, DVec3::new(14.0, 0.0, 0.0)));
    let s = Session::new(atoms(&list), Settings::default()).expect("session");
    let (w, h) = (320u32, 200u32);
    let plain = render_image(&gpu, &s, w, h, &with_cues(Cues::NONE)).expect("render");
    let ao =
        render_image(&gpu, &s, w, h, &with_cues(Cues::parse("ao").expect("cue"))).expect("render");
    let at = |img: &Image, body| {
        let (x, y) = project(&s, body, DVec3::new(0.0, 0.0, 1.7), w, h);
        luma(img.pixel(x, y).expect("px"))
    };
    // sRGB luma: −10 is about −20 % of the light (linear).
    assert!(
        at(&ao, 0) < at(&plain, 0) - 10.0,
        "crevice {} -> {}",
        at(&plain, 0),
        at(&ao, 0)
    );
    assert_eq!(
        at(&ao, 5),
        at(&plain, 5),
        "a lone atom's face is not occluded"
    );
}

#[test]
fn shadows_darken_an_atom_behind_another_from_the_light() {
    let Some(gpu) = gpu() else { return };
    // The light comes from +x; body 1 (large) stands between it and body 0.
    // Body 2 is a copy of body 0 with nothing in its light.
    let list = [
        (1.7, DVec3::ZERO),
        (2.5, DVec3::new(4.0, 0.0, 0.0)),
        (1.7, DVec3::new(0.0, 9.0, 0.0)),
    ];
    let s = Session::new(atoms(&list), Settings::default()).expect("session");
    let params = |cues| ViewParams {
        light: DVec3::new(1.0, 0.0, 0.2),
        cues,
        ..ViewParams::default()
    };
    let (w, h) = (320u32, 240u32);
    let plain = render_image(&gpu, &s, w, h, &params(Cues::NONE)).expect("render");
    let shadowed =
        render_image(&gpu, &s, w, h, &params(Cues::parse("shadow").expect("cue"))).expect("render");
    // A point of the lit side (normal 40° towards +x).
    let side = DVec3::new(
        1.7 * 40f64.to_radians().sin(),
        0.0,
        1.7 * 40f64.to_radians().cos(),
    );
    let at = |img: &Image, body| {
        let (x, y) = project(&s, body, side, w, h);
        luma(img.pixel(x, y).expect("px"))
    };
    assert!(
        // sRGB luma: ×0.7 is about ×0.45 of the light (linear).
        at(&shadowed, 0) < 0.7 * at(&plain, 0),
        "in shadow: {} -> {}",
        at(&plain, 0),
        at(&shadowed, 0)
    );
    assert!(
        (at(&shadowed, 2) - at(&plain, 2)).abs() <= 2.0,
        "in the light: {} -> {}",
        at(&plain, 2),
        at(&shadowed, 2)
    );
}

#[test]
fn a_translucent_receptor_shows_the_drug_behind_it() {
    let Some(gpu) = gpu() else { return };
    // The receptor (grey, body 0) hides the drug (green, body 1) behind it.
    let receptor = one_atom("C", 2.0, DVec3::new(0.0, 0.0, 3.0));
    let drug = one_atom("C", 1.7, DVec3::ZERO);
    let s = Session::new(vec![receptor, drug], Settings::default()).expect("session");
    let (w, h) = (200u32, 200u32);
    let plain = render_image(&gpu, &s, w, h, &with_cues(Cues::NONE)).expect("render");
    let see = render_image(
        &gpu,
        &s,
        w,
        h,
        &with_cues(Cues::parse("translucent").expect("cue")),
    )
    .expect("render");
    let (x, y) = project(&s, 1, DVec3::ZERO, w, h);
    let (a, b) = (plain.pixel(x, y).expect("px"), see.pixel(x, y).expect("px"));
    assert!(!is_green(a), "opaque receptor hides the drug: {a:?}");
    assert!(is_green(b), "translucent receptor shows it: {b:?}");
}
