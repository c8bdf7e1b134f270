//! Image tests of ball-and-stick and hydrogen bonds as cylinders, on
//! whatever adapter there is (Mesa's CPU Vulkan in CI), on DHFR with
//! trimethoprim (6xg5, TOP): a bond's stick lies between its two atoms in
//! the projection (pixels along the segment between the balls change when
//! the sticks are drawn and take the stick's colour; pixels beside it do
//! not change), a hydrogen bond the score reports is drawn as dashes
//! between its donor and acceptor (dash centres take the H-bond colour,
//! the gaps between them do not change), and the bond list is uploaded
//! only when the pocket's set changes.
//!
//! Each case looks at its segment from a direction in which nothing drawn
//! (balls at their drawn radii, other sticks) comes near the rays to the
//! pixels tested, found by a CPU check, so the expectations are exact.

mod common;

use common::gpu;

use bump::model::{LigandSpec, LoadOptions};
use bump::render::cylinders::Stick;
use bump::render::offscreen::{Image, Offscreen};
use bump::render::sticks::{self, HBOND_DASH, StickView};
use bump::render::view::projection;
use bump::render::{Cues, ViewParams};
use bump::session::{FrameInput, Session, Settings};
use glam::{DQuat, DVec3};

fn dhfr_trimethoprim() -> Option<Session> {
    let dir = common::shared_pdb()?;
    let loaded = bump::model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default())
        .expect("load");
    let spec = LigandSpec::parse("TOP").expect("spec");
    let (r, d) = bump::model::split_complex(&loaded.structure, &spec).expect("split");
    let mut s = Session::new(vec![r, d], Settings::default()).expect("session");
    s.enable_score();
    s.step(&FrameInput::default(), 0.0);
    Some(s)
}

const W: u32 = 480;
const H: u32 = 360;

/// Pixel of world point `p`.
fn pixel_of(s: &Session, p: DVec3) -> (u32, u32) {
    let v = s.view_camera().view_matrix().transform_point3(p);
    let clip = projection(s, f64::from(W) / f64::from(H)).as_dmat4() * v.extend(1.0);
    let ndc = clip / clip.w;
    let x = (ndc.x + 1.0) * 0.5 * f64::from(W);
    let y = (1.0 - ndc.y) * 0.5 * f64::from(H);
    (x as u32, y as u32)
}

fn world(s: &Session, body: usize, atom: usize) -> DVec3 {
    let b = &s.bodies()[body];
    b.pose.transform_point(b.molecule.local[atom].as_dvec3())
}

/// Distance from `c` to the ray from `eye` to `target`, counting only
/// points before `target` (a point behind it cannot hide it).
fn ray_distance(eye: DVec3, target: DVec3, c: DVec3) -> f64 {
    let d = target - eye;
    let t = ((c - eye).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    (eye + d * t - c).length()
}

/// Shortest distance between the ray segment eye→target and segment p–q.
fn segment_distance(eye: DVec3, target: DVec3, p: DVec3, q: DVec3) -> f64 {
    (0..=40)
        .map(|i| ray_distance(eye, target, p.lerp(q, f64::from(i) / 40.0)))
        .fold(f64::INFINITY, f64::min)
}

/// Everything drawn: balls (centre, drawn radius) and sticks (ends, radius).
struct Drawn {
    balls: Vec<((usize, usize), DVec3, f64)>,
    sticks: Vec<(Stick, DVec3, DVec3)>,
}

fn drawn(s: &Session, off: &Offscreen) -> Drawn {
    let mut balls = Vec::new();
    let mut at = Vec::new();
    for (k, b) in s.bodies().iter().enumerate() {
        for i in 0..b.molecule.len() {
            let r = f64::from(off.spheres.radius_of(k, i).expect("drawn"));
            balls.push(((k, i), world(s, k, i), r));
            at.push(world(s, k, i));
        }
    }
    let c = off.spheres.cylinders_made().expect("sticks made");
    let sticks = c
        .bonds()
        .iter()
        .chain(c.dashes())
        .map(|st| {
            let (a, b) = (at[st.a as usize], at[st.b as usize]);
            (
                *st,
                a.lerp(b, f64::from(st.t0)),
                a.lerp(b, f64::from(st.t1)),
            )
        })
        .collect();
    Drawn { balls, sticks }
}

/// True when nothing drawn but `except` comes within `margin` Å of the
/// rays from `eye` to each of `targets`.
fn clear(
    d: &Drawn,
    eye: DVec3,
    targets: &[DVec3],
    except: &dyn Fn(&Stick) -> bool,
    margin: f64,
) -> bool {
    targets.iter().all(|&t| {
        d.balls
            .iter()
            .all(|&(_, c, r)| ray_distance(eye, t, c) > r + margin)
            && d.sticks.iter().all(|(st, p, q)| {
                except(st) || segment_distance(eye, t, *p, *q) > f64::from(st.radius) + margin
            })
    })
}

/// Points the camera from `dir` (unit, from the target towards the eye) at
/// `target`, `distance` Å away.
fn look(s: &mut Session, target: DVec3, dir: DVec3, distance: f64) -> DVec3 {
    let cam = s.camera_mut();
    cam.rotation = DQuat::from_rotation_arc(dir, DVec3::Z);
    cam.centre = target;
    cam.distance = distance;
    s.view_camera().eye()
}

fn px(img: &Image, p: (u32, u32)) -> [i32; 3] {
    let v = img.pixel(p.0, p.1).expect("in the image");
    [i32::from(v[0]), i32::from(v[1]), i32::from(v[2])]
}

fn plain() -> ViewParams {
    ViewParams {
        cues: Cues::parse("none").expect("cues"),
        aspect: f64::from(W) / f64::from(H),
        ..ViewParams::default()
    }
}

#[test]
fn a_bond_stick_lies_between_its_atoms() {
    let Some(gpu) = gpu() else { return };
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    let mut off = Offscreen::new(&gpu, &s, W, H).expect("target");
    let mut view = StickView::default();
    assert!(view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0)));
    let bonds: Vec<Stick> = off.spheres.cylinders_made().expect("made").bonds().to_vec();
    // The drug's bonds and the pocket's, every one between two balls.
    let drug_atoms = s.bodies()[1].molecule.len() as u32;
    let first_drug = s.bodies()[0].molecule.len() as u32;
    let drug_bonds: Vec<&Stick> = bonds.iter().filter(|b| b.a >= first_drug).collect();
    assert_eq!(
        drug_bonds.len(),
        s.bodies()[1].molecule.chemistry().bonds.len()
    );
    assert!(
        bonds.len() > drug_bonds.len(),
        "pocket residues have bonds too"
    );
    for b in &bonds {
        for g in [b.a, b.b] {
            let (k, i) = if g >= first_drug {
                (1, (g - first_drug) as usize)
            } else {
                (0, g as usize)
            };
            let r = off.spheres.radius_of(k, i).expect("atom");
            let own = s.bodies()[k].molecule.atoms[i].radius;
            assert!(
                (r - own * sticks::BALL_SCALE).abs() < 1e-6,
                "atom {k}/{i} is a ball"
            );
        }
        assert!(b.a < first_drug + drug_atoms && b.b < first_drug + drug_atoms);
    }
    // A drug bond seen side-on with nothing in front of it.
    let d = drawn(&s, &off);
    let dirs = common::sphere_directions(200);
    let mut found = None;
    'search: for st in &drug_bonds {
        let (a, b) = (d.balls[st.a as usize].1, d.balls[st.b as usize].1);
        let axis = (b - a).normalize();
        let mid = a.lerp(b, 0.5);
        for &dir in &dirs {
            if dir.dot(axis).abs() > 0.25 {
                continue;
            }
            let eye = mid + dir * 12.0;
            let side = axis.cross(dir).normalize();
            let on: Vec<DVec3> = [0.4, 0.5, 0.6].iter().map(|&t| a.lerp(b, t)).collect();
            let beside = [mid + side * 0.9, mid - side * 0.9];
            let this = |x: &Stick| x.a == st.a && x.b == st.b;
            // Balls a and b are not in the way of the points on the stick:
            // the points are outside them and the view is side-on.
            let balls_ok = on.iter().all(|&t| {
                d.balls.iter().enumerate().all(|(g, &(_, c, r))| {
                    g as u32 == st.a || g as u32 == st.b || ray_distance(eye, t, c) > r + 0.15
                })
            });
            let sticks_ok = on.iter().all(|&t| {
                d.sticks.iter().all(|(x, p, q)| {
                    this(x) || segment_distance(eye, t, *p, *q) > f64::from(x.radius) + 0.15
                })
            });
            if balls_ok && sticks_ok && clear(&d, eye, &beside, &|_| false, 0.15) {
                found = Some((**st, a, b, dir, side));
                break 'search;
            }
        }
    }
    let (st, a, b, dir, side) = found.expect("some drug bond can be seen side-on");
    let mid = a.lerp(b, 0.5);
    look(&mut s, mid, dir, 12.0);
    // Both atoms green, so the whole stick is green.
    let green = Some([0.0, 1.0, 0.0]);
    let first = s.bodies()[0].molecule.len();
    off.spheres.set_colors(
        &gpu.queue,
        &[
            (1, st.a as usize - first, green),
            (1, st.b as usize - first, green),
        ],
    );
    let with = off.render(&gpu, &s, &plain()).expect("render");
    off.spheres
        .cylinders(&gpu.device)
        .set_bonds(&gpu.device, &gpu.queue, &[]);
    let without = off.render(&gpu, &s, &plain()).expect("render");
    // The projected stick: at least a few pixels long and wide.
    let (pa, pb) = (pixel_of(&s, a), pixel_of(&s, b));
    let len = f64::from(pa.0.abs_diff(pb.0)).hypot(f64::from(pa.1.abs_diff(pb.1)));
    assert!(len > 20.0, "the bond spans {len} pixels");
    for t in [0.4, 0.5, 0.6] {
        let p = pixel_of(&s, a.lerp(b, t));
        let [r, g, bl] = px(&with, p);
        assert!(
            g >= r + 60 && g >= bl + 60,
            "stick pixel {p:?} (t {t}) is {:?}, not green",
            [r, g, bl]
        );
        assert_ne!(
            px(&with, p),
            px(&without, p),
            "pixel {p:?} changed by the stick"
        );
    }
    for q in [mid + side * 0.9, mid - side * 0.9] {
        let p = pixel_of(&s, q);
        assert_eq!(
            px(&with, p),
            px(&without, p),
            "pixel {p:?} beside the stick"
        );
        let [r, g, bl] = px(&with, p);
        assert!(
            !(g >= r + 60 && g >= bl + 60),
            "pixel {p:?} beside the stick is green"
        );
    }
}

#[test]
fn a_hydrogen_bond_is_dashed_between_donor_and_acceptor() {
    let Some(gpu) = gpu() else { return };
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    let score = s.live_score().cloned().expect("scored");
    assert!(
        !score.score.hbonds.is_empty(),
        "TOP in 6xg5 makes hydrogen bonds"
    );
    let mut off = Offscreen::new(&gpu, &s, W, H).expect("target");
    let mut view = StickView::default();
    view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0));
    assert!(view.show_hbonds(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(&score)));
    // The same bonds again upload nothing.
    let before = off.spheres.cylinders_made().expect("made").uploaded_bytes;
    assert!(!view.show_hbonds(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(&score)));
    assert!(!view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0)));
    assert_eq!(
        off.spheres.cylinders_made().expect("made").uploaded_bytes,
        before
    );
    let d = drawn(&s, &off);
    let first = s.bodies()[0].molecule.len() as u32;
    let dirs = common::sphere_directions(200);
    let mut found = None;
    'search: for h in &score.score.hbonds {
        let (ga, gb) = (first + h.drug_atom, h.receptor_atom);
        let (a, b) = (d.balls[ga as usize].1, d.balls[gb as usize].1);
        // Donor and acceptor: the score's pair, at its distance.
        assert!(((b - a).length() - h.distance).abs() < 1e-3);
        let len = (b - a).length();
        let ranges = bump::render::dashes::dash_ranges(len, HBOND_DASH.0, HBOND_DASH.1);
        if ranges.len() < 3 {
            continue;
        }
        let mid_dash = ranges[ranges.len() / 2];
        let on = a.lerp(b, 0.5 * (mid_dash.0 + mid_dash.1));
        let gap = a.lerp(b, 0.5 * (mid_dash.1 + ranges[ranges.len() / 2 + 1].0));
        let axis = (b - a).normalize();
        for &dir in &dirs {
            if dir.dot(axis).abs() > 0.25 {
                continue;
            }
            let eye = on + dir * 8.0;
            let this = |x: &Stick| x.a == ga && x.b == gb;
            if clear(&d, eye, &[on, gap], &this, 0.12) {
                found = Some((on, gap, dir));
                break 'search;
            }
        }
    }
    let (on, gap, dir) = found.expect("some hydrogen bond can be seen side-on");
    look(&mut s, on, dir, 8.0);
    let with = off.render(&gpu, &s, &plain()).expect("render");
    assert!(view.show_hbonds(&gpu.device, &gpu.queue, &mut off.spheres, &s, None));
    let without = off.render(&gpu, &s, &plain()).expect("render");
    let p = pixel_of(&s, on);
    let [r, g, bl] = px(&with, p);
    // Deep sky blue: no red but the highlight's, blue above green.
    assert!(
        bl >= r + 80 && g >= r + 40 && bl > g,
        "dash pixel {p:?} is {:?}, not the H-bond colour",
        [r, g, bl]
    );
    assert_ne!(px(&with, p), px(&without, p));
    let q = pixel_of(&s, gap);
    assert_eq!(px(&with, q), px(&without, q), "the gap at {q:?} is empty");
}

#[test]
fn moving_the_drug_uploads_bonds_only_when_the_pocket_changes() {
    let Some(gpu) = gpu() else { return };
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    let mut off = Offscreen::new(&gpu, &s, 64, 64).expect("target");
    let mut view = StickView::default();
    assert!(view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0)));
    let bytes = |o: &Offscreen| o.spheres.cylinders_made().map_or(0, |c| c.uploaded_bytes);
    let start = bytes(&off);
    // A tiny move keeps the set: nothing uploaded.
    s.step(
        &FrameInput::with_commands(&[bump::session::Command::MoveBy {
            translate: DVec3::new(0.001, 0.0, 0.0),
            axis: DVec3::Z,
            degrees: 0.0,
        }]),
        0.0,
    );
    assert!(!view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0)));
    assert_eq!(bytes(&off), start);
    // A wider pocket: more residues, bonds uploaded once.
    let n = view.labels().len();
    assert!(view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(8.0)));
    assert!(view.labels().len() > n);
    assert!(bytes(&off) > start);
    // Off: every radius back to its own.
    assert!(view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, None));
    for (k, b) in s.bodies().iter().enumerate() {
        for (i, a) in b.molecule.atoms.iter().enumerate() {
            assert_eq!(off.spheres.radius_of(k, i), Some(a.radius));
        }
    }
    assert!(off.spheres.cylinders_made().expect("made").is_empty());
}

#[test]
fn sticks_draw_once_per_eye_with_every_cue_and_stereo_mode() {
    use bump::render::{Stereo, StereoMode};
    let Some(gpu) = gpu() else { return };
    let Some(s) = dhfr_trimethoprim() else {
        return;
    };
    let score = s.live_score().cloned().expect("scored");
    let mut off = Offscreen::new(&gpu, &s, 96, 64).expect("target");
    let mut view = StickView::default();
    let mut cases: Vec<ViewParams> = ["none", "depth,outline,ao,shadow,translucent", "shadow"]
        .iter()
        .map(|c| ViewParams {
            cues: Cues::parse(c).expect("cues"),
            ..ViewParams::default()
        })
        .collect();
    for mode in StereoMode::ALL {
        cases.push(ViewParams {
            cues: Cues::parse("depth,shadow,translucent").expect("cues"),
            stereo: Stereo {
                mode,
                ..Stereo::default()
            },
            ..ViewParams::default()
        });
    }
    for params in &cases {
        view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, None);
        view.show_hbonds(&gpu.device, &gpu.queue, &mut off.spheres, &s, None);
        let plain = off.render(&gpu, &s, params).expect("render");
        let without = off.spheres.frame_stats();
        view.show_pocket(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(5.0));
        view.show_hbonds(&gpu.device, &gpu.queue, &mut off.spheres, &s, Some(&score));
        let sticks = off.render(&gpu, &s, params).expect("render");
        let with = off.spheres.frame_stats();
        // One more draw per eye: all the sticks in one instanced call.
        assert_eq!(with.draws, without.draws + with.eyes, "{params:?}");
        assert_eq!(with.passes, without.passes);
        assert_eq!((plain.width, plain.height), (sticks.width, sticks.height));
    }
}

#[test]
fn bump_render_draws_sticks_and_hydrogen_bonds_and_refuses_a_bad_distance() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    if gpu().is_none() {
        return;
    }
    let pdb = dir.join("6xg5_tmp_prepared.pdb");
    let out_dir = std::env::temp_dir().join(format!("bump-sticks-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).expect("temp dir");
    let png = out_dir.join("sticks.png");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_bump"))
            .arg("render")
            .arg(&pdb)
            .args(["--ligand", "TOP", "--size", "160x100", "-o"])
            .arg(&png)
            .args(extra)
            .output()
            .expect("run bump")
    };
    let ok = run(&["--sticks", "--hbonds"]);
    let text = String::from_utf8_lossy(&ok.stdout);
    assert!(
        ok.status.success(),
        "{text} {}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(text.contains("H-bonds"), "{text}");
    assert!(png.exists());
    let ok = run(&["--sticks", "7.5"]);
    assert!(ok.status.success());
    let bad = run(&["--sticks", "20"]);
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("--sticks must be between 2 and 12 Å, got 20"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&out_dir);
}
