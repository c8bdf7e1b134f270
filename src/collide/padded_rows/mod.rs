//! Padded rows: a grid's atoms again, in rows of cells that overlap, so
//! that the ball of a drug atom's reach lies in one row.
//!
//! A grid ([`super::collider`]) stores each atom once and a query
//! scans one run of atoms for each row of cells (a line of cells along x)
//! that its ball's box covers: five or six rows for a drug atom's reach,
//! each with its own bounds, loop and exit. Here the rows lie on a finer y-z
//! spacing and each holds, besides the atoms of its own y-z square, every
//! atom within [`PaddedRows::margin`] of it, so an atom is stored in many
//! rows. A ball of radius up to the margin lies wholly in the row of its
//! centre's square, and a query scans one run: the x cells its box covers
//! in that row. Larger balls (a long interval in open space) go to the
//! plain grid, which the collider keeps.
//!
//! The spacing is the finest of a few that keeps the copies within
//! [`MAX_ENTRIES`]; a receptor whose rows cannot (none real) has none. The
//! coordinates are kept four entries to a block, x, y and z in lanes, so a
//! block is one cache line's load rather than three. Each entry's radius
//! is a fourth lane of its block and its tag (the collider's receptor
//! index and polarity) lies beside it, so a search reports an atom from
//! the rows alone.
//!
//! The full grid finds a (row, x cell)'s run of entries in a dense table
//! over the box ([`Buckets::Dense`]), each row starting at a block so that
//! a scan tests whole blocks without masking lanes; the hashed grid in a
//! hash table sized from the number of entries, a row's x cells in
//! consecutive buckets as in its own table ([`Buckets::Hashed`]), each
//! entry tagged with its row so a query skips the entries of other rows
//! that share its buckets.

use glam::{Vec3, Vec4};
use wide::f32x4;

use super::collider::hash_cell;

/// Most stored copies of atoms (20 bytes each: x, y, z, radius and the
/// atom's tag): 80 MiB, a little more than the clearance map's limit.
pub const MAX_ENTRIES: usize = 1 << 22;

/// Most (row, x cell) pairs, each a 4-byte run start.
const MAX_CELLS: u64 = 1 << 24;

/// Row spacings tried, finest first, in Å. A finer one scans fewer atoms
/// a query (the row's cross-section is the spacing plus twice the margin,
/// squared) and stores more copies, which spill out of the caches; 1.5 Å
/// balances the two on a protein's surface.
const SPACINGS: [f32; 6] = [1.5, 2.0, 2.5, 3.0, 4.5, 6.0];

/// A receptor's atoms (in the collider's storage order) in padded rows.
#[derive(Debug, Clone)]
pub struct PaddedRows {
    /// Corner of cell (0, 0, 0), the atoms' smallest coordinates, in lanes
    /// x, y, z and x again.
    origin: f32x4,
    /// Reciprocal x-cell edge, row spacing (y, z) and x-cell edge again.
    inv: f32x4,
    /// Cells along x, rows along y and z.
    dims: [i32; 3],
    /// Largest ball radius the rows answer for.
    margin: f32,
    /// Start of each bucket's run of entries (see [`Buckets`]); one extra
    /// entry at the end.
    start: Vec<u32>,
    /// How a (row, x cell) finds its bucket.
    buckets: Buckets,
    /// The entries' centres and radii, [`LANES`] to a block (x, y, z and
    /// radius lanes, 64 bytes), the last block padded.
    blocks: Vec<[f32x4; 4]>,
    /// The tag of each entry's atom (the collider's receptor index and
    /// polarity): kept here, beside the radius in the block, so a search
    /// reports an atom without loading it from the collider's arrays (two
    /// dependent loads fewer per atom found).
    tag: Vec<u32>,
}

/// How a (row, x cell) finds its bucket of [`PaddedRows`]'s runs.
#[derive(Debug, Clone)]
pub enum Buckets {
    /// One bucket per (row, x cell), rows z-major, x fastest (the full
    /// grid).
    Dense,
    /// Hashed (the hashed grid): row `(y, z)`'s cell `x` in bucket
    /// `(row_hash(y, z) + x) & mask`, so a row's cells are consecutive
    /// buckets (wrapping at the table's end). Buckets hold entries of
    /// other rows too: `row_of` tags each entry with its row's index
    /// `z · ny + y`.
    Hashed {
        /// Table size less one (a power of two less one).
        mask: u32,
        /// Row index of each entry.
        row_of: Vec<u32>,
    },
}

/// An atom's x cell and the first and last of its rows along y and z.
type Home = (i32, (i32, i32), (i32, i32));

/// Entries tested together (f32x4 lanes), as in the collider.
const LANES: usize = 4;

/// The atom of a slot that holds none (the padding that ends a full
/// grid's row).
const UNUSED: u32 = u32::MAX;

/// Integer cell of `x`, as the collider's `cell_of` (saturating; 0 for NaN).
#[inline]
fn cell_of(x: f32, origin: f32, inv: f32) -> i32 {
    let v = (x - origin) * inv;
    let i = v as i32;
    if (i as f32) > v { i - 1 } else { i }
}

/// Where a spacing of rows puts the atoms: the box's corner, cells along
/// x and rows along y and z, the reciprocal edges, each atom's home, and
/// the copies that makes.
struct Layout {
    lo: Vec3,
    dims: [i32; 3],
    inv_x: f32,
    inv_e: f32,
    homes: Vec<Home>,
    entries: u64,
}

impl Layout {
    /// Rows `spacing` Å apart over the box `lo..hi` (each holding its atoms
    /// within `pad` of it) with x cells of `x_edge`, or `None` when they
    /// would exceed the limits (at most `max_entries` copies).
    fn new(
        atoms: &[Vec4],
        (lo, hi): (Vec3, Vec3),
        x_edge: f32,
        spacing: f32,
        pad: f32,
        hashed: bool,
        max_entries: usize,
    ) -> Option<Self> {
        let extent = hi - lo;
        // Counts past 2^31 (absurd extents) saturate, and are refused below.
        let count = |extent: f32, edge: f32| (extent / edge).floor().min(2e9) as u64 + 1;
        let nx = count(extent.x, x_edge);
        let inv_e = 1.0 / spacing;
        let (ny, nz) = (count(extent.y, spacing), count(extent.z, spacing));
        // A hash table's size comes from the entries and the row
        // length, not the box; its row tags (`z · ny + y`) stay within
        // an i32.
        let too_big = if hashed {
            nx > max_entries as u64 || ny.saturating_mul(nz) > i32::MAX as u64
        } else {
            nx.saturating_mul(ny).saturating_mul(nz) > MAX_CELLS
        };
        if too_big {
            return None;
        }
        let dims = [nx as i32, ny as i32, nz as i32];
        // The rows an atom at `v` belongs to, along one axis.
        let span = |v: f32, o: f32, n: i32| {
            let a = cell_of(v - pad, o, inv_e).clamp(0, n - 1);
            let b = cell_of(v + pad, o, inv_e).clamp(0, n - 1);
            (a, b)
        };
        let inv_x = 1.0 / x_edge;
        let homes: Vec<Home> = atoms
            .iter()
            .map(|a| {
                let ix = cell_of(a.x, lo.x, inv_x).clamp(0, dims[0] - 1);
                (ix, span(a.y, lo.y, dims[1]), span(a.z, lo.z, dims[2]))
            })
            .collect();
        let entries: u64 = homes
            .iter()
            .map(|&(_, (y0, y1), (z0, z1))| ((y1 - y0 + 1) as u64) * ((z1 - z0 + 1) as u64))
            .sum();
        (entries <= max_entries as u64).then_some(Self {
            lo,
            dims,
            inv_x,
            inv_e,
            homes,
            entries,
        })
    }
}

impl PaddedRows {
    /// Rows over `atoms` (centre and radius) with their `tags` (one per
    /// atom, reported with it) for balls of radius up to `margin`, with x
    /// cells of `x_edge` Å, in a dense table (`hashed` false) or a hash
    /// table; `None` for no atoms, for a tag missing, or when even the
    /// coarsest spacing would exceed the limits.
    pub fn build(
        atoms: &[Vec4],
        tags: &[u32],
        margin: f32,
        x_edge: f32,
        hashed: bool,
    ) -> Option<Self> {
        Self::build_within(atoms, tags, margin, x_edge, hashed, MAX_ENTRIES)
    }

    /// [`PaddedRows::build`] with at most `max_entries` copies.
    fn build_within(
        atoms: &[Vec4],
        tags: &[u32],
        margin: f32,
        x_edge: f32,
        hashed: bool,
        max_entries: usize,
    ) -> Option<Self> {
        if atoms.is_empty() || tags.len() < atoms.len() || !(margin > 0.0 && x_edge > 0.0) {
            return None;
        }
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for a in atoms {
            lo = lo.min(a.truncate());
            hi = hi.max(a.truncate());
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        // Rows hold their atoms within the margin and this much more: room
        // for the f32 rounding of a query point's cell and of an atom's
        // shifted coordinate (a few units in the last place of the largest
        // coordinate), generously.
        let big = lo.abs().max(hi.abs()).max_element();
        let pad = margin + 1e-3 + big * 1e-5;
        for &spacing in &SPACINGS {
            if let Some(layout) =
                Layout::new(atoms, (lo, hi), x_edge, spacing, pad, hashed, max_entries)
            {
                return Some(Self::lay_out(atoms, tags, &layout, margin, hashed));
            }
        }
        None
    }

    /// The rows of `layout` filled with `atoms` and their `tags`.
    fn lay_out(atoms: &[Vec4], tags: &[u32], layout: &Layout, margin: f32, hashed: bool) -> Self {
        let Layout {
            lo,
            dims,
            inv_x,
            inv_e,
            ref homes,
            entries,
        } = *layout;
        let nx = dims[0] as usize;
        // A hash table of at least two buckets per entry (and one per x
        // cell, so no row's buckets overlap themselves): the (row, x
        // cell)s holding entries, some twenty entries each inside a
        // protein, then rarely share a bucket, and a search scans few
        // entries of other rows.
        let size = (2 * entries as usize).max(nx).next_power_of_two().max(64);
        let mask = (size - 1) as u32;
        let key = |ix: i32, iy: i32, iz: i32| {
            if hashed {
                hash_cell(ix, iy, iz, mask) as usize
            } else {
                ((iz * dims[1] + iy) * dims[0] + ix) as usize
            }
        };
        let cells = if hashed {
            size
        } else {
            dims.iter().map(|&d| d as usize).product()
        };
        let mut start = vec![0u32; cells + 1];
        for &(ix, (y0, y1), (z0, z1)) in homes {
            for iz in z0..=z1 {
                for iy in y0..=y1 {
                    start[key(ix, iy, iz) + 1] += 1;
                }
            }
        }
        // The full grid starts every row at a block: a scan's first
        // block then holds nothing of the row before (see `scan`), and
        // its last nothing of the row after, but the unused slots that
        // end each row, which hold no atom.
        for c in 0..cells {
            start[c + 1] += start[c];
            if !hashed && (c + 1) % nx == 0 {
                start[c + 1] = start[c + 1].next_multiple_of(LANES as u32);
            }
        }
        let total = start[cells] as usize;
        let mut fill = start.clone();
        let mut slot = vec![UNUSED; total];
        let mut row_of = vec![0u32; if hashed { total } else { 0 }];
        for (s, &(ix, (y0, y1), (z0, z1))) in homes.iter().enumerate() {
            for iz in z0..=z1 {
                for iy in y0..=y1 {
                    let k = key(ix, iy, iz);
                    let e = fill[k] as usize;
                    slot[e] = s as u32;
                    if let Some(t) = row_of.get_mut(e) {
                        *t = (iz * dims[1] + iy) as u32;
                    }
                    fill[k] += 1;
                }
            }
        }
        let blocks = slot
            .chunks(LANES)
            .map(|c| {
                [0, 1, 2, 3].map(|k| {
                    let mut v = [0.0f32; LANES];
                    for (l, &s) in c.iter().enumerate() {
                        // An unused slot lies infinitely far away: no
                        // ball holds it.
                        v[l] = atoms.get(s as usize).map_or(f32::INFINITY, |a| a[k]);
                    }
                    f32x4::from(v)
                })
            })
            .collect();
        Self {
            origin: f32x4::from([lo.x, lo.y, lo.z, lo.x]),
            inv: f32x4::from([inv_x, inv_e, inv_e, inv_x]),
            dims,
            margin,
            start,
            buckets: if hashed {
                Buckets::Hashed { mask, row_of }
            } else {
                Buckets::Dense
            },
            blocks,
            tag: slot
                .iter()
                .map(|&s| tags.get(s as usize).map_or(0, |t| *t))
                .collect(),
        }
    }

    /// Largest radius [`PaddedRows::near`] answers.
    #[inline]
    pub fn margin(&self) -> f32 {
        self.margin
    }

    /// Stored copies of atoms.
    #[cfg(test)]
    fn entries(&self) -> usize {
        self.tag.len()
    }

    /// Calls `f(atom, tag, d²)` for every atom (centre and radius) whose
    /// centre lies within `radius` (at most [`PaddedRows::margin`]) of `p`,
    /// with its tag, `d²` summed x, y, z in that order in f32, as the
    /// collider computes it; each atom once.
    #[inline(always)]
    pub fn near(&self, p: Vec3, radius: f32, mut f: impl FnMut(Vec4, u32, f32)) {
        debug_assert!(radius <= self.margin);
        // The first x cell of the ball's box, the y-z square of its
        // centre and the last x cell, truncated rather than floored: the
        // two differ only below the box's corner, where the truncation's
        // cell 0 is clamped to as the floor's −1 would be, or (the ball's
        // far side) holds no atom inside the ball, which the scan tests
        // anyway. Values past i32 (no real point) truncate to i32::MIN: a
        // ball with its last x cell there is far from every atom, and
        // returns at once.
        let v = f32x4::from([p.x - radius, p.y, p.z, p.x + radius]);
        let [a, iy, iz, b] = ((v - self.origin) * self.inv).fast_trunc_int().to_array();
        let [nx, ny, nz] = self.dims;
        let (x0, x1) = (a.max(0), b.min(nx - 1));
        if x0 > x1 {
            return;
        }
        let (iy, iz) = (iy.clamp(0, ny - 1), iz.clamp(0, nz - 1));
        let ball = (
            [p.x, p.y, p.z].map(f32x4::splat),
            f32x4::splat(radius * radius),
        );
        match &self.buckets {
            Buckets::Dense => {
                let row = ((iz * ny + iy) * nx) as usize;
                let (lo, hi) = (
                    self.start[row + x0 as usize] as usize,
                    self.start[row + x1 as usize + 1] as usize,
                );
                self.scan::<false>(lo, hi, ball, |_| true, &mut f);
            }
            Buckets::Hashed { mask, row_of } => {
                let row = (iz * ny + iy) as u32;
                let size = *mask as usize + 1;
                let h0 = hash_cell(x0, iy, iz, *mask) as usize;
                let h1 = h0 + (x1 - x0 + 1) as usize;
                // The row's buckets up to the table's end, then, only when
                // they wrap, those from its start (the build makes the
                // table at least as large as a row is long).
                let keep = |e: usize| row_of.get(e) == Some(&row);
                let (lo, hi) = (self.start[h0] as usize, self.start[h1.min(size)] as usize);
                if h1 > size {
                    self.scan::<true>(lo, hi, ball, keep, &mut f);
                    let hi = self.start[h1 - size] as usize;
                    self.scan::<true>(0, hi, ball, keep, &mut f);
                } else {
                    self.scan::<false>(lo, hi, ball, keep, &mut f);
                }
            }
        }
    }

    /// Tests entries `lo..hi` against the ball (centre in lanes, squared
    /// radius) and calls `f(atom, tag, d²)` for those inside that `keep`.
    ///
    /// Unless `MASKED`, the lanes of the first and last blocks outside
    /// `lo..hi` are tested too. That is for a run of one row's x cells:
    /// those lanes hold the row's own atoms of x cells outside the ball's
    /// box, which lie outside the ball (each is stored once in the row,
    /// and would be reported only if inside it, as any other), or what
    /// `keep` refuses. A full grid's row starts at a block and ends in
    /// unused slots (infinitely far); a hashed row's buckets hold other
    /// rows' entries too, which `keep` refuses. Only a hashed row that
    /// wraps round the table masks: its two runs may lie within a block
    /// of each other, and a lane of one would then repeat an atom of the
    /// other.
    #[inline(always)]
    fn scan<const MASKED: bool>(
        &self,
        lo: usize,
        hi: usize,
        ([px, py, pz], r2): ([f32x4; 3], f32x4),
        keep_entry: impl Fn(usize) -> bool,
        f: &mut impl FnMut(Vec4, u32, f32),
    ) {
        if lo >= hi {
            return;
        }
        // Whole blocks; if `MASKED`, the lanes before `lo` and from `hi`
        // on masked off.
        let last = (hi - 1) / LANES;
        let mut blk = lo / LANES;
        let mut keep = if MASKED { !0u32 << (lo % LANES) } else { !0 };
        loop {
            let Some([bx, by, bz, br]) = self.blocks.get(blk) else {
                return;
            };
            let (dx, dy, dz) = (*bx - px, *by - py, *bz - pz);
            let d2 = dx * dx + dy * dy + dz * dz;
            let mut hits = d2.simd_le(r2).to_bitmask() & keep;
            if MASKED && blk == last {
                hits &= (1 << (hi - LANES * blk)) - 1;
            }
            if hits != 0 {
                let d2 = d2.to_array();
                // The hits' lanes read from the block in place, not copied
                // out as arrays.
                let [x, y, z, r] = [bx, by, bz, br].map(f32x4::as_array);
                while hits != 0 {
                    let l = hits.trailing_zeros() as usize;
                    hits &= hits - 1;
                    let e = LANES * blk + l;
                    if let Some(&tag) = self.tag.get(e)
                        && keep_entry(e)
                    {
                        f(Vec4::new(x[l], y[l], z[l], r[l]), tag, d2[l]);
                    }
                }
            }
            if blk >= last {
                return;
            }
            blk += 1;
            keep = !0;
        }
    }
}

#[cfg(test)]
mod tests;
