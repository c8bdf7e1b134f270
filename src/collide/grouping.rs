//! Spatially compact groups of four drug atoms.
//!
//! Move-to-touch and the static check test a drug's atoms four at a time,
//! first by the bounding ball of the four ([`super::drug::Balls4`]): a
//! ball the clearance map proves far from the receptor spares its four
//! atoms every further test. The smaller the balls, the more of them it
//! proves, so the groups are not the file's runs of four atoms but the
//! atoms gathered by proximity: [`compact_order`] orders the atoms so that
//! each run of four lies close together.
//!
//! For drugs of up to [`GREEDY_MAX`] atoms the order is built greedily (the
//! remaining atom farthest from the others' centroid starts a group, which
//! then takes, three times, the remaining atom nearest its centroid), then
//! improved by swapping atoms between groups while a swap shrinks the sum
//! of the two groups' radii. Larger molecules (a protein moved as a whole)
//! keep their file order, which runs residue by residue and so is compact
//! already.
//!
//! # Performance
//! Once per drug: 0.07 ms for 30 atoms, 4.4 ms for 256 (quadratic).
//!
//! The order changes only which atoms share a group, never an answer: pairs
//! name the drug's own atom indices.

use glam::{DVec3, Vec3};

/// Most atoms ordered greedily (quadratic cost; a drug has tens).
pub const GREEDY_MAX: usize = 256;

/// Most passes of swaps after the greedy order.
const SWAP_PASSES: usize = 4;

/// The atoms' indices ordered so that each run of four (the last run may
/// be shorter) is spatially compact; a permutation of `0..points.len()`.
/// Deterministic: ties go to the lower index.
pub fn compact_order(points: &[Vec3]) -> Vec<u32> {
    if points.len() > GREEDY_MAX {
        // A large molecule is a protein moved as a whole: its file runs
        // residue by residue, so its runs of four are near already.
        return (0..points.len() as u32).collect();
    }
    let p: Vec<DVec3> = points.iter().map(|v| v.as_dvec3()).collect();
    let mut order = greedy(&p);
    improve(&p, &mut order);
    order
}

/// Radius of the ball about the bounding box's centre that holds the
/// points `group` (as [`super::drug::DrugAtoms`] bounds a group).
pub fn group_radius(p: &[DVec3], group: &[u32]) -> f64 {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for &i in group {
        lo = lo.min(p[i as usize]);
        hi = hi.max(p[i as usize]);
    }
    let centre = 0.5 * (lo + hi);
    group
        .iter()
        .map(|&i| p[i as usize].distance(centre))
        .fold(0.0, f64::max)
}

/// Index in `left` of the point minimising `key`, ties to the lower atom
/// index (`left` is not sorted: it loses items by `swap_remove`).
fn best_by(p: &[DVec3], left: &[u32], key: impl Fn(DVec3) -> f64) -> usize {
    let mut best = 0;
    for k in 1..left.len() {
        let (a, b) = (key(p[left[k] as usize]), key(p[left[best] as usize]));
        if a < b || (a == b && left[k] < left[best]) {
            best = k;
        }
    }
    best
}

/// Greedy groups: the remaining point farthest from the remaining points'
/// centroid starts a group (outliers first, while they still have near
/// partners), which takes the remaining point nearest its centroid until
/// it has four.
fn greedy(p: &[DVec3]) -> Vec<u32> {
    let mut left: Vec<u32> = (0..p.len() as u32).collect();
    let mut order = Vec::with_capacity(p.len());
    while !left.is_empty() {
        let centroid = left.iter().map(|&i| p[i as usize]).sum::<DVec3>() / left.len() as f64;
        let seed = best_by(p, &left, |x| -x.distance_squared(centroid));
        let first = order.len();
        order.push(left.swap_remove(seed));
        while order.len() - first < 4 && !left.is_empty() {
            let group = &order[first..];
            let c = group.iter().map(|&i| p[i as usize]).sum::<DVec3>() / group.len() as f64;
            let k = best_by(p, &left, |x| x.distance_squared(c));
            order.push(left.swap_remove(k));
        }
    }
    order
}

/// Swaps atoms between groups (runs of four of `order`) while a swap
/// shrinks the sum of the two groups' radii, for up to [`SWAP_PASSES`]
/// passes. Group sizes do not change, so a short group stays last.
fn improve(p: &[DVec3], order: &mut [u32]) {
    let n = order.len();
    let run = |g: usize| 4 * g..(4 * g + 4).min(n);
    // Each group's radius, kept up to date as swaps are taken, so a trial
    // measures only the two groups as they would be after it.
    let mut radius: Vec<f64> = order.chunks(4).map(|g| group_radius(p, g)).collect();
    for _ in 0..SWAP_PASSES {
        let mut changed = false;
        for a in 0..n {
            for b in (a / 4 + 1) * 4..n {
                let (ga, gb) = (a / 4, b / 4);
                order.swap(a, b);
                let (ra, rb) = (
                    group_radius(p, &order[run(ga)]),
                    group_radius(p, &order[run(gb)]),
                );
                // A margin, so rounding cannot swap back and forth.
                if ra + rb < radius[ga] + radius[gb] - 1e-9 {
                    (radius[ga], radius[gb]) = (ra, rb);
                    changed = true;
                } else {
                    order.swap(a, b);
                }
            }
        }
        if !changed {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bump_testkit::Rng;

    fn is_permutation(order: &[u32], n: usize) -> bool {
        let mut seen = vec![false; n];
        order.len() == n
            && order
                .iter()
                .all(|&i| (i as usize) < n && !std::mem::replace(&mut seen[i as usize], true))
    }

    fn radii_sum(p: &[DVec3], order: &[u32]) -> f64 {
        order.chunks(4).map(|g| group_radius(p, g)).sum()
    }

    /// Every size gives a permutation; on random clouds the groups are no
    /// larger in sum than the file's runs of four, and on a scrambled helix
    /// much smaller; the same points give the same order.
    #[test]
    fn orders_are_compact_permutations() {
        let mut rng = Rng(5);
        for n in [0usize, 1, 3, 4, 5, 9, 30, 64, GREEDY_MAX, GREEDY_MAX + 1] {
            let cloud: Vec<Vec3> = (0..n)
                .map(|_| rng.in_box(DVec3::splat(6.0)).as_vec3())
                .collect();
            let order = compact_order(&cloud);
            assert!(is_permutation(&order, n), "{n}");
            assert_eq!(order, compact_order(&cloud), "{n}: not deterministic");
            let p: Vec<DVec3> = cloud.iter().map(|v| v.as_dvec3()).collect();
            let file: Vec<u32> = (0..n as u32).collect();
            if n <= GREEDY_MAX {
                assert!(radii_sum(&p, &order) <= radii_sum(&p, &file) + 1e-9, "{n}");
            }
        }
        // A helix of 1.5 Å steps visited in a scrambled order: its runs of
        // four are spread over the helix, the compact ones are not.
        let n = 40;
        let helix: Vec<Vec3> = (0..n)
            .map(|k| {
                let a = k as f64 * 0.9;
                DVec3::new(3.0 * a.cos(), 3.0 * a.sin(), 0.5 * k as f64).as_vec3()
            })
            .collect();
        let scrambled: Vec<Vec3> = (0..n).map(|k| helix[(k * 17) % n]).collect();
        let p: Vec<DVec3> = scrambled.iter().map(|v| v.as_dvec3()).collect();
        let file: Vec<u32> = (0..n as u32).collect();
        let order = compact_order(&scrambled);
        assert!(is_permutation(&order, n));
        assert!(
            radii_sum(&p, &order) < 0.5 * radii_sum(&p, &file),
            "{} vs {}",
            radii_sum(&p, &order),
            radii_sum(&p, &file)
        );
    }

    /// A large molecule keeps its file order.
    #[test]
    fn large_molecules_keep_their_order() {
        let mut rng = Rng(8);
        let n = GREEDY_MAX + 1;
        let cloud: Vec<Vec3> = (0..n)
            .map(|_| rng.in_box(DVec3::splat(20.0)).as_vec3())
            .collect();
        assert_eq!(compact_order(&cloud), (0..n as u32).collect::<Vec<_>>());
    }
}
