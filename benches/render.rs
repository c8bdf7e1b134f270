//! Frame time of the sphere-impostor renderer at 1280×720, offscreen, on
//! whatever adapter there is (Mesa's CPU Vulkan without a GPU): the first
//! 1k, 10k, 100k and all 272k atoms of the RYMV capsid assembly, and the
//! built-in scene. Each frame includes reading the image back to the CPU
//! (the window presents instead, which costs less).
//!
//! `idle_frame` measures a frame in which nothing changed: the session step
//! reports `changed == false`, so the window draws nothing at all.
//!
//! `cues_1280x720` measures each depth cue and stereo mode on DHFR with
//! trimethoprim (the built-in scene without ../shared/pdb), against mono
//! with no cue in the same run.
//!
//! `sticks_1280x720` measures a frame in which the drug moved (a session
//! step with the live score, then the frame) with the pocket in
//! ball-and-stick and the hydrogen bonds as dashed sticks, against the
//! same frame with both off, in the same run: the difference is what the
//! sticks add per moved frame (finding the pocket, uploading what changed,
//! drawing the cylinders).
//!
//! `fit_views_1280x720` measures a moved frame (the drug steps 0.1 Å,
//! the live score follows, the frame is drawn and read back) with the
//! ghost of the reference pose, the clipping slab, or both, against the
//! same frame without them in the same run.
//!
//! Run with `cargo bench --bench render` (only the cues:
//! `cargo bench --bench render -- cues_`; only the sticks:
//! `cargo bench --bench render -- sticks_`; the ghost and slab:
//! `cargo bench --bench render -- fit_views`).

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use bump::model::{self, LigandSpec, LoadOptions, Molecule, RadiiSet, builtin};
use bump::render::ghost::Ghost;
use bump::render::offscreen::Offscreen;
use bump::render::slab::Slab;
use bump::render::{Cues, Gpu, Stereo, StereoMode, ViewParams};
use bump::session::{FrameInput, Session, Settings};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

fn capsid() -> Option<Molecule> {
    let d = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    let loaded = model::load(&d.join("1f2n_assembly1.cif.gz"), &LoadOptions::default()).ok()?;
    model::receptor_only(&loaded.structure).ok()
}

fn prefix(m: &Molecule, n: usize) -> Molecule {
    let n = n.min(m.len());
    let pos: Vec<_> = (0..n).map(|i| m.file_position(i)).collect();
    Molecule::new(format!("{n} atoms"), m.atoms[..n].to_vec(), &pos)
}

fn frames(c: &mut Criterion) {
    let gpu = match Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("SKIP: no graphics adapter: {e}");
            return;
        }
    };
    eprintln!("adapter: {}", gpu.describe());
    let mut scenes: Vec<(String, Vec<Molecule>)> = Vec::new();
    let (r, d) = builtin::scene(RadiiSet::Bondi);
    scenes.push(("builtin-98".into(), vec![r, d]));
    match capsid() {
        Some(m) => {
            for n in [1_000, 10_000, 100_000, m.len()] {
                let p = prefix(&m, n);
                scenes.push((format!("{}", p.len()), vec![p]));
            }
        }
        None => eprintln!("SKIP: ../shared/pdb/1f2n_assembly1.cif.gz not readable"),
    }
    let mut g = c.benchmark_group("frame_1280x720");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (label, mols) in scenes {
        let Ok(session) = Session::new(mols, Settings::default()) else {
            continue;
        };
        let Ok(mut target) = Offscreen::new(&gpu, &session, 1280, 720) else {
            continue;
        };
        let params = ViewParams::default();
        g.bench_function(BenchmarkId::new("draw", &label), |b| {
            b.iter(|| black_box(target.render(&gpu, &session, &params)))
        });
        let mut s = session.clone();
        g.bench_function(BenchmarkId::new("idle_frame", &label), |b| {
            b.iter(|| {
                let out = s.step(&FrameInput::default(), 0.016);
                assert!(!out.changed, "an idle frame must not ask for a redraw");
                black_box(out)
            })
        });
    }
    g.finish();
}

fn dhfr() -> Option<Vec<Molecule>> {
    let d = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    let loaded = model::load(&d.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default()).ok()?;
    let spec = LigandSpec::parse("TOP").ok()?;
    let (r, d) = model::split_complex(&loaded.structure, &spec).ok()?;
    Some(vec![r, d])
}

fn cues_and_stereo(c: &mut Criterion) {
    let gpu = match Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("SKIP: no graphics adapter: {e}");
            return;
        }
    };
    let (label, mols) = match dhfr() {
        Some(m) => ("dhfr", m),
        None => {
            eprintln!("SKIP DHFR: ../shared/pdb not readable; using the built-in scene");
            let (r, d) = builtin::scene(RadiiSet::Bondi);
            ("builtin", vec![r, d])
        }
    };
    let Ok(session) = Session::new(mols, Settings::default()) else {
        return;
    };
    let Ok(mut target) = Offscreen::new(&gpu, &session, 1280, 720) else {
        return;
    };
    let cue = |list: &str| Cues::parse(list).unwrap_or(Cues::NONE);
    let mut cases: Vec<(String, ViewParams)> = Vec::new();
    for list in [
        "none",
        "depth",
        "outline",
        "ao",
        "shadow",
        "translucent",
        "depth,outline,ao,shadow,translucent",
    ] {
        cases.push((
            format!("mono_{}", list.replace(',', "+")),
            ViewParams {
                cues: cue(list),
                ..ViewParams::default()
            },
        ));
    }
    for mode in StereoMode::ALL.into_iter().skip(1) {
        cases.push((
            format!("{}_none", mode.name()),
            ViewParams {
                cues: Cues::NONE,
                stereo: Stereo {
                    mode,
                    ..Stereo::default()
                },
                ..ViewParams::default()
            },
        ));
    }
    let mut g = c.benchmark_group(format!("cues_1280x720_{label}"));
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (name, params) in cases {
        g.bench_function(BenchmarkId::new("frame", name), |b| {
            b.iter(|| black_box(target.render(&gpu, &session, &params)))
        });
    }
    g.finish();
}

fn sticks(c: &mut Criterion) {
    use bump::render::sticks::{DEFAULT_DISTANCE, StickView};
    use bump::session::Command;
    use glam::DVec3;
    let gpu = match Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("SKIP: no graphics adapter: {e}");
            return;
        }
    };
    let Some(mols) = dhfr() else {
        eprintln!("SKIP sticks: ../shared/pdb not readable");
        return;
    };
    let Ok(mut session) = Session::new(mols, Settings::default()) else {
        return;
    };
    session.enable_score();
    session.step(&FrameInput::default(), 0.0);
    let Ok(mut target) = Offscreen::new(&gpu, &session, 1280, 720) else {
        return;
    };
    let params = ViewParams::default();
    let mut g = c.benchmark_group("sticks_1280x720_dhfr");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for on in [false, true] {
        let mut view = StickView::default();
        let mut k = 0u64;
        let name = if on { "sticks+hbonds" } else { "spheres" };
        g.bench_function(BenchmarkId::new("moved_frame", name), |b| {
            b.iter(|| {
                // A small back-and-forth move of the drug: a moved frame.
                k += 1;
                let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
                let out = session.step(
                    &FrameInput::with_commands(&[Command::MoveBy {
                        translate: DVec3::new(0.05, 0.02, 0.0) * sign,
                        axis: DVec3::Z,
                        degrees: 0.0,
                    }]),
                    0.016,
                );
                if on {
                    let (d, q) = (&gpu.device, &gpu.queue);
                    let s = &mut target.spheres;
                    view.show_pocket(d, q, s, &session, Some(DEFAULT_DISTANCE));
                    view.show_hbonds(d, q, s, &session, out.score.as_deref());
                }
                black_box(target.render(&gpu, &session, &params))
            })
        });
        // The CPU side alone: the step, and with sticks the pocket and
        // the uploads, submitted (no frame drawn).
        g.bench_function(BenchmarkId::new("moved_step", name), |b| {
            b.iter(|| {
                k += 1;
                let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
                let out = session.step(
                    &FrameInput::with_commands(&[Command::MoveBy {
                        translate: DVec3::new(0.05, 0.02, 0.0) * sign,
                        axis: DVec3::Z,
                        degrees: 0.0,
                    }]),
                    0.016,
                );
                if on {
                    let (d, q) = (&gpu.device, &gpu.queue);
                    let s = &mut target.spheres;
                    view.show_pocket(d, q, s, &session, Some(DEFAULT_DISTANCE));
                    view.show_hbonds(d, q, s, &session, out.score.as_deref());
                }
                // The writes go to the GPU as a frame's would.
                gpu.queue.submit(std::iter::empty());
                black_box(out.changed)
            })
        });
        if on {
            view.show_pocket(&gpu.device, &gpu.queue, &mut target.spheres, &session, None);
            view.show_hbonds(&gpu.device, &gpu.queue, &mut target.spheres, &session, None);
        }
    }
    g.finish();
}

fn fit_views(c: &mut Criterion) {
    use bump::session::Command;
    use glam::DVec3;
    let gpu = match Gpu::headless() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("SKIP: no graphics adapter: {e}");
            return;
        }
    };
    let (label, mols) = match dhfr() {
        Some(m) => ("dhfr", m),
        None => {
            eprintln!("SKIP DHFR: ../shared/pdb not readable; using the built-in scene");
            let (r, d) = builtin::scene(RadiiSet::Bondi);
            ("builtin", vec![r, d])
        }
    };
    let Ok(mut session) = Session::new(mols, Settings::default()) else {
        return;
    };
    session.enable_score();
    let Ok(mut target) = Offscreen::new(&gpu, &session, 1280, 720) else {
        return;
    };
    // The drug off its crystal pose, so that its ghost shows.
    let nudge = |dx: f64| {
        FrameInput::with_commands(&[Command::MoveBy {
            translate: DVec3::new(dx, 0.0, 0.0),
            axis: DVec3::Z,
            degrees: 0.0,
        }])
    };
    session.step(&nudge(2.0), 0.016);
    let ghost = Some(Ghost::default());
    let slab = Some(Slab::default());
    let cases = [
        ("none", None, None),
        ("ghost", ghost, None),
        ("slab", None, slab),
        ("ghost+slab", ghost, slab),
    ];
    let mut g = c.benchmark_group(format!("fit_views_1280x720_{label}"));
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (name, ghost, slab) in cases {
        let params = ViewParams {
            ghost,
            slab,
            ..ViewParams::default()
        };
        let mut k = 0u64;
        g.bench_function(BenchmarkId::new("moved_frame", name), |b| {
            b.iter(|| {
                k += 1;
                let dx = if k.is_multiple_of(2) { 0.1 } else { -0.1 };
                let out = session.step(&nudge(dx), 0.016);
                assert!(
                    out.changed && out.score.is_some(),
                    "a moved frame is scored"
                );
                black_box(target.render(&gpu, &session, &params))
            })
        });
    }
    // A frame in which nothing moved computes nothing, views on or off.
    let out = session.step(&FrameInput::default(), 0.016);
    assert!(
        !out.changed && out.score.is_none(),
        "an idle frame computes nothing"
    );
    g.finish();
}

criterion_group!(benches, frames, cues_and_stereo, sticks, fit_views);
criterion_main!(benches);
