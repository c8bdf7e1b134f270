//! Image tests of the ghost and the clipping slab on whatever adapter there
//! is (Mesa's CPU Vulkan in CI), on hand-placed atoms seen by a camera set
//! exactly: nothing in front of the slab's near plane or behind its far
//! plane is drawn, an atom inside it is, an atom cut by the near plane
//! shows a flat cap, and a clipped atom casts no shadow; the ghost blends
//! over the background by its opacity exactly (in linear light), hides
//! behind a nearer drug, tints a drug behind it, and draws nothing when off.

mod common;

use common::gpu;

use bump::model::Molecule;
use bump::render::ghost::Ghost;
use bump::render::offscreen::{Image, Offscreen};
use bump::render::slab::Slab;
use bump::render::view::projection;
use bump::render::{Cues, Gpu, ViewParams};
use bump::session::{Camera, Command, FrameInput, Session, Settings};
use glam::{DQuat, DVec3};

const W: u32 = 320;
const H: u32 = 240;

/// A session of a "receptor" (the larger molecule) and a one-atom drug at
/// the origin, seen from `distance` Å along +z, looking at `centre`.
fn scene(receptor: &[(&str, DVec3)], drug: (&str, f32), centre: DVec3) -> Session {
    let atoms = receptor
        .iter()
        .enumerate()
        .map(|(k, (e, _))| common::atom(k as i64 + 1, e, 1.7))
        .collect();
    let at: Vec<DVec3> = receptor.iter().map(|(_, p)| *p).collect();
    let r = Molecule::new("receptor", atoms, &at);
    let d = Molecule::new(
        "drug",
        vec![common::atom(1, drug.0, drug.1)],
        &[DVec3::ZERO],
    );
    let mut s = Session::new(vec![r, d], Settings::default()).expect("session");
    *s.camera_mut() = Camera {
        rotation: DQuat::IDENTITY,
        centre,
        distance: 60.0,
        fov_y: 30f64.to_radians(),
    };
    s
}

/// The pixel where world point `p` lands.
fn pixel_of(s: &Session, p: DVec3) -> (u32, u32) {
    let v = s.view_camera().view_matrix().transform_point3(p);
    let clip = projection(s, f64::from(W) / f64::from(H)).as_dmat4() * v.extend(1.0);
    let ndc = clip / clip.w;
    let x = (ndc.x + 1.0) * 0.5 * f64::from(W);
    let y = (1.0 - ndc.y) * 0.5 * f64::from(H);
    (x as u32, y as u32)
}

fn px(img: &Image, (x, y): (u32, u32)) -> [u8; 4] {
    img.pixel(x, y).expect("in the image")
}

fn render(gpu: &Gpu, s: &Session, params: &ViewParams) -> Image {
    Offscreen::new(gpu, s, W, H)
        .expect("target")
        .render(gpu, s, params)
        .expect("render")
}

fn plain() -> ViewParams {
    ViewParams {
        cues: Cues::NONE,
        ..ViewParams::default()
    }
}

#[test]
fn nothing_is_drawn_outside_the_slab_and_a_cut_atom_shows_a_flat_cap() {
    let Some(gpu) = gpu() else { return };
    // The drug at the origin sits 60 Å from the eye; a 10 Å slab keeps
    // view depths 55..65 Å. Radius 1.7 Å each.
    let front = DVec3::new(-6.0, 0.0, 8.0); // 50.3..53.7 Å: all in front
    let inside = DVec3::new(6.0, 0.0, 2.0); // 56.3..59.7 Å: inside
    let behind = DVec3::new(0.0, 6.0, -8.0); // 66.3..69.7 Å: all behind
    let cut = DVec3::new(0.0, -6.0, 5.0); // 53.3..56.7 Å: cut by the near plane
    let s = scene(
        &[("C", front), ("C", inside), ("C", behind), ("C", cut)],
        ("O", 1.5),
        DVec3::ZERO,
    );
    let full = render(&gpu, &s, &plain());
    let slab = ViewParams {
        slab: Some(Slab::new(10.0)),
        ..plain()
    };
    let clipped = render(&gpu, &s, &slab);
    let bg = px(&full, (0, 0));
    assert_eq!(px(&clipped, (0, 0)), bg);
    for (name, p) in [("front", front), ("inside", inside), ("behind", behind)] {
        assert_ne!(
            px(&full, pixel_of(&s, p)),
            bg,
            "{name} drawn without the slab"
        );
    }
    // In front of the near plane and behind the far one: background, over
    // the atom's whole disc (a 3 px margin inside its silhouette).
    for p in [front, behind] {
        let (x, y) = pixel_of(&s, p);
        for (dx, dy) in [(0i32, 0i32), (-6, 0), (6, 0), (0, -6), (0, 6)] {
            let q = ((x as i32 + dx) as u32, (y as i32 + dy) as u32);
            assert_ne!(px(&full, q), bg);
            assert_eq!(px(&clipped, q), bg, "clipped atom drawn at {q:?}");
        }
    }
    // Inside the slab: unchanged, and so is the drug.
    let (x, y) = pixel_of(&s, inside);
    assert_eq!(px(&clipped, (x, y)), px(&full, (x, y)));
    let o = pixel_of(&s, DVec3::ZERO);
    assert_eq!(px(&clipped, o), px(&full, o));
    // The cut atom: its face on the near plane is flat, one colour, where
    // the whole sphere is shaded round.
    let (x, y) = pixel_of(&s, cut);
    // (Only the specular term, which follows the eye ray, may move a
    // level between neighbouring pixels of the cap.)
    let spread = |img: &Image| {
        let c = px(img, (x, y));
        [(-4i32, 0i32), (4, 0), (0, -4), (0, 4)]
            .iter()
            .map(|(dx, dy)| {
                let q = px(img, ((x as i32 + dx) as u32, (y as i32 + dy) as u32));
                (0..3).map(|k| c[k].abs_diff(q[k])).max().unwrap_or(0)
            })
            .max()
            .unwrap_or(0)
    };
    assert_ne!(px(&clipped, (x, y)), bg);
    assert!(
        spread(&clipped) <= 2,
        "the cap is not flat: {}",
        spread(&clipped)
    );
    assert!(
        spread(&full) > 6,
        "the uncut sphere is shaded round: {}",
        spread(&full)
    );
    // A thicker slab (30 Å) keeps all of them.
    let wide = render(
        &gpu,
        &s,
        &ViewParams {
            slab: Some(Slab::new(30.0)),
            ..plain()
        },
    );
    assert!(wide.rgba == full.rgba, "a 30 Å slab clipped something");
}

#[test]
fn an_atom_clipped_away_casts_no_shadow() {
    let Some(gpu) = gpu() else { return };
    let light = ViewParams::default().light.normalize();
    let inside = DVec3::new(6.0, 0.0, 2.0);
    // 8 Å from `inside` towards the light: it shades `inside`'s front, and
    // lies wholly in front of the near plane (view depth ≤ 54.3 Å).
    let blocker = inside + light * 8.0;
    assert!(blocker.z - 1.7 > 5.0);
    let s = scene(
        &[
            ("C", inside),
            ("C", blocker),
            ("C", DVec3::new(-6.0, 0.0, 0.0)),
        ],
        ("O", 1.5),
        DVec3::ZERO,
    );
    let cues = |shadow| Cues {
        shadow,
        ..Cues::NONE
    };
    let with = |shadow, slab: Option<Slab>| {
        render(
            &gpu,
            &s,
            &ViewParams {
                cues: cues(shadow),
                slab,
                ..plain()
            },
        )
    };
    let p = pixel_of(&s, inside);
    let slab = Some(Slab::new(10.0));
    // Without the slab the blocker is drawn and darkens `inside`.
    let lit = px(&with(false, None), p);
    let shaded = px(&with(true, None), p);
    assert!(
        shaded[0] < lit[0] && shaded[1] < lit[1],
        "{shaded:?} vs {lit:?}"
    );
    // With it, the blocker is gone from the shadow map too.
    assert_eq!(px(&with(true, slab), p), px(&with(false, slab), p));
}

fn to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn to_srgb(l: f64) -> f64 {
    let c = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c * 255.0
}

#[test]
fn the_ghost_blends_by_its_opacity_and_is_depth_tested() {
    let Some(gpu) = gpu() else { return };
    let far = |x: f64| ("C", DVec3::new(x, 25.0, -20.0));
    let mut s = scene(&[far(-3.0), far(0.0), far(3.0)], ("O", 1.5), DVec3::ZERO);
    // The drug moves 6 Å right; its ghost stays at its file pose.
    let step = |s: &mut Session, t: DVec3| {
        s.step(
            &FrameInput::with_commands(&[Command::MoveBy {
                translate: t,
                axis: DVec3::Z,
                degrees: 0.0,
            }]),
            0.0,
        );
    };
    step(&mut s, DVec3::new(6.0, 0.0, 0.0));
    let ghost_at = pixel_of(&s, DVec3::ZERO);
    let ghost = |opacity| ViewParams {
        ghost: Some(Ghost {
            opacity,
            ..Ghost::default()
        }),
        ..plain()
    };
    let mut target = Offscreen::new(&gpu, &s, W, H).expect("target");
    let off = target.render(&gpu, &s, &plain()).expect("render");
    let draws_off = target.spheres.frame_stats().draws;
    let half = target.render(&gpu, &s, &ghost(0.3)).expect("render");
    assert_eq!(target.spheres.frame_stats().draws, draws_off + 2);
    let opaque = target.render(&gpu, &s, &ghost(1.0)).expect("render");
    let bg = px(&off, (0, 0));
    // Off: nothing where the ghost would be.
    assert_eq!(px(&off, ghost_at), bg);
    let (b, c, g) = (bg, px(&opaque, ghost_at), px(&half, ghost_at));
    assert_ne!(c, bg, "the opaque ghost is drawn");
    for k in 0..3 {
        let want = to_srgb(0.3 * to_linear(c[k]) + 0.7 * to_linear(b[k]));
        assert!(
            (f64::from(g[k]) - want).abs() <= 1.5,
            "channel {k}: ghost {g:?}, opaque {c:?}, background {b:?}: want {want:.1}"
        );
        assert!(
            b[k].min(c[k]) < g[k] && g[k] < b[k].max(c[k]),
            "channel {k}: {g:?} is not between {b:?} and {c:?}"
        );
    }
    // The drug itself is unchanged by its ghost.
    let drug_at = pixel_of(&s, DVec3::new(6.0, 0.0, 0.0));
    assert_eq!(px(&half, drug_at), px(&off, drug_at));

    // The drug 3 Å in front of its ghost hides it; 3 Å behind, it is
    // seen through it.
    for (dz, hidden) in [(3.0, true), (-3.0, false)] {
        let now = s.bodies()[1].pose.translation;
        step(&mut s, DVec3::new(0.0, 0.0, dz) - now);
        let on = render(&gpu, &s, &ghost(0.3));
        let off = render(&gpu, &s, &plain());
        let at = pixel_of(&s, DVec3::ZERO);
        assert_ne!(px(&off, at), bg, "the drug is over its ghost");
        assert_eq!(px(&on, at) == px(&off, at), hidden, "drug at dz {dz}");
    }
}

/// `bump render` with `args` into `out`; its stderr when it fails.
fn bump_render(args: &[&str], out: &std::path::Path) -> Result<Image, String> {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_bump"))
        .arg("render")
        .args(args)
        .args(["--size", "160x120", "-o"])
        .arg(out)
        .output()
        .expect("run bump");
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let img = image::open(out).expect("read the PNG").to_rgba8();
    Ok(Image {
        width: img.width(),
        height: img.height(),
        rgba: img.into_raw(),
    })
}

#[test]
fn bump_render_draws_the_ghost_and_the_slab() {
    if gpu().is_none() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("bump-ghost-slab-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let png = |n: &str| dir.join(format!("{n}.png"));
    // The built-in scene's E moved 8 Å up, out of the rings (collisions
    // off): its ghost stays in them.
    let moved = ["--no-contacts", "--move", "0,8,0"];
    let plain = bump_render(&moved, &png("plain")).expect("plain");
    let ghost = bump_render(&[&moved[..], &["--ghost"]].concat(), &png("ghost")).expect("ghost");
    assert!(plain.rgba != ghost.rgba, "--ghost drew nothing");
    let slab = bump_render(&[&moved[..], &["--slab", "2"]].concat(), &png("slab")).expect("slab");
    assert!(plain.rgba != slab.rgba, "--slab 2 clipped nothing");
    // A bare --slab is 10 Å.
    let bare = bump_render(&["--slab"], &png("bare")).expect("bare slab");
    let ten = bump_render(&["--slab", "10"], &png("ten")).expect("10 Å slab");
    assert!(bare.rgba == ten.rgba, "a bare --slab is not 10 Å");
    let err = bump_render(&["--slab", "0.2"], &png("thin")).expect_err("too thin");
    assert!(err.contains("0.2") && err.contains("thickness"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
