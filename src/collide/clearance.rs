//! Clearance map: how far any point is, at least, from the receptor's atom
//! surfaces, so a query can skip a drug atom with nothing near it at the
//! cost of one lookup instead of a grid search.
//!
//! The clearance of a point `x` is `f(x) = min_j (|x − q_j| − r_j)` over the
//! receptor's atoms (centre `q_j`, radius `r_j`). The map stores `f` at the
//! vertices of a uniform lattice, rounded down to 1/32 Å and capped at
//! [`CAP`] Å. `f` changes by at most `|x − v|` between `x` and a vertex `v`
//! (it is 1-Lipschitz), so every corner `v` of the lattice cell around `x`
//! gives `f(x) ≥ f(v) − |x − v|`; the best of the eight is the bound
//! [`Clearance::clear`] tests. Beyond the lattice, which covers the atoms'
//! box grown by `CAP` plus the largest radius and one more spacing, `f` is at
//! least `CAP`.
//!
//! Most drug atoms in a pocket have no receptor atom within their reach
//! (on trimethoprim/DHFR move-to-touch, 80 % of them), and the eight-corner
//! bound on a 0.5 Å lattice proves it for most of those; the rest go to the
//! collider's search as before, so the answers do not change.
//!
//! The lattice spacing is 0.5 Å unless that would take more than
//! [`MAX_VERTICES`] vertices (one byte each); large receptors get a coarser
//! lattice, which proves less but stays correct.

use glam::{Vec3, Vec4};
use wide::{f32x4, i32x4};

/// Largest clearance stored, in Å: a drug atom's reach plus its sweep in
/// one interval is below it in ordinary queries; larger thresholds are
/// never proved clear.
pub const CAP: f32 = 3.0;

/// Steps of the stored values per Å (values are `floor(f · SCALE)`).
const SCALE: f32 = 32.0;

/// Finest lattice spacing, Å.
const FINEST: f32 = 0.5;

/// Most lattice vertices (bytes) a map may use.
pub const MAX_VERTICES: usize = 1 << 24;

/// Room, in Å, for the f32 rounding of a query point and of the distances
/// to the corners (receptor-frame coordinates, a few hundred Å at most).
const ROUNDING: f32 = 1e-3;

/// A lattice of clearance values over a receptor (see the module docs).
#[derive(Debug, Clone)]
pub struct Clearance {
    /// Position of vertex (0, 0, 0) (lanes x, y, z, 0).
    origin: f32x4,
    /// The reciprocal of the spacing, in every lane.
    inv_spacing: f32x4,
    /// Lattice coordinates a point's cell must start below: the number of
    /// vertices less one along x, y, z (and 1 in the unused lane).
    last: f32x4,
    /// Lattice spacing, Å.
    spacing: f32,
    /// Vertices along x, y and z (each at least 2).
    dims: [usize; 3],
    /// `floor(SCALE · min(f(v), CAP))` per vertex, x fastest; 0 also
    /// stands for any negative clearance (a vertex inside an atom).
    values: Vec<u8>,
}

impl Clearance {
    /// Builds the map for atoms given as centre and radius (receptor frame).
    /// `None` for no atoms.
    pub fn build(atoms: &[Vec4]) -> Option<Self> {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut max_radius = 0.0f32;
        for a in atoms {
            lo = lo.min(a.truncate());
            hi = hi.max(a.truncate());
            max_radius = max_radius.max(a.w);
        }
        if atoms.is_empty() || !(lo.is_finite() && hi.is_finite() && max_radius.is_finite()) {
            return None;
        }
        let mut spacing = FINEST;
        let margin = CAP + max_radius;
        let dims = loop {
            let span = (hi - lo + Vec3::splat(2.0 * (margin + spacing))) / spacing;
            // Saturating, so absurd coordinates only make the lattice coarser.
            let dims = [span.x, span.y, span.z].map(|s| (s.ceil() as usize).saturating_add(1));
            let total = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
            if total.is_some_and(|n| n <= MAX_VERTICES) {
                break dims;
            }
            spacing *= 1.25;
        };
        let origin = lo - Vec3::splat(margin + spacing);
        let inv_spacing = 1.0 / spacing;
        let [nx, ny, nz] = dims;
        // Working values in f32, exact minima over the atoms within reach.
        let mut f = vec![CAP; nx * ny * nz];
        for a in atoms {
            let (q, r) = (a.truncate(), a.w);
            let reach = r + CAP;
            // Lattice coordinates are positive (the lattice has a margin):
            // truncation is the floor, and one more covers the ceiling.
            let first = (q - Vec3::splat(reach) - origin) * inv_spacing;
            let last = (q + Vec3::splat(reach) - origin) * inv_spacing + Vec3::ONE;
            let clip = |v: f32, n: usize| (v.max(0.0) as usize).min(n - 1);
            let (y0, z0) = (clip(first.y, ny), clip(first.z, nz));
            let (y1, z1) = (clip(last.y, ny), clip(last.z, nz));
            for iz in z0..=z1 {
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
                    let row = (iz * ny + iy) * nx;
                    let dx0 = origin.x + x0 as f32 * spacing - q.x;
                    // Branch-free, so the compiler can use SIMD lanes; the
                    // f32 square root's error is far inside ROUNDING.
                    for (k, value) in (0i32..).zip(&mut f[row + x0..=row + x1]) {
                        let dx = dx0 + k as f32 * spacing;
                        *value = value.min((dx * dx + dyz).sqrt() - r);
                    }
                }
            }
        }
        // Rounded down, and a little more for the f32 rounding of the
        // distances above, so each stored value is at most `f(v)`.
        let values = f
            .iter()
            // Clamped first, so truncation is the floor.
            .map(|&v| ((v - ROUNDING) * SCALE).clamp(0.0, 255.0) as u8)
            .collect();
        Some(Self {
            origin: f32x4::from([origin.x, origin.y, origin.z, 0.0]),
            inv_spacing: f32x4::splat(inv_spacing),
            last: f32x4::from([(nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32, 1.0]),
            spacing,
            dims,
            values,
        })
    }

    /// True when every receptor atom's surface is farther than `d` from `x`
    /// (`|x − q_j| − r_j > d` for all `j`), as far as the map can prove it;
    /// false when it cannot (or for `d ≤ 0`, `d ≥ CAP`, or a NaN).
    #[inline(always)]
    pub fn clear(&self, x: Vec3, d: f32) -> bool {
        // A corner stored as 0 may be inside an atom: with d > 0 it can
        // never prove anything, as it should not.
        if !(d > 0.0 && d < CAP - ROUNDING) {
            return false;
        }
        let u = (f32x4::from([x.x, x.y, x.z, 0.0]) - self.origin) * self.inv_spacing;
        // Outside the lattice (or NaN): the atoms are at least CAP away.
        let inside = u.simd_ge(f32x4::ZERO) & u.simd_lt(self.last);
        if inside.to_bitmask() != 0b1111 {
            return x.is_finite();
        }
        // In range and not negative: truncation is the floor.
        let cell = u.fast_trunc_int();
        let [fx, fy, fz, _] = (u - cell.round_float()).to_array();
        let [ix, iy, iz, _] = cell.to_array();
        let [nx, ny, _] = self.dims;
        let (row, slab) = (nx, nx * ny);
        let base = (iz as usize * ny + iy as usize) * nx + ix as usize;
        let need = d + ROUNDING;
        // The nearest corner first: one byte, and it alone proves most
        // points away from the receptor (those the eight corners prove
        // include all it proves, so the answer is the same).
        let (ox, oy, oz) = (fx >= 0.5, fy >= 0.5, fz >= 0.5);
        let nearest = base + usize::from(ox) + usize::from(oy) * nx + usize::from(oz) * nx * ny;
        if let Some(&v) = self.values.get(nearest) {
            let room = f32::from(v) * (1.0 / SCALE) - need;
            let (ex, ey, ez) = (
                fx - f32::from(u8::from(ox)),
                fy - f32::from(u8::from(oy)),
                fz - f32::from(u8::from(oz)),
            );
            if room > 0.0
                && room * room > (ex * ex + ey * ey + ez * ez) * (self.spacing * self.spacing)
            {
                return true;
            }
        }
        // The corners' values, two x-neighbours at a time.
        let pair = |k: usize| match self.values.get(k..k + 2) {
            Some(&[a, b]) => [i32::from(a), i32::from(b)],
            _ => [0, 0],
        };
        let (n0, n1) = (pair(base), pair(base + row));
        let (f0, f1) = (pair(base + slab), pair(base + slab + row));
        let near = i32x4::from([n0[0], n0[1], n1[0], n1[1]]).round_float();
        let far = i32x4::from([f0[0], f0[1], f1[0], f1[1]]).round_float();
        // Squared distances to the corners in lattice units: x alternates,
        // then y; the near face (z of the cell), then the far one.
        let dx = f32x4::splat(fx) - f32x4::from([0.0, 1.0, 0.0, 1.0]);
        let dy = f32x4::splat(fy) - f32x4::from([0.0, 0.0, 1.0, 1.0]);
        let dxy = dx * dx + dy * dy;
        let fz1 = fz - 1.0;
        let d2_near = dxy + f32x4::splat(fz * fz);
        let d2_far = dxy + f32x4::splat(fz1 * fz1);
        // A corner proves it when value − need > spacing · distance: both
        // sides squared, the left side positive, so no square roots.
        let scale = f32x4::splat(1.0 / SCALE);
        let step2 = f32x4::splat(self.spacing * self.spacing);
        let need = f32x4::splat(need);
        let proves = |value: f32x4, d2: f32x4| {
            let room = value * scale - need;
            room.simd_gt(f32x4::ZERO) & (room * room).simd_gt(d2 * step2)
        };
        (proves(near, d2_near) | proves(far, d2_far)).any()
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
mod tests {
    use super::*;
    use crate::rng::Rng;
    use glam::DVec3;

    fn exact(atoms: &[Vec4], x: Vec3) -> f64 {
        atoms
            .iter()
            .map(|a| (x.as_dvec3() - a.truncate().as_dvec3()).length() - f64::from(a.w))
            .fold(f64::INFINITY, f64::min)
    }

    /// Random atoms, random points and thresholds: whenever the map says
    /// clear, the exact clearance is larger; and it does say clear for most
    /// points well away from the atoms.
    #[test]
    fn clear_is_a_lower_bound_of_the_exact_clearance() {
        let mut rng = Rng(5);
        let atoms: Vec<Vec4> = (0..300)
            .map(|_| {
                let q = rng.in_box(DVec3::splat(15.0)).as_vec3();
                q.extend(rng.range(1.2, 2.0) as f32)
            })
            .collect();
        let map = Clearance::build(&atoms).expect("atoms");
        assert_eq!(map.spacing(), FINEST);
        let (mut said, mut could) = (0, 0);
        for _ in 0..20_000 {
            let x = rng.in_box(DVec3::splat(25.0)).as_vec3();
            let d = rng.range(0.0, 3.2) as f32;
            let f = exact(&atoms, x);
            let clear = map.clear(x, d);
            if clear {
                said += 1;
                assert!(f > f64::from(d), "{x} d {d}: exact {f}");
            }
            // The nearest corner alone proves it past twice its distance
            // (at most half a cell diagonal) plus the rounding of the values.
            if f > f64::from(d) + f64::from(FINEST) * 3f64.sqrt() + 0.05 && d < 2.0 {
                could += 1;
                assert!(clear, "{x} d {d}: exact {f} not proved");
            }
        }
        assert!(said > 1000 && could > 1000, "said {said}, could {could}");
    }

    /// Points on and beyond the lattice's edge, NaN and infinite points, and
    /// thresholds out of range never panic and never claim too much.
    #[test]
    fn edges_and_absurd_input() {
        let atoms = [Vec4::new(0.0, 0.0, 0.0, 1.5), Vec4::new(3.0, 0.0, 0.0, 1.7)];
        let map = Clearance::build(&atoms).expect("atoms");
        for x in [
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(-1e30, 0.0, 0.0),
            Vec3::splat(f32::INFINITY),
        ] {
            assert_eq!(map.clear(x, 1.0), x.is_finite(), "{x}");
        }
        assert!(!map.clear(Vec3::splat(f32::NAN), 1.0));
        assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), 0.0));
        assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), CAP));
        assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), f32::NAN));
        // Inside an atom, and just outside its surface.
        assert!(!map.clear(Vec3::ZERO, 0.1));
        assert!(!map.clear(Vec3::new(-1.6, 0.0, 0.0), 0.2));
        // Along the x axis past the second atom, the clearance is x − 4.7.
        for k in 0..200 {
            let x = 4.7 + k as f32 * 0.05;
            for d in [0.3f32, 1.0, 2.5] {
                if map.clear(Vec3::new(x, 0.0, 0.0), d) {
                    assert!(f64::from(x) - 4.7 > f64::from(d), "x {x} d {d}");
                }
            }
        }
        assert!(Clearance::build(&[]).is_none());
        assert!(Clearance::build(&[Vec4::new(f32::NAN, 0.0, 0.0, 1.0)]).is_none());
    }

    /// A receptor too large for the finest lattice gets a coarser one
    /// within the vertex budget.
    #[test]
    fn large_boxes_get_a_coarser_lattice() {
        let atoms = [
            Vec4::new(-400.0, 0.0, 0.0, 1.5),
            Vec4::new(400.0, 300.0, 200.0, 1.5),
        ];
        let map = Clearance::build(&atoms).expect("atoms");
        assert!(map.spacing() > FINEST);
        assert!(map.bytes() <= MAX_VERTICES);
        assert!(map.clear(Vec3::new(0.0, 100.0, 100.0), 1.0));
        assert!(!map.clear(Vec3::new(-400.0, 0.0, 1.0), 0.2));
        // Absurdly far apart: a very coarse lattice, still a lower bound.
        let atoms = [
            Vec4::new(-1e30, 0.0, 0.0, 1.5),
            Vec4::new(1e30, 1e6, -1e6, 1.5),
        ];
        let map = Clearance::build(&atoms).expect("atoms");
        assert!(map.bytes() <= MAX_VERTICES);
        assert!(!map.clear(Vec3::new(1e30, 1e6, -1e6), 0.2));
    }
}
