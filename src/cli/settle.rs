//! `bump settle`: minimises the drug's score over its position, orientation
//! and torsions from the file pose (optionally moved), never accepting a
//! step that collides or tunnels under the contact rule, and writes the
//! settled drug when asked.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use bump::model::write;
use bump::score::settle::{Collision, settled_molecule};
use bump::score::{
    Contacts, Energies, Evaluator, Exact, Field, MapField, SettleOptions, Workspace, energies,
    settle, torsion_divisor,
};
use clap::Args;
use serde::Serialize;

use super::report::{MoleculeReport, counted, molecule_report, print_molecules};
use super::score::{
    AtomId, ScoringArgs, build_maps, coulomb_energy, parse_evaluator, prepare_scene,
};

/// Arguments of `bump settle`.
#[derive(Debug, Args)]
pub struct SettleArgs {
    #[command(flatten)]
    pub common: ScoringArgs,
    /// Evaluator minimised: maps (as Vina's optimize; grid maps at 0.375 Å
    /// over the drug's box grown by 6 Å, exact outside it) or exact.
    #[arg(long, default_value = "maps", value_parser = parse_evaluator)]
    pub evaluator: Evaluator,
    /// Write the settled drug (with its bonds and hydrogens) to this file:
    /// SDF, PDB when the name ends in .pdb, PDBQT (with its torsion tree,
    /// for Vina) when it ends in .pdbqt and the drug was read from a PDBQT.
    #[arg(short = 'o', long = "output", value_name = "OUT.sdf")]
    pub output: Option<PathBuf>,
    /// Most minimisation steps.
    #[arg(long, default_value_t = SettleOptions::default().max_steps)]
    pub max_steps: usize,
}

#[derive(Debug, Serialize)]
struct EnergyReport {
    /// Vina's affinity: inter / (1 + w·N_tors) (kcal/mol).
    total: f64,
    inter: f64,
    intra: f64,
    /// Coulomb energy (kcal/mol), not part of `total`.
    coulomb: f64,
}

#[derive(Debug, Serialize)]
struct MinimisedReport {
    /// The energies at the start and the end (total, inter, intra).
    before: [f64; 3],
    after: [f64; 3],
}

#[derive(Debug, Serialize)]
struct CollisionReport {
    /// `receptor` or `drug` (two drug atoms).
    with: &'static str,
    a: AtomId,
    b: AtomId,
    distance: f64,
    contact: f64,
}

#[derive(Debug, Serialize)]
struct SettleReport {
    receptor: MoleculeReport,
    drug: MoleculeReport,
    scoring: &'static str,
    evaluator: &'static str,
    /// Vina's score at the start and at the end, exact (as `bump score`
    /// gives it), whichever evaluator settle minimised.
    before: EnergyReport,
    after: EnergyReport,
    /// With the maps: their energies at the start and the end, what settle
    /// minimised (they differ from the exact ones by the maps' error).
    minimised: Option<MinimisedReport>,
    /// Heavy-atom RMSD between the start and the settled drug (Å).
    rmsd: f64,
    rotatable_bonds: usize,
    /// Turn of each rotatable bond from its loaded angle (degrees).
    torsions_deg: Vec<f64>,
    steps: usize,
    evaluations: usize,
    /// Trials the contact rule refused.
    refused: usize,
    /// Time of the minimisation (µs), maps excluded.
    elapsed_us: f64,
    maps_build_ms: Option<f64>,
    start_collisions: Vec<CollisionReport>,
    end_collisions: Vec<CollisionReport>,
    output: Option<String>,
    warnings: Vec<String>,
}

fn energy_report(e: &Energies, divisor: f64, coulomb: f64) -> EnergyReport {
    EnergyReport {
        total: e.inter / divisor,
        inter: e.inter,
        intra: e.intra,
        coulomb,
    }
}

fn collision_reports(scene: &bump::scene::Scene, collisions: &[Collision]) -> Vec<CollisionReport> {
    collisions
        .iter()
        .map(|c| match *c {
            Collision::Receptor(p) => CollisionReport {
                with: "receptor",
                a: AtomId::of(&scene.drug, p.drug),
                b: AtomId::of(&scene.receptor, p.receptor),
                distance: f64::from(p.distance),
                contact: f64::from(p.contact),
            },
            Collision::Inner {
                a,
                b,
                distance,
                contact,
            } => CollisionReport {
                with: "drug",
                a: AtomId::of(&scene.drug, a),
                b: AtomId::of(&scene.drug, b),
                distance,
                contact,
            },
        })
        .collect()
}

/// Runs `bump settle`.
pub fn run(args: &SettleArgs) -> anyhow::Result<()> {
    let c = &args.common;
    let p = prepare_scene(c)?;
    let scene = &p.loaded.scene;
    let exact = Exact::new(&p.receptor, c.scoring);
    let judge = Exact::new(&p.receptor, c.scoring);
    let maps = match args.evaluator {
        Evaluator::Maps => Some(build_maps(&p.receptor, c.scoring, &p.lig, &p.start)?),
        Evaluator::Exact => None,
    };
    let field: Box<dyn Field + '_> = match &maps {
        Some((m, _)) => Box::new(MapField::new(m, exact)),
        None => Box::new(exact),
    };
    let mut contacts = Contacts::new(scene.collider(), scene.rule, &scene.drug, &p.lig);
    let opts = SettleOptions {
        max_steps: args.max_steps,
        ..SettleOptions::default()
    };
    let t0 = Instant::now();
    let s = settle(&*field, &p.lig, &mut contacts, &p.start, &opts);
    let elapsed_us = t0.elapsed().as_secs_f64() * 1e6;
    let divisor = torsion_divisor(p.lig.torsion_count);
    let mut ws = Workspace::default();
    let (exact_before, exact_after) = (
        energies(&judge, &p.lig, &p.start, &mut ws),
        energies(&judge, &p.lig, &s.conf, &mut ws),
    );
    let three = |e: &Energies| [e.inter / divisor, e.inter, e.intra];
    let output = match &args.output {
        Some(path) => {
            let mol = settled_molecule(&scene.drug, &p.lig, &s.conf.torsions);
            let pose = scene.world_from_relative(&s.conf.pose);
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase());
            match ext.as_deref() {
                Some("pdb") => write::write_pdb(&mol, &pose, path),
                Some("pdbqt") => write::write_pdbqt(&mol, &pose, path),
                _ => write::write_sdf(&mol, &pose, path),
            }
            .with_context(|| format!("writing the settled drug to {}", path.display()))?;
            Some(path.display().to_string())
        }
        None => None,
    };
    let report = SettleReport {
        receptor: molecule_report(&p.loaded.receptor_source, &scene.receptor),
        drug: molecule_report(&p.loaded.drug_source, &scene.drug),
        scoring: c.scoring.name(),
        evaluator: args.evaluator.name(),
        before: energy_report(
            &exact_before,
            divisor,
            coulomb_energy(&p.receptor, &p.lig, &p.start),
        ),
        after: energy_report(
            &exact_after,
            divisor,
            coulomb_energy(&p.receptor, &p.lig, &s.conf),
        ),
        minimised: maps.is_some().then(|| MinimisedReport {
            before: three(&s.before),
            after: three(&s.after),
        }),
        rmsd: s.rmsd,
        rotatable_bonds: p.lig.torsions(),
        torsions_deg: s.conf.torsions.iter().map(|t| t.to_degrees()).collect(),
        steps: s.steps,
        evaluations: s.evaluations,
        refused: s.refused,
        elapsed_us,
        maps_build_ms: maps.as_ref().map(|m| m.1),
        start_collisions: collision_reports(scene, &s.start_collisions),
        end_collisions: collision_reports(scene, &s.end_collisions),
        output,
        warnings: p.warnings.clone(),
    };
    if c.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print_molecules(&report.receptor, &report.drug);
    if !report.start_collisions.is_empty() {
        outln!(
            "the start collides ({}): pushed out before the contact rule applies",
            counted(report.start_collisions.len(), "pair")
        );
    }
    outln!(
        "{} score {:.3} -> {:.3} kcal/mol (inter {:.3} -> {:.3}, intra {:.3} -> {:.3}); coulomb {:.3} -> {:.3} (not in the score)",
        report.scoring,
        report.before.total,
        report.after.total,
        report.before.inter,
        report.after.inter,
        report.before.intra,
        report.after.intra,
        report.before.coulomb,
        report.after.coulomb
    );
    if let Some(m) = &report.minimised {
        outln!(
            "minimised on the maps: {:.3} -> {:.3} kcal/mol (the score above is exact, as `bump score` gives it)",
            m.before[0],
            m.after[0]
        );
    }
    outln!(
        "moved {:.3} Å RMSD in {} ({} evaluations, {} refused by the contact rule; {}), {:.0} µs{}",
        report.rmsd,
        counted(report.steps, "step"),
        report.evaluations,
        report.refused,
        counted(report.rotatable_bonds, "rotatable bond"),
        report.elapsed_us,
        report
            .maps_build_ms
            .map_or(String::new(), |ms| format!(" (maps built in {ms:.0} ms)"))
    );
    if !report.end_collisions.is_empty() {
        outln!(
            "still colliding at the end ({}): no way out was found",
            counted(report.end_collisions.len(), "pair")
        );
        for k in &report.end_collisions {
            outln!(
                "  drug {} with {} {}: {:.2} Å (contact {:.2} Å)",
                k.a.label(),
                k.with,
                k.b.label(),
                k.distance,
                k.contact
            );
        }
    }
    if let Some(o) = &report.output {
        outln!("wrote {o}");
    }
    Ok(())
}
