//! `bump render`: the scene drawn offscreen to a PNG, for figures and tests.

use std::path::PathBuf;

use anyhow::bail;
use bump::render::contrib::ContributionColors;
use bump::render::ghost::Ghost;
use bump::render::offscreen::{Offscreen, save_png};
use bump::render::slab::{MAX_THICKNESS, MIN_THICKNESS, Slab};
use bump::render::sticks::{self, DISTANCE_RANGE, StickView};
use bump::render::{Cues, Gpu, Stereo, StereoMode, ViewParams};
use bump::session::{Command, FrameInput, Session, Settings};
use clap::Args;
use glam::DVec3;

use super::scene_args::{SceneArgs, Turn, parse_f32, parse_turn, parse_vec3, within_range};
use bump::text::short_number;

/// Arguments of `bump render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output PNG file.
    #[arg(short, long)]
    output: PathBuf,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// Move the drug's centre by DX,DY,DZ Å first.
    #[arg(long = "move", value_name = "DX,DY,DZ", value_parser = parse_vec3, allow_hyphen_values = true)]
    translate: Option<DVec3>,
    /// Turn the drug about its centre first: axis AX,AY,AZ and degrees.
    #[arg(long, value_name = "AX,AY,AZ,DEG", value_parser = parse_turn, allow_hyphen_values = true)]
    turn: Option<Turn>,
    /// Turn the view: screen axis AX,AY,AZ (x right, y up, z out) and degrees.
    #[arg(long, value_name = "AX,AY,AZ,DEG", value_parser = parse_turn, allow_hyphen_values = true)]
    view_turn: Option<Turn>,
    /// Zoom factor (2 = twice as close).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    zoom: f64,
    /// Direction towards the light, view space X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    light: Option<DVec3>,
    /// Do not highlight the atoms in contact.
    #[arg(long)]
    no_contacts: bool,
    /// Depth cues, comma-separated: depth, outline, ao, shadow, translucent; or none.
    #[arg(long, default_value = "depth", value_parser = Cues::parse)]
    cue: Cues,
    /// Depth-cueing strength, 0..1 (how far the farthest atoms fade).
    #[arg(long, default_value = "0.6", value_parser = parse_f32, allow_negative_numbers = true)]
    depth_strength: f32,
    /// Stereo mode: mono, side-by-side, side-by-side-half, top-bottom,
    /// top-bottom-half, rows, columns, anaglyph, frame-sequential.
    #[arg(long, default_value = "mono", value_parser = parse_stereo)]
    stereo: StereoMode,
    /// Eye separation as a fraction of the convergence distance.
    #[arg(long, default_value_t = 0.03, allow_negative_numbers = true)]
    eye_sep: f64,
    /// Convergence distance as a fraction of the distance to the view centre.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    convergence: f64,
    /// Swap the eyes.
    #[arg(long)]
    swap_eyes: bool,
    /// Frame number (frame-sequential stereo: even frames show the left eye).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    frame: u64,
    /// Atom colours: `element`, or `contribution` (the drug's atoms and the
    /// receptor's within 8 Å by their Vina contribution: blue helps, white
    /// neutral, red hurts).
    #[arg(long, default_value = "element", value_parser = ["element", "contribution"])]
    color: String,
    /// Draw the drug's file pose as a translucent ghost (the drug itself
    /// stands where `--move`/`--turn` put it).
    #[arg(long)]
    ghost: bool,
    /// Clip to a slab THICKNESS Å thick (default 10) through the drug's
    /// centre, facing the eye.
    #[arg(long, value_name = "THICKNESS", num_args = 0..=1, default_missing_value = "10", value_parser = parse_slab)]
    slab: Option<Slab>,
    /// Ball-and-stick for the drug and the receptor's residues within DIST
    /// Å of it (2 to 12, default 5), with their bonds as sticks.
    #[arg(long, value_name = "DIST", num_args = 0..=1, default_missing_value = "5")]
    sticks: Option<f64>,
    /// Draw the hydrogen bonds the Vina score counts, as dashed sticks
    /// (with the pocket in ball-and-stick: they lie inside full spheres).
    #[arg(long)]
    hbonds: bool,
}

fn parse_slab(s: &str) -> Result<Slab, String> {
    let t: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}`: the slab's thickness is a number of Å"))?;
    if !(t.is_finite() && (MIN_THICKNESS..=MAX_THICKNESS).contains(&t)) {
        return Err(format!(
            "`{s}`: the slab's thickness runs from {MIN_THICKNESS} to {MAX_THICKNESS} Å"
        ));
    }
    Ok(Slab::new(t))
}

fn parse_stereo(s: &str) -> Result<StereoMode, String> {
    StereoMode::parse(s).ok_or_else(|| {
        let names: Vec<&str> = StereoMode::ALL.iter().map(|m| m.name()).collect();
        format!("`{s}`: use one of {}", names.join(", "))
    })
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}`: expected WIDTHxHEIGHT, e.g. 1280x720"))?;
    let w: u32 = w.trim().parse().map_err(|e| format!("`{s}`: width: {e}"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|e| format!("`{s}`: height: {e}"))?;
    if !(1..=8192).contains(&w) || !(1..=8192).contains(&h) {
        return Err(format!("`{s}`: sizes run from 1x1 to 8192x8192"));
    }
    Ok((w, h))
}

/// Runs `bump render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    if !(args.zoom.is_finite() && args.zoom > 0.0) {
        bail!(
            "--zoom must be a positive number, got {}",
            short_number(args.zoom)
        );
    }
    if !(args.eye_sep.is_finite() && (0.0..=1.0).contains(&args.eye_sep)) {
        bail!(
            "--eye-sep must be between 0 and 1, got {}",
            short_number(args.eye_sep)
        );
    }
    if !(args.convergence.is_finite() && args.convergence > 0.0) {
        bail!(
            "--convergence must be a positive number, got {}",
            short_number(args.convergence)
        );
    }
    if !(0.0..=1.0).contains(&args.depth_strength) {
        bail!(
            "--depth-strength must be between 0 and 1, got {}",
            args.depth_strength
        );
    }
    let loaded = args.scene.load()?;
    let turn = args.turn.unwrap_or(Turn::NONE);
    // The same range check as `check` and `touch`: a pose the session
    // would refuse to move to is refused here, not drawn unmoved.
    let moved = loaded.scene.file_relative(DVec3::ZERO).moved(
        args.translate.unwrap_or(DVec3::ZERO),
        turn.axis,
        turn.radians(),
    );
    within_range(&loaded.scene, "--move", &moved)?;
    let settings = Settings {
        rule: loaded.scene.rule,
        collider: args.scene.collider,
        ..Settings::default()
    };
    let molecules = vec![loaded.scene.receptor.clone(), loaded.scene.drug.clone()];
    let mut session = Session::new(molecules, settings)?;
    if let Some(d) = args.sticks
        && !DISTANCE_RANGE.contains(&d)
    {
        bail!(
            "--sticks must be between {} and {} Å, got {}",
            DISTANCE_RANGE.start(),
            DISTANCE_RANGE.end(),
            short_number(d)
        );
    }
    let by_contribution = args.color == "contribution";
    if by_contribution || args.hbonds {
        session.enable_score();
    }
    let mut commands = Vec::new();
    if args.translate.is_some() || args.turn.is_some() {
        commands.push(Command::MoveBy {
            translate: args.translate.unwrap_or(DVec3::ZERO),
            axis: turn.axis,
            degrees: turn.shorter_way(),
        });
    }
    if !args.no_contacts {
        commands.push(Command::ToggleCollision);
    }
    let out = session.step(
        &FrameInput {
            commands,
            ..FrameInput::default()
        },
        0.0,
    );
    if let Some(v) = args.view_turn {
        let axis = v.axis.normalize_or(DVec3::Y);
        session
            .camera_mut()
            .move_scene(DVec3::ZERO, axis * v.radians());
    }
    session.camera_mut().distance /= args.zoom;
    let gpu = Gpu::headless()?;
    let mut params = ViewParams {
        cues: Cues {
            depth_strength: args.depth_strength,
            ..args.cue
        },
        stereo: Stereo {
            mode: args.stereo,
            separation: args.eye_sep,
            convergence: args.convergence,
            swap: args.swap_eyes,
        },
        frame: args.frame,
        ghost: args.ghost.then(Ghost::default),
        slab: args.slab,
        ..ViewParams::default()
    };
    if let Some(l) = args.light {
        params.light = l;
    }
    let (w, h) = args.size;
    let mut target = Offscreen::new(&gpu, &session, w, h)?;
    let score = session.live_score().cloned();
    if by_contribution {
        let Some(s) = &score else {
            bail!("--color contribution needs a drug and a receptor to score");
        };
        let changes = ContributionColors::default().update(Some(s));
        target.spheres.set_colors(&gpu.queue, &changes);
    }
    let mut view = StickView::default();
    let pocket = args
        .sticks
        .or(args.hbonds.then_some(sticks::DEFAULT_DISTANCE));
    view.show_pocket(
        &gpu.device,
        &gpu.queue,
        &mut target.spheres,
        &session,
        pocket,
    );
    if args.hbonds {
        let Some(s) = &score else {
            bail!("--hbonds needs a drug and a receptor to score");
        };
        view.show_hbonds(
            &gpu.device,
            &gpu.queue,
            &mut target.spheres,
            &session,
            Some(s),
        );
    }
    let image = target.render(&gpu, &session, &params)?;
    save_png(&image, &args.output)?;
    if let Some(s) = &score {
        outln!(
            "Vina score {:.3} kcal/mol (inter {:.3}), {} H-bonds",
            s.score.total,
            s.score.inter,
            s.score.hbonds.len()
        );
    }
    outln!(
        "wrote {} ({w}x{h}, {} atoms, {} in contact) with {}",
        args.output.display(),
        session
            .bodies()
            .iter()
            .map(|b| b.molecule.len())
            .sum::<usize>(),
        out.contacts.len(),
        gpu.describe()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_size;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("12").is_err());
    }
}
