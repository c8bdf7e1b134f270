//! How the selected molecule meets the others: its *environment* (every
//! other molecule, indexed by one collider, built once per molecule in its
//! own frame or merged when there are several), moves through the
//! collision response, and the contacts and highlights that follow.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use super::{Contact, FrameOutcome, Session};
use crate::collide::{
    Collider, DrugAtoms, Response, SoftIndex, TouchOptions, respond, respond_soft,
};
use crate::model::Molecule;
use crate::motion::Pose;

/// Makes a response's contacts those of the pose it leaves the drug at,
/// touching what stopped it.
///
/// `stop` reports the pairs its rejected step ran into, at a pose never
/// shown: the contacts shown are those where the drug stays. `slide` ends
/// with a leg along the tangent of what it touched, which curves away from
/// a round atom: a leg of 0.2 Å ends about 0.006 Å clear, beyond the
/// tolerance, so the drug pressed into the receptor showed "Contacts: 3",
/// then 0 every other frame while it could not move. When the push was
/// blocked and the slide ends touching nothing, the rest of the push (the
/// part the slide took off) is taken once more, through move-to-touch, so
/// the drug ends against what it slides along (never beyond the push
/// asked for, never overlapping).
fn shown_contacts(
    env: &Environment,
    start: &Pose,
    end: &Pose,
    touch: &TouchOptions,
    r: &mut crate::collide::StepResult,
) {
    match r.response {
        Response::Stop if r.t < 1.0 => {
            r.contacts = crate::collide::pairs_within(
                &env.collider,
                &env.drug,
                start,
                touch.tolerance as f32,
            );
        }
        Response::Slide if r.t < 1.0 && r.contacts.is_empty() => {
            let rest = 1.0 - r.t;
            let q = (end.rotation * start.rotation.conjugate()).normalize();
            let (axis, angle) = q.to_axis_angle();
            let target = r.pose.moved(
                (end.translation - start.translation) * rest,
                axis,
                angle * rest,
            );
            let s =
                crate::collide::move_to_touch(&env.collider, &env.drug, &r.pose, &target, touch);
            r.pose = s.pose;
            r.contacts = s.contacts;
            r.colliding = s.colliding;
        }
        _ => {}
    }
}

/// The environment of the selected molecule: all others.
#[derive(Debug, Clone)]
pub(super) struct Environment {
    pub(super) selected: usize,
    /// Pose of the collider's frame in the world: the molecule's pose for
    /// one molecule, the merged atoms' centre (no rotation) for several.
    pub(super) frame: Pose,
    pub(super) collider: Arc<Collider>,
    pub(super) drug: Arc<DrugAtoms>,
    owners: Owners,
    /// The loosened index of the `soft` response, built on its first step
    /// (and again when its limit changes).
    soft: Option<Arc<SoftIndex>>,
}

/// Which molecule's atom each environment atom is.
#[derive(Debug, Clone)]
enum Owners {
    /// One molecule: atom `i` is its atom `i`.
    One(usize),
    /// Several, merged: (molecule, atom) of each.
    Merged(Vec<(usize, usize)>),
}

impl Owners {
    fn of(&self, i: usize) -> (usize, usize) {
        match self {
            Self::One(k) => (*k, i),
            Self::Merged(v) => v[i],
        }
    }
}

impl Environment {
    /// The selected molecule `mol` changed shape (its torsions turned):
    /// its copies for the collider follow, grouped as `groups`; `copy` is
    /// one already made for a receptor radius (used when it fits).
    pub(super) fn reshaped(
        &mut self,
        mol: &Molecule,
        rule: &crate::collide::ContactRule,
        groups: &[u32],
        copy: Option<(f32, Arc<DrugAtoms>)>,
    ) {
        let r = self.collider.max_radius();
        self.drug = match copy {
            Some((cr, atoms)) if cr.to_bits() == r.to_bits() => atoms,
            _ => Arc::new(DrugAtoms::with_groups(mol, rule, r, groups.to_vec())),
        };
        if let Some(soft) = self.soft.as_mut() {
            match Arc::get_mut(soft) {
                Some(s) => {
                    s.drug = DrugAtoms::with_groups(
                        mol,
                        &s.rule,
                        s.collider.max_radius(),
                        groups.to_vec(),
                    );
                }
                // Shared with a clone of the session: built again when
                // next needed.
                None => self.soft = None,
            }
        }
    }

    /// Pairs between the moving molecule `b` and the environment, as contacts
    /// between molecules.
    fn contacts(&self, b: usize, pairs: &[crate::collide::Pair]) -> Vec<Contact> {
        pairs
            .iter()
            .map(|p| Contact {
                moving: (b, p.drug as usize),
                other: self.owners.of(p.receptor as usize),
                distance: p.distance,
                contact: p.contact,
            })
            .collect()
    }
}

impl Session {
    /// With collision on, builds the selected molecule's environment now
    /// (if it is not built) and waits until its collider's clearance map is
    /// there, so the frames that follow run as every frame will from then
    /// on: for benchmarks. Frames never wait for the map (see
    /// [`Collider::wait_for_clearance`]).
    pub fn wait_for_collider(&mut self) {
        if self.settings.collision
            && let Some(env) = self.environment()
        {
            env.collider.wait_for_clearance();
        }
    }

    /// Builds (or reuses) the environment of the selected molecule.
    pub(super) fn environment(&mut self) -> Option<&Environment> {
        let stale = self
            .env
            .as_ref()
            .is_none_or(|e| e.selected != self.selected);
        if stale {
            self.env = self.build_environment();
        }
        self.env.as_ref()
    }

    fn build_environment(&mut self) -> Option<Environment> {
        let selected = self.selected;
        let mut others = (0..self.bodies.len())
            .filter(|&k| k != selected && !self.bodies[k].molecule.is_empty());
        let (first, second) = (others.next(), others.next());
        let (frame, collider, owners) = match (first, second) {
            (None, _) => return None,
            (Some(k), None) => (self.bodies[k].pose, self.own_collider(k), Owners::One(k)),
            (Some(_), Some(_)) => {
                let (frame, collider, owners) = self.merged_environment();
                (frame, Arc::new(collider), Owners::Merged(owners))
            }
        };
        let drug = self.moving_atoms(selected, collider.max_radius());
        Some(Environment {
            selected,
            frame,
            collider,
            drug,
            owners,
            soft: None,
        })
    }

    /// The selected molecule's loosened index for the soft limit now,
    /// built if it is not (once per limit and environment, never per
    /// frame).
    pub(super) fn soft_index(&mut self) -> Option<Arc<SoftIndex>> {
        let limit = self.settings.soft_limit;
        let env = self.environment()?;
        if let Some(s) = &env.soft
            && s.limit.to_bits() == limit.to_bits()
        {
            return Some(Arc::clone(s));
        }
        // The receptor's body shape does not depend on the limit.
        let body = env.soft.as_ref().and_then(|s| s.body.clone());
        let one = match &env.owners {
            Owners::One(k) => Some(*k),
            Owners::Merged(_) => None,
        };
        let merged;
        let receptor = match one {
            Some(k) => &self.bodies[k].molecule,
            None => {
                merged = self.merged_molecule().0;
                &merged
            }
        };
        let index = SoftIndex::build(
            receptor,
            &self.bodies[self.selected].molecule,
            &self.settings.rule,
            limit,
            self.settings.collider,
            body,
        )
        .ok()?;
        let index = Arc::new(index);
        if let Some(env) = self.env.as_mut() {
            env.soft = Some(Arc::clone(&index));
        }
        Some(index)
    }

    /// Molecule `k`'s collider in its own frame, built on first use.
    pub(super) fn own_collider(&mut self, k: usize) -> Arc<Collider> {
        if let Some(Some(c)) = self.own_colliders.get(k) {
            return Arc::clone(c);
        }
        let c = Arc::new(Collider::build(
            &self.bodies[k].molecule,
            &self.settings.rule,
            self.settings.collider,
        ));
        if let Some(slot) = self.own_colliders.get_mut(k) {
            *slot = Some(Arc::clone(&c));
        }
        c
    }

    /// Molecule `k`'s atoms set up to move against receptor atoms of radius
    /// up to `max_radius`, kept for the next time (for the 272k-atom
    /// assembly they take about 20 ms to set up).
    fn moving_atoms(&mut self, k: usize, max_radius: f32) -> Arc<DrugAtoms> {
        if let Some(Some((r, atoms))) = self.moving_atoms.get(k)
            && r.to_bits() == max_radius.to_bits()
        {
            return Arc::clone(atoms);
        }
        let atoms = Arc::new(DrugAtoms::new(
            &self.bodies[k].molecule,
            &self.settings.rule,
            max_radius,
        ));
        if let Some(slot) = self.moving_atoms.get_mut(k) {
            *slot = Some((max_radius, Arc::clone(&atoms)));
        }
        atoms
    }

    /// Every molecule but the selected one, at its current pose, as one
    /// collider: its frame (the atoms' centre), the collider and each
    /// atom's (molecule, atom).
    fn merged_environment(&self) -> (Pose, Collider, Vec<(usize, usize)>) {
        let (merged, owners) = self.merged_molecule();
        let frame = Pose::from_translation(merged.centre);
        let collider = Collider::build(&merged, &self.settings.rule, self.settings.collider);
        (frame, collider, owners)
    }

    /// Every molecule but the selected one, at its current pose, as one
    /// molecule (centred on its atoms), with each atom's (molecule, atom).
    fn merged_molecule(&self) -> (Molecule, Vec<(usize, usize)>) {
        let mut atoms = Vec::new();
        let mut positions = Vec::new();
        let mut owners = Vec::new();
        for (k, b) in self.bodies.iter().enumerate() {
            if k == self.selected {
                continue;
            }
            for (i, a) in b.molecule.atoms.iter().enumerate() {
                atoms.push(a.clone());
                positions.push(b.pose.transform_point(b.molecule.local[i].as_dvec3()));
                owners.push((k, i));
            }
        }
        (Molecule::new("environment", atoms, &positions), owners)
    }

    pub(super) fn move_selected(
        &mut self,
        translate: DVec3,
        axis: DVec3,
        angle: f64,
        out: &mut FrameOutcome,
    ) {
        let b = self.selected;
        let from = self.bodies[b].pose;
        let to = from.moved(translate, axis, angle);
        if !to.within_range() {
            out.messages.push(format!(
                "refused: a molecule may not move more than {:e} Å from the origin",
                crate::motion::MAX_COORDINATE
            ));
            return;
        }
        if !self.settings.collision {
            self.bodies[b].pose = to;
            self.history.record(b, from, to);
            out.moved = true;
            out.changed = true;
            return;
        }
        let (response, touch) = (self.settings.response, self.settings.touch);
        let soft = if response == Response::Soft {
            self.soft_index()
        } else {
            None
        };
        let Some(env) = self.environment() else {
            // Nothing to collide with.
            self.bodies[b].pose = to;
            self.history.record(b, from, to);
            out.moved = true;
            out.changed = true;
            return;
        };
        let inv = env.frame.inverse();
        let (start, end) = (inv.compose(&from), inv.compose(&to));
        let t0 = Instant::now();
        let mut r = match &soft {
            Some(soft) => respond_soft(&env.collider, &env.drug, soft, &start, &end, &touch),
            None => respond(&env.collider, &env.drug, &start, &end, response, &touch),
        };
        shown_contacts(env, &start, &end, &touch, &mut r);
        out.collision_timed(t0);
        out.resistance = r.resistance;
        let frame = env.frame;
        let contacts = env.contacts(b, &r.contacts);
        out.t = r.t;
        let new_pose = frame.compose(&r.pose);
        if new_pose != from {
            self.bodies[b].pose = new_pose;
            self.history.record(b, from, new_pose);
            out.moved = true;
            out.changed = true;
        }
        if !r.start_colliding.is_empty() && r.t < 1.0 {
            out.messages
                .push("start pose overlaps: only moves that do not deepen it are allowed".into());
        }
        self.set_contacts(contacts, out);
    }

    /// Puts body `b` at `pose` (undo, redo, reset): a jump, not a motion, so
    /// collisions are reported at the new pose, not prevented.
    pub(super) fn place(&mut self, b: usize, pose: Pose, out: &mut FrameOutcome) {
        self.bodies[b].pose = pose;
        // A jump leaves the path the drug came by.
        self.last_clear = None;
        out.changed = true;
        out.moved |= b == self.selected;
        if b != self.selected {
            self.env = None; // the environment held the old pose
        }
        self.refresh_contacts(out);
    }

    /// Recomputes the selected molecule's contacts where it stands.
    pub(super) fn refresh_contacts(&mut self, out: &mut FrameOutcome) {
        if !self.settings.collision || self.bodies.is_empty() {
            self.set_contacts(Vec::new(), out);
            return;
        }
        let b = self.selected;
        let pose = self.bodies[b].pose;
        let tol = self.settings.touch.tolerance as f32;
        // The drug's own pressed pairs, with or without a receptor.
        let inner = match self.flex.get(b).and_then(Option::as_ref) {
            Some(f) if f.pressed => {
                f.pressed_inside(b, &self.bodies[b].molecule, &self.settings.rule)
            }
            _ => Vec::new(),
        };
        let Some(env) = self.environment() else {
            self.set_contacts(inner, out);
            return;
        };
        let rel = env.frame.inverse().compose(&pose);
        let t0 = Instant::now();
        let pairs = crate::collide::pairs_within(&env.collider, &env.drug, &rel, tol);
        out.collision_timed(t0);
        let mut contacts = env.contacts(b, &pairs);
        contacts.extend(inner);
        self.set_contacts(contacts, out);
    }

    /// Grades the highlights again (the response or the soft limit changed).
    pub(super) fn regrade_contacts(&mut self, out: &mut FrameOutcome) {
        let contacts = self.contacts.clone();
        self.set_contacts(contacts, out);
    }

    /// Replaces the contact list, reporting highlight changes and new
    /// contacts. Work is proportional to the contacts, not to the atoms: only
    /// atoms in the old or the new list can change.
    pub(super) fn set_contacts(&mut self, contacts: Vec<Contact>, out: &mut FrameOutcome) {
        use std::collections::{BTreeMap, BTreeSet};
        let key = |c: &Contact| (c.moving, c.other);
        let old: BTreeSet<_> = self.contacts.iter().map(key).collect();
        out.new_contact |= contacts.iter().any(|c| !old.contains(&key(c)));
        // Under `soft`, each atom is graded by its deepest pair.
        let limit = (self.settings.response == Response::Soft).then_some(self.settings.soft_limit);
        let mut now: BTreeMap<(usize, usize), u8> = BTreeMap::new();
        for c in &contacts {
            let level = super::press_level(c.depth(), limit);
            for atom in [c.moving, c.other] {
                let l = now.entry(atom).or_insert(0);
                *l = (*l).max(level);
            }
        }
        let was: BTreeSet<(usize, usize)> = self
            .contacts
            .iter()
            .flat_map(|c| [c.moving, c.other])
            .collect();
        // Sorted (molecule, atom) order keeps the change list deterministic.
        let atoms: BTreeSet<(usize, usize)> = was.into_iter().chain(now.keys().copied()).collect();
        for (k, i) in atoms {
            let level = now.get(&(k, i)).copied().unwrap_or(0);
            if let Some(l) = self.highlighted.get_mut(k).and_then(|h| h.get_mut(i))
                && *l != level
            {
                *l = level;
                out.highlight_changes.push((k, i, level));
            }
        }
        if !out.highlight_changes.is_empty() {
            out.changed = true;
        }
        if self.settings.collision
            && !self.bodies.is_empty()
            && contacts.iter().all(|c| c.depth() <= 0.0)
        {
            let b = self.selected;
            let pose = self.bodies[b].pose;
            let torsions = self
                .flex
                .get(b)
                .and_then(Option::as_ref)
                .map_or(&[][..], |f| f.torsions.as_slice());
            // Kept in place: no allocation per frame.
            match &mut self.last_clear {
                Some((k, p, t)) => {
                    (*k, *p) = (b, pose);
                    t.clear();
                    t.extend_from_slice(torsions);
                }
                None => self.last_clear = Some((b, pose, torsions.to_vec())),
            }
        }
        self.contacts = contacts.clone();
        out.contacts = contacts;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};
    use crate::session::{Command, FrameInput, Settings};
    use std::collections::BTreeMap;

    /// One frame moving the selected molecule (object mode) by `v`.
    fn nudge(s: &mut Session, v: DVec3) {
        s.step(&FrameInput::nudged(v, DVec3::ZERO), 0.0);
    }

    fn env_collider(s: &Session) -> Arc<Collider> {
        Arc::clone(&s.env.as_ref().expect("an environment").collider)
    }

    fn env_drug(s: &Session) -> Arc<DrugAtoms> {
        Arc::clone(&s.env.as_ref().expect("an environment").drug)
    }

    #[test]
    fn a_molecules_collider_and_moving_atoms_are_built_once_whatever_is_selected_or_moved() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        nudge(&mut s, DVec3::new(0.0, 0.0, 1.0));
        let (rings_collider, e_atoms) = (env_collider(&s), env_drug(&s));
        // Select the rings and move them (the E's collider is built), then
        // the E again: the rings' collider is the one built first.
        s.step(&FrameInput::with_commands(&[Command::Select(0)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 2.0, 0.0));
        let (e_collider, rings_atoms) = (env_collider(&s), env_drug(&s));
        s.step(&FrameInput::with_commands(&[Command::Select(1)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 0.0, 1.0));
        assert!(Arc::ptr_eq(&env_collider(&s), &rings_collider));
        assert!(Arc::ptr_eq(&env_drug(&s), &e_atoms));
        assert_eq!(s.env.as_ref().map(|e| e.frame), Some(s.bodies[0].pose));
        s.step(&FrameInput::with_commands(&[Command::Select(0)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 1.0, 0.0));
        assert!(Arc::ptr_eq(&env_collider(&s), &e_collider));
        assert!(Arc::ptr_eq(&env_drug(&s), &rings_atoms));
    }

    #[test]
    fn two_or_more_other_molecules_are_merged_at_their_poses() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let (_, e2) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e, e2], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        nudge(&mut s, DVec3::new(0.0, 30.0, 0.0));
        let env = s.env.as_ref().expect("an environment");
        let n = s.bodies[0].molecule.len() + s.bodies[1].molecule.len();
        assert_eq!(env.collider.len(), n);
        assert!(matches!(&env.owners, Owners::Merged(v) if v.len() == n));
        assert_eq!(env.frame.rotation, glam::DQuat::IDENTITY);
    }

    #[test]
    fn soft_presses_in_up_to_its_limit_with_resistance_and_replays_the_same() {
        let run = |limit: f64| {
            let (rings, e) = builtin::scene(RadiiSet::Bondi);
            let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
            s.step(&FrameInput::docking(), 0.0);
            s.step(
                &FrameInput::with_commands(&[
                    Command::SetResponse(Response::Soft),
                    Command::SetSoftLimit(limit),
                ]),
                0.0,
            );
            let towards = s.bodies[0].pose.translation - s.bodies[1].pose.translation;
            let (mut deepest, mut resisted) = (0.0f32, 0.0f64);
            for _ in 0..300 {
                let out = s.step(
                    &FrameInput::nudged(towards.normalize() * 0.25, DVec3::ZERO),
                    0.0,
                );
                deepest = out
                    .contacts
                    .iter()
                    .map(Contact::depth)
                    .fold(deepest, f32::max);
                resisted = resisted.max(out.resistance);
            }
            (deepest, resisted, s.bodies[1].pose)
        };
        let (deep, resisted, pose) = run(1.0);
        assert!(deep > 0.5 && deep <= 1.0 + 1e-4, "pressed {deep} Å");
        assert!(resisted > 0.5, "resistance {resisted}");
        assert_eq!(run(1.0).2, pose, "the same frames give the same pose");
        let (shallow, _, _) = run(0.25);
        assert!(
            shallow <= 0.25 + 1e-4 && shallow > 0.1,
            "pressed {shallow} Å"
        );
    }

    /// Under `soft`, every atom in contact shows the level of its deepest
    /// pair; changing the response or the limit grades them again.
    #[test]
    fn pressed_atoms_are_graded_by_their_deepest_pair() {
        use crate::session::{PRESS_LEVELS, press_level};
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        s.step(
            &FrameInput::with_commands(&[Command::SetResponse(Response::Soft)]),
            0.0,
        );
        let towards = s.bodies[0].pose.translation - s.bodies[1].pose.translation;
        for _ in 0..300 {
            s.step(
                &FrameInput::nudged(towards.normalize() * 0.25, DVec3::ZERO),
                0.0,
            );
        }
        let levels = |s: &Session| -> BTreeMap<(usize, usize), u8> {
            let mut want = BTreeMap::new();
            let limit = (s.settings.response == Response::Soft).then_some(s.settings.soft_limit);
            for c in s.contacts() {
                for a in [c.moving, c.other] {
                    let l = want.entry(a).or_insert(0);
                    *l = (*l).max(press_level(c.depth(), limit));
                }
            }
            want
        };
        let want = levels(&s);
        assert!(!want.is_empty());
        assert!(
            want.values().any(|&l| l >= PRESS_LEVELS - 1),
            "pressed near the limit: {want:?}"
        );
        let shown = |s: &Session| -> BTreeMap<(usize, usize), u8> {
            let mut m = BTreeMap::new();
            for (k, b) in s.bodies.iter().enumerate() {
                for i in 0..b.molecule.len() {
                    if s.highlight_level(k, i) > 0 {
                        m.insert((k, i), s.highlight_level(k, i));
                    }
                }
            }
            m
        };
        assert_eq!(shown(&s), want);
        // A deeper limit: the same depths are a smaller share of it.
        let out = s.step(
            &FrameInput::with_commands(&[Command::SetSoftLimit(3.0)]),
            0.0,
        );
        assert!(!out.highlight_changes.is_empty());
        assert_eq!(shown(&s), levels(&s));
        assert!(shown(&s).values().all(|&l| l < PRESS_LEVELS - 1));
        // Another response: every contact is one colour again.
        let out = s.step(
            &FrameInput::with_commands(&[Command::SetResponse(Response::Slide)]),
            0.0,
        );
        assert!(out.highlight_changes.iter().all(|c| c.2 == 1));
        assert!(shown(&s).values().all(|&l| l == 1));
        assert_eq!(shown(&s).len(), want.len());
    }

    #[test]
    fn press_levels_step_evenly_through_the_band() {
        use crate::session::{PRESS_LEVELS, press_level};
        assert_eq!(press_level(0.0, Some(1.0)), 1);
        assert_eq!(press_level(0.3, None), 1);
        assert_eq!(press_level(0.3, Some(0.0)), 1);
        assert_eq!(press_level(f32::NAN, Some(1.0)), 1);
        assert_eq!(press_level(1e-6, Some(1.0)), 2);
        assert_eq!(press_level(1.0 / 7.0 + 1e-3, Some(1.0)), 3);
        assert_eq!(press_level(1.0, Some(1.0)), PRESS_LEVELS);
        assert_eq!(press_level(2.5, Some(1.0)), PRESS_LEVELS);
    }
}
