//! Pockets on the receptor alone: where a drug could bind, found on a grid
//! of probe points and ranked by how buried they are.
//!
//! The method is LIGSITE's buriedness on a lattice, with fpocket's idea of a
//! pocket as a cluster of probe positions:
//! 1. A lattice ([`PocketOptions::spacing`]) over the receptor's heavy atoms
//!    (waters left out) marks each point *solid* when it lies within an
//!    atom's radius, and a *probe point* when its distance to every atom
//!    centre is at least [`PocketOptions::probe_clearance`] (where a drug's
//!    heavy atom could sit) yet some atom lies within
//!    [`PocketOptions::shell`] (the first shell round the protein, not bulk
//!    solvent).
//! 2. Each probe point casts [`PocketOptions::rays`] rays spread evenly over
//!    the sphere out to [`PocketOptions::ray_length`]; its *buriedness* is
//!    the fraction of them that hit a solid point.
//! 3. Probe points buried at least [`PocketOptions::min_buriedness`] are
//!    joined into clusters of face-, edge- or corner-touching neighbours.
//!    Each cluster is cut into parts about its densest points (a point's
//!    density: the buriedness of its neighbours within [`CORE_RADIUS`]):
//!    the densest takes every point within [`PocketOptions::split_radius`],
//!    then the densest of the rest, and so on, so that a groove or a channel
//!    gives several pockets, each centred on its deep part. Parts of fewer
//!    than [`PocketOptions::min_points`] points are dropped.
//! 4. A pocket's score is the sum over its points of the square of how far
//!    each is buried beyond the threshold (deep pockets first, then big
//!    ones); its centre is its densest point.
//!    Its box is its points' extent padded by [`PocketOptions::box_pad`],
//!    at least [`PocketOptions::box_min`] and at most
//!    [`PocketOptions::box_max`] along each axis (centred on the centre
//!    where it is cut).
//!
//! Everything runs in file coordinates, in lattice order, so the result is
//! the same on every run; the ray casting is spread over threads by z-plane,
//! each point's value independent of the others.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::chem::grid::NeighbourGrid;
use crate::model::{Molecule, is_water};

/// Radius (Å) about a pocket point within which its buried neighbours are
/// summed to find the pocket's densest part (its centre).
pub const CORE_RADIUS: f64 = 4.0;

/// Most lattice points; a larger receptor gets a coarser lattice.
pub const MAX_POINTS: usize = 16_000_000;

/// How pockets are found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PocketOptions {
    /// Lattice spacing (Å); coarsened for a receptor whose box would need
    /// more than [`MAX_POINTS`] points.
    pub spacing: f64,
    /// Least distance (Å) from a probe point to every atom centre.
    pub probe_clearance: f64,
    /// A probe point has an atom centre within this distance (Å).
    pub shell: f64,
    /// Rays cast from each probe point.
    pub rays: usize,
    /// Length of each ray (Å).
    pub ray_length: f64,
    /// Least buriedness (fraction of rays that hit the receptor) of a point
    /// that belongs to a pocket.
    pub min_buriedness: f64,
    /// A cluster is cut into parts of at most this radius (Å) about its
    /// densest points, so that a long groove or a channel gives several
    /// pockets, each centred on its own deep part.
    pub split_radius: f64,
    /// Fewest points in a pocket.
    pub min_points: usize,
    /// Å added to a pocket's extent on every side for its box.
    pub box_pad: f64,
    /// Shortest box edge (Å).
    pub box_min: f64,
    /// Longest box edge (Å).
    pub box_max: f64,
    /// Most pockets kept (the best ranked).
    pub max_pockets: usize,
}

impl Default for PocketOptions {
    fn default() -> Self {
        Self {
            spacing: 1.0,
            probe_clearance: 3.0,
            shell: 4.5,
            rays: 30,
            ray_length: 10.0,
            min_buriedness: 0.6,
            split_radius: 6.0,
            min_points: 8,
            box_pad: 5.0,
            box_min: 20.0,
            box_max: 30.0,
            max_pockets: 20,
        }
    }
}

/// A docking box: centre and edge lengths (Å, file coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DockBox {
    /// Centre.
    pub centre: DVec3,
    /// Edge lengths.
    pub size: DVec3,
}

impl DockBox {
    /// The box round `points` padded by `pad` on every side, at least
    /// `min_size` along each axis (Vina's autobox from a reference ligand).
    /// `None` for no points.
    pub fn around(points: &[DVec3], pad: f64, min_size: f64) -> Option<Self> {
        let (lo, hi) = extent(points)?;
        Some(Self {
            centre: (lo + hi) / 2.0,
            size: (hi - lo + DVec3::splat(2.0 * pad)).max(DVec3::splat(min_size)),
        })
    }

    /// The lowest corner.
    pub fn lo(&self) -> DVec3 {
        self.centre - self.size / 2.0
    }

    /// The highest corner.
    pub fn hi(&self) -> DVec3 {
        self.centre + self.size / 2.0
    }

    /// True when `p` lies inside (or on) the box.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.lo()).all() && p.cmple(self.hi()).all()
    }

    /// The box moved by `d`.
    pub fn shifted(&self, d: DVec3) -> Self {
        Self {
            centre: self.centre + d,
            size: self.size,
        }
    }
}

/// The lowest and highest corner of `points`.
pub fn extent(points: &[DVec3]) -> Option<(DVec3, DVec3)> {
    let first = *points.first()?;
    Some(
        points
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
    )
}

/// A residue that lines a pocket.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Residue {
    /// Chain identifier.
    pub chain: String,
    /// Residue number.
    pub seq: i64,
    /// Insertion code (empty for none).
    pub insertion: String,
    /// Residue name.
    pub name: String,
}

impl Residue {
    /// `A:ASP27` (`ASP27` without a chain), with any insertion code.
    pub fn label(&self) -> String {
        if self.chain.is_empty() {
            format!("{}{}{}", self.name, self.seq, self.insertion)
        } else {
            format!("{}:{}{}{}", self.chain, self.name, self.seq, self.insertion)
        }
    }
}

/// A candidate binding pocket.
#[derive(Debug, Clone, PartialEq)]
pub struct Pocket {
    /// 1 for the best.
    pub rank: usize,
    /// The rank score: Σ over the points of (buriedness − threshold).
    pub score: f64,
    /// Centre (file coordinates): its densest buried part.
    pub centre: DVec3,
    /// The docking box round it.
    pub dock_box: DockBox,
    /// Volume of its probe points (Å³).
    pub volume: f64,
    /// Mean buriedness of its points (0–1).
    pub buriedness: f64,
    /// Residues with a heavy atom within `probe_clearance + 1.5` Å of a point,
    /// sorted by chain, number and insertion code.
    pub residues: Vec<Residue>,
    /// The probe points (file coordinates), in lattice order.
    pub points: Vec<DVec3>,
}

/// Why pockets cannot be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PocketError {
    /// The receptor has no heavy atoms but water.
    #[error("the receptor has no atoms but water to find pockets on")]
    Empty,
    /// An option is out of its range.
    #[error("pocket option {name} = {value} is out of range ({range})")]
    Option {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it may be.
        range: &'static str,
    },
}

impl PocketOptions {
    fn check(&self) -> Result<(), PocketError> {
        let bad = |name, value: f64, range| Err(PocketError::Option { name, value, range });
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.spacing) || self.spacing > 5.0 {
            return bad("spacing", self.spacing, "above 0 and at most 5 Å");
        }
        if !pos(self.probe_clearance) || !pos(self.shell) || self.shell <= self.probe_clearance {
            return bad("shell", self.shell, "beyond the probe clearance");
        }
        if self.rays == 0 || self.rays > 1000 {
            return bad("rays", self.rays as f64, "1 to 1000");
        }
        if !pos(self.ray_length) || self.ray_length > 50.0 {
            return bad("ray_length", self.ray_length, "above 0 and at most 50 Å");
        }
        if !pos(self.split_radius) {
            return bad("split_radius", self.split_radius, "above 0 Å");
        }
        if !(0.0..=1.0).contains(&self.min_buriedness) {
            return bad("min_buriedness", self.min_buriedness, "0 to 1");
        }
        if !self.box_pad.is_finite() || self.box_pad < 0.0 {
            return bad("box_pad", self.box_pad, "0 or more");
        }
        if !pos(self.box_min) || !pos(self.box_max) || self.box_max < self.box_min {
            return bad("box_max", self.box_max, "at least the least box edge");
        }
        Ok(())
    }
}

/// The lattice the search runs on.
struct Lattice {
    origin: DVec3,
    h: f64,
    n: [usize; 3],
}

impl Lattice {
    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (z * self.n[1] + y) * self.n[0] + x
    }

    fn point(&self, i: usize) -> DVec3 {
        let x = i % self.n[0];
        let y = (i / self.n[0]) % self.n[1];
        let z = i / (self.n[0] * self.n[1]);
        self.origin + DVec3::new(x as f64, y as f64, z as f64) * self.h
    }

    fn len(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    /// The lattice cell of `p`, if inside.
    fn cell(&self, p: DVec3) -> Option<usize> {
        let g = (p - self.origin) / self.h;
        let r = g.round();
        if r.cmplt(DVec3::ZERO).any() {
            return None;
        }
        let (x, y, z) = (r.x as usize, r.y as usize, r.z as usize);
        (x < self.n[0] && y < self.n[1] && z < self.n[2]).then(|| self.index(x, y, z))
    }
}

/// Finds and ranks the pockets of `receptor` (see the module docs).
///
/// # Errors
/// [`PocketError`] for a receptor of water alone or options out of range.
pub fn find_pockets(receptor: &Molecule, opts: &PocketOptions) -> Result<Vec<Pocket>, PocketError> {
    opts.check()?;
    let atoms: Vec<usize> = (0..receptor.len())
        .filter(|&i| !is_water(receptor.atoms[i].residue.as_str()))
        .collect();
    // Relative to the receptor's centre, where f32 grids keep their
    // precision however far from the origin the file puts the receptor.
    let pos: Vec<DVec3> = atoms
        .iter()
        .map(|&i| receptor.local[i].as_dvec3())
        .collect();
    let radii: Vec<f64> = atoms
        .iter()
        .map(|&i| f64::from(receptor.atoms[i].radius))
        .collect();
    let (lo, hi) = extent(&pos).ok_or(PocketError::Empty)?;
    let margin = opts.shell + opts.spacing;
    let (lo, hi) = (lo - margin, hi + margin);
    let mut h = opts.spacing;
    let count = |h: f64| {
        let n = ((hi - lo) / h).ceil() + DVec3::ONE;
        n.x * n.y * n.z
    };
    while count(h) > MAX_POINTS as f64 {
        h *= 1.25;
    }
    let nv = ((hi - lo) / h).ceil() + DVec3::ONE;
    let lattice = Lattice {
        origin: lo,
        h,
        n: [nv.x as usize, nv.y as usize, nv.z as usize],
    };
    // Per point: 0 open and far, 1 near (within the shell), 2 too close to
    // be a probe point, 3 solid.
    let mut mark = vec![0u8; lattice.len()];
    let mut splat = |p: DVec3, reach: f64, value: u8| {
        let g0 = ((p - reach - lattice.origin) / h).ceil().max(DVec3::ZERO);
        let g1 = ((p + reach - lattice.origin) / h).floor();
        let top = DVec3::new(
            (lattice.n[0] - 1) as f64,
            (lattice.n[1] - 1) as f64,
            (lattice.n[2] - 1) as f64,
        );
        let g1 = g1.min(top);
        if g1.cmplt(g0).any() {
            return;
        }
        let r2 = reach * reach;
        for z in g0.z as usize..=g1.z as usize {
            for y in g0.y as usize..=g1.y as usize {
                for x in g0.x as usize..=g1.x as usize {
                    let i = lattice.index(x, y, z);
                    if (lattice.point(i) - p).length_squared() <= r2 && mark[i] < value {
                        mark[i] = value;
                    }
                }
            }
        }
    };
    for (p, r) in pos.iter().zip(&radii) {
        splat(*p, opts.shell, 1);
        splat(*p, opts.probe_clearance, 2);
        splat(*p, *r, 3);
    }
    // Rays: unit steps of half a lattice spacing, as offsets in points.
    let dirs = crate::rng::sphere_directions(opts.rays);
    let steps = (opts.ray_length / (0.5 * h)).ceil() as usize;
    let probes: Vec<usize> = (0..lattice.len()).filter(|&i| mark[i] == 1).collect();
    let buried: Vec<f64> = probes
        .par_iter()
        .map(|&i| {
            let p = lattice.point(i);
            let hits = dirs
                .iter()
                .filter(|d| {
                    (1..=steps).any(|s| {
                        let q = p + **d * (s as f64 * 0.5 * h);
                        lattice.cell(q).is_some_and(|c| mark[c] == 3)
                    })
                })
                .count();
            hits as f64 / opts.rays as f64
        })
        .collect();
    // Kept points, as lattice index → their buriedness.
    let kept = Kept(
        probes
            .iter()
            .zip(&buried)
            .filter(|(_, b)| **b >= opts.min_buriedness)
            .map(|(&i, &b)| (i, b))
            .collect(),
    );
    let clusters = cluster(&lattice, &kept);
    let clusters: Vec<Vec<usize>> = clusters
        .into_iter()
        .flat_map(|c| split_cluster(&lattice, &kept, c, opts.split_radius))
        .collect();
    let mut pockets: Vec<Pocket> = clusters
        .into_iter()
        .filter(|c| c.len() >= opts.min_points)
        .map(|c| pocket_of(&lattice, &kept, &c, opts))
        .collect();
    pockets.sort_by(|a, b| {
        b.score
            .total_cmp(&a.score)
            .then(a.points[0].x.total_cmp(&b.points[0].x))
    });
    pockets.truncate(opts.max_pockets);
    let reach = opts.probe_clearance + 1.5;
    let atom_grid = Near::new(&pos, reach);
    for (k, p) in pockets.iter_mut().enumerate() {
        p.rank = k + 1;
        p.residues = lining(p, &atom_grid, &atoms, receptor);
        // Back to file coordinates.
        let c = receptor.centre;
        p.centre += c;
        p.dock_box = p.dock_box.shifted(c);
        p.points.iter_mut().for_each(|q| *q += c);
    }
    Ok(pockets)
}

/// The probe points buried enough to be in a pocket: (lattice index,
/// buriedness), in lattice order. Kept apart from the lattice, whose size
/// is the receptor's box, so that memory follows the points kept.
struct Kept(Vec<(usize, f64)>);

impl Kept {
    /// The position in the list of lattice point `i`, if kept.
    fn slot(&self, i: usize) -> Option<usize> {
        self.0.binary_search_by_key(&i, |k| k.0).ok()
    }

    /// The buriedness of lattice point `i` (kept).
    fn of(&self, i: usize) -> f64 {
        self.slot(i).map_or(0.0, |k| self.0[k].1)
    }
}

/// The clusters of kept points joined through their 26 neighbours, each in
/// lattice order, in order of their first point.
fn cluster(lattice: &Lattice, kept: &Kept) -> Vec<Vec<usize>> {
    let mut seen = vec![false; kept.0.len()];
    let mut out = Vec::new();
    let [nx, ny, nz] = lattice.n;
    for first in 0..kept.0.len() {
        if seen[first] {
            continue;
        }
        seen[first] = true;
        let mut stack = vec![kept.0[first].0];
        let mut members = Vec::new();
        while let Some(i) = stack.pop() {
            members.push(i);
            let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
            for dz in -1i64..=1 {
                for dy in -1i64..=1 {
                    for dx in -1i64..=1 {
                        let (a, b, c) = (x as i64 + dx, y as i64 + dy, z as i64 + dz);
                        let outside = a < 0
                            || b < 0
                            || c < 0
                            || a >= nx as i64
                            || b >= ny as i64
                            || c >= nz as i64;
                        if outside {
                            continue;
                        }
                        let j = lattice.index(a as usize, b as usize, c as usize);
                        if let Some(k) = kept.slot(j)
                            && !seen[k]
                        {
                            seen[k] = true;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        members.sort_unstable();
        out.push(members);
    }
    out
}

/// The residues with an atom within the grid's radius of one of `p`'s
/// points (receptor frame), sorted.
fn lining(p: &Pocket, grid: &Near<'_>, atoms: &[usize], receptor: &Molecule) -> Vec<Residue> {
    let mut near = Vec::new();
    for q in &p.points {
        grid.within(*q, |j| near.push(j));
    }
    near.sort_unstable();
    near.dedup();
    let mut residues: Vec<Residue> = near
        .into_iter()
        .map(|j| {
            let a = &receptor.atoms[atoms[j]];
            Residue {
                chain: a.chain.to_string(),
                seq: a.seq,
                insertion: a.insertion.to_string().trim().to_string(),
                name: a.residue.to_string(),
            }
        })
        .collect();
    residues.sort();
    residues.dedup();
    residues
}

/// `members` cut into parts of at most `radius` about their densest
/// points: the densest point (the most buriedness within [`CORE_RADIUS`])
/// takes every point within `radius` of it, and so on with what is left.
fn split_cluster(
    lattice: &Lattice,
    kept: &Kept,
    members: Vec<usize>,
    radius: f64,
) -> Vec<Vec<usize>> {
    let points: Vec<DVec3> = members.iter().map(|&i| lattice.point(i)).collect();
    let grid = Near::new(&points, CORE_RADIUS);
    let density: Vec<f64> = points
        .iter()
        .map(|p| {
            let mut sum = 0.0;
            grid.within(*p, |j| sum += kept.of(members[j]));
            sum
        })
        .collect();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| density[b].total_cmp(&density[a]).then(a.cmp(&b)));
    let mut taken = vec![false; points.len()];
    let mut out = Vec::new();
    let parts = Near::new(&points, radius);
    for &seed in &order {
        if taken[seed] {
            continue;
        }
        let mut part = Vec::new();
        parts.within(points[seed], |j| {
            if !taken[j] {
                taken[j] = true;
                part.push(j);
            }
        });
        part.sort_unstable();
        out.push(part.into_iter().map(|j| members[j]).collect());
    }
    out
}

/// The pocket of the cluster `members`.
fn pocket_of(lattice: &Lattice, kept: &Kept, members: &[usize], opts: &PocketOptions) -> Pocket {
    let points: Vec<DVec3> = members.iter().map(|&i| lattice.point(i)).collect();
    let b: Vec<f64> = members.iter().map(|&i| kept.of(i)).collect();
    // Deep points count for more than shallow ones: a big shallow groove
    // must not outrank a small deep pocket.
    let step = 1.0 / opts.rays as f64;
    let score: f64 = 10.0
        * b.iter()
            .map(|v| (v - opts.min_buriedness + step).powi(2))
            .sum::<f64>();
    let buriedness = b.iter().sum::<f64>() / b.len() as f64;
    // The densest part: per point, the buriedness within CORE_RADIUS.
    let grid = Near::new(&points, CORE_RADIUS);
    let mut best = (f64::NEG_INFINITY, 0usize);
    for (k, p) in points.iter().enumerate() {
        let mut sum = 0.0;
        grid.within(*p, |j| sum += b[j]);
        if sum > best.0 {
            best = (sum, k);
        }
    }
    let centre = points[best.1];
    let (lo, hi) = extent(&points).unwrap_or((centre, centre));
    let padded = hi - lo + DVec3::splat(2.0 * opts.box_pad);
    let size = padded
        .max(DVec3::splat(opts.box_min))
        .min(DVec3::splat(opts.box_max));
    // Centred on the extent where it fits, on the densest point along an
    // axis where the box cuts it.
    let box_centre = DVec3::select(padded.cmpgt(size), centre, (lo + hi) / 2.0);
    Pocket {
        rank: 0,
        score,
        centre,
        dock_box: DockBox {
            centre: box_centre,
            size,
        },
        volume: points.len() as f64 * lattice.h.powi(3),
        buriedness,
        residues: Vec::new(),
        points,
    }
}

/// Points within a radius of a point, through the chemistry's grid.
struct Near<'a> {
    grid: NeighbourGrid,
    points: &'a [DVec3],
    r2: f64,
}

impl<'a> Near<'a> {
    fn new(points: &'a [DVec3], r: f64) -> Self {
        let p32: Vec<Vec3> = points.iter().map(|p| p.as_vec3()).collect();
        Self {
            grid: NeighbourGrid::new(&p32, r as f32),
            points,
            r2: r * r,
        }
    }

    /// Calls `f` with each point within the radius of `p`.
    fn within(&self, p: DVec3, mut f: impl FnMut(usize)) {
        self.grid.for_each_near(p.as_vec3(), |j| {
            if (self.points[j as usize] - p).length_squared() <= self.r2 {
                f(j as usize);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::model::molecule::test_carbon;

    /// A hollow ball of carbons (radius `r`) with a hole cut at +z: a pocket
    /// whose centre is the ball's.
    fn cup(r: f64) -> Molecule {
        let mut pos = Vec::new();
        for d in crate::rng::sphere_directions(1200) {
            if d.z < 0.7 {
                pos.push(d * r);
            }
        }
        let atoms = (0..pos.len()).map(|i| test_carbon(i as i64)).collect();
        Molecule::new("cup", atoms, &pos)
    }

    #[test]
    fn a_cup_has_one_pocket_at_its_middle() {
        let m = cup(9.0);
        let p = find_pockets(&m, &PocketOptions::default()).unwrap();
        assert!(!p.is_empty());
        let top = &p[0];
        assert_eq!(top.rank, 1);
        // Inside the cup (its parts are cut 6 Å about their densest points,
        // which lie nearer the wall than the middle).
        assert!(top.centre.length() < 9.0, "{:?}", top.centre);
        assert!(top.buriedness > 0.6);
        assert!(p.iter().any(|q| q.dock_box.contains(DVec3::ZERO)));
        // Nothing of the outside (bulk solvent) is a pocket point.
        for q in &top.points {
            assert!(q.length() < 9.0, "{q:?}");
        }
    }

    #[test]
    fn a_flat_sheet_has_no_pocket() {
        let mut pos = Vec::new();
        for i in -10..=10 {
            for j in -10..=10 {
                pos.push(DVec3::new(i as f64 * 1.5, j as f64 * 1.5, 0.0));
            }
        }
        let atoms = (0..pos.len()).map(|i| test_carbon(i as i64)).collect();
        let m = Molecule::new("sheet", atoms, &pos);
        assert!(
            find_pockets(&m, &PocketOptions::default())
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn autobox_pads_and_keeps_a_least_size() {
        let b = DockBox::around(&[DVec3::ZERO, DVec3::new(14.0, 2.0, 0.0)], 5.0, 20.0).unwrap();
        assert_eq!(b.size, DVec3::new(24.0, 20.0, 20.0));
        assert_eq!(b.centre, DVec3::new(7.0, 1.0, 0.0));
        assert!(DockBox::around(&[], 5.0, 20.0).is_none());
    }

    #[test]
    fn bad_options_are_refused() {
        let m = cup(9.0);
        let o = PocketOptions {
            spacing: 0.0,
            ..PocketOptions::default()
        };
        assert!(matches!(
            find_pockets(&m, &o),
            Err(PocketError::Option { .. })
        ));
    }
}
