//! `bump score`: AutoDock Vina's (or Vinardo's) score of the drug at the
//! file pose, optionally moved: the total, the inter- and intramolecular
//! energies, the terms, the hydrogen bonds and each drug atom's share, with
//! the Coulomb energy beside it (never part of it).
//!
//! The scoring's preparation (typing, torsion tree, maps) lives here too:
//! `bump settle` shares it.

use std::time::Instant;

use anyhow::Context;
use bump::model::Molecule;
use bump::scene::Scene;
use bump::score::coulomb;
use bump::score::maps::{DEFAULT_SPACING, MapBox, Maps};
use bump::score::{
    Conformation, Evaluator, Exact, Field, Ligand, MapField, Receptor, Score, Scoring, Workspace,
    energies, prepare, score,
};
use clap::Args;
use glam::DVec3;
use serde::Serialize;

use super::report::{MoleculeReport, counted, molecule_report, print_molecules};
use super::scene_args::{LoadedScene, SceneArgs, Turn, parse_turn, parse_vec3, placed};

/// Å added around the drug on every side for the maps' box.
pub const MAP_MARGIN: f64 = 6.0;

/// Receptor chemistry warnings printed before the rest are counted.
const RECEPTOR_WARNINGS_SHOWN: usize = 10;

/// Where the drug starts and how it is scored: the options `score` and
/// `settle` share.
#[derive(Debug, Args)]
pub struct ScoringArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Move the drug's centre by DX,DY,DZ Å first.
    #[arg(long = "move", value_name = "DX,DY,DZ", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub translate: Option<DVec3>,
    /// Turn the drug about its centre first: axis AX,AY,AZ and degrees.
    #[arg(long, value_name = "AX,AY,AZ,DEG", value_parser = parse_turn, allow_hyphen_values = true)]
    pub turn: Option<Turn>,
    /// Scoring function: vina or vinardo.
    #[arg(long, default_value = "vina", value_parser = parse_scoring)]
    pub scoring: Scoring,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `bump score`.
#[derive(Debug, Args)]
pub struct ScoreArgs {
    #[command(flatten)]
    pub common: ScoringArgs,
    /// Evaluator of the totals: exact (pairs within 8 Å) or maps (grid maps
    /// at 0.375 Å over the drug's box grown by 6 Å, built first). The terms
    /// and hydrogen bonds always come from the exact pairs.
    #[arg(long, default_value = "exact", value_parser = parse_evaluator)]
    pub evaluator: Evaluator,
}

fn parse_scoring(s: &str) -> Result<Scoring, String> {
    Scoring::parse(s).ok_or_else(|| format!("unknown scoring `{s}` (vina or vinardo)"))
}

/// Parses `exact` or `maps`.
pub fn parse_evaluator(s: &str) -> Result<Evaluator, String> {
    Evaluator::parse(s).ok_or_else(|| format!("unknown evaluator `{s}` (exact or maps)"))
}

/// The scene with the scoring's typed atoms and the drug's start.
pub struct Prepared {
    /// The loaded scene.
    pub loaded: LoadedScene,
    /// The receptor's typed atoms.
    pub receptor: Receptor,
    /// The drug's typed atoms and torsion tree.
    pub lig: Ligand,
    /// The drug's start: its file pose, moved and turned.
    pub start: Conformation,
    /// The drug's chemistry warnings (atoms it could not perceive).
    pub warnings: Vec<String>,
}

/// Loads the scene, types both molecules (printing what the chemistry
/// could not perceive to stderr) and poses the drug as `--move`/`--turn`
/// say.
pub fn prepare_scene(args: &ScoringArgs) -> anyhow::Result<Prepared> {
    let loaded = args.scene.load()?;
    let scene = &loaded.scene;
    let rel = placed(scene, args.translate, args.turn)?;
    let rec_warnings = &scene.receptor.chemistry().warnings;
    for w in rec_warnings.iter().take(RECEPTOR_WARNINGS_SHOWN) {
        eprintln!("bump: warning: receptor chemistry: {w}");
    }
    if rec_warnings.len() > RECEPTOR_WARNINGS_SHOWN {
        eprintln!(
            "bump: warning: receptor chemistry: {} more",
            rec_warnings.len() - RECEPTOR_WARNINGS_SHOWN
        );
    }
    let warnings = scene.drug.chemistry().warnings.clone();
    for w in &warnings {
        eprintln!("bump: warning: drug chemistry: {w}");
    }
    let receptor = prepare::receptor(&scene.receptor);
    let lig = prepare::ligand(&scene.drug)
        .with_context(|| format!("{}: the drug's torsion tree", loaded.drug_source))?;
    let start = lig.rigid(rel);
    Ok(Prepared {
        loaded,
        receptor,
        lig,
        start,
        warnings,
    })
}

/// Builds maps for the drug's types over its box at `conf` grown by
/// [`MAP_MARGIN`], on the machine's threads; returns them with the build
/// time in ms.
pub fn build_maps(
    receptor: &Receptor,
    scoring: Scoring,
    lig: &Ligand,
    conf: &Conformation,
) -> anyhow::Result<(Maps, f64)> {
    let bx = MapBox::around(&lig.place(conf), MAP_MARGIN, DEFAULT_SPACING);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let t0 = Instant::now();
    let maps = Maps::build(receptor, scoring, &lig.xs, &bx, threads).context("grid maps")?;
    Ok((maps, t0.elapsed().as_secs_f64() * 1e3))
}

/// One term's sums.
#[derive(Debug, Serialize)]
struct TermReport {
    name: &'static str,
    weight: f64,
    /// Weighted intermolecular sum (kcal/mol).
    inter: f64,
    /// Unweighted intermolecular sum.
    inter_raw: f64,
    /// Weighted intramolecular sum (kcal/mol).
    intra: f64,
}

/// A drug or receptor atom as reports name it.
#[derive(Debug, Serialize)]
pub struct AtomId {
    pub serial: i64,
    pub name: String,
    pub element: String,
    pub residue: String,
    pub chain: String,
    pub seq: i64,
}

impl AtomId {
    /// Atom `i` of `m` (an empty identity if out of range).
    pub fn of(m: &Molecule, i: u32) -> Self {
        m.atoms.get(i as usize).map_or(
            Self {
                serial: 0,
                name: String::new(),
                element: String::new(),
                residue: String::new(),
                chain: String::new(),
                seq: 0,
            },
            |a| Self {
                serial: a.serial,
                name: a.name.to_string(),
                element: a.element.to_string(),
                residue: a.residue.to_string(),
                chain: a.chain.to_string(),
                seq: a.seq,
            },
        )
    }

    /// `chain/residue seq name #serial`, or `residue name #serial`.
    pub fn label(&self) -> String {
        if self.chain.is_empty() {
            format!("{} {} #{}", self.residue, self.name, self.serial)
        } else {
            format!(
                "{}/{}{} {} #{}",
                self.chain, self.residue, self.seq, self.name, self.serial
            )
        }
    }
}

#[derive(Debug, Serialize)]
struct HBondReport {
    /// `drug`, `receptor` or `either` (both atoms donate and accept).
    donor_side: &'static str,
    donor: AtomId,
    acceptor: AtomId,
    distance: f64,
    /// The pair's weighted H-bond term (kcal/mol).
    energy: f64,
}

#[derive(Debug, Serialize)]
struct AtomReport {
    serial: i64,
    name: String,
    element: String,
    /// Vina's X-Score type; null for an atom the chemistry could not type
    /// (not scored).
    vina_type: Option<&'static str>,
    /// Its share of `inter` (kcal/mol).
    contribution: f64,
}

#[derive(Debug, Serialize)]
struct ScoreReport {
    receptor: MoleculeReport,
    drug: MoleculeReport,
    scoring: &'static str,
    evaluator: &'static str,
    /// Vina's affinity: inter / (1 + w·N_tors) (kcal/mol).
    total: f64,
    /// Intermolecular energy before the torsion division.
    inter: f64,
    intra: f64,
    /// Weighted intermolecular terms by name (kcal/mol).
    terms: serde_json::Map<String, serde_json::Value>,
    term_details: Vec<TermReport>,
    rotatable_bonds: usize,
    /// Vina's torsion count N_tors.
    torsion_count: f64,
    hbonds: Vec<HBondReport>,
    atoms: Vec<AtomReport>,
    /// Coulomb energy with Gasteiger charges and AutoDock 4's dielectric
    /// (kcal/mol, unweighted), never part of `total`.
    coulomb: f64,
    /// Time of one evaluation of the totals by the evaluator (median, µs).
    elapsed_us: f64,
    /// Time to build the maps (ms), for the maps evaluator.
    maps_build_ms: Option<f64>,
    moved: [f64; 3],
    turn_axis: [f64; 3],
    turn_deg: f64,
    warnings: Vec<String>,
}

/// The Coulomb energy of the drug at `conf`.
pub fn coulomb_energy(receptor: &Receptor, lig: &Ligand, conf: &Conformation) -> f64 {
    let mut g = Vec::new();
    coulomb::energy(receptor, &lig.place(conf), &lig.charges, None, &mut g)
}

/// Runs `bump score`.
pub fn run(args: &ScoreArgs) -> anyhow::Result<()> {
    let c = &args.common;
    let p = prepare_scene(c)?;
    let exact = Exact::new(&p.receptor, c.scoring);
    let maps = match args.evaluator {
        Evaluator::Maps => Some(build_maps(&p.receptor, c.scoring, &p.lig, &p.start)?),
        Evaluator::Exact => None,
    };
    let field: Box<dyn Field + '_> = match &maps {
        Some((m, _)) => Box::new(MapField::new(m, exact)),
        None => Box::new(exact),
    };
    let mut ws = Workspace::default();
    let (_, us) = super::scene_args::timed(101, || energies(&*field, &p.lig, &p.start, &mut ws))?;
    let s = score(&*field, args.evaluator, &exact, &p.lig, &p.start);
    let scene = &p.loaded.scene;
    let atoms = atom_reports(&scene.drug, &s);
    let hbonds = hbond_reports(scene, &s);
    let turn = c.turn.unwrap_or(Turn::NONE);
    let report = ScoreReport {
        receptor: molecule_report(&p.loaded.receptor_source, &scene.receptor),
        drug: molecule_report(&p.loaded.drug_source, &scene.drug),
        scoring: c.scoring.name(),
        evaluator: args.evaluator.name(),
        total: s.total,
        inter: s.inter,
        intra: s.intra,
        terms: s
            .terms
            .iter()
            .map(|t| (t.name.to_string(), serde_json::Value::from(t.inter)))
            .collect(),
        term_details: s
            .terms
            .iter()
            .map(|t| TermReport {
                name: t.name,
                weight: t.weight,
                inter: t.inter,
                inter_raw: t.inter_raw,
                intra: t.intra,
            })
            .collect(),
        rotatable_bonds: p.lig.torsions(),
        torsion_count: p.lig.torsion_count,
        hbonds,
        atoms,
        coulomb: coulomb_energy(&p.receptor, &p.lig, &p.start),
        elapsed_us: us,
        maps_build_ms: maps.as_ref().map(|m| m.1),
        moved: c.translate.unwrap_or(DVec3::ZERO).to_array(),
        turn_axis: turn.axis.to_array(),
        turn_deg: turn.degrees,
        warnings: p.warnings.clone(),
    };
    if c.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print_report(&report);
    Ok(())
}

/// Each drug atom with its Vina type (where it has one) and its share of
/// the intermolecular score.
fn atom_reports(drug: &Molecule, s: &Score) -> Vec<AtomReport> {
    let share: std::collections::HashMap<u32, (&'static str, f64)> = s
        .atoms
        .iter()
        .map(|a| (a.atom, (a.xs.name(), a.inter)))
        .collect();
    (0..drug.len() as u32)
        .map(|i| {
            let id = AtomId::of(drug, i);
            let (t, e) = share.get(&i).map_or((None, 0.0), |&(t, e)| (Some(t), e));
            AtomReport {
                serial: id.serial,
                name: id.name,
                element: id.element,
                vina_type: t,
                contribution: e,
            }
        })
        .collect()
}

/// The score's hydrogen bonds, each with its donor and acceptor named.
fn hbond_reports(scene: &Scene, s: &Score) -> Vec<HBondReport> {
    s.hbonds
        .iter()
        .map(|h| {
            let (d, r) = (
                AtomId::of(&scene.drug, h.drug_atom),
                AtomId::of(&scene.receptor, h.receptor_atom),
            );
            let (side, donor, acceptor) = match h.donor {
                bump::score::Donor::Drug => ("drug", d, r),
                bump::score::Donor::Receptor => ("receptor", r, d),
                bump::score::Donor::Either => ("either", d, r),
            };
            HBondReport {
                donor_side: side,
                donor,
                acceptor,
                distance: h.distance,
                energy: h.energy,
            }
        })
        .collect()
}

/// Writes the report as text: the molecules, the score with its terms,
/// the hydrogen bonds and each atom's contribution.
fn print_report(report: &ScoreReport) {
    print_molecules(&report.receptor, &report.drug);
    outln!(
        "{} score {:.3} kcal/mol (inter {:.3}, intra {:.3}; {}, N_tors {}; {} evaluator, {:.2} µs{})",
        report.scoring,
        report.total,
        report.inter,
        report.intra,
        counted(report.rotatable_bonds, "rotatable bond"),
        report.torsion_count,
        report.evaluator,
        report.elapsed_us,
        report
            .maps_build_ms
            .map_or(String::new(), |ms| format!("; maps built in {ms:.0} ms"))
    );
    outln!(
        "coulomb {:.3} kcal/mol (Gasteiger charges, or a PDBQT's own; AutoDock 4 dielectric; not in the score)",
        report.coulomb
    );
    outln!("terms (weighted, intermolecular / intramolecular):");
    for t in &report.term_details {
        outln!("  {:<12} {:>10.4} {:>10.4}", t.name, t.inter, t.intra);
    }
    outln!("{}:", counted(report.hbonds.len(), "hydrogen bond"));
    for h in &report.hbonds {
        outln!(
            "  donor {} -> acceptor {}  {:.2} Å  {:.3} kcal/mol{}",
            h.donor.label(),
            h.acceptor.label(),
            h.distance,
            h.energy,
            if h.donor_side == "either" {
                " (either way)"
            } else {
                ""
            }
        );
    }
    outln!("atoms (serial name element type contribution):");
    for a in &report.atoms {
        outln!(
            "  {:>6} {:<5} {:<2} {:<5} {:>8.4}",
            a.serial,
            a.name,
            a.element,
            a.vina_type.unwrap_or("-"),
            a.contribution
        );
    }
}
