//! The scaling benchmarks' drugs, shared by the report, the criterion
//! bench `benches/collide.rs` and the tests, so all use the same queries:
//! patches of the receptor's own surface, each an
//! outermost atom and that atom's nearest neighbours (a copy), pushed
//! outwards from the receptor's centre until free. A step back along that
//! direction then meets a surface shaped like the patch itself.
//!
//! One patch says little about a receptor: how many atoms it meets depends
//! on the local shape of the surface there (a flat stretch or a protruding
//! side chain), which varies more between two places on one receptor than
//! between receptors. [`surface_drugs`] therefore takes patches from
//! several directions, to be timed in turn.

use bump::collide::{Collider, ColliderKind, ContactRule, DrugAtoms, check};
use bump::model::Molecule;
use bump::motion::Pose;
use glam::DVec3;

use crate::rng::sphere_directions;

/// One surface patch: the drug, its first free pose (relative to the
/// receptor) on the way out, in steps of 0.5 Å, and that way out (a unit
/// vector).
pub struct Patch {
    /// The copied atoms.
    pub drug: Molecule,
    /// Where the drug is first free under the rule, relative to the receptor.
    pub start: Pose,
    /// The direction it was pushed out along.
    pub out: DVec3,
}

impl Patch {
    /// The end of a step of `length` Å from the start back towards the
    /// receptor.
    pub fn step_in(&self, length: f64) -> Pose {
        self.start.moved(-self.out * length, DVec3::ZERO, 0.0)
    }
}

/// `count` patches of `n` atoms: the first about the receptor's outermost
/// atom, the others about the outermost atom in each of `count` directions
/// spread evenly over the sphere (one patch per atom: a direction whose
/// outermost atom an earlier one took is skipped), each free under `rule`.
pub fn surface_drugs(
    receptor: &Molecule,
    rule: &ContactRule,
    n: usize,
    count: usize,
) -> Vec<Patch> {
    if receptor.is_empty() || n == 0 {
        return Vec::new();
    }
    let col = Collider::build(receptor, rule, ColliderKind::Hashed);
    let outermost = |d: DVec3| {
        receptor
            .local
            .iter()
            .enumerate()
            .max_by(|a, b| {
                let (x, y) = (a.1.as_dvec3().dot(d), b.1.as_dvec3().dot(d));
                x.total_cmp(&y).then(b.0.cmp(&a.0))
            })
            .map_or(0, |(i, _)| i)
    };
    let first = receptor
        .local
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.length().total_cmp(&b.1.length()).then(b.0.cmp(&a.0)))
        .map_or(0, |(i, _)| i);
    let mut apexes = vec![first];
    for d in sphere_directions(count.saturating_sub(1)) {
        let i = outermost(d);
        if !apexes.contains(&i) {
            apexes.push(i);
        }
    }
    apexes
        .into_iter()
        .take(count)
        .map(|apex| patch(receptor, &col, rule, apex, n))
        .collect()
}

/// The single patch about the receptor's outermost atom: the first of
/// [`surface_drugs`].
pub fn surface_drug(receptor: &Molecule, rule: &ContactRule, n: usize) -> Option<Patch> {
    surface_drugs(receptor, rule, n, 1).into_iter().next()
}

/// Atom `apex` of `receptor` and its `n − 1` nearest neighbours, pushed
/// out until free.
fn patch(receptor: &Molecule, col: &Collider, rule: &ContactRule, apex: usize, n: usize) -> Patch {
    let p = receptor.local[apex];
    let mut near: Vec<(f32, usize)> = receptor
        .local
        .iter()
        .enumerate()
        .map(|(i, q)| ((*q - p).length_squared(), i))
        .collect();
    let n = n.min(near.len());
    near.select_nth_unstable_by(n - 1, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut pick: Vec<usize> = near[..n].iter().map(|x| x.1).collect();
    pick.sort_unstable();
    let atoms = pick.iter().map(|&i| receptor.atoms[i].clone()).collect();
    let pos: Vec<DVec3> = pick.iter().map(|&i| receptor.file_position(i)).collect();
    let drug = Molecule::new(format!("{n}-atom surface patch"), atoms, &pos);
    let out = (drug.centre - receptor.centre).normalize_or(DVec3::X);
    let atoms = DrugAtoms::new(&drug, rule, col.max_radius());
    let mut shift = 0.5;
    let start = loop {
        let p = Pose::from_translation(drug.centre - receptor.centre + out * shift);
        if check(col, &atoms, &p).is_empty() || shift > 100.0 {
            break p;
        }
        shift += 0.5;
    };
    Patch { drug, start, out }
}
