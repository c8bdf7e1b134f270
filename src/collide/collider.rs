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
//!   y and z (`GRID_EDGE`), so a query covers few rows. It also keeps its
//!   atoms in padded rows ([`super::padded_rows`]), rows on a finer y-z
//!   spacing that overlap, so the ball of a drug atom's reach lies in one
//!   row and its query scans a single run.
//! - [`ColliderKind::Hashed`] hashes cell coordinates into a table whose size is
//!   chosen from the atom count (the thesis's variant: one pass, no bounds).
//!   The hash of cell `(x, y, z)` is a hash of its row `(y, z)` plus `x`
//!   ([`hash_cell`]), so a row's cells sit in consecutive buckets and a query
//!   scans one contiguous run of atoms per row, as in the full grid. Distinct
//!   rows can share buckets, so each stored atom keeps its cell coordinates
//!   and a scan reports only the atoms of the row's own cells: no atom
//!   twice, no far atom. It keeps padded rows too, in a hash table of the
//!   same kind sized from their entries.
//!
//! The cell edges derive from the largest contact distance a receptor atom
//! can have with a drug atom as large as itself. Queries
//! ([`Collider::near`]) test the atoms of a run a few at a time with SIMD
//! lanes (the `wide` crate, SSE2 on any x86-64); the cost of a query does not
//! depend on the receptor's size. Both grids also keep a [`Clearance`] map,
//! so callers can skip the query for a point with nothing in reach
//! ([`Collider::clearance`]); brute force, the reference, has none.

use std::sync::{Arc, OnceLock};

use glam::{Vec3, Vec4};
use serde::Serialize;
use wide::{f32x4, i32x4};

use super::clearance::Clearance;
use super::padded_rows::PaddedRows;
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

/// Largest drug atom radius, in Å, whose searches the padded rows serve:
/// every common drug element's (C, N, O, F, P, S, Cl) but bromine's and
/// iodine's, whose searches go to the plain grid. A receptor's largest
/// radius (1rx1 has an atom of 2.31 Å) sets the grid's cell, but a larger
/// margin than needed scans and stores more for every query.
const ROW_DRUG_RADIUS: f32 = 1.8;

/// Room the padded rows keep beyond a drug atom's reach, in Å: its sweep
/// over half an interval of 1 Å, and the tolerance.
const ROW_SLACK: f32 = 0.75;

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
    /// The grid's atoms again in padded rows, for balls up to their
    /// margin (see [`PaddedRows`]): both grids, built on the
    /// clearance map's thread before the map; queries use the plain grid
    /// until they are there, with the same answers.
    rows: Arc<OnceLock<Option<PaddedRows>>>,
    /// How far points are from the atoms (grids only; the reference
    /// stays plain brute force). Built on its own thread, so a collider
    /// answers at once; queries use the map once it is there. Answers are
    /// the same with or without it, only their speed differs.
    clearance: Arc<OnceLock<Option<Clearance>>>,
    cell: f32,
    max_radius: f32,
    lo: Vec3,
    hi: Vec3,
}

#[derive(Debug, Clone)]
enum Index {
    Brute,
    Grid {
        cells: Cells,
        dims: [i32; 3],
        /// Start of each cell's run in `atoms`; one extra entry at the end.
        start: Vec<u32>,
    },
    Hashed {
        /// Cells in absolute coordinates (origin 0), clipped to the
        /// smallest and largest occupied cell on each axis, so a box larger
        /// than a small receptor does not visit (or hash) empty cells.
        cells: Cells,
        mask: u32,
        /// Start of each bucket's run in `atoms`; one extra entry at the end.
        start: Vec<u32>,
    },
}

/// A uniform grid's geometry in SIMD lanes (x, y, z, unused): where cell
/// (0, 0, 0) starts, the reciprocal cell edges, and the range of cells a
/// query is clipped to.
#[derive(Debug, Clone, Copy)]
struct Cells {
    origin: f32x4,
    inv_cell: f32x4,
    min: i32x4,
    max: i32x4,
}

/// Cell coordinates are clamped to ±this before conversion, so that absurd
/// (or infinite) query boxes convert exactly and clip like any other.
const CELL_LIMIT: f32 = (1u32 << 30) as f32;

impl Cells {
    fn new(origin: Vec3, inv_cell: Vec3, min: [i32; 3], max: [i32; 3]) -> Self {
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
    fn cover(&self, lo: Vec3, hi: Vec3) -> Option<([i32; 3], [i32; 3])> {
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
/// to little more than the ball's width. On trimethoprim/DHFR move-to-touch
/// this shape took 1.44 µs a query against 1.85 µs for cubes of one contact
/// distance; 1.25×, 1.75× and 2× for y and z, and 1× for x, were slower.
const GRID_EDGE: Vec3 = Vec3::new(0.5, 1.5, 1.5);

/// Edges of a hashed-grid cell, in units of the contact-distance edge: the
/// full grid's shape, for the same reason (a query scans one run per row).
/// With the thesis's cubes of one contact distance, trimethoprim/DHFR
/// move-to-touch took 1.85 µs a query against 1.53 µs with these.
const HASH_EDGE: Vec3 = GRID_EDGE;

/// Integer cell coordinate of `x` (saturating for absurd values, 0 for NaN).
#[inline]
fn cell_of(x: f32, origin: f32, inv_cell: f32) -> i32 {
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
    /// Indexes `receptor` (in its own frame) for drugs judged by `rule`;
    /// a grid also builds its padded rows and clearance map, on a thread of
    /// its own.
    pub fn build(receptor: &Molecule, rule: &ContactRule, kind: ColliderKind) -> Self {
        Self::build_with(receptor, rule, kind, true)
    }

    /// [`Collider::build`] without the padded rows and the clearance map,
    /// for a command that asks a few queries and exits: they would take
    /// longer to build than the queries (over a second and 64 MiB for a
    /// 272k-atom receptor), and the answers are the same without them.
    pub fn build_plain(receptor: &Molecule, rule: &ContactRule, kind: ColliderKind) -> Self {
        Self::build_with(receptor, rule, kind, false)
    }

    fn build_with(
        receptor: &Molecule,
        rule: &ContactRule,
        kind: ColliderKind,
        extras: bool,
    ) -> Self {
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
        // Each atom as stored, read straight from the molecule (a copy of
        // them all would be the largest allocation of a 272k-atom build).
        let stored = |i: u32| {
            let (p, a) = (receptor.local[i as usize], &receptor.atoms[i as usize]);
            (p.extend(a.radius), (i << 1) | u32::from(a.polar))
        };

        // Integer cell of each stored atom: the hashed index only.
        let mut cells = Vec::new();
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
                        cells: Cells::new(lo, inv_cell, [0; 3], dims.map(|d| d - 1)),
                        dims,
                        start,
                    },
                )
            }
            ColliderKind::Hashed => {
                let size = hashed_table_size(n);
                let mask = (size - 1) as u32;
                let inv_cell = (HASH_EDGE * cell).recip();
                let atom_cells: Vec<[i32; 3]> = receptor
                    .local
                    .iter()
                    .map(|p| {
                        [
                            cell_of(p.x, 0.0, inv_cell.x),
                            cell_of(p.y, 0.0, inv_cell.y),
                            cell_of(p.z, 0.0, inv_cell.z),
                        ]
                    })
                    .collect();
                let keys: Vec<u32> = atom_cells
                    .iter()
                    .map(|&[x, y, z]| hash_cell(x, y, z, mask))
                    .collect();
                let (order, start) = bucket_sort(&keys, size);
                let mut occupied = [[i32::MAX; 3], [i32::MIN; 3]];
                for c in &atom_cells {
                    for k in 0..3 {
                        occupied[0][k] = occupied[0][k].min(c[k]);
                        occupied[1][k] = occupied[1][k].max(c[k]);
                    }
                }
                cells = order.iter().map(|&i| atom_cells[i as usize]).collect();
                (
                    order,
                    Index::Hashed {
                        cells: Cells::new(Vec3::ZERO, inv_cell, occupied[0], occupied[1]),
                        mask,
                        start,
                    },
                )
            }
        };
        let atoms: Vec<Vec4> = order.iter().map(|&i| stored(i).0).collect();
        let soa = [0, 1, 2].map(|k| padded(atoms.iter().map(|a| a[k])));
        let meta: Vec<u32> = order.iter().map(|&i| stored(i).1).collect();
        let mut slot = vec![0u32; n];
        for (k, &i) in order.iter().enumerate() {
            slot[i as usize] = k as u32;
        }
        let clearance = Arc::new(OnceLock::new());
        let rows = Arc::new(OnceLock::new());
        // The rows serve balls of a drug atom's reach over one interval
        // (its radius less the smallest allowance, plus the largest receptor
        // radius and the interval's sweep); each grid keeps them in a table
        // of its own kind (dense over the box, or hashed).
        let row_margin = (max_radius + ROW_DRUG_RADIUS - rule.min_allowance()).max(1.0) + ROW_SLACK;
        let row_edge = GRID_EDGE.x * cell;
        match kind {
            ColliderKind::Brute => {
                let _ = clearance.set(None);
                let _ = rows.set(None);
            }
            ColliderKind::Grid | ColliderKind::Hashed if !extras => {
                let _ = clearance.set(None);
                let _ = rows.set(None);
            }
            ColliderKind::Grid | ColliderKind::Hashed => {
                let hashed = kind == ColliderKind::Hashed;
                // The map takes longer to build than the grid (40 ms for
                // 1.3k atoms, over a second for 272k), the rows up to a
                // tenth of that; the session builds a collider in the frame
                // that turns collision on, so it must not wait.
                let (rows_slot, map_slot, copy, tags) = (
                    Arc::clone(&rows),
                    Arc::clone(&clearance),
                    atoms.clone(),
                    meta.clone(),
                );
                let spawned = std::thread::Builder::new()
                    .name("bump-clearance".into())
                    .spawn(move || {
                        // Each set even if its build panicked, so nobody
                        // waits forever.
                        let built = std::panic::catch_unwind(|| {
                            PaddedRows::build(&copy, &tags, row_margin, row_edge, hashed)
                        });
                        let _ = rows_slot.set(built.ok().flatten());
                        let map = std::panic::catch_unwind(|| Clearance::build(&copy));
                        let _ = map_slot.set(map.ok().flatten());
                    });
                if spawned.is_err() {
                    // No thread to be had: build them here.
                    let _ = rows.set(PaddedRows::build(
                        &atoms, &meta, row_margin, row_edge, hashed,
                    ));
                    let _ = clearance.set(Clearance::build(&atoms));
                }
            }
        }
        Self {
            kind,
            atoms,
            soa,
            meta,
            slot,
            cells,
            index,
            rows,
            clearance,
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

    /// The clearance map, once built (the grids have one; brute force has
    /// none). Queries look it up once, then ask it per point
    /// ([`Clearance::clear`]).
    pub fn clearance(&self) -> Option<&Clearance> {
        self.clearance.get().and_then(Option::as_ref)
    }

    /// Whether a grid's padded rows are built (never for brute force, nor
    /// for a receptor too sparse for their limits).
    pub fn has_padded_rows(&self) -> bool {
        self.padded_rows().is_some()
    }

    /// Waits until the clearance map is built (at once for brute force),
    /// so benchmarks time the queries as they run from then on. A grid's
    /// padded rows are built before the map, so they are there too.
    pub fn wait_for_clearance(&self) -> Option<&Clearance> {
        self.clearance.wait().as_ref()
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
    /// test distances), each once. Brute force visits every atom.
    ///
    /// # Performance
    /// One contiguous run of atoms per row of cells in both grids; the
    /// hashed grid keeps only the atoms of the row's own cells. Neither
    /// depends on the receptor's size.
    #[inline]
    pub fn visit<F: FnMut(Vec4, u32)>(&self, lo: Vec3, hi: Vec3, mut f: F) {
        let mut run = |a: usize, b: usize, keep: &dyn Fn(usize) -> bool| {
            for k in a..b {
                if keep(k) {
                    f(self.atoms[k], self.meta[k]);
                }
            }
        };
        match &self.index {
            Index::Brute => run(0, self.atoms.len(), &|_| true),
            Index::Grid { cells, dims, start } => {
                if let Some((from, to)) = cells.cover(lo, hi) {
                    grid_rows(start, *dims, from, to, |a, b| run(a, b, &|_| true));
                }
            }
            Index::Hashed { cells, mask, start } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) = cells.cover(lo, hi) else {
                    return;
                };
                let all = !hashed_rows(start, *mask, [x0, y0, z0], [x1, y1, z1], |y, z, a, b| {
                    // Other rows' cells may share these buckets.
                    run(a, b, &|k| {
                        let c = self.cells[k];
                        c[1] == y && c[2] == z && (x0..=x1).contains(&c[0])
                    });
                });
                if all {
                    run(0, self.atoms.len(), &|_| true);
                }
            }
        }
    }

    /// Calls `f(position_and_radius, receptor_index << 1 | polar, d²)` for
    /// every receptor atom whose centre lies within `radius` of `p`, with `d²`
    /// its squared distance from `p` in f32 (`(q − p)·(q − p)`, summed x, y,
    /// z in that order). Exactly the atoms [`Collider::visit`] on the box
    /// around the ball would give that pass the test, with the same `d²`;
    /// the order is the storage order of each row's run.
    ///
    /// # Performance
    /// The grids answer a ball up to their padded rows' margin from one
    /// run of one row (or two, where a hashed row wraps), tested four
    /// stored atoms at a time in whole blocks (lanes outside the run are
    /// masked only where a hashed row wraps), so the cost per run is
    /// nearly constant. The hashed grid's check that an atom belongs to
    /// the row (buckets are shared) is paid only by atoms inside the ball.
    #[inline]
    pub fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F) {
        match self.padded_rows() {
            Some(rows) => RowSearch {
                collider: self,
                rows,
            }
            .near(p, radius, f),
            None => self.near_plain(p, radius, f),
        }
    }

    /// The grid's padded rows, once built.
    #[inline]
    pub(crate) fn padded_rows(&self) -> Option<&PaddedRows> {
        self.rows.get().and_then(Option::as_ref)
    }

    /// [`Collider::near`] without the padded rows.
    #[inline]
    pub(crate) fn near_plain<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, mut f: F) {
        let r2 = radius * radius;
        let (lo, hi) = (p - Vec3::splat(radius), p + Vec3::splat(radius));
        match &self.index {
            Index::Brute => self.scan(0, self.atoms.len(), p, r2, &mut f, |_| true),
            Index::Grid { cells, dims, start } => {
                if let Some((from, to)) = cells.cover(lo, hi) {
                    grid_rows(start, *dims, from, to, |a, b| {
                        self.scan(a, b, p, r2, &mut f, |_| true);
                    });
                }
            }
            Index::Hashed { cells, mask, start } => {
                let Some(([x0, y0, z0], [x1, y1, z1])) = cells.cover(lo, hi) else {
                    return;
                };
                let all = !hashed_rows(start, *mask, [x0, y0, z0], [x1, y1, z1], |y, z, a, b| {
                    // An atom inside the ball lies in one of the box's
                    // cells; it is reported from that cell's row only.
                    self.scan(a, b, p, r2, &mut f, |k| {
                        let c = self.cells[k];
                        c[1] == y && c[2] == z && (x0..=x1).contains(&c[0])
                    });
                });
                if all {
                    self.scan(0, self.atoms.len(), p, r2, &mut f, |_| true);
                }
            }
        }
    }

    /// Tests stored atoms `a..b` against the ball (`p`, `r2`) [`LANES`] at a
    /// time and reports the atoms inside for which `keep` holds.
    #[inline(always)]
    fn scan<F: FnMut(Vec4, u32, f32)>(
        &self,
        a: usize,
        b: usize,
        p: Vec3,
        r2: f32,
        f: &mut F,
        keep: impl Fn(usize) -> bool,
    ) {
        if a >= b {
            return;
        }
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
            // Always false: k < b ≤ len and the arrays carry LANES padding entries.
            if k + LANES > end {
                return;
            }
            let chunk = |v: &[f32]| {
                let mut c = [0.0; LANES];
                c.copy_from_slice(&v[k..k + LANES]);
                f32x4::from(c)
            };
            let (dx, dy, dz) = (chunk(sx) - px, chunk(sy) - py, chunk(sz) - pz);
            // Summed in the order of `Vec3::length_squared`: the same bits.
            let d2 = dx * dx + dy * dy + dz * dz;
            let mut hits = d2.simd_le(r2).to_bitmask();
            if hits != 0 {
                // Lanes past the run's end hold other atoms: drop them.
                let rest = b - k;
                if rest < LANES {
                    hits &= (1 << rest) - 1;
                }
                let d2 = d2.to_array();
                while hits != 0 {
                    let l = hits.trailing_zeros() as usize;
                    hits &= hits - 1;
                    if keep(k + l) {
                        f(self.atoms[k + l], self.meta[k + l], d2[l]);
                    }
                }
            }
            k += LANES;
            if k >= b {
                return;
            }
        }
    }
}

/// A way to ask a collider for the atoms in a ball: [`Collider::near`],
/// split by whether the padded rows are there, so a caller that asks many
/// times (a move-to-touch query) can be compiled once for each and carry
/// only one of the two searches (with both inlined where it asks, the
/// hashed grid's queries on 1rx1's patches were 6 % slower than before by
/// the best of five alternated runs, 13 % by the median).
pub(crate) trait Search {
    /// As [`Collider::near`].
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F);
}

/// The plain index: brute force, a grid before its rows are built.
pub(crate) struct PlainSearch<'a>(pub &'a Collider);

impl Search for PlainSearch<'_> {
    #[inline(always)]
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F) {
        self.0.near_plain(p, radius, f);
    }
}

/// A grid with its padded rows: balls up to their margin from the rows,
/// larger ones from the plain grid.
pub(crate) struct RowSearch<'a> {
    /// The collider.
    pub collider: &'a Collider,
    /// Its rows.
    pub rows: &'a PaddedRows,
}

impl Search for RowSearch<'_> {
    #[inline(always)]
    fn near<F: FnMut(Vec4, u32, f32)>(&self, p: Vec3, radius: f32, f: F) {
        let c = self.collider;
        if radius <= self.rows.margin() {
            self.rows.near(p, radius, f);
        } else {
            c.near_plain(p, radius, f);
        }
    }
}

/// The full grid's rows of cells that the box of cells `x0..=x1`,
/// `y0..=y1`, `z0..=z1` covers: `f(a, b)` with each row's run of stored
/// atoms `a..b` (cells are stored with x fastest, so a row's cells are one
/// run).
#[inline(always)]
fn grid_rows(
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
fn hashed_rows(
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

    #[test]
    fn cover_is_cell_of_on_each_axis_and_clips() {
        let cells = Cells::new(
            Vec3::new(-1.0, 2.0, 0.5),
            Vec3::new(1.0 / 1.5, 1.0 / 4.5, 1.0 / 4.5),
            [-10, -10, -10],
            [10, 10, 10],
        );
        let (inv, o) = ([1.0 / 1.5, 1.0 / 4.5, 1.0 / 4.5], [-1.0, 2.0, 0.5]);
        for (lo, hi) in [
            (Vec3::new(-3.1, 0.0, 2.9), Vec3::new(3.0, 4.5, 3.0)),
            (Vec3::splat(-0.0), Vec3::splat(1e-7)),
            (Vec3::new(-1.0, 2.0, 0.5), Vec3::new(-1.0, 2.0, 0.5)),
        ] {
            let (first, last) = cells.cover(lo, hi).expect("inside");
            for k in 0..3 {
                assert_eq!(first[k], cell_of(lo[k], o[k], inv[k]).max(-10));
                assert_eq!(last[k], cell_of(hi[k], o[k], inv[k]).min(10));
            }
        }
        let (first, last) = cells
            .cover(Vec3::splat(-1e30), Vec3::splat(f32::INFINITY))
            .expect("everything");
        assert_eq!((first, last), ([-10; 3], [10; 3]));
        assert!(cells.cover(Vec3::splat(1e3), Vec3::splat(2e3)).is_none());
        assert!(cells.cover(Vec3::splat(1.0), Vec3::splat(0.0)).is_none());
    }

    /// `n` carbon atoms at random in the box `±half`.
    fn random_carbons(rng: &mut crate::rng::Rng, n: i64, half: glam::DVec3) -> Molecule {
        use crate::model::molecule::test_carbon;
        let atoms = (1..=n).map(test_carbon).collect();
        let pos: Vec<glam::DVec3> = (0..n).map(|_| rng.in_box(half)).collect();
        Molecule::new("random carbons", atoms, &pos)
    }

    /// The grids answer through their padded rows and, for balls past
    /// their margin or before they are built, through the plain grid: both
    /// must give brute force's atoms, each once, with the same `d²`.
    #[test]
    fn grids_with_and_without_their_rows_are_brute_force() {
        use crate::rng::Rng;
        use glam::DVec3;
        let mut rng = Rng(23);
        let mol = random_carbons(&mut rng, 600, DVec3::new(14.0, 10.0, 12.0));
        let rule = ContactRule::default();
        let brute = Collider::build(&mol, &rule, ColliderKind::Brute);
        let sorted = |mut v: Vec<(u32, u32)>| {
            let n = v.len();
            v.sort_unstable();
            v.dedup();
            assert_eq!(v.len(), n, "an atom reported twice");
            v
        };
        for kind in [ColliderKind::Grid, ColliderKind::Hashed] {
            let grid = Collider::build(&mol, &rule, kind);
            grid.wait_for_clearance();
            let rows = grid.padded_rows().expect("padded rows");
            let (mut in_rows, mut past) = (0, 0);
            for _ in 0..3000 {
                let p = rng.in_box(DVec3::splat(22.0)).as_vec3();
                let r = rng.range(0.0, 12.0) as f32;
                let mut want = Vec::new();
                brute.near(p, r, |_, m, d2| want.push((m, d2.to_bits())));
                let mut plain = Vec::new();
                grid.near_plain(p, r, |_, m, d2| plain.push((m, d2.to_bits())));
                let mut both = Vec::new();
                grid.near(p, r, |_, m, d2| both.push((m, d2.to_bits())));
                let want = sorted(want);
                assert_eq!(sorted(plain), want, "{kind:?} plain near {p} {r}");
                assert_eq!(sorted(both), want, "{kind:?} near {p} {r}");
                if r <= rows.margin() {
                    in_rows += 1;
                } else {
                    past += 1;
                }
            }
            assert!(in_rows > 500 && past > 500, "{kind:?} {in_rows} {past}");
        }
    }

    /// A few atoms spread widely: the hashed table is 64 buckets, so rows
    /// share buckets and wrap at the table's end. The plain table's search
    /// (and, once they are built, the padded rows') must still give brute
    /// force's atoms and `visit` every atom of the box once.
    #[test]
    fn hashed_rows_that_share_and_wrap_buckets_report_each_atom_once() {
        use crate::rng::Rng;
        use glam::DVec3;
        let mut rng = Rng(11);
        let mol = random_carbons(&mut rng, 12, DVec3::new(40.0, 6.0, 6.0));
        let rule = ContactRule::default();
        let brute = Collider::build(&mol, &rule, ColliderKind::Brute);
        let hashed = Collider::build(&mol, &rule, ColliderKind::Hashed);
        // Queries below ask the plain table and the rows explicitly, so
        // neither depends on when the rows' thread finishes.
        hashed.wait_for_clearance();
        let Index::Hashed { mask, .. } = &hashed.index else {
            panic!("hashed index");
        };
        assert_eq!(*mask, 63);
        let mut wrapped = false;
        for _ in 0..2000 {
            let p = rng.in_box(DVec3::new(45.0, 8.0, 8.0)).as_vec3();
            let r = rng.range(0.5, 30.0) as f32;
            let sorted = |mut v: Vec<(u32, u32)>| {
                v.sort_unstable();
                v
            };
            let (mut want, mut plain, mut near) = (Vec::new(), Vec::new(), Vec::new());
            brute.near(p, r, |_, m, d2| want.push((m, d2.to_bits())));
            hashed.near_plain(p, r, |_, m, d2| plain.push((m, d2.to_bits())));
            hashed.near(p, r, |_, m, d2| near.push((m, d2.to_bits())));
            let want = sorted(want);
            assert_eq!(sorted(plain), want, "plain near {p} {r}");
            assert_eq!(sorted(near), want, "near {p} {r}");
            let (lo, hi) = (p - Vec3::splat(r), p + Vec3::splat(r));
            let mut seen = Vec::new();
            hashed.visit(lo, hi, |_, m| seen.push(m));
            let before = seen.len();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), before, "an atom visited twice");
            let mut inside = Vec::new();
            brute.visit(lo, hi, |a, m| {
                if a.truncate().cmpge(lo).all() && a.truncate().cmple(hi).all() {
                    inside.push(m);
                }
            });
            assert!(inside.iter().all(|m| seen.binary_search(m).is_ok()));
            if let Index::Hashed { cells, .. } = &hashed.index
                && let Some(([x0, y0, z0], [x1, y1, z1])) = cells.cover(lo, hi)
            {
                let width = (x1 - x0 + 1) as u32;
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        wrapped |= width <= 64 && hash_cell(x0, y, z, 63) + width > 64;
                    }
                }
            }
        }
        assert!(wrapped, "no query wrapped at the table's end");
    }
}
