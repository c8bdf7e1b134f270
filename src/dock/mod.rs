//! The global docking search in a box: the drug's position, orientation and
//! every torsion, from random starts, on the receptor's grid maps, refined
//! and scored exactly, every pose collision-free under bump's contact rule.
//!
//! A run ([`dock`]):
//! 1. builds maps of the drug's types over the box (grown by [`MAP_MARGIN`]);
//! 2. runs [`CHAINS_PER_EXHAUSTIVENESS`] × [`DockOptions::exhaustiveness`]
//!    independent Monte Carlo chains ([`search`]) on rayon's threads, chain
//!    `k` seeded from the run's seed and `k`, each minimising locally on the
//!    maps with the box as a wall ([`local`]). Together they take
//!    [`STEP_FRACTION`] of the steps Vina's chains take at the same
//!    exhaustiveness, spread over four times as many chains: a chain that
//!    falls into a wrong basin seldom leaves it, so more, shorter chains
//!    find the best basin more often for the same work;
//! 3. merges the chains' minima in chain order, best first, and takes the
//!    [`REFINED`] best distinct ones;
//! 4. settles each with the exact evaluator under the contact rule
//!    ([`crate::score::settle()`]: no accepted step collides, and a start that
//!    collides is pushed out first), drops any that still collides with the
//!    receptor or within itself, and scores it exactly (Vina's total,
//!    `inter / (1 + w·N_tors)`);
//! 5. sorts by that total and clusters at [`CLUSTER_RMSD`] (the smallest
//!    heavy-atom RMSD over the drug's graph symmetries): each pose is the
//!    best of its cluster.
//!
//! Every step is deterministic for a seed and independent of the thread
//! count: a chain reads only its own generator, results are collected in
//! chain order, and ties sort by the order they were found in.

pub mod local;
pub mod output;
pub mod search;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use glam::DVec3;
use rayon::prelude::*;

use crate::chem::XsType;
use crate::chem::symmetry::{heavy_swaps, rmsd_over};
use crate::collide::{Collider, ContactRule};
use crate::model::Molecule;
use crate::pocket::DockBox;
use crate::rng::Rng;
use crate::score::maps::{DEFAULT_SPACING, MapBox, Maps, MapsError};
use crate::score::settle::{Collision, SettleOptions};
use crate::score::{
    Conformation, Contacts, Energies, Exact, Ligand, MapField, Receptor, Scoring, Workspace,
    energies, settle, torsion_divisor,
};
use search::{ChainOptions, Minimum, Starts, run_chain};

/// Å added round the box for the maps, so that a drug pressed against the
/// box's wall still reads the maps.
pub const MAP_MARGIN: f64 = 1.0;

/// Distinct minima taken from the chains to be settled and scored exactly.
pub const REFINED: usize = 30;

/// Poses closer than this (Å, symmetry-aware heavy-atom RMSD) are one
/// cluster.
pub const CLUSTER_RMSD: f64 = 2.0;

/// Most chains (`--exhaustiveness`).
pub const MAX_EXHAUSTIVENESS: usize = 1024;

/// Longest box edge (Å).
pub const MAX_BOX_EDGE: f64 = 126.0;

/// How a docking run searches.
#[derive(Debug, Clone)]
pub struct DockOptions {
    /// Independent Monte Carlo chains (Vina's exhaustiveness).
    pub exhaustiveness: usize,
    /// Threads (0: rayon's default, all cores).
    pub threads: usize,
    /// The run's seed.
    pub seed: u64,
    /// Most poses returned.
    pub poses: usize,
    /// Search round this conformation only, its centre within this radius
    /// (Å), instead of the whole box from random starts.
    pub from_pose: Option<(Conformation, f64)>,
    /// Scales the chains' step counts (1: [`steps_for`]'s).
    pub effort: f64,
    /// The scoring function.
    pub scoring: Scoring,
    /// Set (from another thread) to stop the run: it then ends with
    /// [`DockError::Cancelled`] within one Monte Carlo step of each chain.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Default for DockOptions {
    fn default() -> Self {
        Self {
            exhaustiveness: 8,
            threads: 0,
            seed: 1,
            poses: 9,
            from_pose: None,
            effort: 1.0,
            scoring: Scoring::Vina,
            cancel: None,
        }
    }
}

/// Why a docking run cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DockError {
    /// The drug has no scored heavy atoms.
    #[error("the ligand has no atoms to dock")]
    EmptyLigand,
    /// The box has no receptor atom within 8 Å of it.
    #[error(
        "the box (centre {centre:?}, size {size:?} Å) misses the receptor: no receptor atom lies within 8 Å of it"
    )]
    BoxMissesReceptor {
        /// Centre (file coordinates).
        centre: [f64; 3],
        /// Size.
        size: [f64; 3],
    },
    /// The drug cannot fit in the box in any orientation.
    #[error(
        "the ligand spans {span:.1} Å, more than the box's diagonal ({diagonal:.1} Å): give a larger --size or --pad"
    )]
    LigandLargerThanBox {
        /// The ligand's largest heavy-atom distance.
        span: f64,
        /// The box's diagonal.
        diagonal: f64,
    },
    /// An option out of range.
    #[error("{name} = {value} is out of range ({range})")]
    Option {
        /// The option.
        name: &'static str,
        /// Its value.
        value: String,
        /// What it may be.
        range: &'static str,
    },
    /// The run was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The maps cannot be built.
    #[error(transparent)]
    Maps(#[from] MapsError),
}

/// What the run docks: the receptor's typed atoms and collider, the drug,
/// in the receptor's frame (relative to its centre).
pub struct Target<'a> {
    /// The receptor's typed atoms.
    pub receptor: &'a Receptor,
    /// The receptor's collider.
    pub collider: &'a Collider,
    /// The contact rule.
    pub rule: ContactRule,
    /// The receptor's centre (file coordinates): the frame's origin.
    pub receptor_centre: DVec3,
}

/// One docked pose.
#[derive(Debug, Clone, PartialEq)]
pub struct DockedPose {
    /// 1 for the best.
    pub rank: usize,
    /// The conformation (relative to the receptor).
    pub conf: Conformation,
    /// Vina's total: `inter / (1 + w·N_tors)` (kcal/mol), exact.
    pub total: f64,
    /// Exact energies.
    pub energies: Energies,
    /// Heavy atoms (receptor frame).
    pub atoms: Vec<DVec3>,
}

/// A docking run's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Docking {
    /// The poses, best first, each the best of its cluster.
    pub poses: Vec<DockedPose>,
    /// Evaluations on the maps (the chains).
    pub evaluations: u64,
    /// Minima settled and scored exactly.
    pub refined: usize,
    /// Of those, how many still collided after settling and were dropped.
    pub dropped_colliding: usize,
    /// The box searched (file coordinates).
    pub dock_box: DockBox,
    /// Bytes of the maps.
    pub maps_bytes: usize,
}

/// The chains' step counts for a drug of `atoms` heavy atoms and `torsions`
/// rotatable bonds (Vina's heuristic, `70·3·(50 + n)/2` with
/// `n = atoms + 10·(6 + torsions)`, cut to [`STEP_FRACTION`]), and each
/// step's BFGS steps (Vina's `(25 + atoms)/3`).
pub fn steps_for(atoms: usize, torsions: usize, effort: f64) -> ChainOptions {
    let n = atoms + 10 * (6 + torsions);
    let vina = 70.0 * 3.0 * (50 + n) as f64 / 2.0;
    let local = (25 + atoms) / 3;
    ChainOptions {
        steps: ((vina * STEP_FRACTION * effort).ceil() as usize).max(1),
        local_steps: local,
        wall: (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
    }
}

/// Chains run per unit of exhaustiveness, each with that share of the
/// steps.
pub const CHAINS_PER_EXHAUSTIVENESS: usize = 4;

/// The fraction of Vina's step count each chain takes.
pub const STEP_FRACTION: f64 = 0.25;

/// A chain's generator: the run's seed mixed with the chain's number
/// (splitmix64), never zero.
fn chain_rng(seed: u64, chain: usize) -> Rng {
    let mut z = seed ^ (chain as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    Rng(if z == 0 { 0x2545_F491_4F6C_DD1D } else { z })
}

/// The largest distance between two of `points`.
pub fn span(points: &[DVec3]) -> f64 {
    let mut s: f64 = 0.0;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            s = s.max((*a - *b).length());
        }
    }
    s
}

/// Checks the box against the receptor and the drug.
fn check_box(target: &Target<'_>, lig: &Ligand, bx: &DockBox) -> Result<(), DockError> {
    let edge_ok = |v: f64| v.is_finite() && v > 0.0 && v <= MAX_BOX_EDGE;
    let sized = edge_ok(bx.size.x) && edge_ok(bx.size.y) && edge_ok(bx.size.z);
    if !(sized && bx.centre.is_finite()) {
        return Err(DockError::Option {
            name: "box size",
            value: format!("{:?}", bx.size.to_array()),
            range: "each edge above 0 and at most 126 Å",
        });
    }
    let lo = bx.lo() - target.receptor_centre - 8.0;
    let hi = bx.hi() - target.receptor_centre + 8.0;
    let near = target
        .receptor
        .positions
        .iter()
        .any(|p| p.cmpge(lo).all() && p.cmple(hi).all());
    if !near {
        return Err(DockError::BoxMissesReceptor {
            centre: bx.centre.to_array(),
            size: bx.size.to_array(),
        });
    }
    let s = span(&lig.local);
    let diagonal = bx.size.length();
    if s > diagonal {
        return Err(DockError::LigandLargerThanBox { span: s, diagonal });
    }
    Ok(())
}

/// Docks `drug` (typed as `lig`) into `target` within `bx` (file
/// coordinates): see the module docs. Builds maps of the drug's types
/// first ([`box_maps`]).
///
/// # Errors
/// [`DockError`] for an empty drug, a box that misses the receptor or is
/// smaller than the drug, options out of range, or maps that cannot be
/// built.
pub fn dock(
    target: &Target<'_>,
    drug: &Molecule,
    lig: &Ligand,
    bx: &DockBox,
    opts: &DockOptions,
) -> Result<Docking, DockError> {
    validate(target, lig, bx, opts)?;
    let maps = box_maps(target, &lig.xs, bx, opts)?;
    run_on(target, drug, lig, bx, &maps, opts)
}

/// [`dock`] on maps already built over `bx` ([`box_maps`]), as a library
/// run shares them between its molecules; a type the maps lack is scored
/// exactly.
///
/// # Errors
/// As [`dock`].
pub fn dock_on(
    target: &Target<'_>,
    drug: &Molecule,
    lig: &Ligand,
    bx: &DockBox,
    maps: &Maps,
    opts: &DockOptions,
) -> Result<Docking, DockError> {
    validate(target, lig, bx, opts)?;
    run_on(target, drug, lig, bx, maps, opts)
}

/// The threads a run uses.
fn threads(opts: &DockOptions) -> usize {
    if opts.threads == 0 {
        rayon::current_num_threads()
    } else {
        opts.threads
    }
}

/// Maps of `types` over `bx` grown by [`MAP_MARGIN`] (receptor frame), on
/// the run's threads.
///
/// # Errors
/// [`DockError::Maps`] for a box that is no usable lattice.
pub fn box_maps(
    target: &Target<'_>,
    types: &[XsType],
    bx: &DockBox,
    opts: &DockOptions,
) -> Result<Maps, DockError> {
    let map_box = MapBox {
        centre: bx.centre - target.receptor_centre,
        size: bx.size + 2.0 * MAP_MARGIN,
        spacing: DEFAULT_SPACING,
    };
    Ok(Maps::build(
        target.receptor,
        opts.scoring,
        types,
        &map_box,
        threads(opts),
    )?)
}

/// Refuses what cannot be docked: an empty drug, options out of range, a
/// box that misses the receptor, is too large or cannot hold the drug.
///
/// # Errors
/// The [`DockError`] that says which.
pub fn validate(
    target: &Target<'_>,
    lig: &Ligand,
    bx: &DockBox,
    opts: &DockOptions,
) -> Result<(), DockError> {
    if lig.xs.is_empty() || lig.is_empty() {
        return Err(DockError::EmptyLigand);
    }
    if opts.exhaustiveness == 0 || opts.exhaustiveness > MAX_EXHAUSTIVENESS {
        return Err(DockError::Option {
            name: "exhaustiveness",
            value: opts.exhaustiveness.to_string(),
            range: "1 to 1024",
        });
    }
    if opts.poses == 0 {
        return Err(DockError::Option {
            name: "poses",
            value: "0".into(),
            range: "at least 1",
        });
    }
    if !(opts.effort.is_finite() && opts.effort > 0.0 && opts.effort <= 100.0) {
        return Err(DockError::Option {
            name: "effort",
            value: opts.effort.to_string(),
            range: "above 0 and at most 100",
        });
    }
    check_box(target, lig, bx)
}

/// The run itself, its inputs checked.
fn run_on(
    target: &Target<'_>,
    drug: &Molecule,
    lig: &Ligand,
    bx: &DockBox,
    maps: &Maps,
    opts: &DockOptions,
) -> Result<Docking, DockError> {
    let rel_centre = bx.centre - target.receptor_centre;
    let (lo, hi) = (rel_centre - bx.size / 2.0, rel_centre + bx.size / 2.0);
    let threads = threads(opts);
    let maps_bytes = maps.bytes();
    let run = || search_and_refine(target, drug, lig, maps, (lo, hi), opts);
    let (minima, evaluations, settled) = if opts.threads == 0 {
        run()
    } else {
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(run),
            Err(_) => run(),
        }
    };
    if opts
        .cancel
        .as_ref()
        .is_some_and(|c| c.load(Ordering::Relaxed))
    {
        return Err(DockError::Cancelled);
    }
    let refined = minima;
    let dropped_colliding = refined - settled.len();
    let poses = cluster(drug, settled, opts.poses);
    Ok(Docking {
        poses,
        evaluations,
        refined,
        dropped_colliding,
        dock_box: *bx,
        maps_bytes,
    })
}

/// The chains, the merge and the exact settling: (minima settled, map
/// evaluations, the collision-free settled poses in merge order).
fn search_and_refine(
    target: &Target<'_>,
    drug: &Molecule,
    lig: &Ligand,
    maps: &Maps,
    (lo, hi): (DVec3, DVec3),
    opts: &DockOptions,
) -> (usize, u64, Vec<DockedPose>) {
    let exact = Exact::new(target.receptor, opts.scoring);
    let field = MapField::new(maps, exact);
    let starts = match &opts.from_pose {
        Some((around, radius)) => Starts::Near {
            around: around.clone(),
            radius: *radius,
        },
        None => Starts::Box { lo, hi },
    };
    let mut chain_opts = steps_for(lig.len(), lig.torsions(), opts.effort);
    chain_opts.wall = (lo, hi);
    chain_opts.steps = chain_opts.steps.div_ceil(CHAINS_PER_EXHAUSTIVENESS);
    let chains: Vec<_> = (0..opts.exhaustiveness * CHAINS_PER_EXHAUSTIVENESS)
        .into_par_iter()
        .map(|k| {
            run_chain(
                &field,
                lig,
                &starts,
                k,
                chain_rng(opts.seed, k),
                &chain_opts,
                opts.cancel.as_deref(),
            )
        })
        .collect();
    let evaluations = chains.iter().map(|c| c.evaluations).sum();
    // Merged best first; a tie keeps chain order (the sort is stable).
    let mut all: Vec<Minimum> = chains.into_iter().flat_map(|c| c.minima).collect();
    all.sort_by(|a, b| a.energy.total_cmp(&b.energy));
    let mut picked: Vec<Minimum> = Vec::new();
    for m in all {
        if picked.len() >= REFINED {
            break;
        }
        if picked
            .iter()
            .all(|o| search::rmsd(&o.atoms, &m.atoms) >= search::DISTINCT)
        {
            picked.push(m);
        }
    }
    let divisor = torsion_divisor(lig.torsion_count);
    let settled: Vec<Option<DockedPose>> = picked
        .par_iter()
        .map(|m| {
            let exact = Exact::new(target.receptor, opts.scoring);
            let mut contacts = Contacts::new(target.collider, target.rule, drug, lig);
            let s = settle(
                &exact,
                lig,
                &mut contacts,
                &m.conf,
                &SettleOptions::default(),
            );
            let atoms = lig.place(&s.conf);
            let collisions: Vec<Collision> = contacts.collisions(&atoms);
            if !collisions.is_empty() {
                return None;
            }
            let mut ws = Workspace::default();
            let e = energies(&exact, lig, &s.conf, &mut ws);
            Some(DockedPose {
                rank: 0,
                total: e.inter / divisor,
                energies: e,
                conf: s.conf,
                atoms,
            })
        })
        .collect();
    let n = picked.len();
    (n, evaluations, settled.into_iter().flatten().collect())
}

/// The poses sorted by total (ties in merge order) and clustered at
/// [`CLUSTER_RMSD`], at most `max` of them, ranked.
fn cluster(drug: &Molecule, mut poses: Vec<DockedPose>, max: usize) -> Vec<DockedPose> {
    let swaps = heavy_swaps(drug);
    poses.sort_by(|a, b| a.total.total_cmp(&b.total));
    let mut out: Vec<DockedPose> = Vec::new();
    for p in poses {
        if out.len() >= max {
            break;
        }
        if out
            .iter()
            .all(|o| rmsd_over(&swaps, &o.atoms, &p.atoms) >= CLUSTER_RMSD)
        {
            out.push(p);
        }
    }
    for (k, p) in out.iter_mut().enumerate() {
        p.rank = k + 1;
    }
    out
}
