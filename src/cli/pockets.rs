//! `bump pockets`: the receptor's candidate binding pockets, ranked, each
//! with its centre, docking box, volume, buriedness and lining residues
//! ([`bump::pocket`]).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use bump::model::{self, LigandSpec, LoadOptions, Molecule, RadiiSet, receptor_only_owned};
use bump::pocket::{Pocket, PocketOptions, find_pockets};
use clap::Args;
use serde::Serialize;

use super::scene_args::{parse_byte_size, parse_radii};

/// Arguments of `bump pockets`.
#[derive(Debug, Args)]
pub struct PocketsArgs {
    /// Receptor file (PDB, mmCIF, PDBQT, optionally .gz).
    pub receptor: PathBuf,
    /// Leave this hetero residue out (RESNAME, RESNAME:CHAIN:SEQ or auto), as
    /// for a complex whose ligand is to be found again; each pocket then says
    /// whether one of its atoms lies within 4 Å of the pocket's centre.
    #[arg(long)]
    pub ligand: Option<String>,
    /// Most pockets listed.
    #[arg(long, default_value_t = 10)]
    pub max: usize,
    /// Radius table: bondi or thesis.
    #[arg(long, default_value = "bondi", value_parser = parse_radii)]
    pub radii: RadiiSet,
    /// Most bytes a gzipped file may decompress to.
    #[arg(long, value_name = "SIZE", value_parser = parse_byte_size)]
    pub max_decompressed: Option<u64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Serialize)]
struct PocketReport {
    rank: usize,
    score: f64,
    center: [f64; 3],
    box_center: [f64; 3],
    box_size: [f64; 3],
    /// Å³.
    volume: f64,
    /// Mean fraction of rays from its points that hit the receptor.
    buriedness: f64,
    residues: Vec<String>,
    points: usize,
    /// With --ligand: the left-out ligand's nearest heavy atom to the
    /// centre (Å).
    ligand_distance: Option<f64>,
}

#[derive(Debug, Serialize)]
struct PocketsReport {
    receptor: String,
    atoms: usize,
    ligand: Option<String>,
    elapsed_ms: f64,
    pockets: Vec<PocketReport>,
}

/// Loads the receptor, without the `--ligand` residue when given.
pub fn load_receptor(
    path: &std::path::Path,
    ligand: Option<&str>,
    radii: RadiiSet,
    max_decompressed: Option<u64>,
) -> anyhow::Result<(Molecule, Option<Molecule>)> {
    let opts = LoadOptions {
        radii,
        decompressed_limit: max_decompressed,
        ..LoadOptions::default()
    };
    let loaded = model::load(path, &opts)?;
    for w in &loaded.warnings {
        eprintln!("bump: warning: {w}");
    }
    match ligand {
        Some(text) => {
            let spec =
                LigandSpec::parse(text).map_err(|e| anyhow::anyhow!("--ligand {text}: {e}"))?;
            let (r, d) = model::split_complex_owned(loaded.structure, &spec)?;
            Ok((r, Some(d)))
        }
        None => Ok((receptor_only_owned(loaded.structure)?, None)),
    }
}

fn report(p: &Pocket, ligand: Option<&Molecule>) -> PocketReport {
    let arr = |v: glam::DVec3| [v.x, v.y, v.z];
    PocketReport {
        rank: p.rank,
        score: p.score,
        center: arr(p.centre),
        box_center: arr(p.dock_box.centre),
        box_size: arr(p.dock_box.size),
        volume: p.volume,
        buriedness: p.buriedness,
        residues: p.residues.iter().map(|r| r.label()).collect(),
        points: p.points.len(),
        ligand_distance: ligand.map(|l| {
            l.file_positions()
                .iter()
                .map(|q| (*q - p.centre).length())
                .fold(f64::INFINITY, f64::min)
        }),
    }
}

/// Runs `bump pockets`.
pub fn run(args: &PocketsArgs) -> anyhow::Result<()> {
    let (receptor, ligand) = load_receptor(
        &args.receptor,
        args.ligand.as_deref(),
        args.radii,
        args.max_decompressed,
    )?;
    let opts = PocketOptions {
        max_pockets: args.max,
        ..PocketOptions::default()
    };
    let t0 = Instant::now();
    let pockets = find_pockets(&receptor, &opts)
        .with_context(|| format!("{}: pockets", args.receptor.display()))?;
    let elapsed_ms = t0.elapsed().as_secs_f64() * 1e3;
    let out = PocketsReport {
        receptor: args.receptor.display().to_string(),
        atoms: receptor.len(),
        ligand: ligand.as_ref().map(|l| l.name.clone()),
        elapsed_ms,
        pockets: pockets.iter().map(|p| report(p, ligand.as_ref())).collect(),
    };
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    outln!(
        "{}: {} atoms, {} pocket{} in {:.0} ms",
        out.receptor,
        out.atoms,
        out.pockets.len(),
        if out.pockets.len() == 1 { "" } else { "s" },
        out.elapsed_ms
    );
    outln!(
        "rank  score  volume Å³  buried  centre                      box                  residues"
    );
    for p in &out.pockets {
        let mut residues = p
            .residues
            .iter()
            .take(8)
            .cloned()
            .collect::<Vec<_>>()
            .join(" ");
        if p.residues.len() > 8 {
            residues.push_str(&format!(" … ({} in all)", p.residues.len()));
        }
        outln!(
            "{:>4} {:>6.1} {:>10.0} {:>7.2}  {:>8.3},{:>8.3},{:>8.3}  {:>4.1}x{:>4.1}x{:>4.1}  {}{}",
            p.rank,
            p.score,
            p.volume,
            p.buriedness,
            p.center[0],
            p.center[1],
            p.center[2],
            p.box_size[0],
            p.box_size[1],
            p.box_size[2],
            residues,
            p.ligand_distance
                .map_or(String::new(), |d| format!("  (ligand {d:.1} Å)"))
        );
    }
    Ok(())
}
