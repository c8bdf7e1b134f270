//! Skip what a scene doesn't need: what a session step costs and does when
//! nothing moves, when only the camera moves, when the drug moves with
//! collision off and on, when it pushes against a contact, and what the
//! renderer uploads when the drug moves.
//!
//! A frame "asks for a redraw" when [`FrameOutcome::changed`] is set (the
//! window draws nothing otherwise); a collision query ran when
//! [`FrameOutcome::collision_us`] is `Some`.

use std::time::Instant;

use bump::model::{self, LigandSpec, LoadOptions, Molecule, RadiiSet, builtin};
use bump::session::{Command, FrameInput, FrameOutcome, Session, Settings};
use glam::DVec3;

use super::timing::{Progress, median};
use super::{Context, Part, Section};

/// Frames per measured behaviour.
fn frames(ctx: &Context) -> usize {
    if ctx.quick { 2_000 } else { 20_000 }
}

/// What `n` frames of one behaviour did and cost.
struct Tally {
    label: &'static str,
    frames: usize,
    redraws: usize,
    queries: usize,
    moved: usize,
    /// Median of per-batch mean step times, µs.
    step_us: f64,
}

/// Steps `s` through `n` frames of `input(k)`, timing batches of 100.
fn tally(
    label: &'static str,
    s: &mut Session,
    n: usize,
    input: impl Fn(usize) -> FrameInput,
) -> Tally {
    let mut t = Tally {
        label,
        frames: n,
        redraws: 0,
        queries: 0,
        moved: 0,
        step_us: 0.0,
    };
    let inputs: Vec<FrameInput> = (0..n).map(&input).collect();
    let mut batches = Vec::new();
    for chunk in inputs.chunks(100) {
        let t0 = Instant::now();
        let outs: Vec<FrameOutcome> = chunk.iter().map(|f| s.step(f, 0.016)).collect();
        batches.push(t0.elapsed().as_secs_f64() * 1e6 / chunk.len() as f64);
        for o in outs {
            t.redraws += usize::from(o.changed);
            t.queries += usize::from(o.collision_us.is_some());
            t.moved += usize::from(o.moved);
        }
    }
    t.step_us = median(&batches);
    t
}

/// A small back-and-forth wiggle of the drug (it stays where it is on average).
fn wiggle(k: usize) -> FrameInput {
    let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
    FrameInput::nudged(
        DVec3::new(0.01, 0.005, 0.0) * sign,
        DVec3::new(0.0, 0.0, 1e-3) * sign,
    )
}

fn scenes(ctx: &Context) -> Vec<(String, Vec<Molecule>)> {
    let (r, e) = builtin::scene(RadiiSet::Bondi);
    let mut v = vec![("built-in rings + E (98 atoms)".to_string(), vec![r, e])];
    if let Some(dir) = &ctx.data {
        let parts = model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default())
            .ok()
            .and_then(|l| {
                let spec = LigandSpec::parse("TOP").ok()?;
                model::split_complex(&l.structure, &spec).ok()
            });
        if let Some((r, d)) = parts {
            v.push((
                format!("DHFR + trimethoprim ({} atoms)", r.len() + d.len()),
                vec![r, d],
            ));
        }
    }
    v
}

/// The section.
pub const SECTION: Section = Section {
    name: "frames",
    steps,
    run,
};

/// Number of progress steps [`run`] takes.
fn steps(ctx: &Context) -> usize {
    scenes(ctx).len() + 1
}

/// Measures every behaviour on each scene, then the renderer's uploads.
fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let n = frames(ctx);
    let mut md = String::from("## Skip what a scene doesn't need\n\n");
    md.push_str(&format!(
        "Session steps (`Session::step`, the code the window runs each frame), {n} frames per row, \
         step time = median over batches of 100 frames. *Redraws*: frames whose outcome says \
         something visible changed (the window draws nothing otherwise). *Queries*: frames in \
         which a collision query ran.\n\n\
         | scene | frames | redraws | collision queries | drug moved | time per step |\n\
         | --- | --- | ---: | ---: | ---: | ---: |\n"
    ));
    let mut headline = Vec::new();
    for (name, mols) in scenes(ctx) {
        progress.step(&format!("session frames: {name}"));
        let Ok(base) = Session::new(mols, Settings::default()) else {
            continue;
        };
        let mut rows = Vec::new();
        // Collision off (the default), view mode.
        let mut s = base.clone();
        rows.push(tally("idle, collision off", &mut s, n, |_| {
            FrameInput::default()
        }));
        s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
        rows.push(tally("drug moving, collision off", &mut s, n, wiggle));
        // Collision on.
        let mut s = base.clone();
        s.step(&FrameInput::with_commands(&[Command::ToggleCollision]), 0.0);
        // Frames from here on, once the collider's clearance map (built on
        // its own thread) is there: the rows time every frame after the
        // first second or so, not the map's build.
        s.wait_for_collider();
        rows.push(tally("idle, collision on", &mut s, n, |_| {
            FrameInput::default()
        }));
        rows.push(tally(
            "camera moving (view mode), collision on",
            &mut s,
            n,
            wiggle,
        ));
        s.step(&FrameInput::with_commands(&[Command::ToggleMode]), 0.0);
        rows.push(tally("drug moving, collision on", &mut s, n, wiggle));
        let sel = s.selected();
        rows.push(tally(
            "re-selecting the selected molecule, collision on",
            &mut s,
            n.min(2000),
            |_| FrameInput::with_commands(&[Command::Select(sel)]),
        ));
        // Push the drug into its receptor until it is blocked, then keep pushing.
        let dir = {
            let b = s.bodies();
            (b[0].pose.translation - b[1].pose.translation).normalize_or(DVec3::X)
        };
        for _ in 0..2000 {
            s.step(&FrameInput::nudged(dir * 0.05, DVec3::ZERO), 0.016);
        }
        rows.push(tally(
            "pushing into a contact (blocked), collision on",
            &mut s,
            n,
            |_| FrameInput::nudged(dir * 0.05, DVec3::ZERO),
        ));
        for r in &rows {
            md.push_str(&format!(
                "| {name} | {} | {} | {} | {} | {} |\n",
                r.label,
                r.redraws,
                r.queries,
                r.moved,
                if r.step_us < 1.0 {
                    format!("{:.0} ns", r.step_us * 1e3)
                } else {
                    format!("{:.2} µs", r.step_us)
                }
            ));
        }
        let get = |l: &str| rows.iter().find(|r| r.label == l);
        if let (Some(idle), Some(off), Some(on)) = (
            get("idle, collision on"),
            get("drug moving, collision off"),
            get("drug moving, collision on"),
        ) {
            headline.push(format!(
                "{name}: an idle frame costs {:.0} ns with {} redraws and {} collision queries in {} frames; moving the drug costs {:.2} µs a frame with collision on ({} queries / {} frames) and {:.0} ns with it off ({} queries)",
                idle.step_us * 1e3,
                idle.redraws,
                idle.queries,
                idle.frames,
                on.step_us,
                on.queries,
                on.frames,
                off.step_us * 1e3,
                off.queries
            ));
        }
    }
    md.push_str(
        "\nRe-selecting the selected molecule (a click on one of its atoms) keeps its \
         environment's collider. Idle frames and frames blocked against a contact ask for no \
         redraw; idle frames and camera moves run no collision query; with collision off no \
         query runs at all.\n",
    );
    progress.step("renderer uploads");
    md.push_str(&uploads(&mut headline));
    Part {
        markdown: md,
        figures: Vec::new(),
        headline,
    }
}

/// Without the shell (`--no-default-features`) there is no renderer.
#[cfg(not(feature = "app"))]
fn uploads(_: &mut Vec<String>) -> String {
    "\nRenderer uploads: not in this run (built without the `app` feature).\n".into()
}

/// Bytes the sphere renderer uploads while the drug moves (offscreen, 64×64).
#[cfg(feature = "app")]
fn uploads(headline: &mut Vec<String>) -> String {
    use bump::render::offscreen::Offscreen;
    use bump::render::{Gpu, ViewParams};
    let gpu = match Gpu::headless() {
        Ok(g) => g,
        Err(e) => return format!("\nRenderer uploads: skipped, no graphics adapter ({e}).\n"),
    };
    let (r, e) = builtin::scene(RadiiSet::Bondi);
    let Ok(mut s) = Session::new(vec![r, e], Settings::default()) else {
        return String::new();
    };
    let Ok(mut off) = Offscreen::new(&gpu, &s, 64, 64) else {
        return "\nRenderer uploads: skipped, cannot create an offscreen target.\n".into();
    };
    let params = ViewParams::default();
    if off.render(&gpu, &s, &params).is_err() {
        return "\nRenderer uploads: skipped, rendering failed.\n".into();
    }
    let created = off.spheres.upload_stats();
    s.step(&FrameInput::docking(), 0.0);
    let frames = 100;
    let mut drawn = 0;
    for k in 0..frames {
        // Towards the rings and back: contacts begin and end on the way.
        let z = if k < frames / 2 { 0.6 } else { -0.6 };
        let out = s.step(
            &FrameInput::nudged(DVec3::new(0.0, 0.1, z), DVec3::ZERO),
            0.016,
        );
        off.spheres
            .apply_highlights(&gpu.queue, &out.highlight_changes);
        if out.changed && off.render(&gpu, &s, &params).is_ok() {
            drawn += 1;
        }
    }
    let after = off.spheres.upload_stats();
    let per = |a: u64, b: u64| (b - a) as f64 / f64::from(drawn.max(1));
    headline.push(format!(
        "Moving the drug uploads {} bytes of atom data ({} frames drawn); {:.0} bytes of matrices and {:.1} bytes of highlight words per frame",
        after.atom_bytes - created.atom_bytes,
        drawn,
        per(created.matrix_bytes, after.matrix_bytes),
        per(created.highlight_bytes, after.highlight_bytes)
    ));
    format!(
        "\nRenderer uploads (`UploadStats`, built-in scene on `{}`): atom data {} bytes once at \
         creation; over {drawn} frames of the E moving towards the rings and back (collision on) \
         {} more bytes of atom data, {:.0} bytes of matrices per frame (one 64-byte matrix per \
         molecule plus the 96-byte frame uniform) and {:.1} bytes of highlight words per frame \
         (only words whose atoms' highlight levels changed).\n",
        gpu.describe(),
        created.atom_bytes,
        after.atom_bytes - created.atom_bytes,
        per(created.matrix_bytes, after.matrix_bytes),
        per(created.highlight_bytes, after.highlight_bytes)
    )
}
