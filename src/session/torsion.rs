//! Flexible drugs in the session: a drug's conformation (the turn of each
//! rotatable bond from the file's angle), turning the selected bond through
//! the collision response, and settle.
//!
//! A drug's conformation is kept as its torsion angles, radians added to the
//! file's ([`crate::score::Conformation`]'s convention: bond `k` turns its
//! child side right-handed about the axis from the parent atom to the child
//! atom). The molecule's local positions are always computed from the file's
//! positions and those angles, never accumulated, so a conformation reached
//! by any path gives the same positions bit for bit, and the file's angles
//! give the file's positions exactly. In the local frame the torsion tree's
//! root stays put; when the side of a bond that turns for the user (the
//! smaller, [`TorsionBond::moving`]) is the parent side, the body's pose
//! turns the other way about the bond, so that the larger side stays where
//! it is in the world.
//!
//! A turn runs through the collision response ([`crate::collide::torsion`]):
//! the moving side against the receptor by move-to-touch and against the
//! drug's other atoms more than three bonds away in closed form, the largest
//! collision-free part of the turn taken (`soft` presses into the receptor
//! and into the drug's own atoms as its loosened rule lets it, so that the
//! halves of a drug turned into each other's way squeeze past as a real
//! molecule's do, and settle then frees them; `pass` checks nothing). The
//! end is checked once more with the static rule, and the turn halved, up
//! to a few times, if rounding disagrees. With `soft`, the frame's
//! resistance follows the pairs the turn leaves pressed in, the receptor's
//! and the drug's own, as for a rigid push.
//!
//! After a change of conformation the collider's copy of the drug, the live
//! score and the contacts follow; [`Reshaped`] tells the renderer which
//! atoms' local positions changed.

use std::sync::Arc;

use glam::{DMat3, DVec3, Vec3};

use super::{Contact, FrameOutcome, Role, Session};
use crate::collide::torsion::{InnerPair, Turn, inner_fraction, inner_pairs, receptor_fraction};
use crate::collide::{ContactRule, DrugAtoms, Response};
use crate::model::Molecule;
use crate::motion::Pose;
use crate::score::{Conformation, Exact, Ligand, Receptor, Scoring, SettleOptions, prepare};

/// Largest turn of one command or frame, degrees: a longer turn is refused
/// (a turn's path is checked piece by piece, so its length bounds the work).
pub const MAX_TURN_DEGREES: f64 = 360.0;

/// Drugs with more atoms than this are not made flexible (the internal
/// pairs are quadratic in the atom count).
pub const MAX_FLEXIBLE_ATOMS: usize = 1000;

/// Times a turn is halved when its end, checked with the static rule,
/// collides after all (rounding), before it is refused.
const END_CHECKS: usize = 4;

/// A rotatable bond as the session turns it.
#[derive(Debug, Clone, PartialEq)]
pub struct TorsionBond {
    /// The axis atoms: the torsion tree's parent-side atom, then the
    /// child-side atom.
    pub atoms: [u32; 2],
    /// The atoms that turn for the user: the smaller side (fewer atoms; the
    /// child side on a tie), ascending.
    pub moving: Vec<u32>,
    /// The kept hydrogens ([`Molecule::hydrogens`] indices) that turn with
    /// them, ascending.
    pub moving_hydrogens: Vec<u32>,
    /// True when the moving side is the child side.
    pub child_moves: bool,
}

/// The atoms of one molecule whose local positions changed in a frame
/// (a turn, undo, reset, settle): what the renderer uploads again.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Reshaped {
    /// The molecule.
    pub body: usize,
    /// Its atoms whose local position changed, ascending.
    pub atoms: Vec<u32>,
    /// Its kept hydrogens whose local position changed, ascending.
    pub hydrogens: Vec<u32>,
}

/// A settle run of the session, for the window to animate: the session
/// is already at `to` when the frame returns (the animation is only a
/// view of the change).
#[derive(Debug, Clone, PartialEq)]
pub struct SettlePath {
    /// The molecule settled.
    pub body: usize,
    /// Its pose before.
    pub from: Pose,
    /// Its torsions before (radians from the file's).
    pub from_torsions: Vec<f64>,
    /// Its pose after.
    pub to: Pose,
    /// Its torsions after.
    pub to_torsions: Vec<f64>,
    /// Vina's intermolecular energy before and after, kcal/mol.
    pub inter: (f64, f64),
    /// Heavy-atom RMSD between the start and the end, Å.
    pub rmsd: f64,
    /// BFGS steps taken.
    pub steps: usize,
}

/// Why torsions cannot be set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TorsionError {
    /// No such molecule, or it has no torsion tree.
    #[error("molecule {0} is not a flexible drug")]
    NotFlexible(usize),
    /// The angles do not match the rotatable bonds.
    #[error("{got} torsion angles given for {bonds} rotatable bonds")]
    Count {
        /// Angles given.
        got: usize,
        /// Rotatable bonds.
        bonds: usize,
    },
    /// An angle is not a finite number.
    #[error("torsion angle {0} is not a finite number")]
    NotFinite(f64),
}

/// A flexible drug's conformation state.
#[derive(Debug, Clone)]
pub(super) struct Flex {
    /// The drug as the scoring sees it, prepared from the file's positions.
    pub(super) ligand: Arc<Ligand>,
    /// The kept hydrogens' local positions as loaded.
    file_hydrogens: Arc<Vec<Vec3>>,
    /// Per kept hydrogen: its parent atom.
    hydrogen_parent: Arc<Vec<u32>>,
    /// The rotatable bonds, in the torsion tree's order.
    pub(super) bonds: Arc<Vec<TorsionBond>>,
    /// Per bond: the pairs its turn can bring together and the rule they
    /// were made for, made on first use under that rule.
    inner: Vec<Option<(ContactRule, Arc<Vec<InnerPair>>)>>,
    /// Atom pairs more than three bonds apart.
    beyond: Arc<Vec<(u32, u32)>>,
    /// Those of them whose distance the torsions can change
    /// ([`crate::chem::TorsionTree::movable_pairs`]): the pairs a turn can
    /// press into each other.
    /// Two atoms held apart by a rigid piece (the substituents at a
    /// naphthalene's peri positions) may lie within the contact rule in
    /// the file, as they always will: no turn pressed them.
    movable: Arc<Vec<(u32, u32)>>,
    /// The collider's grouping of the loaded shape (it stays compact as
    /// the torsions turn).
    pub(super) groups: Arc<Vec<u32>>,
    /// Radians added to each bond's file angle.
    pub(super) torsions: Vec<f64>,
    /// Counts changes of conformation.
    pub(super) generation: u64,
    /// The selected bond.
    pub(super) selected: Option<usize>,
    /// The torsions when loaded or last saved.
    pub(super) saved: Vec<f64>,
    /// Whether two of the drug's own atoms (more than three bonds apart,
    /// movable relative to each other) overlap under the default rule at
    /// the current conformation (pressed into each other in the `soft`
    /// band).
    pub(super) pressed: bool,
}

impl Flex {
    /// The conformation state of a drug as loaded; `None` for a molecule
    /// that is not a drug the scoring can prepare.
    pub(super) fn of(mol: &Molecule) -> Option<Self> {
        if mol.is_empty() || mol.len() > MAX_FLEXIBLE_ATOMS || Role::of(mol) != Role::Drug {
            return None;
        }
        let ligand = prepare::ligand(mol).ok()?;
        let chem = mol.chemistry();
        let tree = &chem.torsions;
        let bonds: Vec<TorsionBond> = tree
            .bonds
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let (moving, moving_hydrogens, child_moves) = tree.smaller_side(k);
                TorsionBond {
                    atoms: [b.parent_atom, b.child_atom],
                    moving,
                    moving_hydrogens,
                    child_moves,
                }
            })
            .collect();
        if bonds.len() != ligand.torsions() {
            return None;
        }
        let n = bonds.len();
        let torsions = vec![0.0; n];
        Some(Self {
            ligand: Arc::new(ligand),
            file_hydrogens: Arc::new(mol.hydrogens.local.clone()),
            hydrogen_parent: Arc::new(mol.hydrogens.parent.clone()),
            bonds: Arc::new(bonds),
            inner: vec![None; n],
            beyond: Arc::new(crate::chem::torsions::pairs_beyond_three_bonds(
                &chem.adjacency,
            )),
            movable: Arc::new(tree.movable_pairs(&chem.adjacency)),
            groups: Arc::new(crate::collide::grouping::compact_order(&mol.local)),
            saved: torsions.clone(),
            torsions,
            generation: 0,
            selected: None,
            pressed: false,
        })
    }

    /// The local positions of the atoms and kept hydrogens at `torsions`.
    pub(super) fn shape(&self, torsions: &[f64]) -> (Vec<Vec3>, Vec<Vec3>) {
        let conf = Conformation {
            pose: Pose::IDENTITY,
            torsions: torsions.to_vec(),
        };
        let mut frames: Vec<(DMat3, DVec3)> = Vec::new();
        self.ligand.frames_into(&conf, &mut frames);
        let place = |f: u32, p: DVec3| {
            let (m, t) = frames[f as usize];
            (m * p + t).as_vec3()
        };
        let atoms = self
            .ligand
            .local
            .iter()
            .zip(&self.ligand.fragment_of)
            .map(|(p, &f)| place(f, *p))
            .collect();
        let hydrogens = self
            .file_hydrogens
            .iter()
            .zip(self.hydrogen_parent.iter())
            .map(
                |(p, &parent)| match self.ligand.fragment_of.get(parent as usize) {
                    Some(&f) => place(f, p.as_dvec3()),
                    None => *p,
                },
            )
            .collect();
        (atoms, hydrogens)
    }

    /// The pairs a turn of bond `k` can bring together, under `rule`.
    fn inner(&mut self, k: usize, mol: &Molecule, rule: &ContactRule) -> Arc<Vec<InnerPair>> {
        if let Some(Some((r, p))) = self.inner.get(k)
            && r == rule
        {
            return Arc::clone(p);
        }
        let mut moving = vec![false; mol.len()];
        for &i in &self.bonds[k].moving {
            if let Some(m) = moving.get_mut(i as usize) {
                *m = true;
            }
        }
        let pairs = Arc::new(inner_pairs(mol, &moving, &self.beyond, rule));
        if let Some(slot) = self.inner.get_mut(k) {
            *slot = Some((*rule, Arc::clone(&pairs)));
        }
        pairs
    }

    /// The pairs of atoms more than three bonds apart of `mol` (molecule
    /// `body`) that the torsions can move relative to each other and that
    /// collide under `rule`, as contacts (brute force over those pairs, in
    /// their order).
    pub(super) fn pressed_inside(
        &self,
        body: usize,
        mol: &Molecule,
        rule: &ContactRule,
    ) -> Vec<Contact> {
        self.movable
            .iter()
            .filter_map(|&(i, j)| {
                let (a, b) = (mol.atoms.get(i as usize)?, mol.atoms.get(j as usize)?);
                let (p, q) = (mol.local.get(i as usize)?, mol.local.get(j as usize)?);
                rule.collides(a.radius, a.polar, b.radius, b.polar, p.distance_squared(*q))
                    .then(|| Contact {
                        moving: (body, i as usize),
                        other: (body, j as usize),
                        distance: p.distance(*q),
                        contact: rule.contact_distance(a.radius, a.polar, b.radius, b.polar),
                    })
            })
            .collect()
    }
}

/// `x` brought into (−π, π].
fn wrapped(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let y = x.rem_euclid(TAU);
    if y > PI { y - TAU } else { y }
}

/// The indices where two lists differ, bit for bit.
fn changed(a: &[Vec3], b: &[Vec3]) -> Vec<u32> {
    a.iter()
        .zip(b)
        .enumerate()
        .filter(|(_, (p, q))| {
            p.x.to_bits() != q.x.to_bits()
                || p.y.to_bits() != q.y.to_bits()
                || p.z.to_bits() != q.z.to_bits()
        })
        .map(|(i, _)| i as u32)
        .collect()
}

impl Session {
    /// The rotatable bonds of molecule `b`, in the torsion tree's order
    /// (empty for a molecule that is not a flexible drug).
    pub fn rotatable_bonds(&self, b: usize) -> &[TorsionBond] {
        self.flex
            .get(b)
            .and_then(Option::as_ref)
            .map_or(&[], |f| f.bonds.as_slice())
    }

    /// Molecule `b`'s torsion angles, radians added to each bond's file
    /// angle (empty for a molecule that is not a flexible drug).
    pub fn torsion_angles(&self, b: usize) -> &[f64] {
        self.flex
            .get(b)
            .and_then(Option::as_ref)
            .map_or(&[], |f| f.torsions.as_slice())
    }

    /// The selected molecule's selected rotatable bond, if any.
    pub fn selected_torsion(&self) -> Option<usize> {
        self.flex
            .get(self.selected)
            .and_then(Option::as_ref)
            .and_then(|f| f.selected)
    }

    /// A count that changes whenever molecule `b`'s conformation does (0
    /// as loaded).
    pub fn shape_generation(&self, b: usize) -> u64 {
        self.flex
            .get(b)
            .and_then(Option::as_ref)
            .map_or(0, |f| f.generation)
    }

    /// Molecule `b`'s local positions (atoms, kept hydrogens) at
    /// `torsions`, without changing the session: for animating between two
    /// conformations (a settle). `None` when `b` is not a flexible drug or
    /// the count is wrong.
    pub fn shape_at(&self, b: usize, torsions: &[f64]) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
        let f = self.flex.get(b)?.as_ref()?;
        (torsions.len() == f.torsions.len()).then(|| f.shape(torsions))
    }

    /// Sets molecule `b`'s torsions directly, with no collision check and
    /// no undo entry: for setting up a run before it starts (a steering
    /// controller's seeded start), never in the middle of one. The pose
    /// stays (the torsion tree's root keeps its place).
    ///
    /// # Errors
    /// [`TorsionError`] when `b` is not flexible or the angles do not fit.
    pub fn set_torsions(&mut self, b: usize, torsions: &[f64]) -> Result<(), TorsionError> {
        let n = self
            .flex
            .get(b)
            .and_then(Option::as_ref)
            .map(|f| f.torsions.len())
            .ok_or(TorsionError::NotFlexible(b))?;
        if torsions.len() != n {
            return Err(TorsionError::Count {
                got: torsions.len(),
                bonds: n,
            });
        }
        if let Some(&x) = torsions.iter().find(|x| !x.is_finite()) {
            return Err(TorsionError::NotFinite(x));
        }
        let mut out = FrameOutcome::default();
        self.history.close();
        self.last_clear = None;
        self.reshape(b, torsions, &mut out);
        self.refresh_contacts(&mut out);
        Ok(())
    }

    /// Gives molecule `b` the conformation `torsions` (wrapped), updating
    /// its local positions, the collider's copy of it and the outcome's
    /// [`Reshaped`] list. No collision check.
    pub(super) fn reshape(&mut self, b: usize, torsions: &[f64], out: &mut FrameOutcome) {
        let Some(f) = self.flex.get_mut(b).and_then(Option::as_mut) else {
            return;
        };
        let torsions: Vec<f64> = torsions.iter().map(|&x| wrapped(x)).collect();
        let (atoms, hydrogens) = f.shape(&torsions);
        f.torsions = torsions;
        f.generation += 1;
        let groups = Arc::clone(&f.groups);
        let mol = &mut self.bodies[b].molecule;
        let moved = Reshaped {
            body: b,
            atoms: changed(&mol.local, &atoms),
            hydrogens: changed(&mol.hydrogens.local, &hydrogens),
        };
        mol.local = atoms;
        mol.hydrogens.local = hydrogens;
        f.pressed = !f
            .pressed_inside(b, &self.bodies[b].molecule, &self.settings.rule)
            .is_empty();
        if moved.atoms.is_empty() && moved.hydrogens.is_empty() {
            return;
        }
        out.changed = true;
        out.moved |= b == self.selected;
        // The collider's copies of the drug follow its shape; a collider
        // built of it (when another molecule is selected) is built again.
        let mut copy = None;
        if let Some(Some((r, atoms))) = self.moving_atoms.get_mut(b) {
            *atoms = Arc::new(DrugAtoms::with_groups(
                &self.bodies[b].molecule,
                &self.settings.rule,
                *r,
                groups.to_vec(),
            ));
            copy = Some((*r, Arc::clone(atoms)));
        }
        if let Some(slot) = self.own_colliders.get_mut(b) {
            *slot = None;
        }
        match self.env.as_mut() {
            Some(env) if env.selected == b => {
                env.reshaped(&self.bodies[b].molecule, &self.settings.rule, &groups, copy);
            }
            Some(_) => self.env = None,
            None => {}
        }
        if let Some(prev) = out.reshaped.iter_mut().find(|r| r.body == b) {
            prev.atoms.extend(moved.atoms);
            prev.atoms.sort_unstable();
            prev.atoms.dedup();
            prev.hydrogens.extend(moved.hydrogens);
            prev.hydrogens.sort_unstable();
            prev.hydrogens.dedup();
        } else {
            out.reshaped.push(moved);
        }
    }

    /// Selects rotatable bond `k` of the selected molecule (or none).
    pub(super) fn select_torsion(&mut self, k: Option<usize>, out: &mut FrameOutcome) {
        let b = self.selected;
        let Some(f) = self.flex.get_mut(b).and_then(Option::as_mut) else {
            out.messages
                .push("the selected molecule has no rotatable bonds".into());
            return;
        };
        match k {
            Some(k) if k >= f.bonds.len() => {
                out.messages.push(format!(
                    "no rotatable bond {k} (the drug has {})",
                    f.bonds.len()
                ));
            }
            _ => {
                f.selected = k;
                self.history.close();
            }
        }
    }

    /// Steps the selected rotatable bond by `by` (±1), wrapping.
    pub(super) fn cycle_torsion(&mut self, forward: bool, out: &mut FrameOutcome) {
        let n = self.rotatable_bonds(self.selected).len();
        if n == 0 {
            out.messages
                .push("the selected molecule has no rotatable bonds".into());
            return;
        }
        let next = match (self.selected_torsion(), forward) {
            (None, true) => 0,
            (None, false) => n - 1,
            (Some(k), true) => (k + 1) % n,
            (Some(k), false) => (k + n - 1) % n,
        };
        self.select_torsion(Some(next), out);
    }

    /// Selects the rotatable bond nearest atom `atom` of the selected
    /// molecule: the bond whose middle is closest (the lower index on a tie).
    pub(super) fn select_torsion_near(&mut self, atom: usize, out: &mut FrameOutcome) {
        let b = self.selected;
        let mol = &self.bodies[b].molecule;
        let Some(&p) = mol.local.get(atom) else {
            out.messages
                .push(format!("no atom {atom} in the selected molecule"));
            return;
        };
        let best = self
            .rotatable_bonds(b)
            .iter()
            .enumerate()
            .map(|(k, bond)| {
                let [i, j] = bond.atoms.map(|a| mol.local[a as usize]);
                (k, (0.5 * (i + j) - p).length_squared())
            })
            .min_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)))
            .map(|(k, _)| k);
        match best {
            Some(k) => self.select_torsion(Some(k), out),
            None => out
                .messages
                .push("the selected molecule has no rotatable bonds".into()),
        }
    }

    /// Turns the selected rotatable bond of the selected molecule by
    /// `radians` through the collision response; extends the open undo
    /// entry. Returns the turn made.
    pub(super) fn turn_torsion(&mut self, radians: f64, out: &mut FrameOutcome) -> f64 {
        let b = self.selected;
        if !radians.is_finite() || radians.abs() > MAX_TURN_DEGREES.to_radians() {
            out.messages.push(format!(
                "refused a turn of {:.1}°: at most {MAX_TURN_DEGREES}° at once",
                radians.to_degrees()
            ));
            return 0.0;
        }
        let Some(f) = self.flex.get(b).and_then(Option::as_ref) else {
            out.messages
                .push("the selected molecule has no rotatable bonds".into());
            return 0.0;
        };
        let Some(k) = f.selected else {
            out.messages.push("no rotatable bond selected".into());
            return 0.0;
        };
        if radians == 0.0 {
            return 0.0;
        }
        let bond = f.bonds[k].clone();
        let from_torsions = f.torsions.clone();
        let from = self.bodies[b].pose;
        let mol = &self.bodies[b].molecule;
        let mol_before = mol.local.clone();
        let local: Vec<DVec3> = mol.local.iter().map(|p| p.as_dvec3()).collect();
        let origin = local[bond.atoms[0] as usize];
        let axis = (local[bond.atoms[1] as usize] - origin).normalize_or_zero();
        if axis == DVec3::ZERO {
            out.messages
                .push("the bond's atoms coincide: it cannot turn".into());
            return 0.0;
        }
        // The moving side turns by the torsion's change about the axis from
        // the parent atom when it is the child side, the other way when it
        // is the parent side.
        let sign = if bond.child_moves { 1.0 } else { -1.0 };
        let turn = Turn {
            origin,
            axis,
            angle: sign * radians,
        };
        let check = self.settings.collision && self.settings.response != Response::Pass;
        let mut t = if check {
            self.turn_fraction(b, k, &bond, &local, &turn, out)
        } else {
            1.0
        };
        let mut tries = 0;
        loop {
            if t <= 0.0 {
                self.refresh_contacts(out);
                return 0.0;
            }
            let mut to_torsions = from_torsions.clone();
            to_torsions[k] += radians * t;
            let to = if bond.child_moves {
                from
            } else {
                from.compose(
                    &Turn {
                        origin,
                        axis,
                        angle: -radians * t,
                    }
                    .at(1.0),
                )
            };
            self.reshape(b, &to_torsions, out);
            self.bodies[b].pose = to;
            if !check || self.turn_end_clear(b, k, mol_before.clone(), from) {
                let now = self.torsion_angles(b).to_vec();
                self.history
                    .record_shape(b, (from, &from_torsions), (to, &now));
                out.t = out.t.min(t);
                out.moved = true;
                out.changed = true;
                self.refresh_contacts(out);
                if self.settings.response == Response::Soft {
                    // The pairs pressed into the band (the receptor's and
                    // the drug's own) resist as they do a rigid push (what
                    // a controller's rumble follows).
                    let r = crate::collide::soft::resistance_of(
                        self.contacts.iter().map(Contact::depth),
                        self.settings.soft_limit,
                    );
                    out.resistance = out.resistance.max(r);
                }
                return radians * t;
            }
            // Rounding put the end in contact after all: take back half.
            self.reshape(b, &from_torsions, out);
            self.bodies[b].pose = from;
            tries += 1;
            t = if tries >= END_CHECKS { 0.0 } else { t * 0.5 };
        }
    }

    /// The rule a turn's pairs within the drug are held to: the default
    /// rule, loosened by the limit under `soft` (the drug's own atoms press
    /// into each other as into the receptor's).
    fn inner_rule(&self) -> ContactRule {
        let rule = self.settings.rule;
        if self.settings.response == Response::Soft {
            crate::collide::soft::loosened(&rule, self.settings.soft_limit).unwrap_or(rule)
        } else {
            rule
        }
    }

    /// The largest fraction of `turn` (bond `k` of molecule `b`, atoms at
    /// `local`) free of collisions with the receptor and within the drug.
    fn turn_fraction(
        &mut self,
        b: usize,
        k: usize,
        bond: &TorsionBond,
        local: &[DVec3],
        turn: &Turn,
        out: &mut FrameOutcome,
    ) -> f64 {
        let rule = self.settings.rule;
        let inner_rule = self.inner_rule();
        let touch = self.settings.touch;
        let t0 = std::time::Instant::now();
        let pairs = match self.flex.get_mut(b).and_then(Option::as_mut) {
            Some(f) => f.inner(k, &self.bodies[b].molecule, &inner_rule),
            None => return 0.0,
        };
        let (t_inner, _) = inner_fraction(local, &pairs, turn, touch.tolerance);
        let soft = if self.settings.response == Response::Soft {
            self.soft_index()
        } else {
            None
        };
        let pose = self.bodies[b].pose;
        let Some((frame, env_collider)) = self
            .environment()
            .map(|e| (e.frame, Arc::clone(&e.collider)))
        else {
            out.collision_timed(t0);
            return t_inner;
        };
        let (collider, rule) = match &soft {
            Some(s) => (&s.collider, s.rule),
            None => (env_collider.as_ref(), rule),
        };
        let mol = &self.bodies[b].molecule;
        let atoms: Vec<_> = bond
            .moving
            .iter()
            .map(|&i| mol.atoms[i as usize].clone())
            .collect();
        let positions: Vec<DVec3> = bond.moving.iter().map(|&i| local[i as usize]).collect();
        let sub = Molecule::new(String::new(), atoms, &positions);
        let moving = DrugAtoms::new(&sub, &rule, collider.max_radius());
        let drug = frame.inverse().compose(&pose);
        let r = receptor_fraction(
            collider,
            &moving,
            &bond.moving,
            sub.centre,
            &drug,
            turn,
            &touch,
        );
        out.collision_timed(t0);
        t_inner.min(r.t)
    }

    /// True when molecule `b` at its new conformation collides nowhere it
    /// did not collide before the turn of bond `k` (its local positions
    /// `before`, at `from`), or deeper than it did: receptor pairs under
    /// the response's rule, and the bond's pairs within the drug.
    fn turn_end_clear(&mut self, b: usize, k: usize, before: Vec<Vec3>, from: Pose) -> bool {
        let rule = self.settings.rule;
        let inner_rule = self.inner_rule();
        let pairs = match self.flex.get_mut(b).and_then(Option::as_mut) {
            Some(f) => f.inner(k, &self.bodies[b].molecule, &inner_rule),
            None => return true,
        };
        let now = &self.bodies[b].molecule.local;
        let dist = |x: &[Vec3], p: &InnerPair| {
            (x[p.moving as usize].as_dvec3() - x[p.fixed as usize].as_dvec3()).length()
        };
        for p in pairs.iter() {
            let (d0, d1) = (dist(&before, p), dist(now, p));
            if d1 <= p.contact && d1 < d0 {
                return false;
            }
        }
        let soft = if self.settings.response == Response::Soft {
            self.soft_index()
        } else {
            None
        };
        let pose = self.bodies[b].pose;
        let Some((frame, env_collider, env_drug)) = self
            .environment()
            .map(|e| (e.frame, Arc::clone(&e.collider), Arc::clone(&e.drug)))
        else {
            return true;
        };
        let (collider, drug, rule) = match &soft {
            Some(s) => (&s.collider, &s.drug, s.rule),
            None => (env_collider.as_ref(), env_drug.as_ref(), rule),
        };
        let inv = frame.inverse();
        let end = crate::collide::check(collider, drug, &inv.compose(&pose));
        if end.is_empty() {
            return true;
        }
        // Pairs that overlapped at the start may stay, no deeper.
        let mut old = self.bodies[b].molecule.clone();
        old.local = before;
        let old_drug = DrugAtoms::new(&old, &rule, collider.max_radius());
        let start = crate::collide::check(collider, &old_drug, &inv.compose(&from));
        end.iter().all(|p| {
            start.iter().any(|q| {
                q.receptor == p.receptor && q.drug == p.drug && p.distance >= q.distance - 1e-5
            })
        })
    }

    /// Settles the selected drug against its receptor (one undoable move).
    pub(super) fn settle_selected(&mut self, out: &mut FrameOutcome) {
        let b = self.selected;
        let Some(f) = self.flex.get(b).and_then(Option::as_ref) else {
            out.messages
                .push("settle works on a drug: select the drug first".into());
            return;
        };
        let ligand = Arc::clone(&f.ligand);
        let from_torsions = f.torsions.clone();
        let others: Vec<usize> = (0..self.bodies.len())
            .filter(|&k| k != b && !self.bodies[k].molecule.is_empty())
            .collect();
        let [r] = others[..] else {
            out.messages
                .push("settle needs exactly one other molecule: the receptor".into());
            return;
        };
        let receptor = self.typed_receptor(r);
        let collider = self.own_collider(r);
        // Settle sums over the collider's neighbours in the order its
        // search visits them, which differs once the padded rows (built in
        // the background) are there: waiting for them makes the run the
        // same every time, as replay needs.
        collider.wait_for_clearance();
        let from = self.bodies[b].pose;
        let receptor_pose = self.bodies[r].pose;
        let exact = Exact::new(&receptor, Scoring::Vina);
        let mut contacts = crate::score::Contacts::new(
            &collider,
            self.settings.rule,
            &self.bodies[b].molecule,
            &ligand,
        );
        let opts = SettleOptions {
            touch: self.settings.touch,
            ..SettleOptions::default()
        };
        let mut run = |pose: &Pose, torsions: &[f64]| {
            let start = Conformation {
                pose: receptor_pose.inverse().compose(pose),
                torsions: torsions.to_vec(),
            };
            crate::score::settle(&exact, &ligand, &mut contacts, &start, &opts)
        };
        let mut s = run(&from, &from_torsions);
        let mut backed = false;
        if !s.end_collisions.is_empty() {
            // Caged where it stands (pressed into the `soft` band between
            // atoms): settle from the last pose on its way in that
            // overlapped nothing, so the result is free of overlaps.
            let back = self
                .last_clear
                .as_ref()
                .filter(|(k, pose, t)| *k == b && (*pose != from || *t != from_torsions));
            let Some((_, pose, torsions)) = back else {
                out.messages.push(format!(
                    "settle found no pose free of overlaps from here ({} pairs overlap): nothing changed",
                    s.end_collisions.len()
                ));
                return;
            };
            let caged = s.end_collisions.len();
            s = run(pose, torsions);
            if !s.end_collisions.is_empty() {
                out.messages.push(format!(
                    "settle found no pose free of overlaps from here ({caged} pairs overlap), nor from the drug's last pose without overlaps: nothing changed"
                ));
                return;
            }
            out.messages.push(format!(
                "settle could not free the drug from here ({caged} pairs overlap): it settled from the drug's last pose without overlaps"
            ));
            backed = true;
        }
        if s.steps == 0 && !backed {
            out.messages.push(
                "settle: no step lowers the score from here without a collision: nothing changed"
                    .into(),
            );
            return;
        }
        let to = self.bodies[r].pose.compose(&s.conf.pose);
        self.history.close();
        self.reshape(b, &s.conf.torsions, out);
        let to_torsions = self.torsion_angles(b).to_vec();
        self.history
            .record_shape(b, (from, &from_torsions), (to, &to_torsions));
        self.history.close();
        self.place(b, to, out);
        out.messages.push(format!(
            "settled: Vina inter {:.2} → {:.2} kcal/mol, moved {:.2} Å RMSD in {} steps",
            s.before.inter, s.after.inter, s.rmsd, s.steps
        ));
        out.settled = Some(Arc::new(SettlePath {
            body: b,
            from,
            from_torsions,
            to,
            to_torsions,
            inter: (s.before.inter, s.after.inter),
            rmsd: s.rmsd,
            steps: s.steps,
        }));
    }

    /// Molecule `r`'s typed atoms for scoring, kept while its shape stays.
    fn typed_receptor(&mut self, r: usize) -> Arc<Receptor> {
        let generation = self.shape_generation(r);
        if let Some((k, g, rec)) = &self.typed_receptor
            && (*k, *g) == (r, generation)
        {
            return Arc::clone(rec);
        }
        let rec = Arc::new(prepare::receptor(&self.bodies[r].molecule));
        self.typed_receptor = Some((r, generation, Arc::clone(&rec)));
        rec
    }

    /// Undo, redo and reset: molecule `b` to `pose` and (when given)
    /// `torsions`, as a jump.
    pub(super) fn place_shape(
        &mut self,
        b: usize,
        pose: Pose,
        torsions: &[f64],
        out: &mut FrameOutcome,
    ) {
        if !torsions.is_empty() {
            self.reshape(b, torsions, out);
        }
        self.place(b, pose, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_wrap_into_a_half_open_turn() {
        use std::f64::consts::PI;
        assert_eq!(wrapped(0.5), 0.5);
        assert!((wrapped(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrapped(-1.5 * PI) - 0.5 * PI).abs() < 1e-12);
        assert!(wrapped(-PI) > 0.0);
    }

    /// A drug pushed under `soft` into a cage of six atoms (an octahedron
    /// whose faces it can press through but whose middle overlaps all six
    /// a little) is caged there: no local move frees it. Settle then starts
    /// from the last pose on its way in that overlapped nothing, and ends
    /// free of overlaps.
    #[test]
    fn settle_backs_out_of_a_cage_to_the_last_clear_pose() {
        use crate::collide::Response;
        use crate::model::molecule::test_carbon;
        use crate::session::{Command, Contact, FrameInput, Settings};
        let corners: Vec<DVec3> = [DVec3::X, DVec3::Y, DVec3::Z]
            .iter()
            .flat_map(|&a| [a * 2.6, a * -2.6])
            .collect();
        let cage = Molecule::new(
            "cage",
            (1..=6).map(test_carbon).collect(),
            corners.as_slice(),
        );
        let probe = Molecule::new("probe", vec![test_carbon(7)], &[DVec3::splat(3.5)]);
        let mut s = Session::new(
            vec![cage, probe],
            Settings {
                response: Response::Soft,
                ..Settings::default()
            },
        )
        .expect("session");
        s.step(&FrameInput::docking(), 0.0);
        s.step(
            &FrameInput::with_commands(&[Command::SetResponse(Response::Soft)]),
            0.0,
        );
        let mut deepest = 0.0f32;
        for _ in 0..400 {
            let to_middle = -s.bodies()[1].pose.translation;
            let out = s.step(
                &FrameInput::nudged(to_middle.clamp_length_max(0.2), DVec3::ZERO),
                0.0,
            );
            deepest = out
                .contacts
                .iter()
                .map(Contact::depth)
                .fold(deepest, f32::max);
        }
        let at = s.bodies()[1].pose.translation;
        assert!(at.length() < 0.05, "not in the cage's middle: {at}");
        assert!(deepest > 0.1, "never pressed into the band");
        let out = s.step(&FrameInput::with_commands(&[Command::Settle]), 0.0);
        assert!(
            out.messages
                .iter()
                .any(|m| m.contains("last pose without overlaps")),
            "{:?}",
            out.messages
        );
        assert!(out.settled.is_some(), "{:?}", out.messages);
        assert!(
            out.contacts.iter().all(|c| c.depth() <= 0.0),
            "{:?}",
            out.contacts
        );
        let end = s.bodies()[1].pose.translation;
        assert!(end.min_element() > 0.0, "it left by the way it came: {end}");
    }

    /// A drug alone (no receptor) turned under `soft` into syn-pentane,
    /// whose ends press into each other: the pair is listed as a contact
    /// of the drug with itself, pressed no deeper than the limit.
    #[test]
    fn a_drug_alone_lists_its_own_pressed_pairs() {
        use crate::model::{LoadOptions, receptor_only, sdf::parse_sdf};
        use crate::session::{Command, FrameInput, Settings};
        // All-trans pentane, a zigzag of 1.54 Å bonds.
        let mut sdf = String::from("pentane\n  test\n\n  5  4  0  0  0  0  0  0  0  0999 V2000\n");
        for i in 0..5 {
            let (x, y) = (f64::from(i) * 1.26, f64::from(i % 2) * 0.89);
            sdf += &format!(
                "{x:>10.4}{y:>10.4}{:>10.4} C   0  0  0  0  0  0  0  0  0  0  0  0\n",
                0.0
            );
        }
        for i in 1..5 {
            sdf += &format!("{i:>3}{:>3}  1  0\n", i + 1);
        }
        sdf += "M  END\n$$$$\n";
        let loaded = parse_sdf(&sdf, "pentane.sdf", &LoadOptions::default()).expect("loads");
        let drug = receptor_only(&loaded.structure).expect("molecule");
        let mut s = Session::new(vec![drug], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        s.step(
            &FrameInput::with_commands(&[Command::SetResponse(Response::Soft)]),
            0.0,
        );
        assert_eq!(s.rotatable_bonds(0).len(), 2);
        let ends = |s: &Session| {
            s.contacts()
                .iter()
                .filter(|c| {
                    c.moving.0 == 0
                        && c.other.0 == 0
                        && (c.moving.1.min(c.other.1), c.moving.1.max(c.other.1)) == (0, 4)
                })
                .map(Contact::depth)
                .collect::<Vec<_>>()
        };
        assert!(ends(&s).is_empty());
        // Gauche+ then gauche−: the ends come closer than their contact
        // distance.
        for (k, degrees) in [(0, 120.0), (1, -120.0)] {
            s.step(
                &FrameInput::with_commands(&[
                    Command::SelectTorsion(Some(k)),
                    Command::TurnTorsion { degrees },
                ]),
                0.0,
            );
        }
        let depths = ends(&s);
        assert_eq!(depths.len(), 1, "{:?}", s.contacts());
        assert!(depths[0] > 0.0 && depths[0] <= 1.0 + 1e-4, "{depths:?}");
    }

    /// 1,8-dibromo-2-ethylnaphthalene with its bromines 2.9 Å apart: the
    /// rigid rings hold them within the contact rule, more than three
    /// bonds apart, and no turn moves them. A turn of the ethyl group under
    /// `soft` therefore lists no contact between them: only the pairs the
    /// torsions press count.
    #[test]
    fn a_pair_the_rings_hold_within_the_rule_is_no_pressed_contact() {
        use crate::model::molecule::test_carbon;
        use crate::model::{LoadOptions, receptor_only, sdf::parse_sdf};
        use crate::session::{Command, FrameInput, Settings};
        const PERI: &str = "peri\n  test\n\n 14 15  0  0  0  0  0  0  0  0999 V2000\n    1.0017    0.1280    0.0987 C   0  0  0  0  0  0  0  0  0  0  0  0\n    0.4524   -0.4460   -1.1970 C   0  0  0  0  0  0  0  0  0  0  0  0\n    1.0097   -1.8344   -1.3984 C   0  0  0  0  0  0  0  0  0  0  0  0\n    0.2430   -2.9103   -0.9397 C   0  0  0  0  0  0  0  0  0  0  0  0\n    0.7159   -4.2043   -1.0684 C   0  0  0  0  0  0  0  0  0  0  0  0\n    1.9473   -4.4608   -1.6774 C   0  0  0  0  0  0  0  0  0  0  0  0\n    2.2773   -5.8012   -1.8956 C   0  0  0  0  0  0  0  0  0  0  0  0\n    3.3703   -6.1433   -2.6719 C   0  0  0  0  0  0  0  0  0  0  0  0\n    4.2784   -5.1622   -3.0280 C   0  0  0  0  0  0  0  0  0  0  0  0\n    4.0509   -3.8243   -2.6917 C   0  0  0  0  0  0  0  0  0  0  0  0\n    5.3209   -2.4865   -2.9704 Br  0  0  0  0  0  0  0  0  0  0  0  0\n    2.8076   -3.4002   -2.1191 C   0  0  0  0  0  0  0  0  0  0  0  0\n    2.2880   -2.0701   -1.9628 C   0  0  0  0  0  0  0  0  0  0  0  0\n    3.2124   -0.5227   -2.6412 Br  0  0  0  0  0  0  0  0  0  0  0  0\n  1  2  1  0\n  2  3  1  0\n  3  4  1  0\n  3 13  2  0\n  4  5  2  0\n  5  6  1  0\n  6  7  1  0\n  6 12  2  0\n  7  8  2  0\n  8  9  1  0\n  9 10  2  0\n 10 11  1  0\n 10 12  1  0\n 12 13  1  0\n 13 14  1  0\nM  END\n$$$$\n";
        let loaded = parse_sdf(PERI, "peri.sdf", &LoadOptions::default()).expect("loads");
        let drug = receptor_only(&loaded.structure).expect("molecule");
        let bromines: Vec<usize> = (0..drug.len())
            .filter(|&i| drug.atoms[i].element.as_str().eq_ignore_ascii_case("Br"))
            .collect();
        let [a, b] = bromines[..] else {
            panic!("two bromines: {bromines:?}")
        };
        let rule = crate::collide::ContactRule::default();
        let (x, y) = (&drug.atoms[a], &drug.atoms[b]);
        let d2 = drug.local[a].distance_squared(drug.local[b]);
        assert!(rule.collides(x.radius, x.polar, y.radius, y.polar, d2));
        let far = Molecule::new("far", vec![test_carbon(1)], &[DVec3::splat(40.0)]);
        let mut s = Session::new(vec![far, drug], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        s.step(
            &FrameInput::with_commands(&[Command::SetResponse(Response::Soft)]),
            0.0,
        );
        assert_eq!(s.rotatable_bonds(1).len(), 1);
        s.step(
            &FrameInput::with_commands(&[
                Command::SelectTorsion(Some(0)),
                Command::TurnTorsion { degrees: 40.0 },
            ]),
            0.0,
        );
        assert!(s.torsion_angles(1)[0] != 0.0, "the ethyl group turned");
        let bromines = |c: &&Contact| {
            c.moving.0 == 1 && c.other.0 == 1 && {
                let pair = (c.moving.1.min(c.other.1), c.moving.1.max(c.other.1));
                pair == (a.min(b), a.max(b))
            }
        };
        assert!(
            !s.contacts().iter().any(|c| bromines(&c)),
            "{:?}",
            s.contacts()
        );
    }
}
