//! Grid maps: the receptor's intermolecular energy for each X-Score type
//! the drug has, sampled on a lattice over a box around the drug's region,
//! read by trilinear interpolation with its exact gradient.
//!
//! The lattice follows Vina's (`grid_dims`, `cache::populate`): per axis
//! `n = ⌈size/spacing⌉` intervals, the first point at
//! `centre − spacing·n/2`; a point's value is the sum of Vina's table values
//! over the receptor atoms within 8 Å of it. A drug atom inside the box gets
//! the interpolated value (the curl then applies to it, as to the exact sum);
//! an atom **outside the box, or of a type without a map, is scored
//! exactly** ([`MapField`] falls back to [`Exact`]), so a drug that leaves
//! the box is never penalised or clamped, only slower.
//!
//! Building visits each receptor atom near the box once and adds its table
//! values to the lattice points within 8 Å of it, row by row (x fastest):
//! the maps are built interleaved (every mapped type's value of a point
//! side by side, read from a per-receptor-type table laid out the same way,
//! so one point costs one table row and one vector add), then split per
//! type; on as many threads as the machine has, each owning a slab of
//! z-planes;
//! [`MapsJob`] runs the whole build on a background thread.
//!
//! Each type's map keeps, per point, its value and those of the next point
//! along x, and of the two above along y ([`Quads`]): a cell's eight
//! corners are two reads. The drug held rigid
//! ([`MapField`]'s [`Field::rigid_energy_gradient`]) is moved into lattice
//! units with one transform and interpolated four atoms at a time in f32
//! lanes ([`Lattice::interpolate4`]), which the map values' own f32
//! precision allows.

use std::sync::Arc;
use std::thread::JoinHandle;

use glam::{DMat3, DVec3};
use wide::{f32x4, i32x4};

use super::exact::Exact;
use super::field::{Field, RigidDrug};
use super::function::{CUTOFF, CUTOFF2, Scoring, curl_with_slope};
use super::receptor::Receptor;
use super::table::{Row, STRIDE, Table, index};
use crate::chem::XsType;
use crate::motion::Pose;

/// Vina's default lattice spacing, Å.
pub const DEFAULT_SPACING: f64 = 0.375;

/// Largest number of lattice points a map may have (80 MB per type at most,
/// as the maps keep four values a point): a box from a typo must not
/// exhaust memory. A cube of 64 Å at Vina's 0.375 Å spacing fits.
pub const MAX_POINTS: usize = 5_000_000;

/// A box for maps: centre, edge lengths and lattice spacing (Å).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapBox {
    /// Centre.
    pub centre: DVec3,
    /// Edge lengths.
    pub size: DVec3,
    /// Lattice spacing.
    pub spacing: f64,
}

impl MapBox {
    /// A cube of edge `side` around `centre`.
    pub fn cube(centre: DVec3, side: f64, spacing: f64) -> Self {
        Self {
            centre,
            size: DVec3::splat(side),
            spacing,
        }
    }

    /// The box around `points` grown by `margin` on every side.
    pub fn around(points: &[DVec3], margin: f64, spacing: f64) -> Self {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in points {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if points.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
        }
        Self {
            centre: (lo + hi) / 2.0,
            size: hi - lo + 2.0 * margin,
            spacing,
        }
    }

    /// Intervals per axis (Vina's `⌈size/spacing⌉`, at least 1).
    fn intervals(&self) -> [usize; 3] {
        let n = |s: f64| ((s / self.spacing).ceil()).max(1.0) as usize;
        [n(self.size.x), n(self.size.y), n(self.size.z)]
    }
}

/// Why maps cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MapsError {
    /// The spacing or size is not a positive finite length.
    #[error("map box: spacing {spacing} Å and size {size:?} Å must be positive and finite")]
    Box {
        /// The spacing.
        spacing: f64,
        /// The size.
        size: [f64; 3],
    },
    /// Too many lattice points.
    #[error("map box: {points} lattice points per map, more than {max}")]
    TooLarge {
        /// Points asked for.
        points: usize,
        /// The limit.
        max: usize,
    },
}

/// A lattice of points (Vina's grid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    /// The first point.
    pub origin: DVec3,
    /// Spacing (Å).
    pub spacing: f64,
    /// Points per axis.
    pub points: [usize; 3],
    /// The last point along each axis, in lattice units (`points − 1`).
    top: DVec3,
    /// The last cell along each axis (`points − 2`, at least 0).
    last_cell: [i32; 3],
}

impl Lattice {
    /// The lattice of `bx`.
    ///
    /// # Errors
    /// For a spacing or size that is not positive and finite, or a lattice
    /// of more than [`MAX_POINTS`] points.
    pub fn new(bx: &MapBox) -> Result<Self, MapsError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(bx.spacing)
            || !bx.size.is_finite()
            || bx.size.min_element() < 0.0
            || !bx.centre.is_finite()
        {
            return Err(MapsError::Box {
                spacing: bx.spacing,
                size: bx.size.to_array(),
            });
        }
        let limit = (MAX_POINTS as f64).cbrt() * 64.0;
        if (bx.size / bx.spacing).max_element() > limit {
            return Err(MapsError::TooLarge {
                points: usize::MAX,
                max: MAX_POINTS,
            });
        }
        let n = bx.intervals();
        let points = [n[0] + 1, n[1] + 1, n[2] + 1];
        let total = points[0]
            .saturating_mul(points[1])
            .saturating_mul(points[2]);
        if total > MAX_POINTS {
            return Err(MapsError::TooLarge {
                points: total,
                max: MAX_POINTS,
            });
        }
        let half = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64) * (bx.spacing / 2.0);
        // At most `limit` + 1 points per axis: these fit an i32.
        let last = |n: usize| n as i32 - 1;
        Ok(Self {
            origin: bx.centre - half,
            spacing: bx.spacing,
            points,
            top: DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64),
            last_cell: [last(n[0]), last(n[1]), last(n[2])],
        })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points[0] * self.points[1] * self.points[2]
    }

    /// True for a lattice without points (never, once built).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The far corner.
    pub fn end(&self) -> DVec3 {
        self.origin
            + DVec3::new(
                (self.points[0] - 1) as f64,
                (self.points[1] - 1) as f64,
                (self.points[2] - 1) as f64,
            ) * self.spacing
    }

    /// Trilinear interpolation of `values` (one per point, x fastest) at
    /// `x`, with its gradient; `None` outside the lattice.
    #[inline]
    pub fn interpolate(&self, values: &[f32], x: DVec3) -> Option<(f64, DVec3)> {
        let inv = 1.0 / self.spacing;
        let (base, f) = self.locate((x - self.origin) * inv)?;
        let (sy, sz) = (self.points[0], self.points[0] * self.points[1]);
        // Each row's two corners in one read (one bounds check).
        let pair = |o: usize| -> Option<[f32; 2]> { values.get(o..o + 2)?.try_into().ok() };
        let (a, b) = (pair(base)?, pair(base + sy)?);
        let (c, d) = (pair(base + sz)?, pair(base + sz + sy)?);
        let (e, g) = trilinear([a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]], f);
        Some((e, g * inv))
    }

    /// The cell holding `g` (a position in lattice units, `(x − origin) /
    /// spacing`): its first point's index and `g`'s place in it; `None`
    /// outside the lattice.
    #[inline]
    fn locate(&self, g: DVec3) -> Option<(usize, DVec3)> {
        let top = self.top;
        // Comparisons with NaN are false: a NaN position is "outside".
        if !(g.x >= 0.0 && g.y >= 0.0 && g.z >= 0.0 && g.x <= top.x && g.y <= top.y && g.z <= top.z)
        {
            return None;
        }
        // In range (tested above), so the cheap i32 conversions are exact;
        // the last point along an axis belongs to the cell before it.
        let [li, lj, lk] = self.last_cell;
        let (i, j, k) = (
            (g.x as i32).min(li),
            (g.y as i32).min(lj),
            (g.z as i32).min(lk),
        );
        let f = g - DVec3::new(f64::from(i), f64::from(j), f64::from(k));
        let [nx, ny, _] = self.points;
        Some(((k as usize * ny + j as usize) * nx + i as usize, f))
    }
}

/// Trilinear interpolation of a cell's corners `c` (x fastest, then y,
/// then z) at `f` (the place in the cell, each in [0, 1]) and its gradient
/// in lattice units.
#[inline]
fn trilinear(c: [f32; 8], f: DVec3) -> (f64, DVec3) {
    let c = c.map(f64::from);
    let [c000, c100, c010, c110, c001, c101, c011, c111] = c;
    // Along x, then y, then z.
    let (a0, a1, a2, a3) = (c100 - c000, c110 - c010, c101 - c001, c111 - c011);
    let c00 = c000 + f.x * a0;
    let c10 = c010 + f.x * a1;
    let c01 = c001 + f.x * a2;
    let c11 = c011 + f.x * a3;
    let (b0, b1) = (c10 - c00, c11 - c01);
    let c0 = c00 + f.y * b0;
    let c1 = c01 + f.y * b1;
    let dz = c1 - c0;
    let e = c0 + f.z * dz;
    let dx0 = a0 + f.y * (a1 - a0);
    let dx1 = a2 + f.y * (a3 - a2);
    let dx = dx0 + f.z * (dx1 - dx0);
    let dy = b0 + f.z * (b1 - b0);
    (e, DVec3::new(dx, dy, dz))
}

/// A map as each point's square of values: its own, the next along x, and
/// the two above those along y. A cell's eight corners are then two reads,
/// its first point's square and the one a plane above.
pub type Quads = [[f32; 4]];

/// `values` (one per point of `lattice`, x fastest) as [`Quads`]; values
/// beyond the lattice's edges, which no cell reads, are zero.
fn quads(lattice: &Lattice, values: impl Fn(usize) -> f32) -> Vec<[f32; 4]> {
    let [nx, ny, nz] = lattice.points;
    let mut out = vec![[0.0f32; 4]; lattice.len()];
    for z in 0..nz {
        for y in 0..ny {
            let row = (z * ny + y) * nx;
            let up = y + 1 < ny;
            for x in 0..nx {
                let p = row + x;
                let right = x + 1 < nx;
                let v = |ok: bool, o: usize| if ok { values(o) } else { 0.0 };
                out[p] = [
                    values(p),
                    v(right, p + 1),
                    v(up, p + nx),
                    v(up && right, p + nx + 1),
                ];
            }
        }
    }
    out
}

impl Lattice {
    /// Interpolation of the map `quads` at `g` (lattice units) with its
    /// gradient in lattice units; `None` outside the lattice.
    #[inline]
    pub fn interpolate_quads(&self, quads: &Quads, g: DVec3) -> Option<(f64, DVec3)> {
        let (base, f) = self.locate(g)?;
        let sz = self.points[0] * self.points[1];
        let (lo, hi) = (quads.get(base)?, quads.get(base + sz)?);
        Some(trilinear(
            [lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]],
            f,
        ))
    }
}

/// Four atoms' interpolated energies and gradients, one per lane, in
/// lattice units ([`Lattice::interpolate4`]).
#[derive(Debug, Clone, Copy)]
pub struct Lanes {
    /// Bit `l` set: lane `l` is outside the lattice or has no map; its
    /// values are zero.
    pub missed: u32,
    /// Energies.
    pub energy: f32x4,
    /// Gradients, per axis.
    pub gradient: [f32x4; 3],
}

impl Lattice {
    /// [`Self::interpolate_quads`] for four points at once (lanes of `g`,
    /// in lattice units), lane `l` reading `maps[l]` (an empty map for a
    /// lane that has none), in f32: the map values are f32 already, so the
    /// interpolation loses nothing that matters at their accuracy.
    #[inline(always)]
    pub fn interpolate4(&self, maps: [&Quads; 4], g: [f32x4; 3]) -> Lanes {
        let zero = f32x4::ZERO;
        let top = self.top.as_vec3();
        let inside = |v: f32x4, t: f32| v.simd_ge(zero) & v.simd_le(f32x4::splat(t));
        let ok = inside(g[0], top.x) & inside(g[1], top.y) & inside(g[2], top.z);
        // Lanes outside (or NaN) read the first cell instead, and are
        // reported as missed.
        let g = g.map(|v| ok.select(v, zero));
        let [li, lj, lk] = self.last_cell;
        let cell = |v: f32x4, last: i32| v.fast_trunc_int().min(i32x4::splat(last));
        let (i, j, k) = (cell(g[0], li), cell(g[1], lj), cell(g[2], lk));
        let f = [
            g[0] - f32x4::from_i32x4(i),
            g[1] - f32x4::from_i32x4(j),
            g[2] - f32x4::from_i32x4(k),
        ];
        let [nx, ny, _] = self.points;
        let sz = nx * ny;
        let (i, j, k) = (i.to_array(), j.to_array(), k.to_array());
        let mut missed = (!ok.to_bitmask()) & 0b1111;
        // Each lane's cell: its lower square and the one a plane above.
        let (mut lo, mut hi) = ([zero; 4], [zero; 4]);
        for l in 0..4 {
            let base = (k[l] as usize * ny + j[l] as usize) * nx + i[l] as usize;
            match (maps[l].get(base), maps[l].get(base + sz)) {
                (Some(a), Some(b)) => (lo[l], hi[l]) = (f32x4::from(*a), f32x4::from(*b)),
                _ => missed |= 1 << l,
            }
        }
        // Lanes become corners: c000 holds the four lanes' first corners.
        let [c000, c100, c010, c110] = f32x4::transpose(lo);
        let [c001, c101, c011, c111] = f32x4::transpose(hi);
        let [fx, fy, fz] = f;
        let (a0, a1, a2, a3) = (c100 - c000, c110 - c010, c101 - c001, c111 - c011);
        let c00 = c000 + fx * a0;
        let c10 = c010 + fx * a1;
        let c01 = c001 + fx * a2;
        let c11 = c011 + fx * a3;
        let (b0, b1) = (c10 - c00, c11 - c01);
        let c0 = c00 + fy * b0;
        let c1 = c01 + fy * b1;
        let dz = c1 - c0;
        let e = c0 + fz * dz;
        let dx0 = a0 + fy * (a1 - a0);
        let dx1 = a2 + fy * (a3 - a2);
        let dx = dx0 + fz * (dx1 - dx0);
        let dy = b0 + fz * (b1 - b0);
        // Lanes outside read the first cell: zero them.
        Lanes {
            missed,
            energy: ok.select(e, zero),
            gradient: [dx, dy, dz].map(|d| ok.select(d, zero)),
        }
    }
}

/// Grid maps of one receptor for some X-Score types.
#[derive(Debug, Clone)]
pub struct Maps {
    scoring: Scoring,
    lattice: Lattice,
    types: Vec<XsType>,
    /// Per type index, its map's slot (`u8::MAX`: none).
    slot: [u8; 19],
    /// One map per slot, each `lattice.len()` points, x fastest.
    quads: Vec<Vec<[f32; 4]>>,
}

/// Adds a receptor atom at `p` to the interleaved maps' z-planes `z0..z1`
/// (`out` holds exactly those planes, `W` values per point): at each point
/// within 8 Å, the `W` values of `table` (the atom's type against each
/// mapped type, zero-padded to `W`, contiguous per sample) at the point's
/// sample.
fn add_atom<const W: usize>(
    lattice: &Lattice,
    (z0, z1): (usize, usize),
    p: DVec3,
    table: &[[f32; W]],
    out: &mut [[f32; W]],
    ks: &mut Vec<u32>,
) {
    let [nx, ny, _] = lattice.points;
    let h = lattice.spacing;
    let inv = 1.0 / h;
    let g = (p - lattice.origin) * inv;
    let reach = CUTOFF * inv;
    let zlo = ((g.z - reach).ceil().max(z0 as f64)) as usize;
    let zhi_f = (g.z + reach).floor().min((z1 - 1) as f64);
    if zhi_f < zlo as f64 {
        return;
    }
    let zhi = zhi_f as usize;
    let ylo = (g.y - reach).ceil().max(0.0) as usize;
    let yhi_f = (g.y + reach).floor().min((ny - 1) as f64);
    if yhi_f < ylo as f64 {
        return;
    }
    let yhi = yhi_f as usize;
    for z in zlo..=zhi {
        let dz = lattice.origin.z + z as f64 * h - p.z;
        let dz2 = dz * dz;
        for y in ylo..=yhi {
            let dy = lattice.origin.y + y as f64 * h - p.y;
            let dyz2 = dy * dy + dz2;
            if dyz2 >= CUTOFF2 {
                continue;
            }
            let half = (CUTOFF2 - dyz2).sqrt();
            let xlo = ((p.x - half - lattice.origin.x) * inv).ceil().max(0.0);
            let xhi = ((p.x + half - lattice.origin.x) * inv)
                .floor()
                .min((nx - 1) as f64);
            if xhi < xlo {
                continue;
            }
            let (xlo, xhi) = (xlo as usize, xhi as usize);
            // Branch-free: a point at r² ≥ 64 reads sample 2048, all 0.
            ks.clear();
            ks.extend((xlo..=xhi).map(|x| {
                let dx = lattice.origin.x + x as f64 * h - p.x;
                index(dx * dx + dyz2) as u32
            }));
            let row = ((z - z0) * ny + y) * nx + xlo;
            let dst = &mut out[row..row + ks.len()];
            for (d, &k) in dst.iter_mut().zip(ks.iter()) {
                let src = &table[k as usize];
                for (a, &b) in d.iter_mut().zip(src) {
                    *a += b;
                }
            }
        }
    }
}

/// Builds the interleaved maps (`W` values per point) of the receptor atoms
/// `near`, whose per-type sample tables are `tables`.
fn build_interleaved<const W: usize>(
    receptor: &Receptor,
    lattice: &Lattice,
    near: &[usize],
    tables: &[Vec<f32>],
    threads: usize,
) -> Vec<f32> {
    let tables: Vec<&[[f32; W]]> = tables
        .iter()
        .map(|t| {
            let (rows, rest) = t.as_chunks::<W>();
            debug_assert!(rest.is_empty());
            rows
        })
        .collect();
    let mut inter = vec![[0.0f32; W]; lattice.len()];
    let [nx, ny, nz] = lattice.points;
    let plane = nx * ny;
    let threads = threads.clamp(1, nz);
    let per = nz.div_ceil(threads);
    let work = |z0: usize, z1: usize, out: &mut [[f32; W]]| {
        let mut ks = Vec::new();
        for &j in near {
            let tb = tables[receptor.xs[j].index()];
            add_atom(lattice, (z0, z1), receptor.positions[j], tb, out, &mut ks);
        }
    };
    if threads == 1 {
        work(0, nz, &mut inter);
    } else {
        // Each thread: its own z-planes.
        std::thread::scope(|s| {
            for (c, out) in inter.chunks_mut(per * plane).enumerate() {
                let z0 = c * per;
                let z1 = (z0 + per).min(nz);
                s.spawn(move || work(z0, z1, out));
            }
        });
    }
    inter.into_flattened()
}

impl Maps {
    /// Builds maps of `receptor` for `types` (duplicates ignored) over
    /// `bx`, on up to `threads` threads (at least one).
    ///
    /// # Errors
    /// For a box that is not a usable lattice ([`Lattice::new`]).
    pub fn build(
        receptor: &Receptor,
        scoring: Scoring,
        types: &[XsType],
        bx: &MapBox,
        threads: usize,
    ) -> Result<Self, MapsError> {
        let lattice = Lattice::new(bx)?;
        let mut kinds: Vec<XsType> = types.to_vec();
        kinds.sort();
        kinds.dedup();
        let mut slot = [u8::MAX; 19];
        for (s, t) in kinds.iter().enumerate() {
            slot[t.index()] = s as u8;
        }
        let table = Table::of(scoring);
        // The receptor atoms within 8 Å of the box.
        let (lo, hi) = (lattice.origin - CUTOFF, lattice.end() + CUTOFF);
        let near: Vec<usize> = (0..receptor.len())
            .filter(|&j| {
                let p = receptor.positions[j];
                p.cmpge(lo).all() && p.cmple(hi).all()
            })
            .collect();
        // Values per point, padded to a multiple of 4 lanes.
        let w = kinds.len().div_ceil(4).max(1) * 4;
        // Per receptor type, each sample's values against every mapped
        // type, contiguous: one cache line per point and atom.
        let mut tables: Vec<Vec<f32>> = vec![Vec::new(); XsType::ALL.len()];
        for &j in &near {
            let b = receptor.xs[j];
            let tb = &mut tables[b.index()];
            if tb.is_empty() {
                let rows: Vec<&Row> = kinds.iter().map(|&a| table.fast_row(a, b)).collect();
                tb.resize(STRIDE * w, 0.0);
                for (k, v) in tb.chunks_exact_mut(w).enumerate() {
                    for (x, row) in v.iter_mut().zip(&rows) {
                        *x = row[k] as f32;
                    }
                }
            }
        }
        let (l, n) = (&lattice, &near[..]);
        let inter = match w {
            4 => build_interleaved::<4>(receptor, l, n, &tables, threads),
            8 => build_interleaved::<8>(receptor, l, n, &tables, threads),
            12 => build_interleaved::<12>(receptor, l, n, &tables, threads),
            16 => build_interleaved::<16>(receptor, l, n, &tables, threads),
            _ => build_interleaved::<20>(receptor, l, n, &tables, threads),
        };
        let quads: Vec<Vec<[f32; 4]>> = (0..kinds.len())
            .map(|s| quads(&lattice, |p| inter[p * w + s]))
            .collect();
        Ok(Self {
            scoring,
            lattice,
            types: kinds,
            slot,
            quads,
        })
    }

    /// The scoring function the maps hold.
    pub fn scoring(&self) -> Scoring {
        self.scoring
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// Bytes the maps' values take.
    pub fn bytes(&self) -> usize {
        self.quads
            .iter()
            .map(|q| std::mem::size_of_val(q.as_slice()))
            .sum()
    }

    /// The types mapped.
    pub fn types(&self) -> &[XsType] {
        &self.types
    }

    /// True when `x` lies inside the lattice.
    pub fn contains(&self, x: DVec3) -> bool {
        let (lo, hi) = (self.lattice.origin, self.lattice.end());
        x.cmpge(lo).all() && x.cmple(hi).all()
    }

    /// The interpolated energy of type `t` at `x` and its gradient; `None`
    /// outside the box or for a type without a map.
    #[inline]
    pub fn sample(&self, t: XsType, x: DVec3) -> Option<(f64, DVec3)> {
        let s = self.slot[t.index()];
        let quads = self.quads.get(usize::from(s))?;
        let inv = 1.0 / self.lattice.spacing;
        let (e, g) = self
            .lattice
            .interpolate_quads(quads, (x - self.lattice.origin) * inv)?;
        Some((e, g * inv))
    }
}

/// Maps read as a [`Field`], scoring exactly what they do not cover.
#[derive(Debug, Clone, Copy)]
pub struct MapField<'a> {
    maps: &'a Maps,
    exact: Exact<'a>,
}

impl<'a> MapField<'a> {
    /// The field of `maps`, falling back to `exact` (which must score the
    /// same receptor with the same function).
    pub fn new(maps: &'a Maps, exact: Exact<'a>) -> Self {
        Self { maps, exact }
    }
}

impl Field for MapField<'_> {
    fn table(&self) -> &'static Table {
        self.exact.table()
    }

    #[inline]
    fn atom_energy(&self, t: XsType, x: DVec3) -> f64 {
        match self.maps.sample(t, x) {
            Some((e, _)) => e,
            None => self.exact.atom_energy(t, x),
        }
    }

    #[inline]
    fn atom_energy_gradient(&self, t: XsType, x: DVec3) -> (f64, DVec3) {
        match self.maps.sample(t, x) {
            Some(v) => v,
            None => self.exact.atom_energy_gradient(t, x),
        }
    }

    /// Takes the atoms into lattice units with one transform (the spacing
    /// folded into the rotation and translation), four at a time
    /// ([`Lattice::interpolate4`]), and sums the gradient in those units,
    /// scaling once at the end: the moment about the pose's centre is
    /// `Σ (gᵢ − g_T) × ∇ᵢ`, in which the spacing cancels. Atoms the maps
    /// miss are scored exactly.
    fn rigid_energy_gradient(&self, drug: &RigidDrug, pose: &Pose) -> (f64, DVec3, DVec3) {
        let zero = f32x4::ZERO;
        let (mut sum, mut moment) = (DVec3::ZERO, DVec3::ZERO);
        let (e, gt, inv, (s4, t4)) = self.rigid_lanes(
            drug,
            pose,
            ([zero; 3], [zero; 3]),
            |(mut s4, mut t4), _, g, d| {
                for a in 0..3 {
                    s4[a] += d[a];
                }
                t4[0] += g[1] * d[2] - g[2] * d[1];
                t4[1] += g[2] * d[0] - g[0] * d[2];
                t4[2] += g[0] * d[1] - g[1] * d[0];
                (s4, t4)
            },
            |_, gd, d| {
                sum += d;
                moment += gd.cross(d);
            },
        );
        let total = |v: f32x4| f64::from(v.reduce_add());
        sum += DVec3::new(total(s4[0]), total(s4[1]), total(s4[2]));
        moment += DVec3::new(total(t4[0]), total(t4[1]), total(t4[2]));
        (e, sum * inv, moment - gt.cross(sum))
    }

    /// As [`Self::rigid_energy_gradient`], each lane's gradient and moment
    /// about the pose's centre (in lattice units, in which the spacing
    /// cancels) added into its fragment's sums; the gradients are scaled
    /// at the end.
    fn rigid_fragment_sums(
        &self,
        drug: &RigidDrug,
        pose: &Pose,
        sums: &mut Vec<(DVec3, DVec3)>,
    ) -> f64 {
        sums.clear();
        sums.resize(drug.fragment_count(), (DVec3::ZERO, DVec3::ZERO));
        let frags = drug.fragments();
        let l = &self.maps.lattice;
        let gt = (pose.translation - l.origin) * (1.0 / l.spacing);
        let gt4 = gt.to_array().map(|v| f32x4::splat(v as f32));
        // Atoms the maps miss are few (none inside the box): kept aside.
        let mut missed = Vec::new();
        let (e, _, inv, sums) = self.rigid_lanes(
            drug,
            pose,
            sums,
            |sums, c, g, d| {
                let r = [g[0] - gt4[0], g[1] - gt4[1], g[2] - gt4[2]];
                let t = [
                    r[1] * d[2] - r[2] * d[1],
                    r[2] * d[0] - r[0] * d[2],
                    r[0] * d[1] - r[1] * d[0],
                ];
                let (d, t) = (d.map(f32x4::to_array), t.map(f32x4::to_array));
                for (k, &f) in frags.iter().skip(4 * c).take(4).enumerate() {
                    let w = &mut sums[f as usize];
                    w.0 += DVec3::new(d[0][k].into(), d[1][k].into(), d[2][k].into());
                    w.1 += DVec3::new(t[0][k].into(), t[1][k].into(), t[2][k].into());
                }
                sums
            },
            |i, gd, d| missed.push((i, gd, d)),
        );
        for (i, gd, d) in missed {
            let w = &mut sums[frags[i] as usize];
            w.0 += d;
            w.1 += (gd - gt).cross(d);
        }
        for w in sums.iter_mut() {
            w.0 *= inv;
        }
        e
    }
}

impl MapField<'_> {
    /// The walk of [`Field::rigid_energy_gradient`]: each group of four
    /// atoms moved into lattice units and read from the maps, folded into
    /// `state` by `lanes(state, group, positions, gradients)` (gradients
    /// per lattice unit, the curl applied; zero in lanes the maps miss),
    /// and each atom the maps miss scored exactly and handed to
    /// `missed(atom, position, gradient)` in the same units. Returns the
    /// energy, the pose's translation in lattice units, the inverse spacing
    /// and the state. (The state goes by value, so that sums kept in it
    /// stay in registers.)
    #[inline(always)]
    fn rigid_lanes<S>(
        &self,
        drug: &RigidDrug,
        pose: &Pose,
        mut state: S,
        lanes_of: impl Fn(S, usize, &[f32x4; 3], &[f32x4; 3]) -> S,
        mut missed_atom: impl FnMut(usize, DVec3, DVec3),
    ) -> (f64, DVec3, f64, S) {
        let l = &self.maps.lattice;
        let inv = 1.0 / l.spacing;
        let m = DMat3::from_quat(pose.rotation) * inv;
        let gt = (pose.translation - l.origin) * inv;
        let m4 = m.to_cols_array().map(|v| f32x4::splat(v as f32));
        let gt4 = gt.to_array().map(|v| f32x4::splat(v as f32));
        let empty: &Quads = &[];
        let zero = f32x4::ZERO;
        let mut e4 = zero;
        let mut e = 0.0;
        let (local, xs) = (drug.local(), drug.xs());
        for (c, y) in drug.lanes().iter().enumerate() {
            let ts = xs.get(4 * c..).unwrap_or(&[]);
            let n = ts.len().min(4);
            let mut maps = [empty; 4];
            for (map, &t) in maps.iter_mut().zip(ts) {
                *map = self.map_of(t);
            }
            // Columns: m4[0..3] is the first.
            let g = [0, 1, 2].map(|a| m4[a] * y[0] + m4[3 + a] * y[1] + m4[6 + a] * y[2] + gt4[a]);
            let lanes = l.interpolate4(maps, g);
            // The curl, per lane: E·1000/(1000 + E) above zero.
            let v = lanes.energy;
            let up = v.simd_gt(zero);
            let d = if up.any() {
                let t = f32x4::splat(1000.0) / (f32x4::splat(1000.0) + up.select(v, zero));
                e4 += up.select(v * t, v);
                let slope = up.select(t * t, f32x4::ONE);
                lanes.gradient.map(|c| c * slope)
            } else {
                e4 += v;
                lanes.gradient
            };
            state = lanes_of(state, c, &g, &d);
            // Lanes the maps miss (their values are zero): exactly.
            let mut missed = lanes.missed & ((1 << n) - 1);
            while missed != 0 {
                let k = missed.trailing_zeros() as usize;
                missed &= missed - 1;
                let gd = m * local[4 * c + k] + gt;
                let (v, d) = self
                    .exact
                    .atom_energy_gradient(ts[k], l.origin + gd * l.spacing);
                let (v, s) = curl_with_slope(v);
                e += v;
                missed_atom(4 * c + k, gd, d * (s * l.spacing));
            }
        }
        (e + f64::from(e4.reduce_add()), gt, inv, state)
    }

    /// The map of type `t` (empty: none).
    #[inline]
    fn map_of(&self, t: XsType) -> &Quads {
        let s = self.maps.slot[t.index()];
        self.maps
            .quads
            .get(usize::from(s))
            .map_or(&[], Vec::as_slice)
    }
}

/// Maps being built on a background thread.
#[derive(Debug)]
pub struct MapsJob {
    handle: Option<JoinHandle<Result<Maps, MapsError>>>,
    done: Option<Result<Maps, MapsError>>,
}

impl MapsJob {
    /// Starts building maps of `receptor` on a background thread (which uses
    /// the machine's threads for the build itself).
    pub fn spawn(
        receptor: Arc<Receptor>,
        scoring: Scoring,
        types: Vec<XsType>,
        bx: MapBox,
    ) -> Self {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let handle = std::thread::Builder::new()
            .name("bump-maps".into())
            .spawn(move || Maps::build(&receptor, scoring, &types, &bx, threads))
            .ok();
        let done = if handle.is_none() {
            Some(Err(MapsError::Box {
                spacing: f64::NAN,
                size: [f64::NAN; 3],
            }))
        } else {
            None
        };
        Self { handle, done }
    }

    /// True once the build has finished (successfully or not).
    pub fn is_finished(&self) -> bool {
        self.done.is_some() || self.handle.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Waits for the maps. A build thread that panicked reports a box error.
    ///
    /// # Errors
    /// The build's error.
    pub fn wait(mut self) -> Result<Maps, MapsError> {
        if let Some(done) = self.done.take() {
            return done;
        }
        match self.handle.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            _ => Err(MapsError::Box {
                spacing: f64::NAN,
                size: [f64::NAN; 3],
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::rng::Rng;
    use crate::score::{Gradient, Ligand, Workspace};

    fn receptor(seed: u64, n: usize) -> Receptor {
        let mut rng = Rng(seed);
        let pos: Vec<DVec3> = (0..n).map(|_| rng.in_box(DVec3::splat(12.0))).collect();
        let xs: Vec<Option<XsType>> = (0..n)
            .map(|i| Some([XsType::C_H, XsType::O_A, XsType::N_D, XsType::C_P][i % 4]))
            .collect();
        Receptor::new(&pos, &xs, &[])
    }

    #[test]
    fn lattice_points_hold_the_exact_sum() {
        let r = receptor(3, 400);
        let bx = MapBox::cube(DVec3::new(1.0, -2.0, 0.5), 6.0, 0.5);
        let types = [XsType::C_H, XsType::N_A];
        for threads in [1, 3] {
            let maps = Maps::build(&r, Scoring::Vina, &types, &bx, threads).unwrap();
            let l = maps.lattice;
            assert_eq!(l.points, [13, 13, 13]);
            let exact = Exact::new(&r, Scoring::Vina);
            for (i, j, k) in [(0, 0, 0), (5, 7, 12), (12, 12, 12), (3, 0, 9)] {
                let x = l.origin + DVec3::new(i as f64, j as f64, k as f64) * l.spacing;
                for &t in &types {
                    let (e, _) = maps.sample(t, x).unwrap();
                    let want = exact.atom_energy(t, x);
                    assert!(
                        (e - want).abs() < 1e-4 * (1.0 + want.abs()),
                        "{e} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn interpolation_gradient_matches_finite_differences() {
        let r = receptor(5, 300);
        let bx = MapBox::cube(DVec3::ZERO, 8.0, 0.375);
        let maps = Maps::build(&r, Scoring::Vina, &[XsType::O_A], &bx, 1).unwrap();
        let mut rng = Rng(11);
        let h = 1e-6;
        for _ in 0..50 {
            let x = rng.in_box(DVec3::splat(3.5));
            let (_, g) = maps.sample(XsType::O_A, x).unwrap();
            for a in 0..3 {
                let d = DVec3::AXES[a] * h;
                let num = (maps.sample(XsType::O_A, x + d).unwrap().0
                    - maps.sample(XsType::O_A, x - d).unwrap().0)
                    / (2.0 * h);
                assert!(
                    (num - g[a]).abs() < 1e-4 * (1.0 + g[a].abs()),
                    "{num} vs {}",
                    g[a]
                );
            }
        }
        // Outside the box, or a type without a map: no sample.
        assert!(maps.sample(XsType::O_A, DVec3::splat(4.2)).is_none());
        assert!(maps.sample(XsType::C_H, DVec3::ZERO).is_none());
        assert!(maps.sample(XsType::O_A, DVec3::NAN).is_none());
    }

    /// A rigid drug of `n` atoms of `types` in turn, spread over a few Å.
    /// A drug of `n` atoms in a box, split into fragments of up to three
    /// atoms, each joined to an earlier one by a rotatable bond.
    fn rigid_drug(rng: &mut Rng, n: usize, types: &[XsType]) -> Ligand {
        let local: Vec<DVec3> = (0..n).map(|_| rng.in_box(DVec3::splat(3.0))).collect();
        let xs: Vec<Option<XsType>> = (0..n).map(|i| Some(types[i % types.len()])).collect();
        let fragments: Vec<crate::score::Fragment> = (0..n.div_ceil(3))
            .map(|f| {
                let parent = (f > 0).then(|| (rng.next_u64() % f as u64) as u32);
                crate::score::Fragment {
                    parent,
                    bond: parent.map(|p| [3 * p, 3 * f as u32]),
                    atoms: (3 * f as u32..(3 * f as u32 + 3).min(n as u32)).collect(),
                }
            })
            .collect();
        Ligand::from_parts(local, fragments, &xs, vec![0.0; n], &[], 0.0).unwrap()
    }

    #[test]
    fn four_lane_rigid_paths_agree_with_the_per_atom_path() {
        let r = receptor(7, 500);
        // The box covers part of where the drug goes: atoms outside it,
        // and atoms of a type without a map, are scored exactly.
        let bx = MapBox::cube(DVec3::new(1.0, 0.0, 0.0), 7.0, 0.375);
        let maps = Maps::build(&r, Scoring::Vina, &[XsType::C_H, XsType::O_A], &bx, 2).unwrap();
        let exact = Exact::new(&r, Scoring::Vina);
        let fast = MapField::new(&maps, exact);
        let slow = crate::score::PerAtom(&fast);
        let mut rng = Rng(17);
        let types = [XsType::C_H, XsType::O_A, XsType::N_D];
        let close = |a: f64, b: f64| (a - b).abs() <= 2e-4 * (1.0 + b.abs());
        let (mut ws, mut ws0) = (Workspace::default(), Workspace::default());
        let (mut g, mut g0) = (Gradient::default(), Gradient::default());
        for n in [1, 4, 5, 11] {
            let lig = rigid_drug(&mut rng, n, &types);
            let torsions: Vec<f64> = (0..lig.torsions()).map(|_| rng.range(-3.0, 3.0)).collect();
            let drug = RigidDrug::new(&fast, &lig, &torsions);
            for _ in 0..40 {
                let rotation = glam::DQuat::from_axis_angle(rng.unit(), rng.f64() * 3.0);
                let pose = Pose::new(rotation, rng.in_box(DVec3::splat(4.0)));
                let (e, f, m) = drug.energy_gradient(&fast, &pose);
                let (e0, f0, m0) = drug.energy_gradient(&slow, &pose);
                assert!(close(e, e0), "{n} atoms: energy {e} vs {e0}");
                for a in 0..3 {
                    assert!(close(f[a], f0[a]), "{n} atoms: force {f} vs {f0}");
                    assert!(close(m[a], m0[a]), "{n} atoms: moment {m} vs {m0}");
                }
                // The whole gradient: the rigid part is the same, and each
                // bond's torque agrees.
                let h = drug.energy_full_gradient(&fast, &pose, &mut ws, &mut g);
                let h0 = drug.energy_full_gradient(&slow, &pose, &mut ws0, &mut g0);
                assert!(close(h.inter, h0.inter) && close(h.inter, e0), "{n} atoms");
                assert_eq!(g.torsions.len(), lig.torsions());
                for a in 0..3 {
                    assert!(close(g.translation[a], f0[a]), "{n} atoms: {g:?} vs {f0}");
                    assert!(close(g.rotation[a], m0[a]), "{n} atoms: {g:?} vs {m0}");
                }
                for (t, t0) in g.torsions.iter().zip(&g0.torsions) {
                    assert!(close(*t, *t0), "{n} atoms: {g:?} vs {g0:?}");
                }
            }
        }
    }

    #[test]
    fn four_lanes_interpolate_as_one() {
        let r = receptor(9, 300);
        let bx = MapBox::cube(DVec3::ZERO, 6.0, 0.5);
        let maps = Maps::build(&r, Scoring::Vina, &[XsType::C_H], &bx, 1).unwrap();
        let l = maps.lattice;
        let q = maps.quads[0].as_slice();
        let mut rng = Rng(3);
        for _ in 0..200 {
            // Some lanes outside (or NaN), some without a map.
            let g: [DVec3; 4] = std::array::from_fn(|_| rng.in_box(DVec3::splat(16.0)));
            let g = [
                g[0],
                g[1],
                g[2],
                if rng.f64() < 0.1 { DVec3::NAN } else { g[3] },
            ];
            let map: [&Quads; 4] = std::array::from_fn(|_| if rng.f64() < 0.2 { &[] } else { q });
            let lanes = l.interpolate4(map, [0, 1, 2].map(|a| f32x4::from(g.map(|p| p[a] as f32))));
            for k in 0..4 {
                let gk = g[k].as_vec3().as_dvec3();
                let one = l.interpolate_quads(map[k], gk);
                let missed = lanes.missed & (1 << k) != 0;
                assert_eq!(missed, one.is_none(), "lane {k} at {gk}");
                let e = f64::from(lanes.energy.to_array()[k]);
                let d = lanes.gradient.map(|v| f64::from(v.to_array()[k]));
                let (e1, d1) = one.unwrap_or_default();
                assert!((e - e1).abs() <= 1e-4 * (1.0 + e1.abs()), "{e} vs {e1}");
                for a in 0..3 {
                    assert!((d[a] - d1[a]).abs() <= 1e-3 * (1.0 + d1[a].abs()));
                }
            }
        }
    }

    #[test]
    fn absurd_boxes_are_refused() {
        let r = receptor(1, 10);
        let big = MapBox::cube(DVec3::ZERO, 1e6, 0.375);
        assert!(matches!(
            Maps::build(&r, Scoring::Vina, &[XsType::C_H], &big, 1),
            Err(MapsError::TooLarge { .. })
        ));
        let bad = MapBox::cube(DVec3::ZERO, 10.0, 0.0);
        assert!(Maps::build(&r, Scoring::Vina, &[XsType::C_H], &bad, 1).is_err());
    }
}
