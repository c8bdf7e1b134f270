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
use wide::f32x4;

use super::clearance::Clearance;
use super::layers::Layers;
use super::padded_rows::PaddedRows;
use super::rule::ContactRule;
use crate::model::Molecule;
use cells::{Cells, GRID_EDGE, HASH_EDGE, bucket_sort, cell_of, grid_rows, hashed_rows};

mod cells;
mod search;
#[cfg(test)]
mod tests;

pub use cells::{hash_cell, hashed_table_size};
pub(crate) use search::{PlainSearch, RowSearch, Search};

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
/// radius (a selenomethionine's 1.9 Å, a silicon's 2.1 Å) sets the grid's
/// cell, but a larger margin than needed scans and stores more for every
/// query.
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

impl Collider {
    /// Indexes `receptor` (in its own frame) for drugs judged by `rule`.
    pub fn build(receptor: &Molecule, rule: &ContactRule, kind: ColliderKind) -> Self {
        Self::build_with(receptor, rule, kind, &Layers::ALL)
    }

    /// [`Collider::build`] without the padded rows and the clearance map,
    /// for a command that asks a few queries and exits: they would take
    /// longer to build than the queries (over a second and 64 MiB for a
    /// 272k-atom receptor), and the answers are the same without them.
    pub fn build_plain(receptor: &Molecule, rule: &ContactRule, kind: ColliderKind) -> Self {
        let layers = Layers {
            clearance_map: false,
            padded_rows: false,
            ..Layers::ALL
        };
        Self::build_with(receptor, rule, kind, &layers)
    }

    /// [`Collider::build`] with only the clearance map and padded rows
    /// that `layers` asks for (to measure what they save).
    pub fn build_with(
        receptor: &Molecule,
        rule: &ContactRule,
        kind: ColliderKind,
        layers: &Layers,
    ) -> Self {
        let n = receptor.len();
        let max_radius = receptor.max_radius();
        let (lo, hi) = if n == 0 {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            let lo = receptor.local.iter().fold(Vec3::INFINITY, |a, p| a.min(*p));
            let hi = receptor
                .local
                .iter()
                .fold(Vec3::NEG_INFINITY, |a, p| a.max(*p));
            (lo, hi)
        };
        let cell = (2.0 * max_radius - rule.min_allowance()).max(1.0);
        let (order, index, atom_cells) = match kind {
            ColliderKind::Brute => ((0..n as u32).collect(), Index::Brute, Vec::new()),
            ColliderKind::Grid => grid_index(receptor, lo, hi, cell),
            ColliderKind::Hashed => hashed_index(receptor, cell),
        };
        // The atoms in storage order: position and radius, receptor index
        // and polarity, and each one's slot.
        let atoms: Vec<Vec4> = order
            .iter()
            .map(|&i| receptor.local[i as usize].extend(receptor.atoms[i as usize].radius))
            .collect();
        let soa = [0, 1, 2].map(|k| padded(atoms.iter().map(|a| a[k])));
        let meta: Vec<u32> = order
            .iter()
            .map(|&i| (i << 1) | u32::from(receptor.atoms[i as usize].polar))
            .collect();
        let mut slot = vec![0u32; n];
        for (k, &i) in order.iter().enumerate() {
            slot[i as usize] = k as u32;
        }
        let cells = order
            .iter()
            .filter_map(|&i| atom_cells.get(i as usize).copied())
            .collect();
        // The rows serve balls of a drug atom's reach over one interval
        // (its radius less the smallest allowance, plus the largest receptor
        // radius and the interval's sweep); each grid keeps them in a table
        // of its own kind (dense over the box, or hashed).
        let rows_for = RowsFor {
            margin: (max_radius + ROW_DRUG_RADIUS - rule.min_allowance()).max(1.0) + ROW_SLACK,
            x_edge: GRID_EDGE.x * cell,
            hashed: kind == ColliderKind::Hashed,
        };
        let (rows, clearance) = match kind {
            ColliderKind::Brute => (ready(None), ready(None)),
            ColliderKind::Grid | ColliderKind::Hashed
                if !layers.padded_rows && !layers.clearance_map =>
            {
                (ready(None), ready(None))
            }
            ColliderKind::Grid | ColliderKind::Hashed => {
                in_background(&atoms, &meta, rows_for, *layers)
            }
        };
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

/// The full grid over the box `lo..hi` with cells of `GRID_EDGE · cell`
/// (coarser for a sparse, huge receptor): the atoms' storage order, the
/// index, and no per-atom cells.
fn grid_index(
    receptor: &Molecule,
    lo: Vec3,
    hi: Vec3,
    cell: f32,
) -> (Vec<u32>, Index, Vec<[i32; 3]>) {
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
    let index = Index::Grid {
        cells: Cells::new(lo, inv_cell, [0; 3], dims.map(|d| d - 1)),
        dims,
        start,
    };
    (order, index, Vec::new())
}

/// The hashed grid with cells of `HASH_EDGE · cell`: the atoms' storage
/// order, the index, and each atom's cell (by receptor index).
fn hashed_index(receptor: &Molecule, cell: f32) -> (Vec<u32>, Index, Vec<[i32; 3]>) {
    let size = hashed_table_size(receptor.len());
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
    let index = Index::Hashed {
        cells: Cells::new(Vec3::ZERO, inv_cell, occupied[0], occupied[1]),
        mask,
        start,
    };
    (order, index, atom_cells)
}

/// What the padded rows are built for.
#[derive(Debug, Clone, Copy)]
struct RowsFor {
    margin: f32,
    x_edge: f32,
    hashed: bool,
}

/// A slot already holding `value`.
fn ready<T>(value: Option<T>) -> Arc<OnceLock<Option<T>>> {
    let slot = Arc::new(OnceLock::new());
    let _ = slot.set(value);
    slot
}

/// Slots for a grid's padded rows and clearance map, filled (with what
/// `layers` asks for) on a thread of their own: the map takes longer to
/// build than the grid (40 ms for 1.3k atoms, over a second for 272k), the
/// rows up to a tenth of that, and the session builds a collider in the
/// frame that turns collision on, so it must not wait. The rows come
/// first; queries use the plain grid until they are there.
#[allow(clippy::type_complexity)] // two slots, named by the caller
fn in_background(
    atoms: &[Vec4],
    meta: &[u32],
    rows_for: RowsFor,
    layers: Layers,
) -> (
    Arc<OnceLock<Option<PaddedRows>>>,
    Arc<OnceLock<Option<Clearance>>>,
) {
    let RowsFor {
        margin,
        x_edge,
        hashed,
    } = rows_for;
    let build_rows = move |atoms: &[Vec4], meta: &[u32]| {
        layers
            .padded_rows
            .then(|| PaddedRows::build(atoms, meta, margin, x_edge, hashed))
            .flatten()
    };
    let build_map = move |atoms: &[Vec4]| {
        layers
            .clearance_map
            .then(|| Clearance::build(atoms))
            .flatten()
    };
    let (rows, clearance) = (Arc::new(OnceLock::new()), Arc::new(OnceLock::new()));
    let (rows_slot, map_slot, copy, tags) = (
        Arc::clone(&rows),
        Arc::clone(&clearance),
        atoms.to_vec(),
        meta.to_vec(),
    );
    let spawned = std::thread::Builder::new()
        .name("bump-clearance".into())
        .spawn(move || {
            // Each set even if its build panicked, so nobody waits forever.
            let built = std::panic::catch_unwind(|| build_rows(&copy, &tags));
            let _ = rows_slot.set(built.ok().flatten());
            let map = std::panic::catch_unwind(|| build_map(&copy));
            let _ = map_slot.set(map.ok().flatten());
        });
    if spawned.is_err() {
        // No thread to be had: build them here.
        let _ = rows.set(build_rows(atoms, meta));
        let _ = clearance.set(build_map(atoms));
    }
    (rows, clearance)
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
