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
//! coordinates are kept four entries to a block, x, y and z in lanes: kept
//! in three separate arrays instead, the rows made 1rx1's surface queries
//! 5 % slower than the plain grid rather than faster. Each entry's radius
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
/// squared) and stores more copies. On 1rx1's surface patches 1.5 Å was
/// the fastest of 0.75, 1, 1.5, 3 and 4.5 Å (the others 15–20 % slower,
/// at nearly the same instructions; measured on an earlier form of the
/// rows, with three coordinate arrays and a larger margin).
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
        let extent = hi - lo;
        // Counts past 2^31 (absurd extents) saturate, and are refused below.
        let count = |extent: f32, edge: f32| (extent / edge).floor().min(2e9) as u64 + 1;
        let nx = count(extent.x, x_edge);
        for &e in &SPACINGS {
            let inv_e = 1.0 / e;
            let (ny, nz) = (count(extent.y, e), count(extent.z, e));
            // A hash table's size comes from the entries and the row
            // length, not the box; its row tags (`z · ny + y`) stay within
            // an i32.
            let cells = nx.saturating_mul(ny).saturating_mul(nz);
            let too_big = if hashed {
                nx > max_entries as u64 || ny.saturating_mul(nz) > i32::MAX as u64
            } else {
                cells > MAX_CELLS
            };
            if too_big {
                continue;
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
            if entries > max_entries as u64 {
                continue;
            }
            // A hash table of at least two buckets per entry (and one per x
            // cell, so no row's buckets overlap themselves): the (row, x
            // cell)s holding entries, some twenty entries each inside a
            // protein, then rarely share a bucket. With one bucket per
            // entry, other rows' entries made a sixth of those a search on
            // 1rx1's surface patches scanned (474 entries in 146 blocks for
            // its 36 searches, against 385 in 123 with two; the full grid's
            // 405 in 117), and the hashed queries 1 % slower.
            let size = (2 * entries as usize)
                .max(nx as usize)
                .next_power_of_two()
                .max(64);
            let buckets = if hashed {
                Buckets::Hashed {
                    mask: (size - 1) as u32,
                    row_of: Vec::new(),
                }
            } else {
                Buckets::Dense
            };
            let key = |ix: i32, iy: i32, iz: i32| match &buckets {
                Buckets::Dense => ((iz * dims[1] + iy) * dims[0] + ix) as usize,
                Buckets::Hashed { mask, .. } => hash_cell(ix, iy, iz, *mask) as usize,
            };
            let cells = if hashed { size } else { cells as usize };
            let mut start = vec![0u32; cells + 1];
            for &(ix, (y0, y1), (z0, z1)) in &homes {
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
            let row_length = nx as usize;
            for c in 0..cells {
                start[c + 1] += start[c];
                if !hashed && (c + 1) % row_length == 0 {
                    start[c + 1] = start[c + 1].next_multiple_of(LANES as u32);
                }
            }
            let total = start[cells] as usize;
            let mut fill = start.clone();
            let mut slot = vec![UNUSED; total];
            let mut row_tags = vec![0u32; if hashed { total } else { 0 }];
            for (s, &(ix, (y0, y1), (z0, z1))) in homes.iter().enumerate() {
                for iz in z0..=z1 {
                    for iy in y0..=y1 {
                        let k = key(ix, iy, iz);
                        let e = fill[k] as usize;
                        slot[e] = s as u32;
                        if let Some(t) = row_tags.get_mut(e) {
                            *t = (iz * dims[1] + iy) as u32;
                        }
                        fill[k] += 1;
                    }
                }
            }
            let buckets = match buckets {
                Buckets::Dense => Buckets::Dense,
                Buckets::Hashed { mask, .. } => Buckets::Hashed {
                    mask,
                    row_of: row_tags,
                },
            };
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
            return Some(Self {
                origin: f32x4::from([lo.x, lo.y, lo.z, lo.x]),
                inv: f32x4::from([inv_x, inv_e, inv_e, inv_x]),
                dims,
                margin,
                start,
                buckets,
                blocks,
                tag: slot
                    .iter()
                    .map(|&s| tags.get(s as usize).map_or(0, |t| *t))
                    .collect(),
            });
        }
        None
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
                // The hits' lanes read from the block in place (copying
                // its four vectors out as arrays took some 25 moves).
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
mod tests {
    use super::*;
    use crate::rng::Rng;
    use glam::DVec3;

    /// Each atom's index as its tag.
    fn tags(n: usize) -> Vec<u32> {
        (0..n as u32).collect()
    }

    /// The atoms within `radius` of `p` by brute force, with `d²` as the
    /// collider computes it, sorted.
    fn brute(atoms: &[Vec4], p: Vec3, radius: f32) -> Vec<(usize, u32)> {
        let r2 = radius * radius;
        let mut v: Vec<(usize, u32)> = atoms
            .iter()
            .enumerate()
            .filter_map(|(i, a)| {
                let d2 = (a.truncate() - p).length_squared();
                (d2 <= r2).then_some((i, d2.to_bits()))
            })
            .collect();
        v.sort_unstable();
        v
    }

    /// What `rows` (built with each atom's index as its tag) reports.
    fn found(rows: &PaddedRows, atoms: &[Vec4], p: Vec3, radius: f32) -> Vec<(usize, u32)> {
        let mut v = Vec::new();
        rows.near(p, radius, |a, tag, d2| {
            assert_eq!(a, atoms[tag as usize], "atom {tag} as stored");
            v.push((tag as usize, d2.to_bits()));
        });
        let n = v.len();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), n, "an atom reported twice near {p}");
        v
    }

    /// Clustered atoms (a protein-like blob with a few strays), so rows
    /// hold many atoms and some runs are empty.
    fn atoms(rng: &mut Rng, n: usize) -> Vec<Vec4> {
        (0..n)
            .map(|i| {
                let c = if i % 10 == 0 {
                    rng.in_box(DVec3::splat(30.0))
                } else {
                    rng.in_box(DVec3::new(12.0, 8.0, 10.0))
                };
                c.as_vec3().extend(rng.range(1.2, 2.0) as f32)
            })
            .collect()
    }

    #[test]
    fn near_reports_exactly_the_atoms_in_the_ball_each_once() {
        let mut rng = Rng(5);
        for round in 0..12 {
            let atoms = atoms(&mut rng, 200 + 75 * round);
            let margin = rng.range(2.5, 4.5) as f32;
            let hashed = round % 2 == 1;
            let rows =
                PaddedRows::build(&atoms, &tags(atoms.len()), margin, 1.5, hashed).expect("rows");
            for _ in 0..3000 {
                // Inside, around and well outside the atoms' box.
                let p = rng.in_box(DVec3::splat(45.0)).as_vec3();
                let radius = rng.range(0.0, f64::from(margin)) as f32;
                assert_eq!(
                    found(&rows, &atoms, p, radius),
                    brute(&atoms, p, radius),
                    "{p} {radius}"
                );
            }
            // Points on an atom, and a hair off the ball's edge.
            for a in atoms.iter().take(50) {
                let p = a.truncate();
                assert_eq!(found(&rows, &atoms, p, margin), brute(&atoms, p, margin));
                let q = p + Vec3::new(margin, 0.0, 0.0) * (1.0 + f32::EPSILON);
                assert_eq!(found(&rows, &atoms, q, margin), brute(&atoms, q, margin));
            }
        }
    }

    /// A full grid's rows each start at a block (what lets its scans test
    /// whole blocks): each row's atoms, then fewer than a block of unused
    /// slots, infinitely far; and every atom of the row is a real one.
    #[test]
    fn full_grid_rows_start_at_blocks() {
        let mut rng = Rng(7);
        let atoms = atoms(&mut rng, 500);
        let rows = PaddedRows::build(&atoms, &tags(atoms.len()), 3.5, 1.5, false).expect("rows");
        let [nx, ny, nz] = rows.dims.map(|n| n as usize);
        let mut padded = 0;
        for row in 0..ny * nz {
            let (first, end) = (
                rows.start[row * nx] as usize,
                rows.start[(row + 1) * nx] as usize,
            );
            assert_eq!(first % LANES, 0, "row {row} starts at {first}");
            let entry = |e: usize| rows.blocks[e / LANES].map(|v| v.to_array()[e % LANES]);
            let unused = |e: usize| entry(e)[..3].iter().all(|v| *v == f32::INFINITY);
            // The row's real entries first, each an atom as stored.
            let used = (first..end).take_while(|&e| !unused(e)).count();
            for e in first..first + used {
                let tag = rows.tag[e] as usize;
                assert_eq!(
                    Vec4::from_array(entry(e)),
                    atoms[tag],
                    "row {row} entry {e}"
                );
            }
            // Then its padding, to the next block: nothing else.
            assert!(
                (first + used..end).all(unused),
                "row {row}: an atom after padding"
            );
            assert_eq!(end % LANES, 0, "row {row} ends at {end}");
            assert!(
                end - first - used < LANES,
                "row {row}: {} unused",
                end - first - used
            );
            padded += end - first - used;
        }
        assert!(padded > 0, "no row needed padding");
    }

    #[test]
    fn a_coarser_spacing_keeps_the_copies_within_the_limit() {
        let mut rng = Rng(9);
        let atoms = atoms(&mut rng, 400);
        for hashed in [false, true] {
            let fine =
                PaddedRows::build(&atoms, &tags(atoms.len()), 3.75, 1.5, hashed).expect("rows");
            let limit = fine.entries() / 3;
            let coarse =
                PaddedRows::build_within(&atoms, &tags(atoms.len()), 3.75, 1.5, hashed, limit)
                    .expect("coarser rows");
            assert!(coarse.entries() <= limit, "{} > {limit}", coarse.entries());
            let few = PaddedRows::build_within(
                &atoms,
                &tags(atoms.len()),
                3.75,
                1.5,
                hashed,
                atoms.len(),
            );
            assert!(few.is_none());
            for _ in 0..2000 {
                let p = rng.in_box(DVec3::splat(40.0)).as_vec3();
                let radius = rng.range(0.0, 3.75) as f32;
                assert_eq!(found(&coarse, &atoms, p, radius), brute(&atoms, p, radius));
            }
        }
    }

    /// A few atoms spread along x: their rows' (row, x cell)s nearly fill
    /// the table, so runs share buckets with other rows and some wrap at
    /// the table's end; a query still reports exactly the atoms in its
    /// ball, each once.
    #[test]
    fn hashed_rows_that_share_and_wrap_buckets_report_each_atom_once() {
        let mut rng = Rng(17);
        let atoms: Vec<Vec4> = (0..20)
            .map(|_| {
                let c = rng.in_box(DVec3::new(120.0, 9.0, 9.0));
                c.as_vec3().extend(1.7)
            })
            .collect();
        let rows = PaddedRows::build(&atoms, &tags(atoms.len()), 3.0, 1.5, true).expect("rows");
        let Buckets::Hashed { mask, .. } = &rows.buckets else {
            panic!("hashed buckets");
        };
        let size = *mask as usize + 1;
        let (mut wrapped, mut shared) = (0, 0);
        for _ in 0..40_000 {
            let p = rng.in_box(DVec3::new(125.0, 12.0, 12.0)).as_vec3();
            let radius = rng.range(0.0, 3.0) as f32;
            let want = brute(&atoms, p, radius);
            assert_eq!(found(&rows, &atoms, p, radius), want, "{p} {radius}");
            // Count the queries whose buckets wrap, and those whose run
            // holds entries of other rows.
            let cell = |v: f32, o: usize| {
                let inv = rows.inv.to_array()[o];
                let origin = rows.origin.to_array()[o];
                cell_of(v, origin, inv)
            };
            let (x0, x1) = (
                cell(p.x - radius, 0).max(0),
                cell(p.x + radius, 0).min(rows.dims[0] - 1),
            );
            let (iy, iz) = (
                cell(p.y, 1).clamp(0, rows.dims[1] - 1),
                cell(p.z, 2).clamp(0, rows.dims[2] - 1),
            );
            if x0 <= x1 {
                let h0 = hash_cell(x0, iy, iz, *mask) as usize;
                let h1 = h0 + (x1 - x0 + 1) as usize;
                wrapped += usize::from(h1 > size);
                let Buckets::Hashed { row_of: tags, .. } = &rows.buckets else {
                    unreachable!()
                };
                let row = (iz * rows.dims[1] + iy) as u32;
                let (a, b) = (rows.start[h0] as usize, rows.start[h1.min(size)] as usize);
                shared += usize::from(tags[a..b].iter().any(|&t| t != row));
            }
        }
        assert!(
            wrapped > 40 && shared > 500,
            "{wrapped} wrapped, {shared} shared"
        );
    }

    #[test]
    fn odd_input_gives_no_rows_or_no_atoms() {
        let one = [Vec4::new(1.0, 2.0, 3.0, 1.7)];
        for hashed in [false, true] {
            let build = |atoms: &[Vec4], margin| {
                PaddedRows::build(atoms, &tags(atoms.len()), margin, 1.5, hashed)
            };
            assert!(build(&[], 3.0).is_none());
            assert!(build(&one, 0.0).is_none());
            assert!(build(&one, f32::NAN).is_none());
            let far = [one[0], Vec4::new(f32::INFINITY, 0.0, 0.0, 1.7)];
            assert!(build(&far, 3.0).is_none());
            // Atoms too far apart for the limits at any spacing (cells, or
            // a hashed row's length).
            let spread = [
                Vec4::new(-3e7, -3e5, -3e5, 1.7),
                Vec4::new(3e7, 3e5, 3e5, 1.7),
            ];
            assert!(build(&spread, 3.0).is_none());
            // A tag for every atom, or no rows.
            assert!(PaddedRows::build(&one, &[], 3.0, 1.5, hashed).is_none());
            let rows = build(&one, 3.0).expect("one atom");
            assert_eq!(found(&rows, &one, Vec3::new(1.0, 2.0, 3.0), 0.0).len(), 1);
            assert!(found(&rows, &one, Vec3::NAN, 3.0).is_empty());
            assert!(found(&rows, &one, Vec3::splat(1e30), 3.0).is_empty());
            assert!(found(&rows, &one, Vec3::new(1.0, 2.0, 6.01), 3.0).is_empty());
            assert_eq!(found(&rows, &one, Vec3::new(1.0, 2.0, 5.99), 3.0).len(), 1);
        }
    }
}
