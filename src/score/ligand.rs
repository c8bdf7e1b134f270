//! The drug as the scoring sees it: typed heavy atoms, its torsion tree, its
//! intramolecular pairs and Vina's torsion count, and its conformations.
//!
//! A [`Ligand`] holds the drug's heavy atoms in the drug's own frame (relative
//! to its centre, as [`crate::model::Molecule`] stores them), split into rigid
//! [`Fragment`]s joined by rotatable bonds: fragment 0 is the root, every
//! other fragment hangs from an earlier one by one bond (parent atom in the
//! parent, child atom in the child). A [`Conformation`] is the drug's pose
//! relative to the receptor plus one angle per rotatable bond, added to the
//! angle the bond has as loaded: turning bond `k` by `θ` turns the child
//! fragment and everything below it about the axis from the parent atom to
//! the child atom, right-handed.
//!
//! The intramolecular pairs are Vina's (`model::initialize_pairs`,
//! `docs/vina-scoring.md` §6): two scored atoms more than three bonds apart
//! whose distance the tree lets vary — not in one fragment, and neither an
//! axis atom of a bond with the atoms that bond carries (the chemistry's
//! [`crate::chem::TorsionTree::vina_pairs`]).

use glam::{DMat3, DQuat, DVec3};

use crate::chem::XsType;
use crate::motion::Pose;

/// A rigid fragment of the drug: a node of the torsion tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// The parent fragment (an earlier index); `None` for a root.
    pub parent: Option<u32>,
    /// The rotatable bond to the parent: the atom in the parent and the atom
    /// in this fragment (heavy-atom indices); `None` for a root.
    pub bond: Option<[u32; 2]>,
    /// This fragment's heavy atoms.
    pub atoms: Vec<u32>,
}

/// Why a drug's parts do not make a ligand.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LigandError {
    /// Per-atom lists of different lengths.
    #[error("{what} has {got} entries for {atoms} atoms")]
    Length {
        /// Which list.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The number of atoms.
        atoms: usize,
    },
    /// A fragment refers to an atom or fragment that does not exist, or is
    /// not after its parent, or a bond's atoms are not in the fragments it
    /// joins, or an atom is in no fragment or in two.
    #[error("torsion tree: {0}")]
    Tree(String),
}

/// A drug prepared for scoring.
#[derive(Debug, Clone)]
pub struct Ligand {
    /// Heavy-atom positions in the drug's frame (relative to its centre), as
    /// loaded.
    pub local: Vec<DVec3>,
    /// The torsion tree's fragments, parents before children.
    pub fragments: Vec<Fragment>,
    /// Per heavy atom, its fragment.
    pub fragment_of: Vec<u32>,
    /// The scored atoms (those with an X-Score type), ascending.
    pub scored: Vec<u32>,
    /// Per scored atom, its type.
    pub xs: Vec<XsType>,
    /// Per heavy atom, its partial charge (e), for the Coulomb term.
    pub charges: Vec<f64>,
    /// Intramolecular pairs, as indices into `scored`.
    pub pairs: Vec<[u32; 2]>,
    /// Vina's torsion count `N_tors`.
    pub torsion_count: f64,
    /// Per rotatable bond (in fragment order): its fragment.
    torsion_fragment: Vec<u32>,
    /// Per fragment: the parent atom's loaded position and the unit axis
    /// towards the child atom (zero for roots).
    axis: Vec<(DVec3, DVec3)>,
}

/// A drug's conformation: its pose relative to the receptor and the turn of
/// each rotatable bond from its loaded angle.
#[derive(Debug, Clone, PartialEq)]
pub struct Conformation {
    /// The drug's pose (its frame → the receptor's frame).
    pub pose: Pose,
    /// Per rotatable bond, radians added to the loaded angle.
    pub torsions: Vec<f64>,
}

impl Conformation {
    /// The loaded conformation at `pose`.
    pub fn rigid(pose: Pose, torsions: usize) -> Self {
        Self {
            pose,
            torsions: vec![0.0; torsions],
        }
    }
}

/// The derivative of an energy with respect to a conformation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Gradient {
    /// `∂E/∂T` for a translation `T` of the whole drug (kcal/mol/Å); the
    /// force is its negative.
    pub translation: DVec3,
    /// `∂E/∂ω` for a small rotation `ω` (axis × radians) of the whole drug
    /// about its centre (kcal/mol/rad); the torque is its negative.
    pub rotation: DVec3,
    /// `∂E/∂θ_k` per rotatable bond (kcal/mol/rad); the torque about the
    /// bond is its negative.
    pub torsions: Vec<f64>,
}

impl Gradient {
    /// The force on the drug as a rigid body (kcal/mol/Å).
    pub fn force(&self) -> DVec3 {
        -self.translation
    }

    /// The torque on the drug about its centre (kcal/mol/rad).
    pub fn torque(&self) -> DVec3 {
        -self.rotation
    }

    /// The torque about each rotatable bond, positive when it would turn
    /// the bond forwards (kcal/mol/rad).
    pub fn torsion_torques(&self) -> Vec<f64> {
        self.torsions.iter().map(|g| -g).collect()
    }
}

impl Ligand {
    /// A ligand from its parts, with its intramolecular pairs and torsion
    /// count given (as Vina recorded them, for instance).
    ///
    /// `local`, `xs` and `charges` are per heavy atom; atoms whose type is
    /// `None` move with their fragment but are not scored; `pairs` index
    /// heavy atoms.
    ///
    /// # Errors
    /// When the lists disagree in length or the tree is malformed.
    pub fn from_parts(
        local: Vec<DVec3>,
        fragments: Vec<Fragment>,
        xs: &[Option<XsType>],
        charges: Vec<f64>,
        pairs: &[[u32; 2]],
        torsion_count: f64,
    ) -> Result<Self, LigandError> {
        let n = local.len();
        for (what, got) in [("types", xs.len()), ("charges", charges.len())] {
            if got != n {
                return Err(LigandError::Length {
                    what,
                    got,
                    atoms: n,
                });
            }
        }
        let fragment_of = check_tree(n, &fragments)?;
        let mut scored = Vec::new();
        let mut types = Vec::new();
        let mut slot = vec![u32::MAX; n];
        for (i, t) in xs.iter().enumerate() {
            if let Some(t) = t {
                slot[i] = scored.len() as u32;
                scored.push(i as u32);
                types.push(*t);
            }
        }
        let mut kept = Vec::with_capacity(pairs.len());
        for &[a, b] in pairs {
            let (a, b) = (a as usize, b as usize);
            if a >= n || b >= n {
                return Err(LigandError::Tree(format!(
                    "pair ({a}, {b}) beyond {n} atoms"
                )));
            }
            if slot[a] != u32::MAX && slot[b] != u32::MAX {
                kept.push([slot[a], slot[b]]);
            }
        }
        let axis = fragments
            .iter()
            .map(|f| match f.bond {
                Some([a, b]) => {
                    let pa = local[a as usize];
                    (pa, (local[b as usize] - pa).normalize_or_zero())
                }
                None => (DVec3::ZERO, DVec3::ZERO),
            })
            .collect();
        let torsion_fragment = fragments
            .iter()
            .enumerate()
            .filter(|(_, f)| f.bond.is_some())
            .map(|(k, _)| k as u32)
            .collect();
        Ok(Self {
            local,
            fragments,
            fragment_of,
            scored,
            xs: types,
            charges,
            pairs: kept,
            torsion_count,
            torsion_fragment,
            axis,
        })
    }

    /// Number of heavy atoms.
    pub fn len(&self) -> usize {
        self.local.len()
    }

    /// True when the drug has no heavy atoms.
    pub fn is_empty(&self) -> bool {
        self.local.is_empty()
    }

    /// Number of rotatable bonds.
    pub fn torsions(&self) -> usize {
        self.torsion_fragment.len()
    }

    /// The rotatable bonds (parent atom, child atom), in torsion order.
    pub fn rotatable_bonds(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        self.torsion_fragment
            .iter()
            .filter_map(|&f| self.fragments[f as usize].bond)
    }

    /// The fragment turned by rotatable bond `k`.
    pub fn torsion_fragment(&self, k: usize) -> usize {
        self.torsion_fragment[k] as usize
    }

    /// Rotatable bond `k`'s axis with the atoms at `x`: its parent atom and
    /// the unit direction from there to its child atom.
    pub fn torsion_axis(&self, k: usize, x: &[DVec3]) -> (DVec3, DVec3) {
        let [pa, pb] = self.fragments[self.torsion_fragment(k)]
            .bond
            .unwrap_or([0, 0]);
        let o = x[pa as usize];
        (o, (x[pb as usize] - o).normalize_or_zero())
    }

    /// The loaded conformation at `pose`.
    pub fn rigid(&self, pose: Pose) -> Conformation {
        Conformation::rigid(pose, self.torsions())
    }

    /// Each fragment's placement (rotation, translation) in the receptor's
    /// frame at `conf`: atom `i` of fragment `f` sits at
    /// `rotation_f · local_i + translation_f`.
    pub fn frames_into(&self, conf: &Conformation, out: &mut Vec<(DMat3, DVec3)>) {
        out.clear();
        let root = (DMat3::from_quat(conf.pose.rotation), conf.pose.translation);
        let mut k = 0;
        for (f, frag) in self.fragments.iter().enumerate() {
            let frame = match frag.parent {
                None => root,
                Some(p) => {
                    let (mp, tp) = out[p as usize];
                    let theta = conf.torsions.get(k).copied().unwrap_or(0.0);
                    k += 1;
                    let (a0, u0) = self.axis[f];
                    let m = mp * DMat3::from_quat(DQuat::from_scaled_axis(u0 * theta));
                    (m, mp * a0 + tp - m * a0)
                }
            };
            out.push(frame);
        }
    }

    /// Heavy-atom positions in the receptor's frame at `conf`, written into
    /// `out`; `frames` is working storage.
    pub fn place_into(
        &self,
        conf: &Conformation,
        frames: &mut Vec<(DMat3, DVec3)>,
        out: &mut Vec<DVec3>,
    ) {
        self.frames_into(conf, frames);
        out.clear();
        out.extend(self.local.iter().zip(&self.fragment_of).map(|(y, &f)| {
            let (m, t) = frames[f as usize];
            m * *y + t
        }));
    }

    /// Heavy-atom positions in the receptor's frame at `conf`.
    pub fn place(&self, conf: &Conformation) -> Vec<DVec3> {
        let (mut frames, mut out) = (Vec::new(), Vec::new());
        self.place_into(conf, &mut frames, &mut out);
        out
    }

    /// The conformation's gradient from per-atom gradients `g` (`∂E/∂x_i`
    /// per heavy atom, in the receptor's frame) at positions `x` (from
    /// [`Self::place`] at `conf`). `work` is working storage.
    pub fn gradient(
        &self,
        conf: &Conformation,
        x: &[DVec3],
        g: &[DVec3],
        work: &mut Vec<(DVec3, DVec3)>,
        out: &mut Gradient,
    ) {
        // Per fragment: Σ g and Σ x × g (the torque about the origin), then
        // each subtree's sums, children into parents.
        work.clear();
        work.resize(self.fragments.len(), (DVec3::ZERO, DVec3::ZERO));
        for (i, (&f, gi)) in self.fragment_of.iter().zip(g).enumerate() {
            let w = &mut work[f as usize];
            w.0 += *gi;
            w.1 += x[i].cross(*gi);
        }
        out.torsions.clear();
        out.torsions.resize(self.torsions(), 0.0);
        let mut k = self.torsions();
        for f in (0..self.fragments.len()).rev() {
            let frag = &self.fragments[f];
            let (force, moment) = work[f];
            if let (Some(p), Some([a, b])) = (frag.parent, frag.bond) {
                k -= 1;
                let (pa, pb) = (x[a as usize], x[b as usize]);
                let u = (pb - pa).normalize_or_zero();
                out.torsions[k] = u.dot(moment - pa.cross(force));
                let w = &mut work[p as usize];
                w.0 += force;
                w.1 += moment;
            }
        }
        let (mut force, mut moment) = (DVec3::ZERO, DVec3::ZERO);
        for (f, frag) in self.fragments.iter().enumerate() {
            if frag.parent.is_none() {
                force += work[f].0;
                moment += work[f].1;
            }
        }
        out.translation = force;
        out.rotation = moment - conf.pose.translation.cross(force);
    }
}

/// Checks the tree and returns each atom's fragment.
fn check_tree(n: usize, fragments: &[Fragment]) -> Result<Vec<u32>, LigandError> {
    let mut fragment_of = vec![u32::MAX; n];
    for (f, frag) in fragments.iter().enumerate() {
        for &a in &frag.atoms {
            let Some(slot) = fragment_of.get_mut(a as usize) else {
                return Err(LigandError::Tree(format!(
                    "fragment {f}: atom {a} beyond {n}"
                )));
            };
            if *slot != u32::MAX {
                return Err(LigandError::Tree(format!(
                    "atom {a} in fragments {} and {f}",
                    *slot
                )));
            }
            *slot = f as u32;
        }
    }
    if let Some(a) = fragment_of.iter().position(|&f| f == u32::MAX) {
        return Err(LigandError::Tree(format!("atom {a} is in no fragment")));
    }
    for (f, frag) in fragments.iter().enumerate() {
        match (frag.parent, frag.bond) {
            (None, None) => {}
            (Some(p), Some([a, b])) => {
                let ok = (p as usize) < f
                    && fragment_of[a as usize] == p
                    && fragment_of[b as usize] == f as u32;
                if !ok {
                    return Err(LigandError::Tree(format!(
                        "fragment {f}: bond ({a}, {b}) does not join it to its parent {p}"
                    )));
                }
            }
            _ => {
                return Err(LigandError::Tree(format!(
                    "fragment {f}: a parent needs a bond and a bond a parent"
                )));
            }
        }
    }
    Ok(fragment_of)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// A chain of six carbons, 0-1-2-3-4-5, along a zigzag, with rotatable
    /// bonds 1-2 and 3-4: fragments {0,1}, {2,3}, {4,5}.
    fn chain() -> Ligand {
        let local: Vec<DVec3> = (0..6)
            .map(|i| {
                DVec3::new(
                    1.25 * i as f64,
                    if i % 2 == 0 { 0.0 } else { 0.9 },
                    0.1 * i as f64,
                )
            })
            .collect();
        let fragments = vec![
            Fragment {
                parent: None,
                bond: None,
                atoms: vec![0, 1],
            },
            Fragment {
                parent: Some(0),
                bond: Some([1, 2]),
                atoms: vec![2, 3],
            },
            Fragment {
                parent: Some(1),
                bond: Some([3, 4]),
                atoms: vec![4, 5],
            },
        ];
        // Vina's pairs: more than three bonds apart and free to move.
        let pairs = [[0, 4], [0, 5], [1, 5]];
        Ligand::from_parts(
            local,
            fragments,
            &[Some(XsType::C_H); 6],
            vec![0.0; 6],
            &pairs,
            2.0,
        )
        .expect("a valid chain")
    }

    #[test]
    fn turning_a_bond_moves_its_subtree_about_the_axis() {
        let lig = chain();
        let pose = Pose::new(DQuat::from_rotation_y(0.3), DVec3::new(5.0, -2.0, 1.0));
        let x0 = lig.place(&lig.rigid(pose));
        let mut conf = lig.rigid(pose);
        conf.torsions[0] = 1.0;
        let x1 = lig.place(&conf);
        for i in 0..3 {
            assert!((x0[i] - x1[i]).length() < 1e-12);
        }
        // Distances to the axis atoms are kept; the far atoms moved.
        for i in 3..6 {
            assert!(((x1[i] - x1[1]).length() - (x0[i] - x0[1]).length()).abs() < 1e-12);
            assert!(((x1[i] - x1[2]).length() - (x0[i] - x0[2]).length()).abs() < 1e-12);
        }
        assert!((x0[5] - x1[5]).length() > 0.5);
    }

    #[test]
    fn the_gradient_matches_finite_differences() {
        // E = Σ_i c_i · x_i (a linear field) plus |x_0 − x_5|².
        let lig = chain();
        let c: Vec<DVec3> = (0..6)
            .map(|i| DVec3::new(0.3 * i as f64 - 1.0, 0.7, -0.2 * i as f64))
            .collect();
        let energy = |conf: &Conformation| {
            let x = lig.place(conf);
            x.iter().zip(&c).map(|(x, c)| x.dot(*c)).sum::<f64>() + (x[0] - x[5]).length_squared()
        };
        let pose = Pose::new(DQuat::from_rotation_x(0.4), DVec3::new(1.0, 2.0, 3.0));
        let mut conf = lig.rigid(pose);
        conf.torsions = vec![0.3, -0.8];
        let x = lig.place(&conf);
        let mut g = c.clone();
        g[0] += 2.0 * (x[0] - x[5]);
        g[5] -= 2.0 * (x[0] - x[5]);
        let mut grad = Gradient::default();
        lig.gradient(&conf, &x, &g, &mut Vec::new(), &mut grad);
        let h = 1e-6;
        for axis in 0..3 {
            let d = DVec3::AXES[axis] * h;
            let (mut p, mut m) = (conf.clone(), conf.clone());
            p.pose.translation += d;
            m.pose.translation -= d;
            let num = (energy(&p) - energy(&m)) / (2.0 * h);
            assert!((num - grad.translation[axis]).abs() < 1e-6);
            let turn = |s: f64| {
                let mut q = conf.clone();
                q.pose.rotation =
                    DQuat::from_scaled_axis(DVec3::AXES[axis] * s * h) * conf.pose.rotation;
                q
            };
            let num = (energy(&turn(1.0)) - energy(&turn(-1.0))) / (2.0 * h);
            assert!(
                (num - grad.rotation[axis]).abs() < 1e-6,
                "{num} {:?}",
                grad.rotation
            );
        }
        for k in 0..2 {
            let (mut p, mut m) = (conf.clone(), conf.clone());
            p.torsions[k] += h;
            m.torsions[k] -= h;
            let num = (energy(&p) - energy(&m)) / (2.0 * h);
            assert!((num - grad.torsions[k]).abs() < 1e-6);
        }
    }
}
