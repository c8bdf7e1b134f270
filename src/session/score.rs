//! The live score: the drug's AutoDock Vina score against the receptor,
//! term by term, with its hydrogen bonds, each atom's contribution (the
//! drug's and the receptor's within 8 Å) and the heavy-atom RMSD to a
//! reference pose.
//!
//! It is computed here, in the core, at the end of a frame whose outcome
//! says something changed, and only when the drug's pose relative to the
//! receptor differs from the one last scored: a frame in which nothing
//! moved (or only the camera did) computes nothing. The frame's outcome
//! carries the new score; the window only shows it. The typed atoms are
//! prepared once, on the first score after the molecules change.
//!
//! The reference pose is the drug's file pose relative to the receptor's
//! (the crystal pose when both came from one complex), or the pose the
//! user pinned.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use super::torsion::Flex;
use super::{Body, Role};
use crate::model::element::is_hydrogen;
use crate::motion::Pose;
use crate::score::{
    Conformation, Evaluator, Exact, Ligand, Receptor, Score, Scoring, prepare,
    score_with_contributions,
};

/// One frame's score of the drug against the receptor.
#[derive(Debug, Clone)]
pub struct LiveScore {
    /// The drug's molecule index.
    pub drug: usize,
    /// The receptor's molecule index.
    pub receptor: usize,
    /// The score: totals, terms, the drug's atoms, the hydrogen bonds.
    pub score: Score,
    /// `(receptor atom, energy)` for the receptor atoms within 8 Å of the
    /// drug ([`crate::score::contrib::receptor_contributions`]).
    pub receptor_atoms: Vec<(u32, f64)>,
    /// The drug's rotatable bonds.
    pub rotatable: usize,
    /// Heavy-atom RMSD to the reference pose, Å: the least over the swaps
    /// of atoms the drug's bond graph cannot tell apart
    /// ([`crate::chem::symmetry`]).
    pub rmsd: f64,
    /// The reference is a pose the user pinned (else the file pose).
    pub pinned: bool,
    /// How long the score took, µs.
    pub micros: f64,
}

impl LiveScore {
    /// The drug atoms' contributions as `(atom, energy)`, in atom order.
    pub fn drug_atoms(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.score.atoms.iter().map(|a| (a.atom, a.inter))
    }
}

/// The typed atoms of one drug and receptor pair.
#[derive(Debug, Clone)]
struct Prepared {
    drug: usize,
    receptor: usize,
    ligand: Arc<Ligand>,
    atoms: Arc<Receptor>,
    /// The drug's heavy atoms (for the RMSD).
    heavy: Arc<Vec<usize>>,
    /// The swaps of those atoms that keep elements and bonds: the RMSD is
    /// the least over them.
    swaps: Arc<Vec<Vec<u32>>>,
}

/// The live score's state in a session.
#[derive(Debug, Clone, Default)]
pub(super) struct LiveScoring {
    on: bool,
    prepared: Option<Prepared>,
    /// Set when the molecules changed: the next frame prepares and scores.
    stale: bool,
    /// The relative pose and drug shape (its generation) last scored.
    scored_at: Option<(Pose, u64)>,
    /// The pinned reference (relative pose and torsions), if any.
    pinned: Option<(Pose, Vec<f64>)>,
    last: Option<Arc<LiveScore>>,
    /// The last failure, said once.
    failed: bool,
}

/// The drug and the receptor to score it against: the session's drug and
/// the first other molecule that is a receptor (else the first other one).
fn pair(
    bodies: &[Body],
    drug: Option<usize>,
    role: impl Fn(usize) -> Option<Role>,
) -> Option<(usize, usize)> {
    let d = drug?;
    let others = || (0..bodies.len()).filter(move |&k| k != d);
    let r = others()
        .find(|&k| role(k) == Some(Role::Receptor))
        .or_else(|| others().next())?;
    Some((d, r))
}

/// The torsions drug `d` is at (the file's when it is not flexible).
fn torsions_of(flex: &[Option<Flex>], d: usize, ligand: &Ligand) -> Vec<f64> {
    match flex.get(d).and_then(Option::as_ref) {
        Some(f) if f.torsions.len() == ligand.torsions() => f.torsions.clone(),
        _ => vec![0.0; ligand.torsions()],
    }
}

/// Heavy-atom RMSD between the same local atoms placed by `a` and by `b`.
pub fn rmsd(local: &[DVec3], a: &Pose, b: &Pose) -> f64 {
    if local.is_empty() {
        return 0.0;
    }
    let sum: f64 = local
        .iter()
        .map(|p| (a.transform_point(*p) - b.transform_point(*p)).length_squared())
        .sum();
    (sum / local.len() as f64).sqrt()
}

impl LiveScoring {
    /// Switches the live score on (it is then computed on the next frame).
    pub(super) fn enable(&mut self) {
        self.on = true;
        self.stale = true;
    }

    pub(super) fn is_on(&self) -> bool {
        self.on
    }

    /// The molecules changed: prepare again on the next frame.
    pub(super) fn reset(&mut self) {
        self.prepared = None;
        self.scored_at = None;
        self.pinned = None;
        self.last = None;
        self.stale = true;
    }

    pub(super) fn last(&self) -> Option<&Arc<LiveScore>> {
        self.last.as_ref()
    }

    /// Pins the drug's current pose and conformation as the reference;
    /// `false` without a score.
    pub(super) fn pin(&mut self, bodies: &[Body], flex: &[Option<Flex>]) -> bool {
        let Some(p) = &self.prepared else {
            return false;
        };
        let rel = bodies[p.receptor]
            .pose
            .inverse()
            .compose(&bodies[p.drug].pose);
        self.pinned = Some((rel, torsions_of(flex, p.drug, &p.ligand)));
        self.stale = true;
        true
    }

    /// The pinned torsions, when drug `d` is the one pinned.
    pub(super) fn pinned_torsions(&self, d: usize) -> Option<&[f64]> {
        let p = self.prepared.as_ref()?;
        let (_, torsions) = self.pinned.as_ref()?;
        (p.drug == d).then_some(torsions.as_slice())
    }

    /// The reference pose (relative), when prepared.
    pub(super) fn reference(&self, bodies: &[Body]) -> Option<(usize, usize, Pose)> {
        let p = self.prepared.as_ref()?;
        let file = bodies[p.receptor]
            .loaded
            .inverse()
            .compose(&bodies[p.drug].loaded);
        Some((
            p.drug,
            p.receptor,
            self.pinned.as_ref().map_or(file, |x| x.0),
        ))
    }

    /// Scores the drug when it moved relative to the receptor (or the
    /// molecules changed); returns the new score, or `None` when nothing
    /// was computed. Failures are said once in `messages`.
    pub(super) fn update(
        &mut self,
        changed: bool,
        bodies: &[Body],
        flex: &[Option<Flex>],
        drug: Option<usize>,
        role: impl Fn(usize) -> Option<Role>,
        messages: &mut Vec<String>,
    ) -> Option<Arc<LiveScore>> {
        if !self.on || !(changed || self.stale) {
            return None;
        }
        let (d, r) = pair(bodies, drug, role)?;
        if self
            .prepared
            .as_ref()
            .is_none_or(|p| (p.drug, p.receptor) != (d, r))
        {
            self.prepared = None;
            self.scored_at = None;
            self.pinned = None;
            // A flexible drug's ligand is prepared from its file shape, and
            // scored at its torsions.
            let ligand = match flex.get(d).and_then(Option::as_ref) {
                Some(f) => Ok(Arc::clone(&f.ligand)),
                None => prepare::ligand(&bodies[d].molecule).map(Arc::new),
            };
            match ligand {
                Ok(l) => {
                    let m = &bodies[d].molecule;
                    let heavy = m
                        .atoms
                        .iter()
                        .enumerate()
                        .filter(|(_, a)| !is_hydrogen(&a.element))
                        .map(|(i, _)| i)
                        .collect();
                    self.prepared = Some(Prepared {
                        drug: d,
                        receptor: r,
                        ligand: l,
                        atoms: Arc::new(prepare::receptor(&bodies[r].molecule)),
                        heavy: Arc::new(heavy),
                        swaps: Arc::new(crate::chem::symmetry::heavy_swaps(m)),
                    });
                    self.failed = false;
                }
                Err(e) => {
                    if !self.failed {
                        messages.push(format!("no live score: {e}"));
                        self.failed = true;
                    }
                    return None;
                }
            }
        }
        let p = self.prepared.as_ref()?;
        let rel = bodies[r].pose.inverse().compose(&bodies[d].pose);
        let generation = flex
            .get(d)
            .and_then(Option::as_ref)
            .map_or(0, |f| f.generation);
        if !self.stale && self.scored_at == Some((rel, generation)) {
            return None;
        }
        self.stale = false;
        self.scored_at = Some((rel, generation));
        let t0 = Instant::now();
        let exact = Exact::new(&p.atoms, Scoring::Vina);
        let conf = Conformation {
            pose: rel,
            torsions: torsions_of(flex, d, &p.ligand),
        };
        let (s, receptor_atoms) =
            score_with_contributions(&exact, Evaluator::Exact, &exact, &p.ligand, &conf);
        let x = p.ligand.place(&conf);
        let file = bodies[r].loaded.inverse().compose(&bodies[d].loaded);
        let reference = match &self.pinned {
            Some((pose, torsions)) => p.ligand.place(&Conformation {
                pose: *pose,
                torsions: torsions.clone(),
            }),
            None => p.ligand.place(&p.ligand.rigid(file)),
        };
        let live = Arc::new(LiveScore {
            drug: d,
            receptor: r,
            score: s,
            receptor_atoms,
            rotatable: p.ligand.torsions(),
            rmsd: crate::chem::symmetry::rmsd_over(
                &p.swaps,
                &p.heavy.iter().map(|&i| x[i]).collect::<Vec<_>>(),
                &p.heavy.iter().map(|&i| reference[i]).collect::<Vec<_>>(),
            ),
            pinned: self.pinned.is_some(),
            micros: t0.elapsed().as_secs_f64() * 1e6,
        });
        self.last = Some(live.clone());
        Some(live)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn rmsd_of_a_shift_is_its_length() {
        let local = [DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, -2.0)];
        let a = Pose::from_translation(DVec3::ZERO);
        let b = Pose::from_translation(DVec3::new(0.0, 3.0, 4.0));
        assert!((rmsd(&local, &a, &b) - 5.0).abs() < 1e-12);
        assert_eq!(rmsd(&local, &a, &a), 0.0);
        // A turn about an atom leaves that atom in place.
        let t = Pose::new(DQuat::from_rotation_z(std::f64::consts::PI), DVec3::ZERO);
        let r = rmsd(&[DVec3::X], &a, &t);
        assert!((r - 2.0).abs() < 1e-12);
    }
}
