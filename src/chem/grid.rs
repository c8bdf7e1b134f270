//! A uniform grid over points, for finding the points near a point in time
//! independent of how many there are: bond perception and attaching
//! hydrogens to their heavy atoms are linear in the atom count with it.
//!
//! Points are binned into cubic cells of the search radius; the points of a
//! cell lie together in one sorted array, found through a hash map from the
//! cell to its range. A query visits the 27 cells around its point.

use std::collections::HashMap;

use glam::Vec3;

/// Points binned by cell.
#[derive(Debug, Clone)]
pub struct NeighbourGrid {
    cell: f32,
    /// Point indices, grouped by cell.
    order: Vec<u32>,
    /// Cell -> range in `order`.
    cells: HashMap<(i32, i32, i32), (u32, u32)>,
}

impl NeighbourGrid {
    /// Bins `points` into cells of side `cell` (Å), at least 0.1 Å.
    pub fn new(points: &[Vec3], cell: f32) -> Self {
        let cell = cell.max(0.1);
        let key = |p: Vec3| {
            let c = (p / cell).floor();
            // Coordinates are within ±1e6 Å of the molecule's centre, so
            // the cell indices fit an i32.
            (c.x as i32, c.y as i32, c.z as i32)
        };
        let mut keyed: Vec<((i32, i32, i32), u32)> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (key(*p), u32::try_from(i).unwrap_or(u32::MAX)))
            .collect();
        keyed.sort_unstable();
        let mut cells = HashMap::with_capacity(keyed.len() / 2 + 1);
        let mut start = 0;
        for i in 1..=keyed.len() {
            if i == keyed.len() || keyed[i].0 != keyed[start].0 {
                cells.insert(
                    keyed[start].0,
                    (
                        u32::try_from(start).unwrap_or(u32::MAX),
                        u32::try_from(i).unwrap_or(u32::MAX),
                    ),
                );
                start = i;
            }
        }
        Self {
            cell,
            order: keyed.into_iter().map(|(_, i)| i).collect(),
            cells,
        }
    }

    /// Calls `f` with the index of every binned point in the 27 cells around
    /// `p` (a superset of those within one cell side of it), in no
    /// particular order.
    pub fn for_each_near(&self, p: Vec3, mut f: impl FnMut(u32)) {
        let c = (p / self.cell).floor();
        let (x, y, z) = (c.x as i32, c.y as i32, c.z as i32);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(&(s, e)) = self.cells.get(&(x + dx, y + dy, z + dz)) {
                        for &i in &self.order[s as usize..e as usize] {
                            f(i);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_every_point_within_a_cell() {
        let pts: Vec<Vec3> = (0..200)
            .map(|i| {
                let f = i as f32;
                Vec3::new(
                    (f * 0.37).sin() * 9.0,
                    (f * 0.91).cos() * 9.0,
                    f * 0.05 - 5.0,
                )
            })
            .collect();
        let g = NeighbourGrid::new(&pts, 2.0);
        for p in &pts {
            let mut near = Vec::new();
            g.for_each_near(*p, |j| near.push(j));
            for (j, q) in pts.iter().enumerate() {
                if p.distance(*q) <= 2.0 {
                    assert!(near.contains(&(j as u32)));
                }
            }
        }
    }
}
