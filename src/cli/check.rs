//! `bump check`: the colliding pairs at the file pose, optionally moved.

use anyhow::Context;
use clap::Args;
use glam::DVec3;
use serde::Serialize;

use super::report::{
    MoleculeReport, PairReport, RuleReport, counted, molecule_report, pair_reports,
    print_molecules, print_pairs, rule_report,
};
use super::scene_args::{SceneArgs, Turn, parse_turn, parse_vec3, placed, timed};

/// Arguments of `bump check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Move the drug's centre by DX,DY,DZ Å first.
    #[arg(long = "move", value_name = "DX,DY,DZ", value_parser = parse_vec3, allow_hyphen_values = true)]
    translate: Option<DVec3>,
    /// Turn the drug about its centre first: axis AX,AY,AZ and degrees.
    #[arg(long, value_name = "AX,AY,AZ,DEG", value_parser = parse_turn, allow_hyphen_values = true)]
    turn: Option<Turn>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct CheckReport {
    receptor: MoleculeReport,
    drug: MoleculeReport,
    rule: RuleReport,
    collider: &'static str,
    moved: [f64; 3],
    turn_axis: [f64; 3],
    turn_deg: f64,
    build_us: f64,
    elapsed_us: f64,
    clash_count: usize,
    clashes: Vec<PairReport>,
}

/// Runs `bump check`.
pub fn run(args: &CheckArgs) -> anyhow::Result<()> {
    let loaded = args.scene.load()?;
    let scene = &loaded.scene;
    let offset = args.translate.unwrap_or(DVec3::ZERO);
    let turn = args.turn.unwrap_or(Turn::NONE);
    let rel = placed(scene, args.translate, args.turn)?;
    let (pairs, us) = timed(5, || scene.check(&rel)).context("static check")?;
    let report = CheckReport {
        receptor: molecule_report(&loaded.receptor_source, &scene.receptor),
        drug: molecule_report(&loaded.drug_source, &scene.drug),
        rule: rule_report(&args.scene, &scene.rule),
        collider: scene.collider().kind().name(),
        moved: offset.to_array(),
        turn_axis: turn.axis.to_array(),
        turn_deg: turn.degrees,
        build_us: loaded.build_us,
        elapsed_us: us,
        clash_count: pairs.len(),
        clashes: pair_reports(&scene.rule, &scene.receptor, &scene.drug, &pairs),
    };
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print_molecules(&report.receptor, &report.drug);
    outln!(
        "rule: overlap >= {} Å (+{} Å for N/O pairs), {} radii, hydrogens {}; collider {}",
        report.rule.overlap,
        report.rule.hbond_allowance,
        report.rule.radii,
        report.rule.hydrogens,
        report.collider
    );
    outln!(
        "{} ({:.1} µs; collider built in {:.0} µs)",
        counted(report.clash_count, "colliding pair"),
        report.elapsed_us,
        report.build_us
    );
    print_pairs(&report.clashes);
    Ok(())
}
