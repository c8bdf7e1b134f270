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

use std::sync::Arc;
use std::thread::JoinHandle;

use glam::DVec3;

use super::exact::Exact;
use super::field::Field;
use super::function::{CUTOFF, CUTOFF2, Scoring};
use super::receptor::Receptor;
use super::table::{Row, STRIDE, Table, index};
use crate::chem::XsType;

/// Vina's default lattice spacing, Å.
pub const DEFAULT_SPACING: f64 = 0.375;

/// Largest number of lattice points a map may have (about 80 MB of f32 per
/// type at most): a box from a typo must not exhaust memory.
pub const MAX_POINTS: usize = 20_000_000;

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
        Ok(Self {
            origin: bx.centre - half,
            spacing: bx.spacing,
            points,
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
        let g = (x - self.origin) * inv;
        let [nx, ny, nz] = self.points;
        let top = DVec3::new((nx - 1) as f64, (ny - 1) as f64, (nz - 1) as f64);
        // Comparisons with NaN are false: a NaN position is "outside".
        if !(g.x >= 0.0 && g.y >= 0.0 && g.z >= 0.0 && g.x <= top.x && g.y <= top.y && g.z <= top.z)
        {
            return None;
        }
        // In range (tested above), so the cheap i32 conversions are exact.
        let i = (g.x as i32 as usize).min(nx - 2);
        let j = (g.y as i32 as usize).min(ny - 2);
        let k = (g.z as i32 as usize).min(nz - 2);
        let (fx, fy, fz) = (g.x - i as f64, g.y - j as f64, g.z - k as f64);
        let base = (k * ny + j) * nx + i;
        let (sy, sz) = (nx, nx * ny);
        // One bounds check for the eight corners.
        let cell = &values[base..base + sz + sy + 2];
        let v = |o: usize| f64::from(cell[o]);
        let (c000, c100, c010, c110) = (v(0), v(1), v(sy), v(sy + 1));
        let (c001, c101, c011, c111) = (v(sz), v(sz + 1), v(sz + sy), v(sz + sy + 1));
        // Along x, then y, then z.
        let c00 = c000 + fx * (c100 - c000);
        let c10 = c010 + fx * (c110 - c010);
        let c01 = c001 + fx * (c101 - c001);
        let c11 = c011 + fx * (c111 - c011);
        let c0 = c00 + fy * (c10 - c00);
        let c1 = c01 + fy * (c11 - c01);
        let e = c0 + fz * (c1 - c0);
        let dx0 = (c100 - c000) + fy * ((c110 - c010) - (c100 - c000));
        let dx1 = (c101 - c001) + fy * ((c111 - c011) - (c101 - c001));
        let dx = dx0 + fz * (dx1 - dx0);
        let dy = (c10 - c00) + fz * ((c11 - c01) - (c10 - c00));
        let dz = c1 - c0;
        Some((e, DVec3::new(dx, dy, dz) * inv))
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
    /// One map per slot, each `lattice.len()` values, x fastest.
    values: Vec<Vec<f32>>,
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
        let values: Vec<Vec<f32>> = (0..kinds.len())
            .map(|s| inter.iter().skip(s).step_by(w).copied().collect())
            .collect();
        Ok(Self {
            scoring,
            lattice,
            types: kinds,
            slot,
            values,
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
        let values = self.values.get(usize::from(s))?;
        self.lattice.interpolate(values, x)
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
