//! One Monte Carlo chain of the search (Vina's `monte_carlo`): from a random
//! conformation in the box, each step changes one thing (the position, the
//! orientation or one torsion), minimises locally, and keeps the result by
//! Metropolis's rule at [`TEMPERATURE`]; every conformation that betters the
//! chain's best, or that the chain's list still has room for, is minimised
//! further and kept among the chain's [`KEPT`] best distinct minima.
//!
//! A chain reads only its own generator (seeded from the run's seed and the
//! chain's number), so its result does not depend on which thread runs it.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{DQuat, DVec3};

use super::local::Objective;
use crate::motion::Pose;
use crate::rng::Rng;
use crate::score::field::Field;
use crate::score::ligand::{Conformation, Ligand};

/// Metropolis's temperature (kcal/mol), Vina's.
pub const TEMPERATURE: f64 = 1.2;

/// How far a position step moves the drug at most (Å), Vina's amplitude.
pub const AMPLITUDE: f64 = 2.0;

/// Minima a chain keeps.
pub const KEPT: usize = 20;

/// Two minima closer than this (heavy-atom RMSD, Å) are one in a chain's list.
pub const DISTINCT: f64 = 1.0;

/// Where a chain's starts lie.
#[derive(Debug, Clone)]
pub enum Starts {
    /// Anywhere in the box (receptor frame), any orientation and torsions.
    Box {
        /// Lowest corner.
        lo: DVec3,
        /// Highest corner.
        hi: DVec3,
    },
    /// Within `radius` of `around`'s centre; chain 0 starts at `around`
    /// itself, the others in any orientation and torsions.
    Near {
        /// The user's conformation.
        around: Conformation,
        /// Å.
        radius: f64,
    },
}

/// A minimum the search found.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The conformation.
    pub conf: Conformation,
    /// The objective there (maps: continuous inter + intra, box wall).
    pub energy: f64,
    /// Its heavy atoms (receptor frame).
    pub atoms: Vec<DVec3>,
}

/// What one chain found.
#[derive(Debug, Clone)]
pub struct ChainResult {
    /// Its distinct minima, best first.
    pub minima: Vec<Minimum>,
    /// Evaluations it made.
    pub evaluations: u64,
}

/// A random rotation, uniform over all (Shoemake's).
pub fn random_rotation(rng: &mut Rng) -> DQuat {
    let (u1, u2, u3) = (rng.f64(), rng.f64(), rng.f64());
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    DQuat::from_xyzw(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
    .normalize()
}

/// A random point in the unit ball.
fn in_ball(rng: &mut Rng) -> DVec3 {
    loop {
        let v = rng.in_box(DVec3::ONE);
        if v.length_squared() <= 1.0 {
            return v;
        }
    }
}

/// A random start for chain `chain`.
pub fn start(starts: &Starts, torsions: usize, chain: usize, rng: &mut Rng) -> Conformation {
    let angles = |rng: &mut Rng| {
        (0..torsions)
            .map(|_| rng.range(-std::f64::consts::PI, std::f64::consts::PI))
            .collect()
    };
    match starts {
        Starts::Box { lo, hi } => {
            let t = *lo + (*hi - *lo) * DVec3::new(rng.f64(), rng.f64(), rng.f64());
            let q = random_rotation(rng);
            Conformation {
                pose: Pose::new(q, t),
                torsions: angles(rng),
            }
        }
        Starts::Near { around, radius } => {
            if chain == 0 {
                return around.clone();
            }
            let t = around.pose.translation + in_ball(rng) * *radius;
            let q = random_rotation(rng);
            Conformation {
                pose: Pose::new(q, t),
                torsions: angles(rng),
            }
        }
    }
}

/// The plain heavy-atom RMSD of two placements.
pub fn rmsd(a: &[DVec3], b: &[DVec3]) -> f64 {
    crate::score::settle::rmsd(a, b)
}

/// Adds `m` to `list` (best first, at most `KEPT`, none within [`DISTINCT`]
/// of another): a minimum near a kept one replaces it if better.
fn keep(list: &mut Vec<Minimum>, m: Minimum) {
    if let Some(k) = list
        .iter()
        .position(|o| rmsd(&o.atoms, &m.atoms) < DISTINCT)
    {
        if m.energy < list[k].energy {
            list.remove(k);
        } else {
            return;
        }
    }
    let at = list.partition_point(|o| o.energy <= m.energy);
    if at < KEPT {
        list.insert(at, m);
        list.truncate(KEPT);
    }
}

/// How a chain runs.
#[derive(Debug, Clone, Copy)]
pub struct ChainOptions {
    /// Monte Carlo steps.
    pub steps: usize,
    /// BFGS steps of each step's minimisation.
    pub local_steps: usize,
    /// The box's lowest and highest corner (receptor frame): the wall.
    pub wall: (DVec3, DVec3),
}

/// Runs one chain: see the module docs.
pub fn run_chain<F: Field + ?Sized>(
    field: &F,
    lig: &Ligand,
    starts: &Starts,
    chain: usize,
    mut rng: Rng,
    opts: &ChainOptions,
    cancel: Option<&AtomicBool>,
) -> ChainResult {
    let mut obj = Objective::new(field, lig, opts.wall.0, opts.wall.1);
    let torsions = lig.torsions();
    let gyration = (lig.local.iter().map(|p| p.length_squared()).sum::<f64>()
        / lig.len().max(1) as f64)
        .sqrt()
        .max(1.0);
    let mut current = start(starts, torsions, chain, &mut rng);
    let mut e_current = obj.minimise(&mut current, opts.local_steps, true);
    let mut minima: Vec<Minimum> = Vec::new();
    let mut best = f64::INFINITY;
    for _ in 0..opts.steps {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            break;
        }
        let mut cand = current.clone();
        let which = (rng.f64() * (2 + torsions) as f64) as usize;
        match which {
            0 => cand.pose.translation += in_ball(&mut rng) * AMPLITUDE,
            1 => {
                let w = in_ball(&mut rng) * (AMPLITUDE / gyration);
                cand.pose.rotation = (DQuat::from_scaled_axis(w) * cand.pose.rotation).normalize();
            }
            k => {
                let k = (k - 2).min(torsions.saturating_sub(1));
                cand.torsions[k] = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
            }
        }
        let e = obj.minimise(&mut cand, opts.local_steps, true);
        let accept = e < e_current || rng.f64() < ((e_current - e) / TEMPERATURE).exp();
        if !accept {
            continue;
        }
        current = cand;
        e_current = e;
        if e < best || minima.len() < KEPT {
            // As Vina: minimised further at the full curl, and the chain
            // goes on from there.
            let er = obj.minimise(&mut current, opts.local_steps, false);
            e_current = er;
            let atoms = lig.place(&current);
            keep(
                &mut minima,
                Minimum {
                    conf: current.clone(),
                    energy: er,
                    atoms,
                },
            );
            best = best.min(er);
        }
    }
    ChainResult {
        minima,
        evaluations: obj.evaluations,
    }
}
