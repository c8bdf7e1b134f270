//! Receptor colliders: one interface over three spatial indexes.
//!
//! A collider is built once per receptor, in the receptor's own frame
//! (coordinates relative to its centre, f32). It answers one question fast:
//! which receptor atoms may lie in an axis-aligned box. The caller applies the
//! exact contact rule to what it is given, so every index returns the same
//! pairs as brute force (and tests check that it does).
//!
//! - [`ColliderKind::Brute`] visits every atom: the reference.
//! - [`ColliderKind::Grid`] is a full 3-D grid over the bounding box (the
//!   thesis's first variant). Atoms are stored sorted by cell, x fastest, so a
//!   row of cells is one contiguous run; its cells are short in x and long in
//!   y and z (`GRID_EDGE`), so a query covers few rows.
//! - [`ColliderKind::Hashed`] hashes cell coordinates into a table whose size is
//!   chosen from the atom count (the thesis's variant: one pass, no bounds).
//!   Distinct cells can share a bucket, so each stored atom keeps its cell
//!   coordinates and a scan of a bucket reports only the atoms of the cell
//!   asked for: no atom twice, no far atom.
//!
//! The cell edge is the largest contact distance a receptor atom can have with
//! a drug atom as large as itself, so a static query touches at most 27 cells
//! of the hashed grid. Queries ([`Collider::near`]) test the atoms of a run a
//! few at a time with SIMD lanes (the `wide` crate, SSE2 on any x86-64).

use glam::{Vec3, Vec4};
use serde::Serialize;
use wide::f32x4;

use super::rule::ContactRule;
use crate::model::Molecule;

/// Which spatial index a collider uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ColliderKind {
    /// Every pair: the reference.
    Brute,
    /// Full 3-D grid over the receptor's bounding box.
    Grid,
    /// Hashed uniform grid.
    #[default]
    Hashed,
}

impl ColliderKind {
    /// All kinds, reference first.
    pub const ALL: [ColliderKind; 3] = [Self::Brute, Self::Grid, Self::Hashed];

    /// Parses `brute`, `grid` or `hashed`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "brute" => Some(Self::Brute),
            "grid" => Some(Self::Grid),
            "hashed" | "hash" => Some(Self::Hashed),
            _ => None,
        }
    }

    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Brute => "brute",
            Self::Grid => "grid",
            Self::Hashed => "hashed",
        }
    }
}

/// Largest number of cells a full grid may have before its cell grows.
const MAX_GRID_CELLS: usize = 1 << 24;

/// Atoms tested together by [`Collider::near`]: a run of stored atoms is
/// tested in chunks of this many SIMD lanes (f32x4: SSE2, so any x86-64), the
/// lanes past its end masked off. The coordinate arrays carry this many
/// padding entries so a chunk never reads out of bounds.
const LANES: usize = 4;

/// A receptor indexed for collision queries.
#[derive(Debug, Clone)]
pub struct Collider {
    kind: ColliderKind,
    /// x, y, z (receptor-local) and radius, in storage order.
    atoms: Vec<Vec4>,
    /// The same coordinates as separate arrays, each padded with [`LANES`]
    /// entries, for the chunked distance tests of [`Collider::near`].
    soa: [Vec<f32>; 3],
    /// Receptor atom index << 1 | polar bit, in storage order.
    meta: Vec<u32>,
    /// Storage slot of each receptor atom, by receptor index.
    slot: Vec<u32>,
    /// Integer cell of each stored atom (hashed index only; empty otherwise),
    /// so a bucket scan keeps just the atoms of the cell asked for.
    cells: Vec<[i32; 3]>,
    index: Index,
    cell: f32,
    max_radius: f32,
    lo: Vec3,
    hi: Vec3,
}

#[derive(Debug, Clone)]
enum Index {
    Brute,
    Grid {
        origin: Vec3,
        /// Reciprocal cell edges: see [`GRID_EDGE`].
        inv_cell: Vec3,
        dims: [i32; 3],
        /// Start of each cell's run in `atoms`; one extra entry at the end.
        start: Vec<u32>,
    },
    Hashed {
        inv_cell: f32,
        mask: u32,
        /// Start of each bucket's run in `atoms`; one extra entry at the end.
        start: Vec<u32>,
        /// The smallest and largest occupied cell on each axis: a query box
        /// is clipped to them, so a box larger than a small receptor does
        /// not visit (or hash) empty cells.
        occupied: [[i32; 3]; 2],
    },
}

/// Edges of a full-grid cell, in units of the contact-distance edge: short in
/// x, long in y and z. A query scans one contiguous run of atoms for each
/// (y, z) row of cells it covers, so long y and z edges mean few rows (about
/// four for the ball of a moving drug atom) and a short x edge trims each run
/// to little more than the ball's width. On trimethoprim/DHFR move-to-touch
/// this shape took 1.44 µs a query against 1.85 µs for cubes of one contact
/// distance; 1.25×, 1.75× and 2× for y and z, and 1× for x, were slower.
const GRID_EDGE: Vec3 = Vec3::new(0.5, 1.5, 1.5);

/// Integer cell coordinate of `x` (saturating for absurd values, 0 for NaN).
#[inline]
fn cell_of(x: f32, origin: f32, inv_cell: f32) -> i32 {
    // floor without the library call that f32::floor is on baseline x86-64.
    let v = (x - origin) * inv_cell;
    let i = v as i32;
    if (i as f32) > v { i - 1 } else { i }
}

/// The cells `[first, last]` (inclusive, per axis) that the box `[lo, hi]`
/// covers in a grid with `origin` and reciprocal edges `inv_cell`, clipped to
/// `[min, max]`; `None` when nothing is left.
#[inline(always)]
fn cell_box(
    lo: Vec3,
    hi: Vec3,
    origin: Vec3,
    inv_cell: Vec3,
    min: [i32; 3],
    max: [i32; 3],
) -> Option<([i32; 3], [i32; 3])> {
    let first = [
        cell_of(lo.x, origin.x, inv_cell.x).max(min[0]),
        cell_of(lo.y, origin.y, inv_cell.y).max(min[1]),
        cell_of(lo.z, origin.z, inv_cell.z).max(min[2]),
    ];
    let last = [
        cell_of(hi.x, origin.x, inv_cell.x).min(max[0]),
        cell_of(hi.y, origin.y, inv_cell.y).min(max[1]),
        cell_of(hi.z, origin.z, inv_cell.z).min(max[2]),
    ];
    (first[0] <= last[0] && first[1] <= last[1] && first[2] <= last[2]).then_some((first, last))
}

/// The thesis's style of spatial hash (Teschner et al. primes).
#[inline]
pub fn hash_cell(ix: i32, iy: i32, iz: i32, mask: u32) -> u32 {
    ((ix as u32).wrapping_mul(73_856_093)
        ^ (iy as u32).wrapping_mul(19_349_663)
        ^ (iz as u32).wrapping_mul(83_492_791))
        & mask
}

/// Hash-table size for `n` atoms: the next power of two at or above `n`,
/// at least 64 buckets and at most 2^22.
pub fn hashed_table_size(n: usize) -> usize {
    n.next_power_of_two().clamp(64, 1 << 22)
}

/// Counting sort of atom indices by key into CSR form.
fn bucket_sort(keys: &[u32], nbuckets: usize) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; nbuckets + 1];
    for &k in keys {
        start[k as usize + 1] += 1;
    }
    for b in 0..nbuckets {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; keys.len()];
    for (i, &k) in keys.iter().enumerate() {
        order[fill[k as usize] as usize] = i as u32;
        fill[k as usize] += 1;
    }
    (order, start)
}

impl Collider {
    /// Indexes `receptor` (in its own frame) for drugs judged by `rule`.
    pub fn build(receptor: &Molecule, rule: &ContactRule, kind: ColliderKind) -> Self {
        let n = receptor.len();
        let max_radius = receptor.max_radius();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in &receptor.local {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if n == 0 {
            lo = Vec3::ZERO;
            hi = Vec3::ZERO;
        }
        let cell = (2.0 * max_radius - rule.min_allowance()).max(1.0);
        let raw: Vec<(Vec4, u32)> = receptor
            .local
            .iter()
            .zip(&receptor.atoms)
            .enumerate()
            .map(|(i, (p, a))| (p.extend(a.radius), ((i as u32) << 1) | u32::from(a.polar)))
            .collect();

        let (order, index) = match kind {
            ColliderKind::Brute => ((0..n as u32).collect(), Index::Brute),
            ColliderKind::Grid => {
                let extent = hi - lo;
                let mut edge = GRID_EDGE * cell;
                let mut dims;
                loop {
                    dims = [
                        (extent.x / edge.x).floor() as i32 + 1,
                        (extent.y / edge.y).floor() as i32 + 1,
                        (extent.z / edge.z).floor() as i32 + 1,
                    ];
                    let total = dims.iter().map(|&d| d.max(1) as usize).product::<usize>();
                    if total <= MAX_GRID_CELLS {
                        break;
                    }
                    // A sparse, huge receptor: coarser cells keep memory bounded.
                    edge *= 2.0;
                }
                let inv_cell = edge.recip();
                let keys: Vec<u32> = receptor
                    .local
                    .iter()
                    .map(|p| {
                        let ix = cell_of(p.x, lo.x, inv_cell.x).clamp(0, dims[0] - 1);
                        let iy = cell_of(p.y, lo.y, inv_cell.y).clamp(0, dims[1] - 1);
                        let iz = cell_of(p.z, lo.z, inv_cell.z).clamp(0, dims[2] - 1);
                        ((iz * dims[1] + iy) * dims[0] + ix) as u32
                    })
                    .collect();
                let total = (dims[0] * dims[1] * dims[2]) as usize;
                let (order, start) = bucket_sort(&keys, total);
                (
                    order,
                    Index::Grid {
                        origin: lo,
                        inv_cell,
                        dims,
                        start,
                    },
                )
            }
            ColliderKind::Hashed => {
                let size = hashed_table_size(n);
                let mask = (size - 1) as u32;
                let inv_cell = 1.0 / cell;
                let keys: Vec<u32> = receptor
                    .local
                    .iter()
                    .map(|p| {
                        hash_cell(
                            cell_of(p.x, 0.0, inv_cell),
                            cell_of(p.y, 0.0, inv_cell),
                            cell_of(p.z, 0.0, inv_cell),
                            mask,
                        )
                    })
                    .collect();
                let (order, start) = bucket_sort(&keys, size);
                let mut occupied = [[i32::MAX; 3], [i32::MIN; 3]];
                for p in &receptor.local {
                    let c = [
                        cell_of(p.x, 0.0, inv_cell),
                        cell_of(p.y, 0.0, inv_cell),
                        cell_of(p.z, 0.0, inv_cell),
                    ];
                    for k in 0..3 {
                        occupied[0][k] = occupied[0][k].min(c[k]);
                        occupied[1][k] = occupied[1][k].max(c[k]);
                    }
                }
                (
                    order,
                    Index::Hashed {
                        inv_cell,
                        mask,
                        start,
                        occupied,
                    },
                )
            }
        };
        let atoms: Vec<Vec4> = order.iter().map(|&i| raw[i as usize].0).collect();
        let soa = [0, 1, 2].map(|k| padded(atoms.iter().map(|a| a[k])));
        let meta = order.iter().map(|&i| raw[i as usize].1).collect();
        let mut slot = vec![0u32; n];
        for (k, &i) in order.iter().enumerate() {
            slot[i as usize] = k as u32;
        }
        let cells = match &index {
            Index::Hashed { inv_cell, .. } => order
                .iter()
                .map(|&i| {
                    receptor.local[i as usize]
                        .to_array()
                        .map(|v| cell_of(v, 0.0, *inv_cell))
                })
                .collect(),
            _ => Vec::new(),
        };
        Self {
            kind,
            atoms,
            soa,
            meta,
            slot,
            cells,
            index,
            cell,
            max_radius,
            lo,
            hi,
        }
    }

    /// Which index this is.
    pub fn kind(&self) -> ColliderKind {
        self.kind
    }

    /// Cell edge in Å (the brute collider reports the edge a grid would use).
    pub fn cell_size(&self) -> f32 {
        self.cell
    }

    /// Largest receptor atom radius.
    pub fn max_radius(&self) -> f32 {
        self.max_radius
    }

    /// Bounding box of the receptor atom centres, receptor frame.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.lo, self.hi)
    }

    /// Position (receptor frame) of receptor atom `index`.
    ///
    /// # Panics
    /// When `index` is not a receptor atom index.
    pub fn atom_position(&self, index: u32) -> Vec3 {
        self.atoms[self.slot[index as usize] as usize].truncate()
    }

    /// Number of receptor atoms.
    pub fn len(&self) -> usize {
        self.atoms.len()
    }

    /// True for an empty receptor.
    pub fn is_empty(&self) -> bool {
        self.atoms.is_empty()
    }

    /// Calls `f(position_and_radius, receptor_index << 1 | polar)` for every
    /// receptor atom that may lie in the box `[lo, hi]` (a superset: callers
    /// test distances). Brute force visits every atom.
    ///
    /// # Performance
    /// Grid: one contiguous run per row of cells. Hashed: one bucket per cell,
    /// filtered by cell. Neither depends on the receptor's size.
    #[inline]
    pub fn visit<F: FnMut(Vec4, u32)>(&self, lo: Vec3, hi: Vec3, mut f: F) {
        match &self.index {
            Index::Brute => {
                for (a, m) in self.atoms.iter().zip(&self.meta) {
                    f(*a, *m);
                }
            }
            Index::Grid {
                origin,
                inv_cell,
                dims,
                start,
            } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) = cell_box(
                    lo,
                    hi,
                    *origin,
                    *inv_cell,
                    [0; 3],
                    [dims[0] - 1, dims[1] - 1, dims[2] - 1],
                ) else {
                    return;
                };
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        let row = ((z * dims[1] + y) * dims[0]) as usize;
                        let a = start[row + x0 as usize] as usize;
                        let b = start[row + x1 as usize + 1] as usize;
                        for (atom, m) in self.atoms[a..b].iter().zip(&self.meta[a..b]) {
                            f(*atom, *m);
                        }
                    }
                }
            }
            Index::Hashed {
                inv_cell,
                mask,
                start,
                occupied: [olo, ohi],
            } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) =
                    cell_box(lo, hi, Vec3::ZERO, Vec3::splat(*inv_cell), *olo, *ohi)
                else {
                    return;
                };
                let count = (i64::from(x1) - i64::from(x0) + 1)
                    * (i64::from(y1) - i64::from(y0) + 1)
                    * (i64::from(z1) - i64::from(z0) + 1);
                if count > i64::from(*mask) + 1 {
                    // The box covers more cells than there are buckets: every
                    // atom once is cheaper than every cell.
                    for (a, m) in self.atoms.iter().zip(&self.meta) {
                        f(*a, *m);
                    }
                    return;
                }
                // Distinct cells may share a bucket: keep only the atoms of the
                // cell being visited, so each atom is reported once.
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            let b = hash_cell(x, y, z, *mask) as usize;
                            let (a, e) = (start[b] as usize, start[b + 1] as usize);
                            for k in a..e {
                                if self.cells[k] == [x, y, z] {
                                    f(self.atoms[k], self.meta[k]);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Calls `f(position_and_radius, receptor_index << 1 | polar, d²)` for
    /// every receptor atom whose centre lies within `radius` of `p`, with `d²`
    /// its squared distance from `p` in f32 (`(q − p)·(q − p)`, summed x, y,
    /// z in that order). Exactly the atoms [`Collider::visit`] on the box
    /// around the ball would give that pass the test, with the same `d²`;
    /// the order is the storage order of each cell run.
    ///
    /// # Performance
    /// Each run of stored atoms is tested four at a time with the lanes
    /// past its end masked off, so the cost per row of cells is nearly
    /// constant and free of mispredicted loop exits.
    #[inline]
    pub fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, mut f: F) {
        let r2 = radius * radius;
        let (lo, hi) = (p - Vec3::splat(radius), p + Vec3::splat(radius));
        match &self.index {
            Index::Brute => self.scan(0, self.atoms.len(), p, r2, &mut f),
            Index::Grid {
                origin,
                inv_cell,
                dims,
                start,
            } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) = cell_box(
                    lo,
                    hi,
                    *origin,
                    *inv_cell,
                    [0; 3],
                    [dims[0] - 1, dims[1] - 1, dims[2] - 1],
                ) else {
                    return;
                };
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        let row = ((z * dims[1] + y) * dims[0]) as usize;
                        let a = start[row + x0 as usize] as usize;
                        let b = start[row + x1 as usize + 1] as usize;
                        self.scan(a, b, p, r2, &mut f);
                    }
                }
            }
            Index::Hashed {
                inv_cell,
                mask,
                start,
                occupied: [olo, ohi],
            } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) =
                    cell_box(lo, hi, Vec3::ZERO, Vec3::splat(*inv_cell), *olo, *ohi)
                else {
                    return;
                };
                let count = (i64::from(x1) - i64::from(x0) + 1)
                    * (i64::from(y1) - i64::from(y0) + 1)
                    * (i64::from(z1) - i64::from(z0) + 1);
                if count > i64::from(*mask) + 1 {
                    // More cells than buckets: every atom once is cheaper.
                    self.scan(0, self.atoms.len(), p, r2, &mut f);
                    return;
                }
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            let b = hash_cell(x, y, z, *mask) as usize;
                            let (a, e) = (start[b] as usize, start[b + 1] as usize);
                            // Distinct cells may share a bucket: keep only the
                            // atoms of this cell, so each atom comes once. A
                            // bucket is a random place in memory: one record
                            // per atom (not the lanes' separate arrays) keeps
                            // that to one or two cache lines on big receptors.
                            for k in a..e {
                                if self.cells[k] == [x, y, z] {
                                    let q = self.atoms[k];
                                    let d2 = (q.truncate() - p).length_squared();
                                    if d2 <= r2 {
                                        f(q, self.meta[k], d2);
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Tests stored atoms `a..b` against the ball (`p`, `r2`) [`LANES`] at a
    /// time and reports the atoms inside.
    #[inline(always)]
    fn scan<F: FnMut(Vec4, u32, f32)>(&self, a: usize, b: usize, p: Vec3, r2: f32, f: &mut F) {
        let [sx, sy, sz] = &self.soa;
        // One bound for the three arrays (they have one length), so the
        // chunk loads below need no checks of their own.
        let end = sx.len().min(sy.len()).min(sz.len());
        let (px, py, pz, r2) = (
            f32x4::splat(p.x),
            f32x4::splat(p.y),
            f32x4::splat(p.z),
            f32x4::splat(r2),
        );
        let mut k = a;
        loop {
            // Always true: k ≤ len and the arrays carry LANES padding entries.
            if k + LANES > end {
                return;
            }
            let chunk = |v: &[f32]| {
                let mut c = [0.0; LANES];
                c.copy_from_slice(&v[k..k + LANES]);
                f32x4::from(c)
            };
            let (xs, ys, zs) = (chunk(sx), chunk(sy), chunk(sz));
            let (dx, dy, dz) = (xs - px, ys - py, zs - pz);
            // Summed in the order of `Vec3::length_squared`: the same bits.
            let d2 = dx * dx + dy * dy + dz * dz;
            let live = (1u32 << b.saturating_sub(k).min(LANES)) - 1;
            let mut hits = d2.simd_le(r2).to_bitmask() & live;
            if hits != 0 {
                let d2 = d2.to_array();
                while hits != 0 {
                    let l = hits.trailing_zeros() as usize;
                    hits &= hits - 1;
                    f(self.atoms[k + l], self.meta[k + l], d2[l]);
                }
            }
            k += LANES;
            if k >= b {
                return;
            }
        }
    }
}

/// `values` followed by [`LANES`] zeros.
fn padded(values: impl Iterator<Item = f32>) -> Vec<f32> {
    let mut out: Vec<f32> = values.collect();
    out.extend([0.0; LANES]);
    out
}

/// Splits a collider's `meta` word into (receptor atom index, polar).
#[inline]
pub fn unpack_meta(meta: u32) -> (u32, bool) {
    (meta >> 1, meta & 1 == 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_of_is_floor() {
        for v in [-3.5f32, -3.0, -0.2, 0.0, 0.2, 2.999, 3.0, 1e9, -1e9] {
            assert_eq!(cell_of(v, 0.0, 1.0), v.floor() as i32, "{v}");
        }
        assert_eq!(cell_of(f32::NAN, 0.0, 1.0), 0);
        assert_eq!(cell_of(1e30, 0.0, 1.0), i32::MAX);
    }
}
