//! The search's local optimisation: Vina's BFGS (`quasi_newton`) over the
//! drug's position, orientation and torsions on an evaluator (the maps),
//! with the docking box as a wall.
//!
//! What is minimised is the continuous `inter + intra` ([`energy_gradient`])
//! plus [`BOX_WALL`] kcal/mol for every Å a heavy atom lies outside the box,
//! along each axis (Vina's grid cache charges atoms outside its grid the same
//! way, more steeply). The steps are settle's ([`mod@crate::score::settle`]):
//! the inverse Hessian starts as the identity and is scaled after the first
//! step; each line search halves `α` up to ten times until Armijo's condition
//! holds, from the `α` at which no atom travels more than [`MAX_TRAVEL`].
//! No contact rule applies here: the search's results are settled under it
//! afterwards.

use glam::DVec3;

use crate::score::field::{Field, Workspace, energy_gradient, energy_gradient_capped};
use crate::score::ligand::{Conformation, Gradient, Ligand};
use crate::score::settle::{bfgs_update, descent, dot, flat, identity, stepped};

/// kcal/mol per Å that a heavy atom lies outside the box, per axis.
pub const BOX_WALL: f64 = 10.0;

/// Longest travel (Å) of any atom in a line search's first trial.
pub const MAX_TRAVEL: f64 = 2.0;

/// The search's objective: an evaluator, the drug and the box.
pub struct Objective<'a, F: ?Sized> {
    field: &'a F,
    lig: &'a Ligand,
    lo: DVec3,
    hi: DVec3,
    /// The farthest heavy atom from the drug's centre (Å), for the travel
    /// bound.
    reach: f64,
    ws: Workspace,
    grad: Gradient,
    wall: Gradient,
    atom_g: Vec<DVec3>,
    tree: Vec<(DVec3, DVec3)>,
    /// Evaluations so far.
    pub evaluations: u64,
    /// The curl's caps (inter, intra) while hunting; `None`: Vina's own.
    cap: Option<(f64, f64)>,
}

/// Vina's caps of the curl during the Monte Carlo's minimisations
/// (`hunt_cap`: intermolecular 1.5, intramolecular 10 kcal/mol).
pub const HUNT_CAP: (f64, f64) = (1.5, 10.0);

impl<'a, F: Field + ?Sized> Objective<'a, F> {
    /// The objective of `lig` on `field` inside the box `lo..hi` (receptor
    /// frame).
    pub fn new(field: &'a F, lig: &'a Ligand, lo: DVec3, hi: DVec3) -> Self {
        let reach = lig.local.iter().map(|p| p.length()).fold(0.0, f64::max);
        Self {
            field,
            lig,
            lo,
            hi,
            reach: reach.max(1.0),
            ws: Workspace::default(),
            grad: Gradient::default(),
            wall: Gradient::default(),
            atom_g: Vec::new(),
            tree: Vec::new(),
            evaluations: 0,
            cap: None,
        }
    }

    /// The objective at `conf`, its gradient (translation, rotation,
    /// torsions) into `g`.
    pub fn eval(&mut self, conf: &Conformation, g: &mut Vec<f64>) -> f64 {
        self.evaluations += 1;
        let e = match self.cap {
            Some(cap) => energy_gradient_capped(
                self.field,
                self.lig,
                conf,
                &mut self.ws,
                &mut self.grad,
                cap,
            ),
            None => energy_gradient(self.field, self.lig, conf, &mut self.ws, &mut self.grad),
        }
        .sum();
        let mut wall = 0.0;
        let mut outside = false;
        self.atom_g.clear();
        self.atom_g.resize(self.ws.positions.len(), DVec3::ZERO);
        for (x, ag) in self.ws.positions.iter().zip(self.atom_g.iter_mut()) {
            let below = (self.lo - *x).max(DVec3::ZERO);
            let above = (*x - self.hi).max(DVec3::ZERO);
            if below != DVec3::ZERO || above != DVec3::ZERO {
                outside = true;
                wall += BOX_WALL * (below + above).element_sum();
                let sign = |b: f64, a: f64| {
                    if a > 0.0 {
                        1.0
                    } else if b > 0.0 {
                        -1.0
                    } else {
                        0.0
                    }
                };
                *ag = BOX_WALL
                    * DVec3::new(
                        sign(below.x, above.x),
                        sign(below.y, above.y),
                        sign(below.z, above.z),
                    );
            }
        }
        if outside {
            self.lig.gradient(
                conf,
                &self.ws.positions,
                &self.atom_g,
                &mut self.tree,
                &mut self.wall,
            );
            self.grad.translation += self.wall.translation;
            self.grad.rotation += self.wall.rotation;
            for (a, b) in self.grad.torsions.iter_mut().zip(&self.wall.torsions) {
                *a += b;
            }
        }
        flat(&self.grad, g);
        e + wall
    }

    /// Minimises from `conf` for at most `max_steps` BFGS steps, with the
    /// curl capped at [`HUNT_CAP`] when `hunt`; returns the objective at the
    /// end (`conf` is left there).
    pub fn minimise(&mut self, conf: &mut Conformation, max_steps: usize, hunt: bool) -> f64 {
        self.cap = hunt.then_some(HUNT_CAP);
        let n = 6 + self.lig.torsions();
        let mut g = Vec::with_capacity(n);
        let mut g_new = Vec::with_capacity(n);
        let mut f0 = self.eval(conf, &mut g);
        let mut h = identity(n);
        for step in 0..max_steps {
            let Some((p, pg)) = descent(&mut h, &g, n) else {
                break;
            };
            let travel = DVec3::new(p[0], p[1], p[2]).length()
                + self.reach
                    * (DVec3::new(p[3], p[4], p[5]).length()
                        + p[6..].iter().map(|v| v.abs()).sum::<f64>());
            let mut alpha = if travel > MAX_TRAVEL {
                MAX_TRAVEL / travel
            } else {
                1.0
            };
            let mut accepted = None;
            for _ in 0..10 {
                let trial = stepped(conf, &p, alpha);
                let f1 = self.eval(&trial, &mut g_new);
                if f1 - f0 < 1e-4 * alpha * pg {
                    accepted = Some((trial, f1));
                    break;
                }
                alpha *= 0.5;
            }
            let Some((trial, f1)) = accepted else {
                break;
            };
            let y: Vec<f64> = g_new.iter().zip(&g).map(|(a, b)| a - b).collect();
            let s: Vec<f64> = p.iter().map(|v| v * alpha).collect();
            *conf = trial;
            f0 = f1;
            std::mem::swap(&mut g, &mut g_new);
            if dot(&g, &g).sqrt() < 1e-5 {
                break;
            }
            bfgs_update(&mut h, &s, &y, step == 0);
        }
        f0
    }
}
