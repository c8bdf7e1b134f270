//! The uniform grids' cells: a point's cell, a box's range of cells, the
//! hashed grid's bucket of a cell, and the runs of stored atoms a box's rows
//! of cells cover in either grid.

use glam::Vec3;
use wide::{f32x4, i32x4};

/// A uniform grid's geometry in SIMD lanes (x, y, z, unused): where cell
/// (0, 0, 0) starts, the reciprocal cell edges, and the range of cells a
/// query is clipped to.
#[derive(Debug, Clone, Copy)]
pub(super) struct Cells {
    origin: f32x4,
    inv_cell: f32x4,
    min: i32x4,
    max: i32x4,
}

/// Cell coordinates are clamped to ±this before conversion, so that absurd
/// (or infinite) query boxes convert exactly and clip like any other.
const CELL_LIMIT: f32 = (1u32 << 30) as f32;

impl Cells {
    pub(super) fn new(origin: Vec3, inv_cell: Vec3, min: [i32; 3], max: [i32; 3]) -> Self {
        Self {
            origin: f32x4::from([origin.x, origin.y, origin.z, 0.0]),
            inv_cell: f32x4::from([inv_cell.x, inv_cell.y, inv_cell.z, 0.0]),
            min: i32x4::from([min[0], min[1], min[2], 0]),
            max: i32x4::from([max[0], max[1], max[2], 0]),
        }
    }

    /// The cells `[first, last]` (inclusive, per axis) that the box
    /// `[lo, hi]` covers, clipped to the grid's range; `None` when nothing is
    /// left. The cell of a coordinate is the same as [`cell_of`] gives for
    /// it (same f32 arithmetic, then floor), three axes at once.
    #[inline(always)]
    pub(super) fn cover(&self, lo: Vec3, hi: Vec3) -> Option<([i32; 3], [i32; 3])> {
        let at = |v: Vec3| {
            let v = (f32x4::from([v.x, v.y, v.z, 0.0]) - self.origin) * self.inv_cell;
            // NaN becomes the lower limit (maxps returns its second operand).
            let v = v
                .fast_max(f32x4::splat(-CELL_LIMIT))
                .fast_min(f32x4::splat(CELL_LIMIT));
            // floor: truncate, then step down where that rounded up.
            let t = v.fast_trunc_int().round_float();
            (t - (t.simd_gt(v) & f32x4::ONE)).fast_trunc_int()
        };
        let first = at(lo).max(self.min).to_array();
        let last = at(hi).min(self.max).to_array();
        (first[0] <= last[0] && first[1] <= last[1] && first[2] <= last[2])
            .then_some(([first[0], first[1], first[2]], [last[0], last[1], last[2]]))
    }
}

/// Edges of a full-grid cell, in units of the contact-distance edge: short in
/// x, long in y and z. A query scans one contiguous run of atoms for each
/// (y, z) row of cells it covers, so long y and z edges mean few rows (about
/// four for the ball of a moving drug atom) and a short x edge trims each run
/// to little more than the ball's width.
///
/// # Performance
/// On trimethoprim/DHFR move-to-touch this shape is about a fifth faster
/// than the thesis's cubes of one contact distance, and faster than y and z
/// edges of 1.25, 1.75 or 2 or an x edge of 1.
pub(super) const GRID_EDGE: Vec3 = Vec3::new(0.5, 1.5, 1.5);

/// Edges of a hashed-grid cell, in units of the contact-distance edge: the
/// full grid's shape, for the same reason (a query scans one run per row).
pub(super) const HASH_EDGE: Vec3 = GRID_EDGE;

/// Integer cell coordinate of `x` (saturating for absurd values, 0 for NaN).
#[inline]
pub(super) fn cell_of(x: f32, origin: f32, inv_cell: f32) -> i32 {
    // floor without the library call that f32::floor is on baseline x86-64.
    let v = (x - origin) * inv_cell;
    let i = v as i32;
    if (i as f32) > v { i - 1 } else { i }
}

/// Bucket of cell `(ix, iy, iz)` in a table of `mask + 1` buckets: a
/// hash of the row `(iy, iz)` plus `ix`, so the cells of one row fall in
/// consecutive buckets (wrapping at the table's end) and a query scans one
/// contiguous run of atoms per row, as in the full grid.
#[inline]
pub fn hash_cell(ix: i32, iy: i32, iz: i32, mask: u32) -> u32 {
    (ix as u32).wrapping_add(row_hash(iy, iz)) & mask
}

/// A row's hash: `(iy, iz)` combined without collisions between nearby
/// rows, then mixed (MurmurHash3's 32-bit finaliser) so that the low bits
/// a table keeps spread the rows evenly. Products of small coordinates
/// with primes, XORed (Teschner et al.'s cell hash), share their low bits
/// and put neighbouring rows in the same buckets.
#[inline]
fn row_hash(iy: i32, iz: i32) -> u32 {
    let mut h = (iy as u32)
        .wrapping_mul(0x9E37_79B1)
        .wrapping_add(iz as u32);
    h ^= h >> 16;
    h = h.wrapping_mul(0x85EB_CA6B);
    h ^= h >> 13;
    h = h.wrapping_mul(0xC2B2_AE35);
    h ^ (h >> 16)
}

/// Hash-table size for `n` atoms: the next power of two at or above `4n`,
/// at least 64 buckets and at most 2^22. Rows of cells land at random
/// places in the table and a query scans whole runs of buckets, so the table
/// is kept sparse: other rows' atoms in a run are scanned for nothing.
pub fn hashed_table_size(n: usize) -> usize {
    (4 * n).next_power_of_two().clamp(64, 1 << 22)
}

/// Counting sort of atom indices by key into CSR form.
pub(super) fn bucket_sort(keys: &[u32], nbuckets: usize) -> (Vec<u32>, Vec<u32>) {
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

/// The full grid's rows of cells that the box of cells `x0..=x1`,
/// `y0..=y1`, `z0..=z1` covers: `f(a, b)` with each row's run of stored
/// atoms `a..b` (cells are stored with x fastest, so a row's cells are one
/// run).
#[inline(always)]
pub(super) fn grid_rows(
    start: &[u32],
    dims: [i32; 3],
    [x0, y0, z0]: [i32; 3],
    [x1, y1, z1]: [i32; 3],
    mut f: impl FnMut(usize, usize),
) {
    for z in z0..=z1 {
        for y in y0..=y1 {
            let row = ((z * dims[1] + y) * dims[0]) as usize;
            f(
                start[row + x0 as usize] as usize,
                start[row + x1 as usize + 1] as usize,
            );
        }
    }
}

/// Calls `f(y, z, a, b)` for each row `(y, z)` of the cells `[first,
/// last]` in a hashed table (`start`, `mask`) and each run `a..b` of stored
/// atoms in the row's buckets (two runs when they wrap at the table's end).
/// Returns false, calling nothing, when the box covers more cells than
/// there are buckets: scanning every atom once is cheaper then (and no
/// row's buckets overlap themselves).
#[inline(always)]
pub(super) fn hashed_rows(
    start: &[u32],
    mask: u32,
    [x0, y0, z0]: [i32; 3],
    [x1, y1, z1]: [i32; 3],
    mut f: impl FnMut(i32, i32, usize, usize),
) -> bool {
    let width = i64::from(x1) - i64::from(x0) + 1;
    let count = width * (i64::from(y1) - i64::from(y0) + 1) * (i64::from(z1) - i64::from(z0) + 1);
    let size = mask as usize + 1;
    if count > size as i64 {
        return false;
    }
    let width = width as usize;
    for z in z0..=z1 {
        for y in y0..=y1 {
            let h0 = hash_cell(x0, y, z, mask) as usize;
            let h1 = h0 + width;
            // One call site (so `f` is inlined): the buckets up to the
            // table's end, then, only when the row wraps, those from its
            // start.
            let (mut a, mut b) = (h0, h1.min(size));
            loop {
                f(y, z, start[a] as usize, start[b] as usize);
                if b == h1 || a == 0 {
                    break;
                }
                (a, b) = (0, h1 - size);
            }
        }
    }
    true
}
