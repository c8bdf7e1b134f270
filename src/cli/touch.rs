//! `bump touch`: propose a motion from the (shifted) file pose and report how
//! much of it the collision response allows.

use anyhow::Context;
use bump::collide::sweep::MIN_TOLERANCE;
use bump::collide::{Method, Pair, Response, TouchOptions};
use bump::motion::Pose;
use bump::scene::Scene;
use clap::Args;
use glam::DVec3;
use serde::Serialize;

use super::report::{
    MoleculeReport, PairReport, RuleReport, counted, fraction, molecule_report, pair_report,
    pair_reports, print_pairs, rule_report,
};
use super::scene_args::{SceneArgs, Turn, parse_turn, parse_vec3, timed, within_range};
use bump::motion::pose::PoseSummary;

/// How far beyond contact the nearest-pair report looks first, in Å (the
/// grid's usual search; beyond it every pair is measured).
const NEAREST_WITHIN: f32 = 4.0;

/// Arguments of `bump touch`.
#[derive(Debug, Args)]
pub struct TouchArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Proposed translation of the drug's centre, DX,DY,DZ Å.
    #[arg(long = "move", value_name = "DX,DY,DZ", value_parser = parse_vec3, allow_hyphen_values = true)]
    translate: DVec3,
    /// Proposed turn about the drug's centre: axis AX,AY,AZ and degrees. The
    /// motion is the screw from the start pose to the turned end pose, so a
    /// turn goes the shorter way round: 270° runs as −90°, −180° as 180°, 360° is no turn.
    #[arg(long, value_name = "AX,AY,AZ,DEG", value_parser = parse_turn, allow_hyphen_values = true)]
    turn: Option<Turn>,
    /// Start at the file pose shifted by DX,DY,DZ Å.
    #[arg(long, value_name = "DX,DY,DZ", value_parser = parse_vec3, allow_hyphen_values = true)]
    start: Option<DVec3>,
    /// Collision response: touch, stop, slide, soft or pass.
    #[arg(long, default_value = "touch", value_parser = parse_response)]
    response: Response,
    /// Move-to-touch method: swept (never tunnels) or thesis (Turk's bisection).
    #[arg(long, default_value = "swept", value_parser = parse_method)]
    method: Method,
    /// Distance tolerance of the touch, Å (at least 1e-5: closer than that,
    /// f32 coordinates cannot tell touching from colliding; at most 1: the
    /// drug stops within it of contact, so a larger one stops it short).
    #[arg(long, default_value_t = 1e-3, allow_hyphen_values = true)]
    tolerance: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

fn parse_response(s: &str) -> Result<Response, String> {
    Response::parse(s)
        .ok_or_else(|| format!("unknown response `{s}` (stop, touch, slide, soft or pass)"))
}

fn parse_method(s: &str) -> Result<Method, String> {
    Method::parse(s).ok_or_else(|| format!("unknown method `{s}` (swept or thesis)"))
}

#[derive(Serialize)]
struct FinalPose {
    /// Where the drug's centre ends, in the receptor file's coordinates.
    #[serde(flatten)]
    pose: PoseSummary,
    /// How far the centre moved from the start.
    displacement: [f64; 3],
}

#[derive(Serialize)]
struct TouchReport {
    receptor: MoleculeReport,
    drug: MoleculeReport,
    rule: RuleReport,
    collider: &'static str,
    response: &'static str,
    method: &'static str,
    tolerance: f64,
    start_offset: [f64; 3],
    proposed_move: [f64; 3],
    proposed_turn_axis: [f64; 3],
    proposed_turn_deg: f64,
    start_collides: bool,
    start_clashes: Vec<PairReport>,
    t: f64,
    legs: usize,
    /// `stop` rejected the step: the drug stays at the start, and
    /// `contacts` are the pairs the step would have run into.
    step_rejected: bool,
    final_pose: FinalPose,
    contacts: Vec<PairReport>,
    colliding_at_end: Vec<PairReport>,
    min_gap: Option<f32>,
    nearest: Option<PairReport>,
    build_us: f64,
    elapsed_us: f64,
}

/// The pair nearest to contact with the drug at `pose` (relative to the
/// receptor): looked for within [`NEAREST_WITHIN`] of contact first (the
/// grid's usual search), else among every pair (a drug far from the
/// receptor: a ball that holds the whole receptor from every drug atom).
/// `None` only for an empty receptor or drug.
fn nearest_pair(scene: &Scene, pose: &Pose) -> Option<Pair> {
    let (collider, drug) = (scene.collider(), scene.drug_atoms());
    bump::collide::min_gap(collider, drug, pose, NEAREST_WITHIN).or_else(|| {
        let (lo, hi) = collider.bounds();
        let c = pose.translation;
        // The farthest any receptor atom's centre lies from any drug atom's,
        // plus the most the rule can take off a contact distance (an
        // overlap allowance beyond the two radii makes a gap exceed the
        // centres' distance).
        let corner = (c - lo.as_dvec3()).abs().max((hi.as_dvec3() - c).abs());
        let rule = &scene.rule;
        let allowance = f64::from(rule.overlap.max(0.0) + rule.hbond_allowance.max(0.0));
        let all = corner.length() + drug.extent + allowance + 1.0;
        bump::collide::min_gap(collider, drug, pose, all as f32)
    })
}

/// Says how a turn of more than half a revolution will run.
fn warn_long_turn(turn: &Turn) {
    let degrees = turn.degrees;
    if degrees.abs() <= 180.0 {
        return;
    }
    let runs = turn.shorter_way();
    let degrees = bump::text::short_number(degrees);
    if runs == 0.0 {
        eprintln!(
            "bump: warning: --turn of {degrees}° is whole turns: the drug ends as it starts, so the step is only the move"
        );
    } else {
        eprintln!(
            "bump: warning: --turn of {degrees}° runs the shorter way round, as {runs}°; split a longer turn into steps of at most 180°"
        );
    }
}

/// Largest `--tolerance`, Å: a touch stops within the tolerance of contact,
/// and one larger than the N/O allowance would stop well short of it.
const MAX_TOLERANCE: f64 = 1.0;

/// Runs `bump touch`.
pub fn run(args: &TouchArgs) -> anyhow::Result<()> {
    if !args.tolerance.is_finite() || args.tolerance <= 0.0 {
        anyhow::bail!(
            "--tolerance must be a positive number of Å, got {}",
            bump::text::short_number(args.tolerance)
        );
    }
    if args.tolerance > MAX_TOLERANCE {
        anyhow::bail!(
            "--tolerance must be at most {MAX_TOLERANCE} Å, got {}: the drug stops within the \
             tolerance of contact, so a larger one stops it short of touching",
            // Exponent form for a huge value, not a few hundred digits.
            bump::text::short_number(args.tolerance)
        );
    }
    let loaded = args.scene.load()?;
    let scene = &loaded.scene;
    let offset = args.start.unwrap_or(DVec3::ZERO);
    let turn = args.turn.unwrap_or(Turn::NONE);
    warn_long_turn(&turn);
    let start = scene.file_relative(offset);
    let end = start.moved(args.translate, turn.axis, turn.radians());
    within_range(scene, "--start", &start)?;
    within_range(scene, "--move", &end)?;
    let tolerance = args.tolerance.max(MIN_TOLERANCE);
    if tolerance > args.tolerance {
        eprintln!(
            "bump: warning: --tolerance {} raised to {MIN_TOLERANCE:e} Å: f32 coordinates cannot tell touching from colliding closer than that",
            bump::text::short_number(args.tolerance)
        );
    }
    let opts = TouchOptions {
        tolerance,
        method: args.method,
    };
    let (r, us) =
        timed(5, || scene.respond(&start, &end, args.response, &opts)).context("move-to-touch")?;
    let world = scene.world_from_relative(&r.pose);
    let nearest = nearest_pair(scene, &r.pose);
    let rep = |p| pair_reports(&scene.rule, &scene.receptor, &scene.drug, p);
    let report = TouchReport {
        receptor: molecule_report(&loaded.receptor_source, &scene.receptor),
        drug: molecule_report(&loaded.drug_source, &scene.drug),
        rule: rule_report(&args.scene, &scene.rule),
        collider: scene.collider().kind().name(),
        response: args.response.name(),
        method: args.method.name(),
        tolerance,
        start_offset: offset.to_array(),
        proposed_move: args.translate.to_array(),
        proposed_turn_axis: turn.axis.to_array(),
        proposed_turn_deg: turn.degrees,
        start_collides: !r.start_colliding.is_empty(),
        start_clashes: rep(&r.start_colliding),
        t: r.t,
        legs: r.legs,
        step_rejected: args.response == Response::Stop && r.t < 1.0,
        final_pose: FinalPose {
            pose: world.summary(),
            displacement: (r.pose.translation - start.translation).to_array(),
        },
        contacts: rep(&r.contacts),
        colliding_at_end: rep(&r.colliding),
        min_gap: nearest.map(|p| p.gap()),
        nearest: nearest.map(|p| pair_report(&scene.rule, &scene.receptor, &scene.drug, &p)),
        build_us: loaded.build_us,
        elapsed_us: us,
    };
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    outln!(
        "receptor {} ({}), drug {} ({}); collider {}, response {}, method {}",
        report.receptor.name,
        counted(report.receptor.atoms, "atom"),
        report.drug.name,
        counted(report.drug.atoms, "atom"),
        report.collider,
        report.response,
        report.method
    );
    if report.start_collides {
        let allowed = if args.response == Response::Pass {
            "pass lets the drug move anyway"
        } else {
            "only motions that do not deepen them are allowed"
        };
        outln!(
            "WARNING: the start pose already collides ({}); {allowed}:",
            counted(report.start_clashes.len(), "pair")
        );
        print_pairs(&report.start_clashes);
    }
    let f = &report.final_pose;
    let of = if args.response == Response::Slide {
        let d = |v: [f64; 3]| DVec3::from_array(v).length();
        format!(
            "of its first leg; {} moved the centre {:.4} of the {:.4} Å proposed",
            counted(report.legs, "leg"),
            d(f.displacement),
            d(report.proposed_move)
        )
    } else {
        "of the motion".to_string()
    };
    outln!(
        "t = {} {of} ({:.1} µs)\nfinal centre ({:.4}, {:.4}, {:.4}), moved ({:.4}, {:.4}, {:.4}); rotation {:.3}° about ({:.3}, {:.3}, {:.3})",
        fraction(report.t),
        report.elapsed_us,
        f.pose.centre[0],
        f.pose.centre[1],
        f.pose.centre[2],
        f.displacement[0],
        f.displacement[1],
        f.displacement[2],
        f.pose.angle_deg,
        f.pose.axis[0],
        f.pose.axis[1],
        f.pose.axis[2]
    );
    match report.min_gap {
        Some(g) => outln!("smallest gap {g:.4} Å"),
        None => outln!("no pair of atoms (an empty molecule)"),
    }
    let pairs = counted(report.contacts.len(), "pair");
    if report.step_rejected {
        outln!(
            "the step was rejected (stop); it would have run into {pairs} (gap <= {} Å):",
            report.tolerance
        );
    } else {
        outln!("{pairs} in contact (gap <= {} Å):", report.tolerance);
    }
    print_pairs(&report.contacts);
    if !report.colliding_at_end.is_empty() {
        match report.colliding_at_end.len() {
            1 => outln!("1 pair collides at the final pose"),
            n => outln!("{n} pairs collide at the final pose"),
        }
    }
    Ok(())
}
