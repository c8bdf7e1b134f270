//! The views of the fit per moved frame (issue 45): what colour by
//! contribution, the pocket in ball-and-stick with the hydrogen bonds, the
//! ghost of the reference pose and the clipping slab add to a frame in
//! which the drug moved, on the renderer's adapter (Mesa's CPU Vulkan where
//! there is no GPU).
//!
//! DHFR with trimethoprim (6xg5/TOP; the built-in scene without the
//! structures), offscreen at 640×360, the drug 2 Å off its crystal pose so
//! that its ghost shows. A moved frame is what the window does when the
//! drug moves: the session's step (with the live score), the view's updates
//! (the colours of the atoms whose contribution step changed, the pocket's
//! radii and bonds when its residues change, the H-bond dashes when they
//! do), then the frame drawn and read back. The CPU side is the same
//! without the frame: the step and the updates, submitted. The views are
//! measured in alternating rounds, each against the plain frame in the same
//! round, so that the machine's drift falls on all alike.

use super::timing::Progress;
use super::{Context, Part, Section};

/// The section.
pub const SECTION: Section = Section {
    name: "views",
    steps: |_| 1,
    run,
};

#[cfg(not(feature = "app"))]
fn run(_: &Context, _: &mut Progress) -> Part {
    Part::text(
        "## The views of the fit per moved frame\n\nNot in this run (built without the `app` feature).\n"
            .into(),
    )
}

#[cfg(feature = "app")]
fn run(ctx: &Context, progress: &mut Progress) -> Part {
    progress.step("views of the fit");
    match measure(ctx) {
        Ok(p) => p,
        Err(e) => Part::text(format!(
            "## The views of the fit per moved frame\n\nSkipped: {e}.\n"
        )),
    }
}

/// One view, as the window turns it on.
#[cfg(feature = "app")]
#[derive(Clone, Copy)]
struct View {
    name: &'static str,
    contribution: bool,
    sticks: bool,
    ghost: bool,
    slab: bool,
}

#[cfg(feature = "app")]
const VIEWS: [View; 6] = [
    View {
        name: "none (spheres, element colours)",
        contribution: false,
        sticks: false,
        ghost: false,
        slab: false,
    },
    View {
        name: "colour by contribution (U)",
        contribution: true,
        sticks: false,
        ghost: false,
        slab: false,
    },
    View {
        name: "pocket in ball-and-stick and H-bonds (P, N)",
        contribution: false,
        sticks: true,
        ghost: false,
        slab: false,
    },
    View {
        name: "ghost of the reference pose (Y)",
        contribution: false,
        sticks: false,
        ghost: true,
        slab: false,
    },
    View {
        name: "clipping slab (4)",
        contribution: false,
        sticks: false,
        ghost: false,
        slab: true,
    },
    View {
        name: "all of them",
        contribution: true,
        sticks: true,
        ghost: true,
        slab: true,
    },
];

/// Per view: frame times (ms), CPU-side times (µs), bytes uploaded.
#[cfg(feature = "app")]
#[derive(Default, Clone)]
struct Tally {
    frame_ms: Vec<f64>,
    cpu_us: Vec<f64>,
    bytes: u64,
    frames: u64,
}

#[cfg(feature = "app")]
use bump::render::{
    Gpu, ViewParams, contrib::ContributionColors, offscreen::Offscreen, sticks::StickView,
};
#[cfg(feature = "app")]
use bump::session::{Command, FrameInput, Session, Settings};

/// A 0.1 Å move of the drug along x (or any `dx`).
#[cfg(feature = "app")]
fn nudge(dx: f64) -> FrameInput {
    FrameInput::with_commands(&[Command::MoveBy {
        translate: glam::DVec3::new(dx, 0.0, 0.0),
        axis: glam::DVec3::Z,
        degrees: 0.0,
    }])
}

/// The session, its offscreen target and the views' state.
#[cfg(feature = "app")]
struct Rig {
    gpu: Gpu,
    session: Session,
    target: Offscreen,
    colors: ContributionColors,
    sticks: StickView,
    /// Moved frames so far (the move's sign alternates).
    k: u64,
}

#[cfg(feature = "app")]
impl Rig {
    /// One moved frame of view `v`: the step, the view's updates, and the
    /// frame drawn and read back when `draw` (else the writes submitted).
    fn frame(&mut self, v: &View, params: &ViewParams, draw: bool) -> Result<(), String> {
        self.k += 1;
        let dx = if self.k.is_multiple_of(2) { 0.1 } else { -0.1 };
        let out = self.session.step(&nudge(dx), 0.016);
        let score = out.score.as_deref();
        let (d, q) = (&self.gpu.device, &self.gpu.queue);
        if v.contribution && score.is_some() {
            let changes = self.colors.update(score);
            self.target.spheres.set_colors(q, &changes);
        }
        if v.sticks {
            let s = &mut self.target.spheres;
            let near = Some(bump::render::sticks::DEFAULT_DISTANCE);
            self.sticks.show_pocket(d, q, s, &self.session, near);
            if score.is_some() {
                self.sticks.show_hbonds(d, q, s, &self.session, score);
            }
        }
        if draw {
            self.target
                .render(&self.gpu, &self.session, params)
                .map_err(|e| e.to_string())?;
        } else {
            q.submit(std::iter::empty());
        }
        Ok(())
    }

    /// Turns view `v` off again, as the window does.
    fn off(&mut self, v: &View) {
        let (d, q) = (&self.gpu.device, &self.gpu.queue);
        if v.contribution {
            let changes = self.colors.update(None);
            self.target.spheres.set_colors(q, &changes);
        }
        if v.sticks {
            let s = &mut self.target.spheres;
            self.sticks.show_pocket(d, q, s, &self.session, None);
            self.sticks.show_hbonds(d, q, s, &self.session, None);
        }
    }
}

#[cfg(feature = "app")]
fn measure(ctx: &Context) -> Result<Part, String> {
    use std::time::Instant;

    use bump::model::{self, LigandSpec, LoadOptions, RadiiSet, builtin};
    use bump::render::ghost::Ghost;
    use bump::render::slab::Slab;

    use super::timing::median;

    let gpu = Gpu::headless().map_err(|e| format!("no graphics adapter ({e})"))?;
    let dhfr = ctx.data.as_ref().and_then(|d| {
        let loaded = model::load(&d.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default()).ok()?;
        let spec = LigandSpec::parse("TOP").ok()?;
        model::split_complex_owned(loaded.structure, &spec).ok()
    });
    let (scene, mols) = match dhfr {
        Some((r, d)) => ("DHFR with trimethoprim (6xg5/TOP)", vec![r, d]),
        None => {
            let (r, d) = builtin::scene(RadiiSet::Bondi);
            ("the built-in scene", vec![r, d])
        }
    };
    let mut session = Session::new(mols, Settings::default()).map_err(|e| e.to_string())?;
    session.enable_score();
    let (w, h) = (640, 360);
    let target = Offscreen::new(&gpu, &session, w, h).map_err(|e| e.to_string())?;
    session.step(&nudge(2.0), 0.016);
    let rounds = if ctx.queries < 100 { 1 } else { 15 };
    let per_round = if ctx.queries < 100 { 2 } else { 8 };
    let mut tallies = vec![Tally::default(); VIEWS.len()];
    let describe = gpu.describe();
    let mut rig = Rig {
        gpu,
        session,
        target,
        colors: ContributionColors::default(),
        sticks: StickView::default(),
        k: 0,
    };
    for _ in 0..rounds {
        for (v, tally) in VIEWS.iter().zip(&mut tallies) {
            let params = ViewParams {
                ghost: v.ghost.then(Ghost::default),
                slab: v.slab.then(Slab::default),
                aspect: f64::from(w) / f64::from(h),
                ..ViewParams::default()
            };
            // Turning the view on is not a moved frame's cost: one frame
            // first, untimed.
            rig.frame(v, &params, true)?;
            let before = rig.target.spheres.upload_stats();
            for _ in 0..per_round {
                let t0 = Instant::now();
                rig.frame(v, &params, true)?;
                tally.frame_ms.push(t0.elapsed().as_secs_f64() * 1e3);
                let t0 = Instant::now();
                rig.frame(v, &params, false)?;
                tally.cpu_us.push(t0.elapsed().as_secs_f64() * 1e6);
            }
            let after = rig.target.spheres.upload_stats();
            tally.bytes += (after.color_bytes - before.color_bytes)
                + (after.radius_bytes - before.radius_bytes)
                + (after.position_bytes - before.position_bytes)
                + (after.matrix_bytes - before.matrix_bytes)
                + (after.highlight_bytes - before.highlight_bytes);
            tally.frames += 2 * per_round as u64;
            rig.off(v);
        }
    }
    // A frame in which nothing moved: no score, nothing to redraw.
    let idle = rig.session.step(&FrameInput::default(), 0.016);
    let idle = if !idle.changed && idle.score.is_none() {
        "A frame in which nothing moved computes nothing and asks for no redraw (checked), views on \
         or off."
    } else {
        "**A frame in which nothing moved still computed something.**"
    };
    let base_ms = median(&tallies[0].frame_ms);
    let base_us = median(&tallies[0].cpu_us);
    let mut md = format!(
        "## The views of the fit per moved frame\n\n\
         {scene}, offscreen {w}×{h} on `{}`, the drug 2 Å off its crystal pose. A *moved frame* \
         is what the window does when the drug moves 0.1 Å: the session's step with the live \
         score, the view's updates (the colours of the atoms whose contribution step changed; \
         the pocket's radii and bonds when its residues change; the H-bond dashes when they \
         do), then the frame drawn and read back. *CPU side*: the step and the updates, \
         submitted, no frame drawn. {rounds} alternating rounds of {per_round} frames of each; \
         medians; *added* against the plain frame of the same run. *Bytes*: what the renderer \
         uploaded per moved frame (matrices, highlights, colours, radii, positions; the bonds \
         and dashes, which go to their own buffers when the pocket or the H-bonds change, are \
         not counted). The ghost and the slab change only what is drawn: their CPU-side \
         differences are the measurement's noise. {idle}\n\n\
         | view | moved frame ms | added ms | CPU side µs | added µs | bytes per moved frame |\n\
         | --- | ---: | ---: | ---: | ---: | ---: |\n",
        describe
    );
    let mut headline = Vec::new();
    for (v, t) in VIEWS.iter().zip(&tallies) {
        let ms = median(&t.frame_ms);
        let us = median(&t.cpu_us);
        md.push_str(&format!(
            "| {} | {ms:.1} | {:+.1} | {us:.0} | {:+.0} | {:.0} |\n",
            v.name,
            ms - base_ms,
            us - base_us,
            t.bytes as f64 / t.frames.max(1) as f64
        ));
        if v.name == "all of them" {
            headline.push(format!(
                "The views of the fit, all on, add {:.1} ms to a moved frame of {base_ms:.1} ms ({:+.0} µs on the CPU side), offscreen {w}×{h} on {}",
                ms - base_ms,
                us - base_us,
                describe
            ));
        }
    }
    Ok(Part {
        markdown: md,
        figures: Vec::new(),
        headline,
    })
}
