//! Settle: a local minimisation of the score over the drug's position,
//! orientation and torsions (Vina's `optimize`), in which no accepted step
//! collides or tunnels under bump's contact rule.
//!
//! # The minimiser
//! What is minimised is what Vina's optimiser minimises — the continuous
//! intermolecular plus intramolecular energy ([`super::field`]), without the
//! torsion divisor — plus a penalty `10·(c + 0.3 − d)²` kcal/mol on every
//! pair closer than 0.3 Å beyond its contact distance `c` under bump's rule
//! ([`ESCAPE_WEIGHT`], [`ESCAPE_MARGIN`]). The penalty is zero wherever no
//! pair comes within 0.3 Å of colliding (Vina's own repulsion keeps good
//! poses much farther out), so it leaves their minima alone; it lets the
//! minimiser see a contact coming and slide along it rather than push into
//! it, and it pushes a colliding start out. The method is Vina's BFGS (`bfgs.h`): the variables are
//! the drug's translation, a rotation vector about its centre and one angle
//! per rotatable bond; the inverse Hessian starts as the identity, is scaled
//! after the first step and updated by BFGS; each step's line search halves
//! `α` from 1 up to 10 times until Armijo's condition holds
//! (`f(x + αp) − f(x) < 10⁻⁴ α p·g`), starting from the `α` at which no atom
//! travels more than [`MAX_STEP`] if 1 would go farther. Unlike Vina, a trial the contact rule
//! refuses counts as a failed trial, a line search with no accepted trial
//! ends the minimisation (the drug rests against a contact or at a minimum),
//! and so does a step that lowers the energy by less than
//! [`SettleOptions::min_decrease`]. Everything is deterministic.
//!
//! # The contact rule along every step
//! A step from conformation A to B is the path: first each changed torsion
//! in tree order (parents first), turning its moving side rigidly about the
//! bond's axis — a screw motion of those atoms — with the rest of the drug
//! held; then the whole drug along the screw motion from A's pose to B's. A
//! step is accepted only if no atom pair collides anywhere on that path:
//! - receptor–drug pairs through the collider: a torsion piece asks
//!   move-to-touch with the moving atoms alone, the rigid piece with the
//!   whole drug (neither can tunnel, [`crate::collide::sweep`]);
//! - pairs within the drug more than three bonds apart whose distance the
//!   tree lets change: along a turn their squared distance is
//!   `A + B cos φ + C sin φ`, whose minimum over the turn is found in
//!   closed form.
//!
//! Most steps never need those sweeps: after each accepted step settle keeps
//! every atom's clearance (its smallest gap to the receptor under the rule,
//! capped at [`SettleOptions::margin`]) and every drug pair's; a trial whose
//! atoms provably travel less than their clearance (the arc of each turn,
//! and the rigid piece's chord stretched by the screw's
//! `(θ/2)/sin(θ/2)`) cannot collide on the way, and is accepted as clear;
//! a line search's first trial is shortened to what the clearances prove
//! when that keeps at least a tenth of it.
//!
//! # A start that collides
//! Settle says so ([`Settled::start_collisions`]) and first lets the
//! energy and the penalty push the drug out: the same BFGS steps without
//! the contact rule, but short ones (no atom travels more than
//! [`ESCAPE_STEP`] in a step, so none can jump over an atom), until every
//! pair is [`ESCAPE_CLEARANCE`] clear of contact, or until the minimiser
//! gets no farther from a pose that collides nowhere
//! ([`Settled::escape_steps`]); from there the rule holds for every step.
//! Where the energy holds the drug in an overlap (an attraction, such as a
//! hydrogen bond pulling a pair closer than the rule allows, balancing the
//! penalty) or the escape stalls, the penalty alone goes on pushing, in the
//! same short steps, and the energy returns once the drug is out. If even
//! that ends before the drug is out (it is caged), the result's collisions
//! are reported ([`Settled::end_collisions`]).
//!
//! # Why one module
//! The minimiser and the checks of its steps share one working state (the
//! drug's atoms, their clearances, the moving side of each bond, the
//! conformation being tried), and each check is written for the steps the
//! minimiser takes; apart, neither would be read alone. The module is
//! longer than most for that reason; its tests follow it.

use glam::{DMat3, DQuat, DVec3};

use super::field::{Energies, Field, Workspace, energies, energy_gradient};
use super::ligand::{Conformation, Gradient, Ligand};
use crate::collide::collider::unpack_meta;
use crate::collide::rule::{reported_distance, within};
use crate::collide::{Collider, ContactRule, DrugAtoms, Pair, TouchOptions, move_to_touch};
use crate::model::Molecule;
use crate::motion::Pose;

/// Longest travel (Å) of any atom in one step out of a colliding start,
/// before the contact rule applies: short enough that no step jumps over
/// an atom.
pub const ESCAPE_STEP: f64 = 0.3;

/// Weight (kcal/mol/Å²) of the penalty on pairs near or in contact.
pub const ESCAPE_WEIGHT: f64 = 10.0;

/// Gap (Å) beyond the contact distance within which the penalty acts.
pub const ESCAPE_MARGIN: f64 = 0.3;

/// Longest travel (Å) of any atom in one step once the drug collides
/// nowhere: a longer step would mostly be refused or need a sweep.
pub const MAX_STEP: f64 = 2.0;

/// Gap (Å) from contact every pair needs before the pushing out of a
/// colliding start ends (or the first pose that collides nowhere, if the
/// minimisation gets no farther).
pub const ESCAPE_CLEARANCE: f32 = 0.1;

/// Room (Å) a clearance keeps beyond an atom's travel for the step to be
/// proved clear without a sweep: far above the f32 rounding of the
/// distances the clearances come from.
const PROOF_SLACK: f64 = 1e-3;

/// A first trial is shortened to what the clearances prove clear (no sweep)
/// when that keeps at least this fraction of it.
const PROVED_SHORTER: f64 = 0.1;

/// How settle runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettleOptions {
    /// Most BFGS steps.
    pub max_steps: usize,
    /// A step that lowers the energy by less than this (kcal/mol) ends the
    /// minimisation.
    pub min_decrease: f64,
    /// Clearances are measured up to this gap (Å); a larger one proves
    /// longer steps clear without a sweep, at the cost of more pairs found.
    pub margin: f32,
    /// Move-to-touch's options for the sweeps.
    pub touch: TouchOptions,
}

impl Default for SettleOptions {
    fn default() -> Self {
        Self {
            max_steps: 300,
            min_decrease: 1e-4,
            margin: 1.0,
            touch: TouchOptions::default(),
        }
    }
}

/// A pair of drug atoms checked for internal collisions, with its contact
/// distance.
#[derive(Debug, Clone, Copy, PartialEq)]
struct InnerPair {
    a: u32,
    b: u32,
    contact: f64,
}

/// The collision side of settle: the receptor's collider, the contact rule
/// and the drug's atoms.
#[derive(Debug, Clone)]
pub struct Contacts<'a> {
    collider: &'a Collider,
    rule: ContactRule,
    /// The drug's atoms (radii and polarity); its coordinates are replaced
    /// by each conformation's before a query.
    shape: Molecule,
    /// The drug's atoms grouped as the collider groups them, computed once
    /// from the loaded shape.
    groups: Vec<u32>,
    inner: Vec<InnerPair>,
}

/// A collision found at a pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Collision {
    /// A receptor–drug pair.
    Receptor(Pair),
    /// Two drug atoms (heavy-atom indices) at a centre distance (Å) no more
    /// than their contact distance.
    Inner {
        /// The first atom.
        a: u32,
        /// The second atom.
        b: u32,
        /// Their distance.
        distance: f64,
        /// Their contact distance.
        contact: f64,
    },
}

impl<'a> Contacts<'a> {
    /// The contacts of `drug` (whose heavy atoms are `lig`'s) against the
    /// receptor indexed by `collider`, judged by `rule`. Drug pairs are those
    /// more than three bonds apart that the torsion tree lets move.
    pub fn new(collider: &'a Collider, rule: ContactRule, drug: &Molecule, lig: &Ligand) -> Self {
        let chem = drug.chemistry();
        let inner = chem
            .torsions
            .movable_pairs(&chem.adjacency)
            .into_iter()
            .filter(|&(a, b)| (a as usize) < lig.len() && (b as usize) < lig.len())
            .map(|(a, b)| {
                let (x, y) = (&drug.atoms[a as usize], &drug.atoms[b as usize]);
                InnerPair {
                    a,
                    b,
                    contact: f64::from(rule.contact_distance(x.radius, x.polar, y.radius, y.polar)),
                }
            })
            .collect();
        Self {
            collider,
            rule,
            shape: Molecule::new(
                drug.name.clone(),
                drug.atoms.clone(),
                &drug.file_positions(),
            ),
            groups: crate::collide::grouping::compact_order(&drug.local),
            inner,
        }
    }

    /// The drug atoms at positions `x` (receptor frame) prepared for the
    /// collider, and the pose that places them there.
    fn prepared(&mut self, x: &[DVec3]) -> (DrugAtoms, Pose) {
        let centre = x.iter().copied().sum::<DVec3>() / x.len().max(1) as f64;
        self.shape.centre = centre;
        self.shape.local.clear();
        self.shape
            .local
            .extend(x.iter().map(|p| (*p - centre).as_vec3()));
        let atoms = DrugAtoms::with_groups(
            &self.shape,
            &self.rule,
            self.collider.max_radius(),
            self.groups.clone(),
        );
        (atoms, Pose::from_translation(centre))
    }

    /// The drug atoms `subset` at positions `x`, prepared for the collider.
    fn prepared_subset(&self, x: &[DVec3], subset: &[u32]) -> (DrugAtoms, DVec3) {
        let atoms: Vec<_> = subset
            .iter()
            .map(|&i| self.shape.atoms[i as usize].clone())
            .collect();
        let pos: Vec<DVec3> = subset.iter().map(|&i| x[i as usize]).collect();
        let mol = Molecule::new(String::new(), atoms, &pos);
        let centre = mol.centre;
        (
            DrugAtoms::new(&mol, &self.rule, self.collider.max_radius()),
            centre,
        )
    }

    /// Calls `f(drug atom, receptor atom, receptor position, d², contact)`
    /// for every receptor–drug pair at positions `x` whose distance is at
    /// most its contact distance plus `extra` (d² and the contact distance
    /// in f32, as the collider's static check has them), drug atom by drug
    /// atom and, within one, in receptor atom order: the collider's search
    /// order changes once its background structures are built, and the
    /// penalty's sums must not (the same start settles bit for bit alike).
    fn near_pairs(&self, x: &[DVec3], extra: f32, mut f: impl FnMut(usize, u32, DVec3, f32, f32)) {
        let rule = &self.rule;
        let reach_extra = self.collider.max_radius() - rule.min_allowance() + extra.max(0.0);
        let mut hits: Vec<(u32, DVec3, f32, f32)> = Vec::new();
        for (i, xi) in x.iter().enumerate() {
            let a = &self.shape.atoms[i];
            hits.clear();
            self.collider
                .near(xi.as_vec3(), a.radius + reach_extra, |q, meta, d2| {
                    let (j, polar) = unpack_meta(meta);
                    let c = rule.contact_distance(a.radius, a.polar, q.w, polar);
                    if within(d2, c + extra) {
                        hits.push((j, q.truncate().as_dvec3(), d2, c));
                    }
                });
            hits.sort_unstable_by_key(|h| h.0);
            for &(j, q, d2, c) in &hits {
                f(i, j, q, d2, c);
            }
        }
    }

    /// Every collision at positions `x`: receptor pairs, then drug pairs.
    pub fn collisions(&mut self, x: &[DVec3]) -> Vec<Collision> {
        let mut out = Vec::new();
        self.near_pairs(x, 0.0, |i, j, _, d2, c| {
            out.push(Collision::Receptor(Pair {
                receptor: j,
                drug: i as u32,
                distance: reported_distance(d2, c),
                contact: c,
            }));
        });
        for p in &self.inner {
            let d = (x[p.a as usize] - x[p.b as usize]).length();
            if p.contact >= 0.0 && d <= p.contact {
                out.push(Collision::Inner {
                    a: p.a,
                    b: p.b,
                    distance: d,
                    contact: p.contact,
                });
            }
        }
        out
    }

    /// The escape penalty at positions `x`: `w·(c + m − d)²` for every pair
    /// closer than its contact distance `c` plus the margin `m`
    /// ([`ESCAPE_WEIGHT`], [`ESCAPE_MARGIN`]), with each atom's gradient
    /// added to `g`.
    fn penalty(&mut self, x: &[DVec3], g: &mut [DVec3]) -> f64 {
        let (w, m) = (ESCAPE_WEIGHT, ESCAPE_MARGIN);
        let mut e = 0.0;
        let push = |d: DVec3, c: f64| -> (f64, DVec3) {
            let dist = d.length();
            let over = c + m - dist;
            if over > 0.0 && c >= 0.0 {
                let f = if dist > 0.0 {
                    d * (2.0 * w * over / dist)
                } else {
                    DVec3::ZERO
                };
                (w * over * over, f)
            } else {
                (0.0, DVec3::ZERO)
            }
        };
        self.near_pairs(x, m as f32, |i, _, q, _, c| {
            let (v, f) = push(x[i] - q, f64::from(c));
            e += v;
            g[i] -= f;
        });
        for p in &self.inner {
            let (a, b) = (p.a as usize, p.b as usize);
            let (v, f) = push(x[a] - x[b], p.contact);
            e += v;
            g[a] -= f;
            g[b] += f;
        }
        e
    }

    /// True when no pair at positions `x` is within `gap` of colliding.
    fn clear_by(&self, x: &[DVec3], gap: f32) -> bool {
        let mut clear = true;
        self.near_pairs(x, gap, |_, _, _, _, _| clear = false);
        clear
            && self
                .inner
                .iter()
                .all(|p| (x[p.a as usize] - x[p.b as usize]).length() > p.contact + f64::from(gap))
    }

    /// Each atom's clearance from the receptor (its smallest gap, at most
    /// `margin`), and each drug pair's gap, at positions `x`.
    fn clearances(&mut self, x: &[DVec3], margin: f32, atoms: &mut Vec<f64>, pairs: &mut Vec<f64>) {
        atoms.clear();
        atoms.resize(x.len(), f64::from(margin));
        self.near_pairs(x, margin, |i, _, _, d2, c| {
            let g = &mut atoms[i];
            *g = g.min(f64::from(d2).sqrt() - f64::from(c));
        });
        pairs.clear();
        pairs.extend(
            self.inner
                .iter()
                .map(|p| (x[p.a as usize] - x[p.b as usize]).length() - p.contact),
        );
    }
}

/// What settle did.
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    /// The settled conformation.
    pub conf: Conformation,
    /// Vina's energies (table, curl) at the start.
    pub before: Energies,
    /// Vina's energies at the end.
    pub after: Energies,
    /// What was minimised at the start and the end: the continuous
    /// `inter + intra` plus the contact penalty (see the module docs).
    pub minimised: (f64, f64),
    /// Heavy-atom RMSD between the start and the end (Å).
    pub rmsd: f64,
    /// BFGS steps taken.
    pub steps: usize,
    /// Energy and gradient evaluations.
    pub evaluations: usize,
    /// Trials the contact rule refused.
    pub refused: usize,
    /// Trials that needed the collider's sweeps (the others were proved
    /// clear by their atoms' clearances).
    pub sweeps: usize,
    /// Collisions at the start.
    pub start_collisions: Vec<Collision>,
    /// Collisions at the end (empty unless the start collided and settle
    /// found no way out).
    pub end_collisions: Vec<Collision>,
    /// Steps taken from a colliding start before the first pose that
    /// collides nowhere (0 for a clear start).
    pub escape_steps: usize,
}

/// The heavy-atom RMSD between two placements of the same atoms.
pub fn rmsd(a: &[DVec3], b: &[DVec3]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length_squared())
        .sum();
    (s / a.len() as f64).sqrt()
}

/// The conformation `x ⊕ α p` (translation, rotation vector, torsions).
pub(crate) fn stepped(x: &Conformation, p: &[f64], alpha: f64) -> Conformation {
    let t = DVec3::new(p[0], p[1], p[2]) * alpha;
    let w = DVec3::new(p[3], p[4], p[5]) * alpha;
    let rotation = (DQuat::from_scaled_axis(w) * x.pose.rotation).normalize();
    let torsions = x
        .torsions
        .iter()
        .zip(&p[6..])
        .map(|(th, d)| wrap(th + alpha * d))
        .collect();
    Conformation {
        pose: Pose {
            rotation,
            translation: x.pose.translation + t,
        },
        torsions,
    }
}

/// An angle in (−π, π].
fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = a.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

/// The gradient as one vector: translation, rotation, torsions.
pub(crate) fn flat(g: &Gradient, out: &mut Vec<f64>) {
    out.clear();
    out.extend(g.translation.to_array());
    out.extend(g.rotation.to_array());
    out.extend(&g.torsions);
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The smallest squared distance between `p`, turned about the axis through
/// `a` along unit `u` by every angle between 0 and `phi`, and the fixed point
/// `q`; and the squared distance at the start.
fn min_turning_distance2(p: DVec3, q: DVec3, a: DVec3, u: DVec3, phi: f64) -> (f64, f64) {
    let v = p - a;
    let par = u * v.dot(u);
    let perp = v - par;
    let c = par - (q - a);
    // |c + cos φ perp + sin φ (u × perp)|² = A + B cos φ + C sin φ
    let big_a = c.length_squared() + perp.length_squared();
    let big_b = 2.0 * c.dot(perp);
    let big_c = 2.0 * c.dot(u.cross(perp));
    let at = |f: f64| big_a + big_b * f.cos() + big_c * f.sin();
    let start = at(0.0);
    let (lo, hi) = if phi < 0.0 { (phi, 0.0) } else { (0.0, phi) };
    let mut best = at(lo).min(at(hi));
    // The minimum of B cos φ + C sin φ is at φ0 + π, φ0 = atan2(C, B).
    let amp = big_b.hypot(big_c);
    if amp > 0.0 {
        let m = big_c.atan2(big_b) + std::f64::consts::PI;
        let tau = std::f64::consts::TAU;
        let k = ((lo - m) / tau).ceil();
        let candidate = m + k * tau;
        if candidate <= hi {
            best = best.min(big_a - amp);
        }
    }
    (best.max(0.0), start)
}

/// Working state of a settle run.
struct Run<'r, 'l, 'c> {
    lig: &'l Ligand,
    contacts: &'r mut Contacts<'c>,
    opts: SettleOptions,
    /// Clearances at the current conformation.
    atom_gap: Vec<f64>,
    pair_gap: Vec<f64>,
    frames: Vec<(DMat3, DVec3)>,
    /// Per rotatable bond, the atoms that turn with it, ascending.
    moving: Vec<Vec<u32>>,
    /// Working positions.
    xm: Vec<DVec3>,
    xb: Vec<DVec3>,
    refused: usize,
    sweeps: usize,
}

impl<'r, 'l, 'c> Run<'r, 'l, 'c> {
    /// A run of `lig` against `contacts`, nothing measured yet.
    fn new(lig: &'l Ligand, contacts: &'r mut Contacts<'c>, opts: &SettleOptions) -> Self {
        Run {
            lig,
            contacts,
            opts: *opts,
            atom_gap: Vec::new(),
            pair_gap: Vec::new(),
            frames: Vec::new(),
            moving: (0..lig.torsions()).map(|k| moving_atoms(lig, k)).collect(),
            xm: Vec::new(),
            xb: Vec::new(),
            refused: 0,
            sweeps: 0,
        }
    }

    /// The first step length tried along `p` from `x` (atoms at `xs`): no
    /// atom travels more than the step cap, and while free, a step the
    /// clearances prove clear (needing no sweep) is taken rather than a
    /// longer one that would need one, unless it is far shorter.
    fn first_alpha(&mut self, x: &Conformation, xs: &[DVec3], p: &[f64], free: bool) -> f64 {
        let cap = if free { MAX_STEP } else { ESCAPE_STEP };
        let full = stepped(x, p, 1.0);
        let longest = self.travel(x, xs, &full).into_iter().fold(0.0, f64::max);
        let mut alpha = if longest > cap { cap / longest } else { 1.0 };
        if free {
            let travel = self.travel(x, xs, &stepped(x, p, alpha));
            let proved = self.proved_fraction(&travel);
            if (PROVED_SHORTER..1.0).contains(&proved) {
                alpha *= proved * (1.0 - 1e-9);
            }
        }
        alpha
    }
    /// A bound on each atom's travel along the path from `a` (atoms at
    /// `xa`) to `b`: the turns (arc = angle × distance to the axis,
    /// measured before any turn: parents turn first and carry their
    /// children's axes along), then the rigid screw (chord ×
    /// `(θ/2)/sin(θ/2)`).
    fn travel(&mut self, a: &Conformation, xa: &[DVec3], b: &Conformation) -> Vec<f64> {
        let lig = self.lig;
        let n = lig.len();
        let mut travel = vec![0.0f64; n];
        for k in 0..lig.torsions() {
            let d = wrap(b.torsions[k] - a.torsions[k]);
            if d == 0.0 {
                continue;
            }
            let (o, u) = lig.torsion_axis(k, xa);
            for &i in &self.moving[k] {
                let v = xa[i as usize] - o;
                travel[i as usize] += d.abs() * (v - u * v.dot(u)).length();
            }
        }
        // The rigid piece: from A's pose with B's torsions to B.
        let turned = Conformation {
            pose: a.pose,
            torsions: b.torsions.clone(),
        };
        lig.place_into(&turned, &mut self.frames, &mut self.xm);
        lig.place_into(b, &mut self.frames, &mut self.xb);
        let dq = (b.pose.rotation * a.pose.rotation.conjugate()).normalize();
        let theta = 2.0 * dq.w.abs().min(1.0).acos();
        let stretch = if theta > 1e-9 {
            (theta / 2.0) / (theta / 2.0).sin()
        } else {
            1.0
        };
        for (t, (xb, xm)) in travel.iter_mut().zip(self.xb.iter().zip(&self.xm)) {
            *t += (*xb - *xm).length() * stretch;
        }
        travel
    }

    /// The largest fraction of the travels `travel` that the clearances
    /// prove clear (≥ 1: all of it), with room for their f32 rounding.
    fn proved_fraction(&self, travel: &[f64]) -> f64 {
        let ratio = |gap: f64, t: f64| {
            if t > 0.0 {
                (gap - PROOF_SLACK) / t
            } else {
                f64::INFINITY
            }
        };
        let atoms = (0..travel.len())
            .map(|i| ratio(self.atom_gap[i], travel[i]))
            .fold(f64::INFINITY, f64::min);
        let pairs = self
            .contacts
            .inner
            .iter()
            .zip(&self.pair_gap)
            .map(|(p, &g)| ratio(g, travel[p.a as usize] + travel[p.b as usize]))
            .fold(f64::INFINITY, f64::min);
        atoms.min(pairs)
    }

    /// True when the path from `a` (atoms at `xa`) to `b` collides nowhere.
    fn clear(&mut self, a: &Conformation, xa: &[DVec3], b: &Conformation) -> bool {
        let travel = self.travel(a, xa, b);
        if self.proved_fraction(&travel) > 1.0 {
            return true;
        }
        self.sweeps += 1;
        self.swept(a, xa, b)
    }

    /// The exact check of the path from `a` to `b` (see the module docs).
    fn swept(&mut self, a: &Conformation, xa: &[DVec3], b: &Conformation) -> bool {
        let lig = self.lig;
        let mut cur = a.clone();
        let mut x = xa.to_vec();
        for k in 0..lig.torsions() {
            let d = wrap(b.torsions[k] - a.torsions[k]);
            if d == 0.0 {
                continue;
            }
            let (o, u) = lig.torsion_axis(k, &x);
            let moving = &self.moving[k];
            // Drug pairs across the bond.
            for p in &self.contacts.inner {
                let (ma, mb) = (
                    moving.binary_search(&p.a).is_ok(),
                    moving.binary_search(&p.b).is_ok(),
                );
                if ma == mb {
                    continue;
                }
                let (m, f) = if ma { (p.a, p.b) } else { (p.b, p.a) };
                let (min2, _) = min_turning_distance2(x[m as usize], x[f as usize], o, u, d);
                if p.contact >= 0.0 && min2 <= p.contact * p.contact {
                    return false;
                }
            }
            // The moving atoms against the receptor, in turns of at most a
            // quarter turn (a screw between two poses takes the shorter way).
            let (atoms, centre) = self.contacts.prepared_subset(&x, moving);
            let parts = (d.abs() / std::f64::consts::FRAC_PI_2).ceil().max(1.0) as usize;
            for s in 0..parts {
                let at = |f: f64| {
                    let q = DQuat::from_axis_angle(u, d * f);
                    Pose::new(q, o + q * (centre - o))
                };
                let (p0, p1) = (
                    at(s as f64 / parts as f64),
                    at((s + 1) as f64 / parts as f64),
                );
                let r = move_to_touch(self.contacts.collider, &atoms, &p0, &p1, &self.opts.touch);
                if r.t < 1.0 {
                    return false;
                }
            }
            cur.torsions[k] = b.torsions[k];
            lig.place_into(&cur, &mut self.frames, &mut x);
        }
        // The rigid piece, in turns of at most a quarter turn too.
        let (atoms, start) = self.contacts.prepared(&x);
        let dq = (b.pose.rotation * a.pose.rotation.conjugate()).normalize();
        let centre = start.translation;
        let end = Pose::new(dq, dq * (centre - a.pose.translation) + b.pose.translation);
        let r = move_to_touch(
            self.contacts.collider,
            &atoms,
            &start,
            &end,
            &self.opts.touch,
        );
        r.t >= 1.0
    }
}

/// Settles the drug from `start`: see the module docs. `field` evaluates the
/// intermolecular energy (maps or exact); `contacts` holds the receptor's
/// collider.
pub fn settle<F: Field + ?Sized>(
    field: &F,
    lig: &Ligand,
    contacts: &mut Contacts<'_>,
    start: &Conformation,
    opts: &SettleOptions,
) -> Settled {
    let mut ws = Workspace::default();
    let before = energies(field, lig, start, &mut ws);
    let x0 = ws.positions.clone();
    let start_collisions = contacts.collisions(&x0);
    let mut run = Run::new(lig, contacts, opts);
    let n = 6 + lig.torsions();
    let mut grad = Gradient::default();
    let mut x = start.clone();
    let mut free = start_collisions.is_empty();
    // The energy, plus the escape penalty while not yet free.
    let mut extra = Gradient::default();
    let mut atom_g: Vec<DVec3> = Vec::new();
    let mut tree = Vec::new();
    let mut frames = Vec::new();
    let mut evaluate = |conf: &Conformation,
                        ws: &mut Workspace,
                        run: &mut Run<'_, '_, '_>,
                        push_only: bool,
                        out: &mut Vec<f64>|
     -> f64 {
        let mut f = if push_only {
            // The penalty alone: its positions, and no energy to pull back.
            lig.place_into(conf, &mut frames, &mut ws.positions);
            grad.translation = DVec3::ZERO;
            grad.rotation = DVec3::ZERO;
            grad.torsions.clear();
            grad.torsions.resize(lig.torsions(), 0.0);
            0.0
        } else {
            energy_gradient(field, lig, conf, ws, &mut grad).sum()
        };
        {
            atom_g.clear();
            atom_g.resize(ws.positions.len(), DVec3::ZERO);
            f += run.contacts.penalty(&ws.positions, &mut atom_g);
            lig.gradient(conf, &ws.positions, &atom_g, &mut tree, &mut extra);
            grad.translation += extra.translation;
            grad.rotation += extra.rotation;
            for (a, b) in grad.torsions.iter_mut().zip(&extra.torsions) {
                *a += b;
            }
        }
        flat(&grad, out);
        f
    };
    let mut g = Vec::with_capacity(n);
    // Out of a colliding start, the energy may hold the drug in an overlap
    // (an attraction balancing the penalty) or stall it there; then the
    // penalty alone pushes it out, and the energy returns once it is free.
    let mut push_only = false;
    let mut f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
    let minimised_start = f0;
    let mut xs = ws.positions.clone();
    let mut evaluations = 1;
    let mut h = identity(n);
    let mut steps = 0;
    let mut g_new = Vec::with_capacity(n);
    let mut escape_steps = 0;
    if free {
        run.contacts
            .clearances(&xs, opts.margin, &mut run.atom_gap, &mut run.pair_gap);
    }
    let mut restarted = false;
    while steps < opts.max_steps {
        let Some((p, pg)) = descent(&mut h, &g, n) else {
            if !free && !push_only && !run.contacts.collisions(&xs).is_empty() {
                push_only = true;
                f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
                evaluations += 1;
                continue;
            }
            break;
        };
        let mut alpha = run.first_alpha(&x, &xs, &p, free);
        let mut accepted = None;
        for _ in 0..10 {
            let trial = stepped(&x, &p, alpha);
            let allowed = if free {
                run.clear(&x, &xs, &trial)
            } else {
                // Out of a colliding start: short steps, no rule yet.
                run.travel(&x, &xs, &trial)
                    .iter()
                    .all(|&t| t <= ESCAPE_STEP)
            };
            if !allowed {
                run.refused += 1;
                alpha *= 0.5;
                continue;
            }
            let f1 = evaluate(&trial, &mut ws, &mut run, push_only, &mut g_new);
            evaluations += 1;
            if f1 - f0 < 1e-4 * alpha * pg {
                accepted = Some((trial, f1));
                break;
            }
            alpha *= 0.5;
        }
        let Some((trial, f1)) = accepted else {
            if !free && run.contacts.collisions(&xs).is_empty() {
                // Out of the overlaps but not clear by the escape margin,
                // and no farther: the rule holds from here.
                free = true;
                escape_steps = steps;
                run.contacts
                    .clearances(&xs, opts.margin, &mut run.atom_gap, &mut run.pair_gap);
                h = identity(n);
                if push_only {
                    push_only = false;
                    f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
                    evaluations += 1;
                }
                continue;
            }
            if restarted && !free && !push_only {
                push_only = true;
                restarted = false;
                h = identity(n);
                f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
                evaluations += 1;
                continue;
            }
            if restarted {
                break;
            }
            // Once more from steepest descent before giving up.
            restarted = true;
            h = identity(n);
            continue;
        };
        restarted = false;
        steps += 1;
        let decrease = f0 - f1;
        let y: Vec<f64> = g_new.iter().zip(&g).map(|(a, b)| a - b).collect();
        let s: Vec<f64> = p.iter().map(|v| v * alpha).collect();
        x = trial;
        f0 = f1;
        xs.clone_from(&ws.positions);
        std::mem::swap(&mut g, &mut g_new);
        if !free && run.contacts.clear_by(&xs, ESCAPE_CLEARANCE) {
            // Out, with room to move: from here the rule holds.
            free = true;
            escape_steps = steps;
            if push_only {
                push_only = false;
                h = identity(n);
                f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
                evaluations += 1;
                run.contacts
                    .clearances(&xs, opts.margin, &mut run.atom_gap, &mut run.pair_gap);
                continue;
            }
        }
        if free {
            run.contacts
                .clearances(&xs, opts.margin, &mut run.atom_gap, &mut run.pair_gap);
        }
        if decrease < opts.min_decrease || dot(&g, &g).sqrt() < 1e-5 {
            if !free && !push_only && !run.contacts.collisions(&xs).is_empty() {
                push_only = true;
                h = identity(n);
                f0 = evaluate(&x, &mut ws, &mut run, push_only, &mut g);
                evaluations += 1;
                continue;
            }
            break;
        }
        bfgs_update(&mut h, &s, &y, steps == 1);
    }
    let minimised_end = if push_only {
        evaluations += 1;
        evaluate(&x, &mut ws, &mut run, false, &mut g)
    } else {
        f0
    };
    let after = energies(field, lig, &x, &mut ws);
    let end_collisions = if free {
        Vec::new()
    } else {
        run.contacts.collisions(&ws.positions)
    };
    Settled {
        rmsd: rmsd(&x0, &ws.positions),
        conf: x,
        before,
        after,
        minimised: (minimised_start, minimised_end),
        steps,
        evaluations,
        refused: run.refused,
        sweeps: run.sweeps,
        start_collisions,
        end_collisions,
        escape_steps,
    }
}

/// The atoms that turn with rotatable bond `k`: those of its fragment and
/// the fragments below it, ascending.
fn moving_atoms(lig: &Ligand, k: usize) -> Vec<u32> {
    let f = lig.torsion_fragment(k) as u32;
    let mut below = vec![false; lig.fragments.len()];
    for (g, frag) in lig.fragments.iter().enumerate() {
        // Parents come before their children.
        below[g] = g as u32 == f || frag.parent.is_some_and(|p| below[p as usize]);
    }
    (0..lig.len() as u32)
        .filter(|&i| below[lig.fragment_of[i as usize] as usize])
        .collect()
}

/// The quasi-Newton direction `-H g` and its slope `p · g`, or steepest
/// descent (with `h` reset) when that is not a descent direction; `None`
/// when neither descends.
pub(crate) fn descent(h: &mut Vec<f64>, g: &[f64], n: usize) -> Option<(Vec<f64>, f64)> {
    let p: Vec<f64> = (0..n).map(|i| -dot(&h[i * n..(i + 1) * n], g)).collect();
    let pg = dot(&p, g);
    if pg < 0.0 {
        return Some((p, pg));
    }
    *h = identity(n);
    let p: Vec<f64> = g.iter().map(|v| -v).collect();
    let pg = dot(&p, g);
    (pg < 0.0).then_some((p, pg))
}

pub(crate) fn identity(n: usize) -> Vec<f64> {
    let mut h = vec![0.0; n * n];
    for i in 0..n {
        h[i * n + i] = 1.0;
    }
    h
}

/// Vina's BFGS update of the inverse Hessian `h` (row-major, symmetric) with
/// step `s` and gradient change `y`; the first step scales `h` first.
pub(crate) fn bfgs_update(h: &mut [f64], s: &[f64], y: &[f64], first: bool) {
    let n = s.len();
    let ys = dot(y, s);
    let yy = dot(y, y);
    if first && yy > 1e-12 && ys > 0.0 {
        let scale = ys / yy;
        h.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..n {
            h[i * n + i] = scale;
        }
    }
    if ys <= 1e-12 {
        return;
    }
    let hy: Vec<f64> = (0..n).map(|i| dot(&h[i * n..(i + 1) * n], y)).collect();
    let yhy = dot(y, &hy);
    let r = 1.0 / ys;
    for i in 0..n {
        for j in 0..n {
            h[i * n + j] += -r * (hy[i] * s[j] + s[i] * hy[j]) + (r * r * yhy + r) * s[i] * s[j];
        }
    }
}

/// A copy of `drug` whose heavy atoms and hydrogens are placed at `conf`'s
/// torsions (in the drug's own frame; place it with `conf.pose`), for
/// writing the settled drug with its bonds and hydrogens.
pub fn settled_molecule(drug: &Molecule, lig: &Ligand, torsions: &[f64]) -> Molecule {
    let conf = Conformation {
        pose: Pose::IDENTITY,
        torsions: torsions.to_vec(),
    };
    let mut frames = Vec::new();
    lig.frames_into(&conf, &mut frames);
    let mut out = drug.clone();
    for (i, p) in out.local.iter_mut().enumerate() {
        if let Some(&f) = lig.fragment_of.get(i) {
            let (m, t) = frames[f as usize];
            *p = (m * p.as_dvec3() + t).as_vec3();
        }
    }
    for (k, p) in out.hydrogens.local.iter_mut().enumerate() {
        let parent = out.hydrogens.parent.get(k).copied().unwrap_or(u32::MAX) as usize;
        if let Some(&f) = lig.fragment_of.get(parent) {
            let (m, t) = frames[f as usize];
            *p = (m * p.as_dvec3() + t).as_vec3();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn the_closest_approach_of_a_turn_is_found_exactly() {
        let a = DVec3::ZERO;
        let u = DVec3::Z;
        let p = DVec3::new(2.0, 0.0, 0.0);
        let q = DVec3::new(-3.0, 0.0, 1.0);
        // Half a turn brings p to (−2, 0, 0): 1² + 1² from q.
        let (min2, start2) = min_turning_distance2(p, q, a, u, std::f64::consts::PI);
        assert!((min2 - 2.0).abs() < 1e-12);
        assert!((start2 - 26.0).abs() < 1e-12);
        // A quarter turn either way does not get there.
        let (min2, _) = min_turning_distance2(p, q, a, u, std::f64::consts::FRAC_PI_2);
        assert!((min2 - (9.0 + 4.0 + 1.0)).abs() < 1e-12);
        let (min2, _) = min_turning_distance2(p, q, a, u, -std::f64::consts::FRAC_PI_2);
        assert!((min2 - 14.0).abs() < 1e-12);
        // Compared with a dense sampling of random turns.
        let mut rng = crate::rng::Rng(4);
        for _ in 0..200 {
            let (p, q, a) = (
                rng.in_box(DVec3::ONE * 3.0),
                rng.in_box(DVec3::ONE * 3.0),
                rng.in_box(DVec3::ONE),
            );
            let u = rng.unit();
            let phi = rng.range(-4.0, 4.0);
            let (min2, _) = min_turning_distance2(p, q, a, u, phi);
            let sampled = (0..=4000)
                .map(|k| {
                    let f = phi * k as f64 / 4000.0;
                    let r = DQuat::from_axis_angle(u, f) * (p - a) + a;
                    (r - q).length_squared()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                min2 <= sampled + 1e-9 && sampled - min2 < 1e-4,
                "{min2} {sampled}"
            );
        }
    }

    #[test]
    fn bfgs_keeps_the_inverse_hessian_symmetric() {
        let mut h = identity(3);
        bfgs_update(&mut h, &[0.1, -0.2, 0.3], &[0.5, 0.1, 0.4], true);
        for i in 0..3 {
            for j in 0..3 {
                assert!((h[i * 3 + j] - h[j * 3 + i]).abs() < 1e-12);
            }
        }
    }
}
