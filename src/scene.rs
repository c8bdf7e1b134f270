//! A docking scene: a receptor and a drug, judged by one contact rule, with
//! the receptor indexed once by a collider.
//!
//! Both molecules keep their file coordinates as their starting poses. The
//! collider lives in the receptor's frame; [`Scene::relative`] turns the drug's
//! world pose into the pose the collider is queried with.

use glam::DVec3;

use crate::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Pair, Response, StepResult, TouchOptions,
    TouchResult, check, move_to_touch, respond,
};
use crate::model::Molecule;
use crate::motion::Pose;

/// Centre distance, in Å, under which two atoms count as coincident (the
/// same atom twice): far below any bond length (H–H, the shortest, is
/// 0.74 Å).
pub const COINCIDENT_WITHIN: f32 = 0.5;

/// A receptor, a drug and a collider over the receptor.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The fixed molecule.
    pub receptor: Molecule,
    /// The molecule that moves.
    pub drug: Molecule,
    /// The contact rule.
    pub rule: ContactRule,
    collider: Collider,
    drug_atoms: DrugAtoms,
}

impl Scene {
    /// Builds the collider for `receptor` and prepares `drug`.
    pub fn new(receptor: Molecule, drug: Molecule, rule: ContactRule, kind: ColliderKind) -> Self {
        let collider = Collider::build(&receptor, &rule, kind);
        Self::with_collider(receptor, drug, rule, collider)
    }

    /// [`Scene::new`] with a plain collider ([`Collider::build_plain`]),
    /// for a command that asks a few queries and exits.
    pub fn new_plain(
        receptor: Molecule,
        drug: Molecule,
        rule: ContactRule,
        kind: ColliderKind,
    ) -> Self {
        let collider = Collider::build_plain(&receptor, &rule, kind);
        Self::with_collider(receptor, drug, rule, collider)
    }

    fn with_collider(
        receptor: Molecule,
        drug: Molecule,
        rule: ContactRule,
        collider: Collider,
    ) -> Self {
        let drug_atoms = DrugAtoms::new(&drug, &rule, collider.max_radius());
        Self {
            receptor,
            drug,
            rule,
            collider,
            drug_atoms,
        }
    }

    /// The receptor's collider.
    pub fn collider(&self) -> &Collider {
        &self.collider
    }

    /// The prepared drug.
    pub fn drug_atoms(&self) -> &DrugAtoms {
        &self.drug_atoms
    }

    /// The receptor's pose as loaded (centre at its file position).
    pub fn receptor_file_pose(&self) -> Pose {
        Pose::from_translation(self.receptor.centre)
    }

    /// The drug's pose as loaded.
    pub fn drug_file_pose(&self) -> Pose {
        Pose::from_translation(self.drug.centre)
    }

    /// The drug's pose relative to the receptor, from world poses of both.
    pub fn relative(&self, receptor: &Pose, drug: &Pose) -> Pose {
        receptor.inverse().compose(drug)
    }

    /// The drug's file pose relative to the receptor's file pose, shifted by
    /// `offset` (world Å): computed as a difference of f64 centres, so it is
    /// exact however far from the origin the files put the molecules.
    pub fn file_relative(&self, offset: DVec3) -> Pose {
        Pose::from_translation(self.drug.centre - self.receptor.centre + offset)
    }

    /// The world pose of the drug for a pose relative to the file-posed receptor.
    pub fn world_from_relative(&self, rel: &Pose) -> Pose {
        self.receptor_file_pose().compose(rel)
    }

    /// Colliding pairs at relative pose `rel`.
    pub fn check(&self, rel: &Pose) -> Vec<Pair> {
        check(&self.collider, &self.drug_atoms, rel)
    }

    /// Drug atoms lying on top of receptor atoms at relative pose `rel`:
    /// for each drug atom whose centre is within [`COINCIDENT_WITHIN`] of a
    /// receptor atom's, the closest such pair, in drug-atom order. Such atoms
    /// collide whatever the motion; most often the receptor file still holds
    /// the drug that was also given as its own file. Pairs this close always
    /// collide under any rule whose overlap is under the two radii, so they
    /// are taken from the static check.
    pub fn coincident_atoms(&self, rel: &Pose) -> Vec<Pair> {
        let mut close: Vec<Pair> = self
            .check(rel)
            .into_iter()
            .filter(|p| p.distance <= COINCIDENT_WITHIN)
            .collect();
        close.sort_by(|a, b| {
            a.drug
                .cmp(&b.drug)
                .then(a.distance.total_cmp(&b.distance))
                .then(a.receptor.cmp(&b.receptor))
        });
        close.dedup_by_key(|p| p.drug);
        close
    }

    /// Move-to-touch from `start` to `end` (relative poses).
    pub fn move_to_touch(&self, start: &Pose, end: &Pose, opts: &TouchOptions) -> TouchResult {
        move_to_touch(&self.collider, &self.drug_atoms, start, end, opts)
    }

    /// Applies a collision response to the step from `start` to `end`.
    pub fn respond(
        &self,
        start: &Pose,
        end: &Pose,
        response: Response,
        opts: &TouchOptions,
    ) -> StepResult {
        respond(&self.collider, &self.drug_atoms, start, end, response, opts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};

    #[test]
    fn a_drug_copied_from_the_receptor_is_found_atom_by_atom() {
        let (_, e) = builtin::scene(RadiiSet::Bondi);
        let scene = Scene::new(
            e.clone(),
            e.clone(),
            ContactRule::default(),
            ColliderKind::Hashed,
        );
        let on_top = scene.coincident_atoms(&scene.file_relative(DVec3::ZERO));
        assert_eq!(on_top.len(), e.len());
        for (i, p) in on_top.iter().enumerate() {
            assert_eq!((p.drug, p.receptor), (i as u32, i as u32));
            assert_eq!(p.distance, 0.0);
        }
        // Shifted by more than the limit, nothing is coincident, though
        // the copies still collide.
        let shifted = scene.file_relative(DVec3::new(0.0, 0.0, 0.6));
        assert!(!scene.check(&shifted).is_empty());
        assert!(scene.coincident_atoms(&shifted).is_empty());
        let near = scene.file_relative(DVec3::new(0.0, 0.0, 0.4));
        assert_eq!(scene.coincident_atoms(&near).len(), e.len());
    }
}
