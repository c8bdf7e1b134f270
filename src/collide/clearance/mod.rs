//! Clearance map: how far any point is, at least, from the receptor's atom
//! surfaces, so a query can skip a drug atom with nothing near it at the
//! cost of one lookup instead of a grid search.
//!
//! The clearance of a point `x` is `f(x) = min_j (|x − q_j| − r_j)` over the
//! receptor's atoms (centre `q_j`, radius `r_j`). The map stores `f` at the
//! vertices of a uniform lattice, rounded down to 1/32 Å and capped at
//! [`CAP`] Å. `f` changes by at most `|x − v|` between `x` and a vertex `v`
//! (it is 1-Lipschitz), so any vertex `v` gives `f(x) ≥ f(v) − |x − v|`;
//! the queries take the vertex nearest `x`, four points at a time
//! ([`Clearance::clear_nearest4`]). Beyond the lattice, which covers the
//! atoms' box grown by `CAP` plus the largest radius and one more spacing,
//! `f` is at least `CAP`: a point more than half a spacing beyond it (its
//! offset from the nearest vertex, clamped into the lattice, then exceeds
//! any that a point inside can have) is proved clear of every threshold
//! the map answers; one nearer is measured from the nearest vertex on the
//! edge.
//!
//! Most drug atoms in a pocket have no receptor atom within their reach
//! (on trimethoprim/DHFR move-to-touch, 80 % of them), and the nearest
//! vertex of a fine lattice proves it for most of those; the rest go to the
//! collider's search as before, so the answers do not change. The queries
//! first ask it of whole groups of four atoms (their bounding ball grown by
//! the atoms' reach): on a drug approaching a receptor's surface most
//! groups are that far from it, and one test then stands for four atoms'.
//! Only the nearest vertex is asked: the best of the eight corners of the
//! point's lattice cell proves a little more, but costs more than the
//! searches it saves.
//!
//! The lattice spacing is 0.25 Å (`FINEST`) unless that would take more
//! than [`MAX_VERTICES`] vertices (one byte each); larger receptors get a
//! coarser lattice, which proves less but stays correct. The map is filled by
//! every core, slabs of planes at a time, on the collider's own thread, so
//! queries run without it (and answer the same) until it is there.

use glam::{Vec3, Vec4};
use wide::{f32x4, i32x4};

/// Largest clearance stored, in Å; larger thresholds are never proved
/// clear. A drug atom's own part of its reach and its sweep in one interval
/// are below 3 Å in ordinary queries, and a group of four atoms adds its
/// bounding ball's radius (1–2.5 Å), so 6 Å lets most groups be proved
/// clear at once.
///
/// # Performance
/// The build's cost grows with the cap (each atom lowers the vertices
/// within `r + CAP`): 6 Å takes 2 to 4 times as long as 3 Å.
pub const CAP: f32 = 6.0;

/// Steps of the stored values per Å (values are `floor(f · SCALE)`).
const SCALE: f32 = 32.0;

/// Finest lattice spacing, Å: a finer lattice proves more points clear
/// (its nearest vertex is nearer), for more memory and a longer build
/// (DHFR's map takes 11 MiB and 0.16 s). Receptors of more than a few
/// thousand atoms get a coarser one (below).
const FINEST: f32 = 0.25;

/// Most lattice vertices (bytes) a map may use: 64 MiB, which gives the
/// 272k-atom 1f2n capsid a 0.95 Å lattice and the 59k-atom 1aon 0.49 Å
/// (each built in about 1.6 s on two cores, on the collider's own thread).
pub const MAX_VERTICES: usize = 1 << 26;

/// Room, in Å, for the f32 rounding of a query point and of the distances
/// to the vertices (receptor-frame coordinates, within
/// [`MAX_LATTICE_COORDINATE`] wherever the map answers).
const ROUNDING: f32 = 1e-3;

/// Farthest a lattice vertex may lie from the receptor frame's origin (the
/// receptor's centre), per axis, in Å. [`ROUNDING`] covers the f32
/// rounding of coordinates up to this size (a unit in the last place is
/// 1.2·10⁻⁴ Å here, and the tests round a few times); a receptor whose
/// lattice would reach farther (no real one: the 272k-atom 1f2n capsid
/// reaches about 200 Å) gets no map, and its queries are only slower.
const MAX_LATTICE_COORDINATE: f32 = 1024.0;

/// True when a threshold `d` is one the map can prove: positive (a vertex
/// stored as 0 may be inside an atom, and proves nothing, as it should not)
/// and below the cap.
#[inline(always)]
fn usable(d: f32) -> bool {
    d > 0.0 && d < CAP - ROUNDING
}

/// A lattice of clearance values over a receptor (see the module docs).
#[derive(Debug, Clone)]
pub struct Clearance {
    /// Position of vertex (0, 0, 0).
    origin: Vec3,
    /// The reciprocal of the spacing.
    inv_spacing: f32,
    /// Lattice spacing, Å.
    spacing: f32,
    /// Vertices along x, y and z (each at least 2).
    dims: [usize; 3],
    /// `floor(SCALE · min(f(v), CAP))` per vertex, x fastest; 0 also
    /// stands for any negative clearance (a vertex inside an atom).
    values: Vec<u8>,
    /// The same lattice constants, each in every lane, for
    /// [`Clearance::clear_nearest4`], so a call does not splat them.
    lanes: Lanes,
}

/// A lattice's constants splatted across SIMD lanes.
#[derive(Debug, Clone, Copy)]
struct Lanes {
    /// Vertex (0, 0, 0): x, y and z.
    origin: [f32x4; 3],
    /// The reciprocal of the spacing.
    inv_spacing: f32x4,
    /// The number of vertices less one along x, y and z.
    last: [f32x4; 3],
    /// Vertices along y (a vertex index is `(z·ny + y)·nx + x`).
    ny: f32x4,
    /// Vertices along x.
    nx: f32x4,
    /// The spacing squared.
    step2: f32x4,
    /// Three quarters of it: a point whose squared distance from its
    /// nearest vertex is larger lies more than half a spacing beyond the
    /// lattice, where the clearance exceeds [`CAP`].
    beyond: f32x4,
    /// Whether every vertex index is below 2^24, where f32 holds integers
    /// exactly.
    exact_in_f32: bool,
}

/// Stored value of a clearance `f`: rounded down to 1/32 Å, less
/// [`ROUNDING`] for the f32 rounding of the distances, clamped to a byte
/// (so truncation is the floor).
#[inline(always)]
fn quantize(f: f32) -> u8 {
    ((f - ROUNDING) * SCALE).clamp(0.0, 255.0) as u8
}

/// Planes of a lattice with `nx · ny` vertices each that one slab of the
/// build takes: about 1 MiB of working values, so they stay in the
/// core's cache while every atom within reach lowers them.
fn slab_planes(nx: usize, ny: usize) -> usize {
    ((1 << 18) / (nx * ny).max(1)).max(1)
}

/// A lattice being filled: its first vertex, spacing and vertex counts.
#[derive(Debug, Clone, Copy)]
struct Raster {
    origin: Vec3,
    spacing: f32,
    dims: [usize; 3],
}

impl Raster {
    /// Lowers the values of the vertices in `slab` (the planes `z0 ..` of
    /// the lattice, x fastest) to each atom's clearance within its reach.
    fn fill(&self, atoms: &[Vec4], z0: usize, slab: &mut [u8]) {
        let Self {
            origin,
            spacing,
            dims: [nx, ny, nz],
        } = *self;
        let planes = slab.len() / (nx * ny);
        if planes == 0 {
            return;
        }
        let z_last = (z0 + planes - 1).min(nz - 1);
        let inv_spacing = 1.0 / spacing;
        // Working values in f32 (the slab's own), rounded once at the end.
        let mut f = vec![CAP; slab.len()];
        let steps = f32x4::from([0.0, 1.0, 2.0, 3.0]) * f32x4::splat(spacing);
        for a in atoms {
            let (q, r) = (a.truncate(), a.w);
            let reach = r + CAP;
            // Lattice coordinates are positive (the lattice has a margin):
            // truncation is the floor, and one more covers the ceiling.
            let first = (q - Vec3::splat(reach) - origin) * inv_spacing;
            let last = (q + Vec3::splat(reach) - origin) * inv_spacing + Vec3::ONE;
            let clip = |v: f32, n: usize| (v.max(0.0) as usize).min(n - 1);
            let (y0, y1) = (clip(first.y, ny), clip(last.y, ny));
            let (za, zb) = (clip(first.z, nz).max(z0), clip(last.z, nz).min(z_last));
            for iz in za..=zb {
                let dz = origin.z + iz as f32 * spacing - q.z;
                for iy in y0..=y1 {
                    let dy = origin.y + iy as f32 * spacing - q.y;
                    let dyz = dy * dy + dz * dz;
                    if dyz > reach * reach {
                        continue;
                    }
                    // Only the vertices of the row within reach: the chord.
                    let chord = (reach * reach - dyz).sqrt();
                    let x0 = clip((q.x - chord - origin.x) * inv_spacing, nx);
                    let x1 = clip((q.x + chord - origin.x) * inv_spacing + 1.0, nx);
                    let row = &mut f[((iz - z0) * ny + iy) * nx..][..nx];
                    // Four vertices at a time (the f32 square root's error
                    // is far inside ROUNDING), up to three past the chord
                    // where the row has room: their distances are exact
                    // too, only further than needed.
                    let (dyz4, r4) = (f32x4::splat(dyz), f32x4::splat(r));
                    let mut k = x0;
                    while k <= x1 && k + 4 <= nx {
                        let dx = f32x4::splat(origin.x + k as f32 * spacing - q.x) + steps;
                        let near = (dx * dx + dyz4).sqrt() - r4;
                        let mut four = [0.0; 4];
                        four.copy_from_slice(&row[k..k + 4]);
                        row[k..k + 4].copy_from_slice(&f32x4::from(four).fast_min(near).to_array());
                        k += 4;
                    }
                    for (x, value) in row.iter_mut().enumerate().take(x1 + 1).skip(k) {
                        let dx = origin.x + x as f32 * spacing - q.x;
                        *value = value.min((dx * dx + dyz).sqrt() - r);
                    }
                }
            }
        }
        for (v, f) in slab.iter_mut().zip(&f) {
            *v = quantize(*f);
        }
    }
}

impl Clearance {
    /// Builds the map for atoms given as centre and radius (receptor frame).
    /// `None` for no atoms.
    pub fn build(atoms: &[Vec4]) -> Option<Self> {
        // Atoms with a NaN anywhere (which no loaded file has) are left
        // out: they would lower no value, but would spoil the box below
        // (a SIMD minimum with NaN takes the other operand) and the order
        // by z that the slabs search.
        let mut by_z: Vec<Vec4> = atoms.iter().copied().filter(|a| a.is_finite()).collect();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut max_radius = 0.0f32;
        for a in &by_z {
            lo = lo.min(a.truncate());
            hi = hi.max(a.truncate());
            max_radius = max_radius.max(a.w);
        }
        if by_z.is_empty() || !(lo.is_finite() && hi.is_finite() && max_radius.is_finite()) {
            return None;
        }
        let mut spacing = FINEST;
        let margin = CAP + max_radius;
        let dims = loop {
            let span = (hi - lo + Vec3::splat(2.0 * (margin + spacing))) / spacing;
            // Saturating, so absurd coordinates only make the lattice
            // coarser (until the size check below refuses it).
            let dims = [span.x, span.y, span.z].map(|s| (s.ceil() as usize).saturating_add(1));
            let total = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
            // A row index `z · ny + y` stays exact in f32 (see
            // `clear_nearest4`).
            if total.is_some_and(|n| n <= MAX_VERTICES) && dims[1] * dims[2] <= 1 << 24 {
                break dims;
            }
            spacing *= 1.25;
        };
        let origin = lo - Vec3::splat(margin + spacing);
        let far = origin + Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32) * spacing;
        if origin.abs().max(far.abs()).max_element() > MAX_LATTICE_COORDINATE {
            return None;
        }
        let inv_spacing = 1.0 / spacing;
        let [nx, ny, nz] = dims;
        // The stored values, each the exact minimum over the atoms within
        // reach: the rounding down to steps of 1/32 Å is monotone, so the
        // least of the rounded values is the rounded least. Slabs of a few
        // planes along z, each with the atoms (sorted by z) that reach it,
        // are filled by every core, each taking the next slab left.
        // Every slab is filled below (or the build panics); 0 proves
        // nothing, should one not be.
        let mut values = vec![0u8; nx * ny * nz];
        by_z.sort_unstable_by(|a, b| a.z.total_cmp(&b.z));
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get().min(8));
        let planes = slab_planes(nx, ny);
        let lattice = Raster {
            origin,
            spacing,
            dims,
        };
        let reach = max_radius + CAP;
        let work = std::sync::Mutex::new(values.chunks_mut(planes * nx * ny).enumerate());
        let run = || {
            // A poisoned lock means a filling thread panicked, and so
            // will the scope (the map is then not used at all).
            while let Some((k, slab)) = work.lock().ok().and_then(|mut w| w.next()) {
                let z0 = k * planes;
                let below = origin.z + z0 as f32 * spacing - reach - spacing;
                let above = origin.z + (z0 + planes) as f32 * spacing + reach + spacing;
                let first = by_z.partition_point(|a| a.z < below);
                let last = by_z.partition_point(|a| a.z <= above);
                lattice.fill(&by_z[first..last.max(first)], z0, slab);
            }
        };
        std::thread::scope(|scope| {
            for _ in 1..threads {
                // A thread that cannot start leaves its slabs to the others.
                if std::thread::Builder::new()
                    .spawn_scoped(scope, run)
                    .is_err()
                {
                    break;
                }
            }
            run();
        });
        let last = [nx, ny, nz].map(|n| (n - 1) as f32);
        Some(Self {
            origin,
            inv_spacing,
            spacing,
            dims,
            values,
            lanes: Lanes {
                origin: [origin.x, origin.y, origin.z].map(f32x4::splat),
                inv_spacing: f32x4::splat(inv_spacing),
                last: last.map(f32x4::splat),
                ny: f32x4::splat(ny as f32),
                nx: f32x4::splat(nx as f32),
                step2: f32x4::splat(spacing * spacing),
                beyond: f32x4::splat(0.75 * (spacing * spacing)),
                exact_in_f32: nx * ny * nz <= 1 << 24,
            },
        })
    }

    /// True when every receptor atom's surface is farther than `d` from `x`
    /// (`|x − q_j| − r_j > d` for all `j`), as far as the lattice vertex
    /// nearest `x` can prove it, or `x` lies more than half a spacing
    /// beyond the lattice; false when neither holds (or for `d ≤ 0`,
    /// `d ≥ CAP`, or a NaN).
    ///
    /// The queries ask four points at a time
    /// ([`Clearance::clear_nearest4`]); this one-point form, written apart
    /// from it, is its reference in the tests below.
    pub fn clear(&self, x: Vec3, d: f32) -> bool {
        if !usable(d) {
            return false;
        }
        let (index, e2) = self.nearest(x);
        let value = f32::from(self.values.get(index).copied().unwrap_or(0));
        // value − need > distance, both sides squared (the left positive);
        // or the point lies beyond the lattice, farther from every atom
        // than the cap.
        let room = value * (1.0 / SCALE) - (d + ROUNDING);
        (room > 0.0 && room * room > e2) || e2 > self.lanes.beyond.as_array()[0]
    }

    /// The index of the lattice vertex nearest `x` (clamped into the
    /// lattice; NaN coordinates to vertex 0) and `x`'s squared distance
    /// from it (not a number for a NaN point, infinite for an infinite
    /// one), computed as [`Clearance::clear_nearest4`] computes them.
    fn nearest(&self, x: Vec3) -> (usize, f32) {
        let [nx, ny, _] = self.dims;
        let last = self.dims.map(|n| (n - 1) as f32);
        let mut index = [0usize; 3];
        let mut e2 = 0.0;
        for k in 0..3 {
            let u = (x[k] - self.origin[k]) * self.inv_spacing;
            // `max` takes 0 for NaN, as the lanes' `fast_max` does.
            let c = u.max(0.0).min(last[k]).round_ties_even();
            index[k] = c as usize;
            e2 += (u - c) * (u - c);
        }
        (
            (index[2] * ny + index[1]) * nx + index[0],
            e2 * (self.spacing * self.spacing),
        )
    }

    /// [`Clearance::clear`] for four points at once (`p`: their x, y and z
    /// in lanes): bit `k` is set when the lattice vertex nearest point `k`
    /// proves it clear by `d[k]`. Lanes with `d ≤ 0` (padding) are never
    /// set.
    #[inline(always)]
    pub fn clear_nearest4(&self, p: [f32x4; 3], d: f32x4) -> u32 {
        let Lanes {
            origin,
            inv_spacing,
            last,
            ny,
            nx,
            step2,
            beyond,
            exact_in_f32,
        } = self.lanes;
        // As `usable`, in lanes.
        let usable = d.simd_gt(f32x4::ZERO) & d.simd_lt(f32x4::splat(CAP - ROUNDING));
        let u = [
            (p[0] - origin[0]) * inv_spacing,
            (p[1] - origin[1]) * inv_spacing,
            (p[2] - origin[2]) * inv_spacing,
        ];
        // The vertex nearest the point, clamped into the lattice (NaN to
        // vertex 0: `fast_max` takes its second operand then), and the
        // point's offset from it in lattice units. The bound below holds
        // for any vertex, so a point beyond the lattice needs no test of
        // its own: it is measured from the nearest vertex on the edge.
        // Which of two vertices a point halfway between takes does not
        // matter.
        let near = |u: f32x4, last: f32x4| {
            let c = u.fast_max(f32x4::ZERO).fast_min(last).fast_round_int();
            let f = c.round_float();
            (c, f, u - f)
        };
        let (ix, cx, ex) = near(u[0], last[0]);
        let (_, cy, ey) = near(u[1], last[1]);
        let (_, cz, ez) = near(u[2], last[2]);
        // Its index, `row · nx + x` with `row = z · ny + y`. In f32 where
        // every index is below 2^24 (exact there: one conversion for all
        // four); else the row in f32 (exact: the build keeps `ny · nz`
        // within 2^24) and the rest in integers, since a map may have up
        // to 2^26 vertices and in f32 an index past 2^24 rounds to a
        // neighbouring vertex, whose value can prove a point that is not
        // clear. The indices are not negative (the vertex is clamped into
        // the lattice), so they widen without sign extension.
        let row = cz * ny + cy;
        let index: [usize; 4] = if exact_in_f32 {
            (row * nx + cx)
                .fast_trunc_int()
                .to_array()
                .map(|i| i as u32 as usize)
        } else {
            let (row, x) = (row.fast_trunc_int().to_array(), ix.to_array());
            let nx = self.dims[0];
            std::array::from_fn(|k| row[k] as u32 as usize * nx + x[k] as u32 as usize)
        };
        let value = |k: usize| i32::from(self.values.get(index[k]).copied().unwrap_or(0));
        let v = i32x4::from([value(0), value(1), value(2), value(3)]).round_float();
        let room = v * f32x4::splat(1.0 / SCALE) - (d + f32x4::splat(ROUNDING));
        let e2 = (ex * ex + ey * ey + ez * ez) * step2;
        // value − need > spacing · distance, both sides squared (the left
        // positive), so no square roots.
        let proved =
            usable & ((room.simd_gt(f32x4::ZERO) & (room * room).simd_gt(e2)) | e2.simd_gt(beyond));
        proved.to_bitmask() & 0b1111
    }

    /// Bytes the map takes.
    pub fn bytes(&self) -> usize {
        self.values.len()
    }

    /// Lattice spacing, Å.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }
}

#[cfg(test)]
mod tests;
