//! `bump dock`: the global docking search ([`bump::dock`]) in a box from a
//! reference ligand, from numbers or from a ranked pocket; each molecule of
//! a multi-molecule SDF in turn (or every N-th, `--shard`), with a progress
//! bar; poses written as SDF (bond orders and hydrogens as read, scores as
//! SD tags) or PDBQT (Vina's models), and reported as JSON or a table.
//!
//! Output files are written whole at the end (a temporary file, then a
//! rename); Ctrl+C stops the molecule in progress and writes the ones
//! finished.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, bail};
use bump::chem::symmetry::{heavy_swaps, rmsd_over};
use bump::dock::{DockError, DockOptions, DockedPose, Target, box_maps, dock_on, output, validate};
use bump::model::{self, LoadOptions, Molecule, receptor_only, write};
use bump::pocket::{DockBox, PocketOptions, find_pockets};
use bump::score::{Contacts, Evaluator, Exact, Ligand, Maps, prepare, score};
use clap::Args;
use glam::DVec3;
use serde::Serialize;

use super::scene_args::{SceneArgs, parse_vec3};

/// Arguments of `bump dock`.
#[derive(Debug, Args)]
pub struct DockArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The box: a reference ligand's heavy atoms plus --pad on every side,
    /// at least --min-size along each axis.
    #[arg(long, value_name = "REF")]
    pub box_from: Option<PathBuf>,
    /// Å added round the reference ligand.
    #[arg(long, default_value_t = 5.0)]
    pub pad: f64,
    /// Shortest box edge from --box-from (Å).
    #[arg(long, default_value_t = 20.0)]
    pub min_size: f64,
    /// The box's centre (file coordinates), with --size.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub center: Option<DVec3>,
    /// The box's edges (Å), with --center.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3)]
    pub size: Option<DVec3>,
    /// The box of the K-th ranked pocket (`bump pockets`); the default
    /// when no other box is given is the first.
    #[arg(long, value_name = "K")]
    pub pocket: Option<usize>,
    /// Independent Monte Carlo chains (as Vina's).
    #[arg(long, default_value_t = 8)]
    pub exhaustiveness: usize,
    /// Threads (0: every core).
    #[arg(long, default_value_t = 0)]
    pub cpu: usize,
    /// The search's seed: the same seed gives the same poses, whatever the
    /// thread count.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Most poses per molecule.
    #[arg(long, default_value_t = 9)]
    pub poses: usize,
    /// Search round the drug's pose in its file (within --radius of its
    /// centre) instead of from random starts over the whole box.
    #[arg(long)]
    pub from_pose: bool,
    /// With --from-pose: how far (Å) the drug's centre may start from its
    /// pose; the box is the drug's extent plus this, unless one is given.
    #[arg(long, default_value_t = 4.0)]
    pub radius: f64,
    /// Scales the search's step count (1 = the default search).
    #[arg(long, default_value_t = 1.0)]
    pub effort: f64,
    /// Docks every N-th molecule of the file starting at the K-th (K from
    /// 0 to N−1), so that a job array spreads a library over machines.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Write the poses: SDF (scores as SD tags), or PDBQT when the name ends
    /// in .pdbqt (a PDBQT drug's models with Vina's result lines).
    #[arg(short = 'o', long = "output", value_name = "OUT.sdf")]
    pub output: Option<PathBuf>,
    /// Report each pose's heavy-atom RMSD to this file's (symmetry-aware;
    /// the same heavy atoms in the same order).
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("`{s}`: expected K/N"))?;
    let k: usize = k
        .trim()
        .parse()
        .map_err(|_| format!("`{s}`: K is not a whole number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("`{s}`: N is not a whole number"))?;
    if n == 0 || k >= n {
        return Err(format!("`{s}`: need 0 <= K < N"));
    }
    Ok((k, n))
}

#[derive(Debug, Serialize)]
struct HBondOut {
    drug_atom: String,
    receptor_atom: String,
    donor: &'static str,
    distance: f64,
    energy: f64,
}

#[derive(Debug, Serialize)]
struct PoseOut {
    rank: usize,
    total: f64,
    inter: f64,
    intra: f64,
    terms: serde_json::Map<String, serde_json::Value>,
    hbonds: Vec<HBondOut>,
    collides: bool,
    rmsd_to_reference: Option<f64>,
    center: [f64; 3],
    torsions_deg: Vec<f64>,
}

#[derive(Debug, Serialize)]
struct MoleculeOut {
    /// 1-based record in the drug file.
    record: usize,
    name: String,
    atoms: usize,
    rotatable_bonds: usize,
    elapsed_s: f64,
    evaluations: u64,
    refined: usize,
    dropped_colliding: usize,
    maps_mb: f64,
    poses: Vec<PoseOut>,
}

#[derive(Debug, Serialize)]
struct BoxOut {
    center: [f64; 3],
    size: [f64; 3],
    from: String,
}

#[derive(Debug, Serialize)]
struct DockOut {
    receptor: String,
    ligand: String,
    #[serde(rename = "box")]
    dock_box: BoxOut,
    seed: u64,
    exhaustiveness: usize,
    threads: usize,
    elapsed_s: f64,
    evaluations: u64,
    molecules: Vec<MoleculeOut>,
    interrupted: bool,
    output: Option<String>,
}

/// The box the options name, and where it came from.
fn resolve_box(
    args: &DockArgs,
    receptor: &Molecule,
    drug: &Molecule,
) -> anyhow::Result<(DockBox, String)> {
    let named = [
        args.box_from.is_some(),
        args.center.is_some() || args.size.is_some(),
        args.pocket.is_some(),
    ]
    .iter()
    .filter(|b| **b)
    .count();
    if named > 1 {
        bail!("give one box: --box-from, --center with --size, or --pocket");
    }
    for (name, v) in [
        ("--pad", args.pad),
        ("--min-size", args.min_size),
        ("--radius", args.radius),
    ] {
        if !(0.0..=100.0).contains(&v) {
            bail!("{name} {v}: expected 0 to 100 Å");
        }
    }
    if let Some(path) = &args.box_from {
        let m = model::load(path, &LoadOptions::default())?;
        let mol = receptor_only(&m.structure)?;
        let b = DockBox::around(&mol.file_positions(), args.pad, args.min_size)
            .with_context(|| format!("{}: no atoms for the box", path.display()))?;
        return Ok((b, format!("{} + {} Å", path.display(), args.pad)));
    }
    match (args.center, args.size) {
        (Some(c), Some(s)) => {
            return Ok((DockBox { centre: c, size: s }, "--center/--size".into()));
        }
        (Some(_), None) | (None, Some(_)) => bail!("--center and --size go together"),
        (None, None) => {}
    }
    if args.from_pose && args.pocket.is_none() {
        let b = DockBox::around(&drug.file_positions(), args.radius, 0.0)
            .context("the drug has no atoms")?;
        return Ok((b, format!("the drug's pose + {} Å", args.radius)));
    }
    let k = args.pocket.unwrap_or(1);
    if k == 0 {
        bail!("--pocket 0: pockets are ranked from 1");
    }
    let pockets = find_pockets(receptor, &PocketOptions::default())?;
    let Some(p) = pockets.get(k - 1) else {
        bail!(
            "--pocket {k}: the receptor has {} pocket{}",
            pockets.len(),
            if pockets.len() == 1 { "" } else { "s" }
        );
    };
    if args.pocket.is_none() {
        eprintln!(
            "bump: no box given: docking in the top-ranked pocket (centre {:.2},{:.2},{:.2}; `bump pockets` lists them)",
            p.centre.x, p.centre.y, p.centre.z
        );
    }
    Ok((p.dock_box, format!("pocket {k}")))
}

/// The heavy atoms of `path` in file coordinates, checked against the drug:
/// the whole file, or, for a complex, the `--ligand` residue split from it.
fn reference_atoms(
    path: &Path,
    drug: &Molecule,
    ligand: Option<&str>,
) -> anyhow::Result<Vec<DVec3>> {
    let m = model::load(path, &LoadOptions::default())?;
    let whole = receptor_only(&m.structure)?;
    let r = match ligand {
        Some(text) if whole.len() != drug.len() => {
            let spec = model::LigandSpec::parse(text)
                .map_err(|e| anyhow::anyhow!("--ligand {text}: {e}"))?;
            model::split_complex_owned(m.structure, &spec)?.1
        }
        _ => whole,
    };
    let same = r.len() == drug.len()
        && r.atoms
            .iter()
            .zip(&drug.atoms)
            .all(|(a, b)| a.element.eq_ignore_ascii_case(&b.element));
    if !same {
        bail!(
            "{}: its {} heavy atoms are not the ligand's {} in the same order",
            path.display(),
            r.len(),
            drug.len()
        );
    }
    Ok(r.file_positions())
}

fn pose_out(
    p: &DockedPose,
    contacts: &mut Contacts<'_>,
    lig: &Ligand,
    exact: &Exact<'_>,
    receptor: &Molecule,
    drug: &Molecule,
    reference: Option<&(Vec<DVec3>, Vec<Vec<u32>>)>,
) -> PoseOut {
    let centre = receptor.centre;
    let s = score(exact, Evaluator::Exact, exact, lig, &p.conf);
    let name = |m: &Molecule, i: u32| {
        m.atoms.get(i as usize).map_or(String::new(), |a| {
            format!("{}{} {}", a.residue, a.seq, a.name)
        })
    };
    let world: Vec<DVec3> = p.atoms.iter().map(|a| *a + centre).collect();
    PoseOut {
        rank: p.rank,
        total: p.total,
        inter: p.energies.inter,
        intra: p.energies.intra,
        terms: s
            .terms
            .iter()
            .map(|t| (t.name.to_string(), serde_json::json!(t.inter)))
            .collect(),
        hbonds: s
            .hbonds
            .iter()
            .map(|h| HBondOut {
                drug_atom: name(drug, h.drug_atom),
                receptor_atom: name(receptor, h.receptor_atom),
                donor: match h.donor {
                    bump::score::Donor::Drug => "drug",
                    bump::score::Donor::Receptor => "receptor",
                    bump::score::Donor::Either => "either",
                },
                distance: h.distance,
                energy: h.energy,
            })
            .collect(),
        collides: !contacts.collisions(&p.atoms).is_empty(),
        rmsd_to_reference: reference.map(|(r, swaps)| rmsd_over(swaps, r, &world)),
        center: (p.conf.pose.translation + centre).to_array(),
        torsions_deg: p.conf.torsions.iter().map(|t| t.to_degrees()).collect(),
    }
}

/// Runs `bump dock`.
pub fn run(args: &DockArgs) -> anyhow::Result<()> {
    let t_all = Instant::now();
    let loaded = args.scene.load()?;
    let scene = &loaded.scene;
    let receptor_typed = prepare::receptor(&scene.receptor);
    let (dock_box, box_from) = resolve_box(args, &scene.receptor, &scene.drug)?;
    let target = Target {
        receptor: &receptor_typed,
        collider: scene.collider(),
        rule: scene.rule,
        receptor_centre: scene.receptor.centre,
    };
    let exact = Exact::new(&receptor_typed, bump::score::Scoring::Vina);
    // The records to dock: a multi-molecule SDF is a library.
    let drug_path = args.scene.drug.clone();
    let is_sdf = drug_path.as_ref().is_some_and(|p| {
        let l = p.to_string_lossy().to_ascii_lowercase();
        let l = l.strip_suffix(".gz").unwrap_or(&l).to_string();
        l.ends_with(".sdf") || l.ends_with(".sd")
    });
    // Each molecule is named by its record's title, as SDF readers show it.
    let titles = match &drug_path {
        Some(p) if is_sdf => model::sdf::record_titles(
            p,
            &LoadOptions {
                decompressed_limit: args.scene.max_decompressed,
                ..LoadOptions::default()
            },
        )?,
        _ => Vec::new(),
    };
    let records: Vec<usize> = match args.scene.record {
        Some(r) => vec![r],
        None if !titles.is_empty() => (1..=titles.len()).collect(),
        None => vec![1],
    };
    let records: Vec<usize> = match args.shard {
        Some((k, n)) => records
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k)
            .map(|(_, r)| r)
            .collect(),
        None => records,
    };
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let c = cancel.clone();
        // A second Ctrl+C ends at once.
        let _ = ctrlc::set_handler(move || {
            if c.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            eprintln!("bump: interrupted: writing the molecules finished so far");
        });
    }
    let bar = (records.len() > 1).then(|| {
        let b = indicatif::ProgressBar::new(records.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} molecules, {elapsed} elapsed, ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let threads = if args.cpu == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        args.cpu
    };
    let want_pdbqt = args
        .output
        .as_ref()
        .is_some_and(|p| p.to_string_lossy().to_ascii_lowercase().ends_with(".pdbqt"));
    let mut text = String::new();
    let mut molecules = Vec::new();
    let mut interrupted = false;
    let mut evaluations = 0;
    let mut maps: Option<Maps> = None;
    for &record in &records {
        if cancel.load(Ordering::SeqCst) {
            interrupted = true;
            break;
        }
        let mut drug: Molecule = if record == 1 || drug_path.is_none() {
            scene.drug.clone()
        } else {
            let p = drug_path.as_ref().context("a drug file")?;
            let opts = LoadOptions {
                radii: args.scene.radii,
                hydrogens: args.scene.hydrogens,
                sdf_record: Some(record),
                decompressed_limit: args.scene.max_decompressed,
            };
            let d = match model::load(p, &opts) {
                Ok(d) => d,
                Err(e) => {
                    eprintln!(
                        "bump: warning: {}: record {record} skipped: {e}",
                        p.display()
                    );
                    continue;
                }
            };
            let mut m = receptor_only(&d.structure)?;
            m.name = d.structure.name.clone();
            m
        };
        if let Some(t) = titles.get(record - 1).filter(|t| !t.is_empty()) {
            drug.name.clone_from(t);
        }
        for w in &drug.chemistry().warnings {
            eprintln!("bump: warning: {} (record {record}): {w}", drug.name);
        }
        let lig = prepare::ligand(&drug)
            .with_context(|| format!("{} record {record}: the torsion tree", drug.name))?;
        let rel = bump::motion::Pose::from_translation(drug.centre - scene.receptor.centre);
        let opts = DockOptions {
            exhaustiveness: args.exhaustiveness,
            threads: args.cpu,
            seed: args.seed,
            poses: args.poses,
            from_pose: args.from_pose.then(|| (lig.rigid(rel), args.radius)),
            effort: args.effort,
            cancel: Some(cancel.clone()),
            ..DockOptions::default()
        };
        let t0 = Instant::now();
        // A library shares its maps: rebuilt only for a molecule with a
        // type they lack, for every type seen so far.
        if let Err(e) = validate(&target, &lig, &dock_box, &opts) {
            if records.len() > 1 {
                eprintln!("bump: warning: {} record {record} skipped: {e}", drug.name);
                if let Some(b) = &bar {
                    b.inc(1);
                }
                continue;
            }
            return Err(e).with_context(|| format!("docking {}", drug.name));
        }
        let covered = maps
            .as_ref()
            .is_some_and(|m: &Maps| lig.xs.iter().all(|t| m.types().contains(t)));
        if !covered {
            let mut types = maps.as_ref().map_or(Vec::new(), |m| m.types().to_vec());
            types.extend_from_slice(&lig.xs);
            maps = match box_maps(&target, &types, &dock_box, &opts) {
                Ok(m) => Some(m),
                Err(e) => return Err(e).context("grid maps over the box"),
            };
        }
        let Some(maps_now) = maps.as_ref() else {
            bail!("no maps");
        };
        let d = match dock_on(&target, &drug, &lig, &dock_box, maps_now, &opts) {
            Ok(d) => d,
            Err(DockError::Cancelled) => {
                interrupted = true;
                break;
            }
            Err(e) => return Err(e).with_context(|| format!("docking {}", drug.name)),
        };
        let elapsed_s = t0.elapsed().as_secs_f64();
        evaluations += d.evaluations;
        let reference = match &args.reference {
            Some(p) => Some((
                reference_atoms(p, &drug, args.scene.ligand.as_deref())?,
                heavy_swaps(&drug),
            )),
            None => None,
        };
        let centre = scene.receptor.centre;
        let mut contacts = Contacts::new(scene.collider(), scene.rule, &drug, &lig);
        if want_pdbqt {
            let swaps = heavy_swaps(&drug);
            match output::pdbqt_models(&drug, &lig, &d.poses, &swaps, centre) {
                Some(t) => text.push_str(&t),
                None if !d.poses.is_empty() => bail!(
                    "{}: PDBQT output needs a drug read from a PDBQT (its AutoDock types); write SDF instead",
                    drug.name
                ),
                None => {}
            }
        } else {
            for p in &d.poses {
                text.push_str(&output::sdf_record(&drug, &lig, p, centre));
            }
        }
        molecules.push(MoleculeOut {
            record,
            name: drug.name.clone(),
            atoms: drug.len(),
            rotatable_bonds: lig.torsions(),
            elapsed_s,
            evaluations: d.evaluations,
            refined: d.refined,
            dropped_colliding: d.dropped_colliding,
            maps_mb: d.maps_bytes as f64 / 1e6,
            poses: d
                .poses
                .iter()
                .map(|p| {
                    pose_out(
                        p,
                        &mut contacts,
                        &lig,
                        &exact,
                        &scene.receptor,
                        &drug,
                        reference.as_ref(),
                    )
                })
                .collect(),
        });
        if let Some(b) = &bar {
            b.inc(1);
        }
    }
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let output = match &args.output {
        Some(path) => {
            write::write_atomically(path, text.as_bytes())
                .with_context(|| format!("writing the poses to {}", path.display()))?;
            Some(path.display().to_string())
        }
        None => None,
    };
    let out = DockOut {
        receptor: loaded.receptor_source.clone(),
        ligand: loaded.drug_source.clone(),
        dock_box: BoxOut {
            center: dock_box.centre.to_array(),
            size: dock_box.size.to_array(),
            from: box_from,
        },
        seed: args.seed,
        exhaustiveness: args.exhaustiveness,
        threads,
        elapsed_s: t_all.elapsed().as_secs_f64(),
        evaluations,
        molecules,
        interrupted,
        output,
    };
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        print_text(&out);
    }
    if interrupted {
        std::process::exit(130);
    }
    Ok(())
}

fn print_text(out: &DockOut) {
    outln!(
        "box {} centre {:.3},{:.3},{:.3} size {:.1}x{:.1}x{:.1} Å; {} chains, seed {}, {} threads",
        out.dock_box.from,
        out.dock_box.center[0],
        out.dock_box.center[1],
        out.dock_box.center[2],
        out.dock_box.size[0],
        out.dock_box.size[1],
        out.dock_box.size[2],
        out.exhaustiveness,
        out.seed,
        out.threads
    );
    for m in &out.molecules {
        outln!(
            "{} (record {}, {} heavy atoms, {} rotatable bonds): {:.2} s, {} evaluations",
            m.name,
            m.record,
            m.atoms,
            m.rotatable_bonds,
            m.elapsed_s,
            m.evaluations
        );
        outln!("mode  affinity   inter   intra  h-bonds  rmsd-ref");
        outln!("      kcal/mol");
        for p in &m.poses {
            outln!(
                "{:>4} {:>9.3} {:>7.3} {:>7.3} {:>8} {:>9}",
                p.rank,
                p.total,
                p.inter,
                p.intra,
                p.hbonds.len(),
                p.rmsd_to_reference
                    .map_or("-".to_string(), |r| format!("{r:.2}"))
            );
        }
    }
    if let Some(o) = &out.output {
        outln!("wrote {o}");
    }
}
