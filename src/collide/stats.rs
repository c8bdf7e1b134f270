//! Atom density of the uniform grids: Turk's Table 1 for real files.
//!
//! For a molecule and a cell edge, counts the average number of atoms per
//! non-empty cell for a full grid and for a hashed table of a fixed size (4096
//! cells, as in the thesis), both counting an atom in every cell its sphere
//! overlaps (as the thesis did) and, separately, only in the cell holding its
//! centre.

use std::collections::{HashMap, HashSet};

use glam::Vec3;
use serde::Serialize;

use super::collider::hash_cell;
use crate::model::Molecule;

/// The thesis's hash-table size.
pub const THESIS_HASH_CELLS: usize = 4096;

/// Occupancy of one kind of grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Occupancy {
    /// Cells (or buckets) holding at least one atom.
    pub nonempty_cells: usize,
    /// Atom entries over all cells.
    pub entries: usize,
    /// `entries / nonempty_cells`.
    pub atoms_per_cell: f64,
}

impl Occupancy {
    fn new(nonempty_cells: usize, entries: usize) -> Self {
        Self {
            nonempty_cells,
            entries,
            atoms_per_cell: if nonempty_cells == 0 {
                0.0
            } else {
                entries as f64 / nonempty_cells as f64
            },
        }
    }
}

/// One row of Table 1.
#[derive(Debug, Clone, Serialize)]
pub struct DensityRow {
    /// Atoms counted.
    pub atoms: usize,
    /// Cell edge in Å.
    pub cell_size: f32,
    /// Buckets of the hashed table.
    pub hash_cells: usize,
    /// Hashed table, atoms in every cell their sphere overlaps.
    pub hashed_overlap: Occupancy,
    /// Full grid, atoms in every cell their sphere overlaps.
    pub grid_overlap: Occupancy,
    /// Hashed table, atoms by centre.
    pub hashed_centre: Occupancy,
    /// Full grid, atoms by centre.
    pub grid_centre: Occupancy,
}

/// The thesis's cell edge: the diameter of the largest sphere.
pub fn thesis_cell_size(mol: &Molecule) -> f32 {
    (2.0 * mol.max_radius()).max(0.1)
}

#[inline]
fn cell(p: Vec3, inv: f32) -> (i32, i32, i32) {
    let c = (p * inv).floor();
    (c.x as i32, c.y as i32, c.z as i32)
}

/// Computes Table 1's densities for `mol` with cell edge `cell_size` and a
/// hashed table of `hash_cells` buckets (a power of two).
pub fn density(mol: &Molecule, cell_size: f32, hash_cells: usize) -> DensityRow {
    let inv = 1.0 / cell_size;
    let mask = (hash_cells.next_power_of_two() - 1) as u32;
    let mut grid_overlap: HashMap<(i32, i32, i32), u32> = HashMap::new();
    let mut grid_centre: HashMap<(i32, i32, i32), u32> = HashMap::new();
    let mut hash_overlap = vec![0u32; mask as usize + 1];
    let mut hash_centre = vec![0u32; mask as usize + 1];
    let mut buckets = HashSet::new();
    for (p, a) in mol.local.iter().zip(&mol.atoms) {
        let r = a.radius;
        let c = cell(*p, inv);
        *grid_centre.entry(c).or_default() += 1;
        hash_centre[hash_cell(c.0, c.1, c.2, mask) as usize] += 1;
        let lo = cell(*p - Vec3::splat(r), inv);
        let hi = cell(*p + Vec3::splat(r), inv);
        buckets.clear();
        for z in lo.2..=hi.2 {
            for y in lo.1..=hi.1 {
                for x in lo.0..=hi.0 {
                    // Sphere–box test: distance from the centre to the cell.
                    let bmin = Vec3::new(x as f32, y as f32, z as f32) * cell_size;
                    let bmax = bmin + Vec3::splat(cell_size);
                    let nearest = p.clamp(bmin, bmax);
                    if (nearest - *p).length_squared() <= r * r {
                        *grid_overlap.entry((x, y, z)).or_default() += 1;
                        buckets.insert(hash_cell(x, y, z, mask));
                    }
                }
            }
        }
        for b in &buckets {
            hash_overlap[*b as usize] += 1;
        }
    }
    let occ_map = |m: &HashMap<(i32, i32, i32), u32>| {
        Occupancy::new(m.len(), m.values().map(|&v| v as usize).sum())
    };
    let occ_vec = |v: &[u32]| {
        Occupancy::new(
            v.iter().filter(|&&c| c > 0).count(),
            v.iter().map(|&c| c as usize).sum(),
        )
    };
    DensityRow {
        atoms: mol.len(),
        cell_size,
        hash_cells: mask as usize + 1,
        hashed_overlap: occ_vec(&hash_overlap),
        grid_overlap: occ_map(&grid_overlap),
        hashed_centre: occ_vec(&hash_centre),
        grid_centre: occ_map(&grid_centre),
    }
}
