//! The receptor as the scoring sees it: typed heavy atoms in the receptor's
//! frame, indexed by a cell list so that the atoms within the 8 Å cutoff of
//! a point are found at a cost that depends on the local density only.
//!
//! The cells are cubes of [`CELL`] Å over the receptor's bounding box (larger
//! for a receptor spread so thin that the box would hold far more cells than
//! atoms); the atoms are stored sorted by cell, x fastest, so the cells of
//! one row are one contiguous slice. A query visits, row by row, only the
//! cells that the sphere of the cutoff reaches.

use glam::DVec3;

use super::candidates::CandidateLists;
use crate::chem::XsType;

/// Edge of a cell, Å: a quarter of the 8 Å cutoff's diameter, so a query
/// reads about 1.5 times the atoms its sphere holds.
pub const CELL: f64 = 2.0;

/// A receptor atom in the cell list.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellAtom {
    /// Position in the receptor's frame.
    pub position: DVec3,
    /// X-Score type index.
    pub xs: u32,
    /// Index into [`Receptor`]'s atoms.
    pub atom: u32,
}

/// A cell list over points.
#[derive(Debug, Clone)]
pub struct Cells {
    origin: DVec3,
    cell: f64,
    inv: f64,
    dims: [usize; 3],
    /// Per cell (x fastest), the start of its atoms in `atoms`; one more
    /// entry at the end.
    start: Vec<u32>,
    atoms: Vec<CellAtom>,
}

impl Cells {
    /// Indexes `atoms`.
    pub fn new(atoms: &[CellAtom]) -> Self {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for a in atoms {
            lo = lo.min(a.position);
            hi = hi.max(a.position);
        }
        if atoms.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
        }
        // Never more than about 8 cells per atom plus a million: the box of
        // a file's coordinates must not decide how much memory is taken.
        let extent = (hi - lo).max(DVec3::splat(1e-9));
        let budget = 8.0 * atoms.len() as f64 + 1e6;
        let mut cell = CELL;
        let count = |c: f64| {
            let d = (extent / c).floor() + 1.0;
            d.x * d.y * d.z
        };
        while count(cell) > budget {
            cell *= 1.5;
        }
        let d = (extent / cell).floor() + 1.0;
        let dims = [d.x as usize, d.y as usize, d.z as usize];
        let inv = 1.0 / cell;
        let cell_of = |p: DVec3| {
            let c = ((p - lo) * inv).floor();
            let ix = (c.x as usize).min(dims[0] - 1);
            let iy = (c.y as usize).min(dims[1] - 1);
            let iz = (c.z as usize).min(dims[2] - 1);
            (iz * dims[1] + iy) * dims[0] + ix
        };
        let n_cells = dims[0] * dims[1] * dims[2];
        let mut start = vec![0u32; n_cells + 1];
        for a in atoms {
            start[cell_of(a.position) + 1] += 1;
        }
        for c in 0..n_cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut sorted = vec![
            CellAtom {
                position: DVec3::ZERO,
                xs: 0,
                atom: 0
            };
            atoms.len()
        ];
        for a in atoms {
            let c = cell_of(a.position);
            sorted[fill[c] as usize] = *a;
            fill[c] += 1;
        }
        Self {
            origin: lo,
            cell,
            inv,
            dims,
            start,
            atoms: sorted,
        }
    }

    /// The cells' edge (Å).
    pub fn cell(&self) -> f64 {
        self.cell
    }

    /// The corner of cell (0, 0, 0).
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The number of cells along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The atoms, in cell order.
    pub fn atoms(&self) -> &[CellAtom] {
        &self.atoms
    }

    /// Calls `f` for every atom in a cell that the ball of radius `cutoff`
    /// around `x` reaches (a superset of the atoms within `cutoff`; the
    /// caller tests the distance), in cell order.
    #[inline]
    pub fn visit(&self, x: DVec3, cutoff: f64, mut f: impl FnMut(&CellAtom)) {
        self.visit_ranges(x, cutoff, |a, b| self.atoms[a..b].iter().for_each(&mut f));
    }

    /// [`Cells::visit`] by index into [`Cells::atoms`].
    #[inline]
    pub fn visit_indices(&self, x: DVec3, cutoff: f64, mut f: impl FnMut(usize)) {
        self.visit_ranges(x, cutoff, |a, b| (a..b).for_each(&mut f));
    }

    /// Calls `f(a, b)` for the atoms `a..b` of each row of cells that the
    /// ball reaches, in cell order.
    #[inline]
    fn visit_ranges(&self, x: DVec3, cutoff: f64, mut f: impl FnMut(usize, usize)) {
        let rel = (x - self.origin) * self.inv;
        let reach = cutoff * self.inv;
        let [nx, ny, nz] = self.dims;
        // Cell ranges per axis, clamped; empty when the ball misses the box.
        let range = |v: f64, n: usize| -> Option<(usize, usize)> {
            let lo = floor_index(v - reach).max(0);
            let hi = floor_index(v + reach).min(n as i64 - 1);
            (lo <= hi).then_some((lo as usize, hi as usize))
        };
        let (Some((z0, z1)), Some((y0, y1)), Some(_)) =
            (range(rel.z, nz), range(rel.y, ny), range(rel.x, nx))
        else {
            return;
        };
        // Squared distances (in cells) from `x` to each slab along y and z.
        let gap2 = |v: f64, k: usize| {
            let g = (k as f64 - v).max(v - (k as f64 + 1.0)).max(0.0);
            g * g
        };
        let r2 = reach * reach;
        let mut gy2 = [0.0f64; 24];
        let ny_used = (y1 - y0 + 1).min(gy2.len());
        for (k, g) in gy2.iter_mut().enumerate().take(ny_used) {
            *g = gap2(rel.y, y0 + k);
        }
        for z in z0..=z1 {
            let gz2 = gap2(rel.z, z);
            for y in y0..=y1 {
                let gy = if y - y0 < ny_used {
                    gy2[y - y0]
                } else {
                    gap2(rel.y, y)
                };
                let rem = r2 - gz2 - gy;
                if rem < 0.0 {
                    continue;
                }
                let h = rem.sqrt();
                let x0 = floor_index(rel.x - h).max(0) as usize;
                let x1 = floor_index(rel.x + h).min(nx as i64 - 1);
                if x1 < x0 as i64 {
                    continue;
                }
                let row = (z * ny + y) * nx;
                let a = self.start[row + x0] as usize;
                let b = self.start[row + x1 as usize + 1] as usize;
                f(a, b);
            }
        }
    }
}

/// `⌊v⌋` as an integer, without a call to `floor` (which is a library call
/// on machines without SSE 4.1): cell indices of positions within the
/// file-coordinate range.
#[inline]
fn floor_index(v: f64) -> i64 {
    // Within ±2³¹ cells: i32 conversions are the cheap ones.
    let t = v as i32;
    i64::from(if (t as f64) > v { t - 1 } else { t })
}

/// The receptor's typed heavy atoms and their cell list.
#[derive(Debug, Clone)]
pub struct Receptor {
    /// Positions of the typed atoms in the receptor's frame.
    pub positions: Vec<DVec3>,
    /// Their X-Score types.
    pub xs: Vec<XsType>,
    /// Their partial charges (e), for the Coulomb term.
    pub charges: Vec<f64>,
    /// Per typed atom, its index in the atom list it was built from.
    pub source: Vec<u32>,
    cells: Cells,
    candidates: CandidateLists,
}

impl Receptor {
    /// The receptor from its atoms' positions (receptor frame), types and
    /// charges; atoms without a type (hydrogens, elements Vina does not
    /// know) are left out. A missing charge counts as 0.
    pub fn new(positions: &[DVec3], xs: &[Option<XsType>], charges: &[f64]) -> Self {
        let mut kept = Receptor {
            positions: Vec::new(),
            xs: Vec::new(),
            charges: Vec::new(),
            source: Vec::new(),
            cells: Cells::new(&[]),
            candidates: CandidateLists::default(),
        };
        for (i, (p, t)) in positions.iter().zip(xs).enumerate() {
            if let Some(t) = t {
                kept.positions.push(*p);
                kept.xs.push(*t);
                kept.charges.push(charges.get(i).copied().unwrap_or(0.0));
                kept.source.push(i as u32);
            }
        }
        let atoms: Vec<CellAtom> = kept
            .positions
            .iter()
            .zip(&kept.xs)
            .enumerate()
            .map(|(i, (p, t))| CellAtom {
                position: *p,
                xs: t.index() as u32,
                atom: i as u32,
            })
            .collect();
        kept.cells = Cells::new(&atoms);
        kept
    }

    /// Number of typed atoms.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when no atom has a type.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The cell list.
    pub fn cells(&self) -> &Cells {
        &self.cells
    }

    /// The exact evaluator's per-cell candidate lists.
    pub(crate) fn candidates(&self) -> &CandidateLists {
        &self.candidates
    }

    /// Drops the exact evaluator's candidate lists, which it builds again
    /// as drug atoms land in their cells: for measuring what a drug pays on
    /// entering cells it has not visited. Results do not change.
    pub fn forget_candidates(&self) {
        self.candidates.forget();
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::rng::Rng;

    #[test]
    fn visits_every_atom_within_the_cutoff_once() {
        let mut rng = Rng(7);
        let atoms: Vec<CellAtom> = (0..3000)
            .map(|i| CellAtom {
                position: rng.in_box(DVec3::new(20.0, 15.0, 25.0)),
                xs: 0,
                atom: i,
            })
            .collect();
        let cells = Cells::new(&atoms);
        for _ in 0..200 {
            let x = rng.in_box(DVec3::splat(30.0));
            let mut seen = Vec::new();
            cells.visit(x, 8.0, |a| seen.push(a.atom));
            let mut near: Vec<u32> = seen
                .iter()
                .copied()
                .filter(|&i| (atoms[i as usize].position - x).length_squared() < 64.0)
                .collect();
            near.sort_unstable();
            let len = near.len();
            near.dedup();
            assert_eq!(near.len(), len, "an atom visited twice");
            let want: Vec<u32> = atoms
                .iter()
                .filter(|a| (a.position - x).length_squared() < 64.0)
                .map(|a| a.atom)
                .collect();
            assert_eq!(near, want);
        }
    }

    #[test]
    fn far_flung_atoms_do_not_take_memory_by_their_spread() {
        let atoms = [0.0, 1e7]
            .iter()
            .enumerate()
            .map(|(i, &x)| CellAtom {
                position: DVec3::new(x, -x, x),
                xs: 0,
                atom: i as u32,
            })
            .collect::<Vec<_>>();
        let cells = Cells::new(&atoms);
        assert!(cells.start.len() < 2_000_000);
        let mut seen = 0;
        cells.visit(DVec3::new(1e7, -1e7, 1e7), 8.0, |_| seen += 1);
        assert_eq!(seen, 1);
    }
}
