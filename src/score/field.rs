//! What an evaluator of the intermolecular energy provides, and the energy
//! of a whole conformation built on it.
//!
//! An evaluator ([`Field`]) gives the energy of one drug atom of a given type
//! at a point of the receptor's frame: Vina's value (the table, as `score()`
//! reads it) and a continuous value with its gradient (what an optimiser
//! follows). [`energies`] and [`energy_gradient`] add the intramolecular
//! pairs, apply the curl (per drug atom to its summed intermolecular energy,
//! per pair to the intramolecular one) and, for the gradient, carry each
//! atom's gradient up the torsion tree to the force, torque and torsion
//! torques ([`Ligand::gradient`]).
//!
//! [`RigidDrug`] holds one conformation for a drug moved rigidly: its
//! intramolecular energy and that energy's torques on the bonds are kept
//! (distances within the drug do not change), so a query reads only the
//! intermolecular field, and its whole gradient comes from the field's
//! gradient summed per fragment, carried up the tree.

use glam::{DMat3, DVec3};
use wide::f32x4;

use super::function::{CURL_CAP, CUTOFF2, curl, curl_capped_with_slope, curl_with_slope};
use super::ligand::{Conformation, Gradient, Ligand};
use super::table::{Table, index, smooth_at};
use crate::chem::XsType;
use crate::motion::Pose;

/// An evaluator of the intermolecular energy of single drug atoms.
pub trait Field {
    /// The pair table of the scoring function the field evaluates.
    fn table(&self) -> &'static Table;

    /// Vina's intermolecular energy of an atom of type `t` at `x` (receptor
    /// frame), before the curl.
    fn atom_energy(&self, t: XsType, x: DVec3) -> f64;

    /// A continuous version of [`Self::atom_energy`] and its gradient with
    /// respect to `x`.
    fn atom_energy_gradient(&self, t: XsType, x: DVec3) -> (f64, DVec3);

    /// [`Self::atom_energy`] of many atoms: `out[k]` for type `xs[k]` at
    /// `at[k]`. An evaluator that shares work between nearby atoms provides
    /// a faster way that gives the same values.
    fn atoms_energy(&self, xs: &[XsType], at: &[DVec3], out: &mut [f64]) {
        for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
            *o = self.atom_energy(t, x);
        }
    }

    /// [`Self::atom_energy_gradient`] of many atoms, as
    /// [`Self::atoms_energy`].
    fn atoms_energy_gradient(&self, xs: &[XsType], at: &[DVec3], out: &mut [(f64, DVec3)]) {
        for ((o, &t), &x) in out.iter_mut().zip(xs).zip(at) {
            *o = self.atom_energy_gradient(t, x);
        }
    }

    /// The intermolecular energy (the curl applied per atom) of `drug` at
    /// `pose`, with `∂E/∂T` and `∂E/∂ω` about the pose's centre: what
    /// [`RigidDrug::energy_gradient`] gives. An evaluator with a faster way
    /// to take many atoms through one transform provides it.
    #[inline]
    fn rigid_energy_gradient(&self, drug: &RigidDrug, pose: &Pose) -> (f64, DVec3, DVec3) {
        let m = DMat3::from_quat(pose.rotation);
        let (mut e, mut force, mut moment) = (0.0, DVec3::ZERO, DVec3::ZERO);
        for (y, &t) in drug.local().iter().zip(drug.xs()) {
            let r = m * *y;
            let (v, g) = self.atom_energy_gradient(t, r + pose.translation);
            let (v, s) = curl_with_slope(v);
            let g = g * s;
            e += v;
            force += g;
            moment += r.cross(g);
        }
        (e, force, moment)
    }

    /// The intermolecular energy (the curl applied per atom) of `drug` at
    /// `pose`, with the gradient summed per fragment of its torsion tree
    /// into `sums` (one entry per fragment): `(Σ ∂E/∂xᵢ, Σ rᵢ × ∂E/∂xᵢ)`
    /// over the fragment's scored atoms, `rᵢ` from the pose's centre. What
    /// [`RigidDrug::energy_full_gradient`] carries up the tree. An
    /// evaluator with a faster way to take many atoms through one
    /// transform provides it.
    fn rigid_fragment_sums(
        &self,
        drug: &RigidDrug,
        pose: &Pose,
        sums: &mut Vec<(DVec3, DVec3)>,
    ) -> f64 {
        let m = DMat3::from_quat(pose.rotation);
        sums.clear();
        sums.resize(drug.fragment_count(), (DVec3::ZERO, DVec3::ZERO));
        let mut e = 0.0;
        for ((y, &t), &f) in drug.local().iter().zip(drug.xs()).zip(drug.fragments()) {
            let r = m * *y;
            let (v, g) = self.atom_energy_gradient(t, r + pose.translation);
            let (v, s) = curl_with_slope(v);
            let g = g * s;
            e += v;
            let w = &mut sums[f as usize];
            w.0 += g;
            w.1 += r.cross(g);
        }
        e
    }
}

/// `F` read one atom at a time: its [`Field::atom_energy`] and
/// [`Field::atom_energy_gradient`] without any faster way of its own to
/// take many atoms (the trait's defaults for the rest). The reference a
/// faster path is tested and timed against.
#[derive(Debug, Clone, Copy)]
pub struct PerAtom<'a, F: ?Sized>(pub &'a F);

impl<F: Field + ?Sized> Field for PerAtom<'_, F> {
    fn table(&self) -> &'static Table {
        self.0.table()
    }

    fn atom_energy(&self, t: XsType, x: DVec3) -> f64 {
        self.0.atom_energy(t, x)
    }

    fn atom_energy_gradient(&self, t: XsType, x: DVec3) -> (f64, DVec3) {
        self.0.atom_energy_gradient(t, x)
    }
}

/// Working storage for evaluations, kept between calls so that none
/// allocates.
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    frames: Vec<(DMat3, DVec3)>,
    /// Heavy-atom positions of the last conformation evaluated.
    pub positions: Vec<DVec3>,
    gradients: Vec<DVec3>,
    /// The scored atoms' positions, in scored order.
    scored_at: Vec<DVec3>,
    /// Their intermolecular energies (and gradients) before the curl.
    inter: Vec<(f64, DVec3)>,
    inter_energy: Vec<f64>,
    tree: Vec<(DVec3, DVec3)>,
}

impl Workspace {
    /// The scored atoms' intermolecular energies (before the curl, in
    /// scored order) of the last [`energies`] call.
    pub fn inter_energy(&self) -> &[f64] {
        &self.inter_energy
    }
}

/// The intermolecular and intramolecular energies of a conformation
/// (kcal/mol), each after the curl, before the torsion divisor.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    /// Intermolecular.
    pub inter: f64,
    /// Intramolecular.
    pub intra: f64,
}

impl Energies {
    /// `inter + intra`: what the optimiser minimises.
    pub fn sum(&self) -> f64 {
        self.inter + self.intra
    }
}

/// Vina's energies of `conf` (the table's values, as `score()` gives them).
pub fn energies<F: Field + ?Sized>(
    field: &F,
    lig: &Ligand,
    conf: &Conformation,
    ws: &mut Workspace,
) -> Energies {
    lig.place_into(conf, &mut ws.frames, &mut ws.positions);
    let x = &ws.positions;
    gather_scored(lig, x, &mut ws.scored_at);
    ws.inter_energy.clear();
    ws.inter_energy.resize(lig.xs.len(), 0.0);
    field.atoms_energy(&lig.xs, &ws.scored_at, &mut ws.inter_energy);
    let mut inter = 0.0;
    for &e in &ws.inter_energy {
        inter += curl(e);
    }
    let table = field.table();
    let mut intra = 0.0;
    for &[a, b] in &lig.pairs {
        let (i, j) = (
            lig.scored[a as usize] as usize,
            lig.scored[b as usize] as usize,
        );
        let r2 = (x[i] - x[j]).length_squared();
        if r2 < CUTOFF2 {
            intra += curl(table.fast_row(lig.xs[a as usize], lig.xs[b as usize])[index(r2)]);
        }
    }
    Energies { inter, intra }
}

/// The scored atoms' positions of `x` (all heavy atoms), in scored order.
fn gather_scored(lig: &Ligand, x: &[DVec3], out: &mut Vec<DVec3>) {
    out.clear();
    out.extend(lig.scored.iter().map(|&i| x[i as usize]));
}

/// The continuous energies of `conf` and the gradient of their sum.
pub fn energy_gradient<F: Field + ?Sized>(
    field: &F,
    lig: &Ligand,
    conf: &Conformation,
    ws: &mut Workspace,
    grad: &mut Gradient,
) -> Energies {
    energy_gradient_capped(field, lig, conf, ws, grad, (CURL_CAP, CURL_CAP))
}

/// [`energy_gradient`] with Vina's curl at other caps: each atom's
/// intermolecular energy curled with `inter_cap` and each intramolecular
/// pair's with `intra_cap` (`e·v/(v + e)` for `e > 0`), as Vina's Monte
/// Carlo minimises (its `hunt_cap`, 1.5 and 10), so that overlaps cost
/// little while the search looks for a basin; [`CURL_CAP`] for both is
/// [`energy_gradient`].
#[inline]
pub fn energy_gradient_capped<F: Field + ?Sized>(
    field: &F,
    lig: &Ligand,
    conf: &Conformation,
    ws: &mut Workspace,
    grad: &mut Gradient,
    (inter_cap, intra_cap): (f64, f64),
) -> Energies {
    lig.place_into(conf, &mut ws.frames, &mut ws.positions);
    let x = &ws.positions;
    ws.gradients.clear();
    ws.gradients.resize(x.len(), DVec3::ZERO);
    let g = &mut ws.gradients;
    gather_scored(lig, x, &mut ws.scored_at);
    ws.inter.clear();
    ws.inter.resize(lig.xs.len(), (0.0, DVec3::ZERO));
    field.atoms_energy_gradient(&lig.xs, &ws.scored_at, &mut ws.inter);
    let mut inter = 0.0;
    for (&i, &(e, de)) in lig.scored.iter().zip(&ws.inter) {
        let (e, s) = curl_capped_with_slope(e, inter_cap);
        inter += e;
        g[i as usize] += de * s;
    }
    let intra = intra_gradient(field.table(), lig, x, g, intra_cap);
    lig.gradient(conf, x, g, &mut ws.tree, grad);
    Energies { inter, intra }
}

/// The continuous intramolecular energy of the heavy atoms at `x`, its
/// gradient added into `g` (per heavy atom), each pair curled at `cap`.
fn intra_gradient(table: &Table, lig: &Ligand, x: &[DVec3], g: &mut [DVec3], cap: f64) -> f64 {
    let mut intra = 0.0;
    for &[a, b] in &lig.pairs {
        let (i, j) = (
            lig.scored[a as usize] as usize,
            lig.scored[b as usize] as usize,
        );
        let d = x[i] - x[j];
        let r2 = d.length_squared();
        if r2 < CUTOFF2 {
            let (e, de) = smooth_at(table.smooth_row(lig.xs[a as usize], lig.xs[b as usize]), r2);
            let (e, s) = curl_capped_with_slope(e, cap);
            intra += e;
            let f = d * (2.0 * de * s);
            g[i] += f;
            g[j] -= f;
        }
    }
    intra
}

/// The drug held in one conformation and moved rigidly: what a haptic loop
/// asks for while the user moves the drug without turning its bonds. The
/// intramolecular energy does not change under a rigid motion, so it is
/// computed once; each query is the intermolecular energy and the force and
/// torque (as `∂E/∂T` and `∂E/∂ω` about the drug's centre).
#[derive(Debug, Clone, Default)]
pub struct RigidDrug {
    /// Scored atoms' positions in the drug's frame at the held conformation.
    local: Vec<DVec3>,
    /// Their types.
    xs: Vec<XsType>,
    /// `local` in f32, four atoms a lane group.
    lanes: Vec<[f32x4; 3]>,
    /// Vina's intramolecular energy at the held conformation.
    pub intra: f64,
    /// Per scored atom, its fragment of the torsion tree.
    fragment: Vec<u32>,
    /// Per fragment, parents before children: its rotatable bond to its
    /// parent, if any.
    bonds: Vec<Option<HeldBond>>,
    /// The continuous intramolecular energy at the held conformation (what
    /// [`energy_gradient`] gives as `intra`).
    intra_continuous: f64,
    /// `∂E_intra/∂θ_k` per rotatable bond at the held conformation: the
    /// intramolecular energy depends only on distances within the drug, so
    /// its gradient stays the same however the drug is moved rigidly.
    intra_torsions: Vec<f64>,
}

/// A fragment's rotatable bond to its parent, in the drug's frame at the
/// held conformation.
#[derive(Debug, Clone, Copy)]
struct HeldBond {
    /// The parent fragment.
    parent: u32,
    /// The bond's index among the rotatable bonds.
    torsion: u32,
    /// The parent atom's position.
    at: DVec3,
    /// The unit axis towards the child atom.
    axis: DVec3,
}

impl RigidDrug {
    /// `lig` held at `torsions` (radians from the loaded angles).
    pub fn new<F: Field + ?Sized>(field: &F, lig: &Ligand, torsions: &[f64]) -> Self {
        let conf = Conformation {
            pose: Pose::IDENTITY,
            torsions: torsions.to_vec(),
        };
        let mut ws = Workspace::default();
        let intra = energies(field, lig, &conf, &mut ws).intra;
        let x = &ws.positions;
        let mut g = vec![DVec3::ZERO; x.len()];
        let intra_continuous = intra_gradient(field.table(), lig, x, &mut g, CURL_CAP);
        let mut held = Gradient::default();
        lig.gradient(&conf, x, &g, &mut ws.tree, &mut held);
        let mut torsion = lig.torsions();
        let mut bonds = vec![None; lig.fragments.len()];
        for (f, frag) in lig.fragments.iter().enumerate().rev() {
            if let (Some(parent), Some([a, b])) = (frag.parent, frag.bond) {
                torsion -= 1;
                let (pa, pb) = (x[a as usize], x[b as usize]);
                bonds[f] = Some(HeldBond {
                    parent,
                    torsion: torsion as u32,
                    at: pa,
                    axis: (pb - pa).normalize_or_zero(),
                });
            }
        }
        let fragment = lig
            .scored
            .iter()
            .map(|&i| lig.fragment_of[i as usize])
            .collect();
        let local: Vec<DVec3> = lig
            .scored
            .iter()
            .map(|&i| ws.positions[i as usize])
            .collect();
        let lanes = local
            .chunks(4)
            .map(|c| {
                let mut v = [[0.0f32; 4]; 3];
                for (l, y) in c.iter().enumerate() {
                    let y = y.as_vec3();
                    (v[0][l], v[1][l], v[2][l]) = (y.x, y.y, y.z);
                }
                v.map(f32x4::from)
            })
            .collect();
        Self {
            local,
            xs: lig.xs.clone(),
            lanes,
            intra,
            fragment,
            bonds,
            intra_continuous,
            intra_torsions: held.torsions,
        }
    }

    /// The scored atoms' positions in the drug's frame.
    pub fn local(&self) -> &[DVec3] {
        &self.local
    }

    /// The scored atoms' types.
    pub fn xs(&self) -> &[XsType] {
        &self.xs
    }

    /// Per scored atom, its fragment of the torsion tree.
    pub fn fragments(&self) -> &[u32] {
        &self.fragment
    }

    /// How many fragments the torsion tree has.
    pub fn fragment_count(&self) -> usize {
        self.bonds.len()
    }

    /// [`Self::local`] in f32, per group of four atoms (the last padded
    /// with zeros) per axis: for evaluators that move four atoms at once.
    pub fn lanes(&self) -> &[[f32x4; 3]] {
        &self.lanes
    }

    /// The intermolecular energy at `pose` (after the curl) with `∂E/∂T`
    /// and `∂E/∂ω`.
    #[inline]
    pub fn energy_gradient<F: Field + ?Sized>(
        &self,
        field: &F,
        pose: &Pose,
    ) -> (f64, DVec3, DVec3) {
        field.rigid_energy_gradient(self, pose)
    }

    /// The energies at `pose` and their whole gradient (force, torque and
    /// each rotatable bond's torque) into `out`: what [`energy_gradient`]
    /// gives for the held conformation at `pose`, without placing the atoms
    /// through the torsion tree or summing the intramolecular pairs again
    /// (both stay as they were when the conformation was held). Each
    /// fragment's gradient sums ([`Field::rigid_fragment_sums`]) are
    /// carried up the tree as
    /// [`Ligand::gradient`] does.
    pub fn energy_full_gradient<F: Field + ?Sized>(
        &self,
        field: &F,
        pose: &Pose,
        ws: &mut Workspace,
        out: &mut Gradient,
    ) -> Energies {
        let sums = &mut ws.tree;
        let inter = field.rigid_fragment_sums(self, pose, sums);
        let m = DMat3::from_quat(pose.rotation);
        out.torsions.clear();
        out.torsions.extend_from_slice(&self.intra_torsions);
        let (mut force, mut moment) = (DVec3::ZERO, DVec3::ZERO);
        for (f, bond) in self.bonds.iter().enumerate().rev() {
            let (sum, turn) = sums[f];
            match bond {
                Some(b) => {
                    let (at, axis) = (m * b.at, m * b.axis);
                    out.torsions[b.torsion as usize] += axis.dot(turn - at.cross(sum));
                    let w = &mut sums[b.parent as usize];
                    w.0 += sum;
                    w.1 += turn;
                }
                None => {
                    force += sum;
                    moment += turn;
                }
            }
        }
        out.translation = force;
        out.rotation = moment;
        Energies {
            inter,
            intra: self.intra_continuous,
        }
    }
}
