//! The receptor's shape at the scale of its body: its Gaussian density
//! smoothed over [`BODY_SIGMA`] Å, on a grid, for `soft`'s glide round the
//! receptor.
//!
//! At a point `x` the field holds `W = Σ w` and `G = Σ (x − q) w` over the
//! receptor's atoms `q`, `w = exp(−|x − q|² / 2σ²)`. `G` points away from
//! the receptor's mass (the outward normal of its smoothed surface), and
//! `|G| / (σ W)` says how one-sided that mass is: about `√(2/π)` ≈ 0.8 at
//! a flat surface, more on a convex body's outside, less inside a pocket
//! with atoms all round ([`BodyShape::at`]).
//!
//! Built once per receptor: each atom's unit mass is spread over the eight
//! nodes round it (trilinear), then convolved with the separable kernels
//! `K(u) = exp(−u² / 2σ²)` and `u K(u)` along each axis (nine passes of
//! `2 ⌈3σ / h⌉ + 1` taps), so the cost grows with the grid, not with atoms
//! × nodes. Queries interpolate the eight nodes round the point. The grid
//! spans the atoms plus [`MARGIN`] Å; its spacing starts at [`SPACING`] Å
//! and grows so that it never holds more than [`MAX_NODES`] nodes,
//! whatever the coordinates.

use glam::DVec3;

/// Width of the smoothing Gaussian, Å: about a small protein domain's
/// radius, so grooves and bumps between residues are smoothed away and
/// what is left is the body the drug must go round.
pub const BODY_SIGMA: f64 = 10.0;

/// Grid spacing, Å, where the receptor's size allows it.
pub const SPACING: f64 = 2.5;

/// Space round the receptor's atoms that the grid covers, Å: two σ, where
/// an atom's weight has fallen to e⁻² (and a drug pressed against the
/// receptor has its centre well inside).
pub const MARGIN: f64 = 2.0 * BODY_SIGMA;

/// Most grid nodes (16 bytes each, a few times that while building).
pub const MAX_NODES: usize = 1 << 20;

/// The receptor's body-scale density and its moment, on a grid.
#[derive(Debug, Clone)]
pub struct BodyShape {
    origin: DVec3,
    spacing: f64,
    dims: [usize; 3],
    /// Per node: `G` (x, y, z) and `W`.
    nodes: Vec<[f32; 4]>,
}

/// What [`BodyShape::at`] says about a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPoint {
    /// Unit outward normal of the smoothed surface.
    pub normal: DVec3,
    /// `|G| / (σ W)`: how one-sided the receptor's mass is round the point
    /// (about 0.8 at a flat surface, less in a pocket).
    pub one_sidedness: f64,
}

impl BodyShape {
    /// The shape of the atoms at `points` (any frame; queries use the
    /// same). `None` without atoms or with a coordinate that is not finite.
    pub fn build(points: &[DVec3]) -> Option<Self> {
        let first = *points.first()?;
        let (mut lo, mut hi) = (first, first);
        for p in points {
            if !p.is_finite() {
                return None;
            }
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let origin = lo - DVec3::splat(MARGIN);
        let span = hi - lo + DVec3::splat(2.0 * MARGIN);
        // Spacing: SPACING, or as coarse as MAX_NODES needs (with one node
        // of slack per axis for the rounding up).
        let fit = (span.x * span.y * span.z / MAX_NODES as f64).cbrt();
        let mut spacing = SPACING.max(fit);
        let dims_at = |h: f64| span.to_array().map(|s| (s / h).ceil() as usize + 2);
        let mut dims = dims_at(spacing);
        while dims.iter().product::<usize>() > MAX_NODES {
            spacing *= 1.05;
            dims = dims_at(spacing);
        }
        let [nx, ny, nz] = dims;
        let index = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let mut mass = vec![0.0f32; nx * ny * nz];
        for p in points {
            let f = (*p - origin) / spacing;
            let i0 = f.floor();
            let t = f - i0;
            let [i, j, k] = i0.to_array().map(|v| v as usize);
            for (dk, wk) in [(0, 1.0 - t.z), (1, t.z)] {
                for (dj, wj) in [(0, 1.0 - t.y), (1, t.y)] {
                    for (di, wi) in [(0, 1.0 - t.x), (1, t.x)] {
                        mass[index(i + di, j + dj, k + dk)] += (wi * wj * wk) as f32;
                    }
                }
            }
        }
        let reach = (3.0 * BODY_SIGMA / spacing).ceil() as usize;
        let even: Vec<f32> = (0..=2 * reach)
            .map(|t| {
                let u = (t as f64 - reach as f64) * spacing;
                (-u * u / (2.0 * BODY_SIGMA * BODY_SIGMA)).exp() as f32
            })
            .collect();
        let odd: Vec<f32> = even
            .iter()
            .enumerate()
            .map(|(t, k)| k * ((t as f64 - reach as f64) * spacing) as f32)
            .collect();
        let conv = |src: &[f32], kernel: &[f32], axis: usize| convolve(src, dims, axis, kernel);
        let (kx, gx_) = (conv(&mass, &even, 0), conv(&mass, &odd, 0));
        drop(mass);
        let (kk, k_gy) = (conv(&kx, &even, 1), conv(&kx, &odd, 1));
        drop(kx);
        let gx_k = conv(&gx_, &even, 1);
        drop(gx_);
        let w = conv(&kk, &even, 2);
        let gz = conv(&kk, &odd, 2);
        drop(kk);
        let gy = conv(&k_gy, &even, 2);
        let gx = conv(&gx_k, &even, 2);
        let nodes = (0..w.len()).map(|n| [gx[n], gy[n], gz[n], w[n]]).collect();
        Some(Self {
            origin,
            spacing,
            dims,
            nodes,
        })
    }

    /// The grid spacing in use, Å.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The smoothed surface's outward normal at `p` and how one-sided the
    /// receptor's mass is there. `None` outside the grid or where the
    /// density or its gradient vanishes.
    pub fn at(&self, p: DVec3) -> Option<BodyPoint> {
        let f = (p - self.origin) / self.spacing;
        let [nx, ny, nz] = self.dims;
        let inside = f.x >= 0.0
            && f.y >= 0.0
            && f.z >= 0.0
            && f.x < (nx - 1) as f64
            && f.y < (ny - 1) as f64
            && f.z < (nz - 1) as f64;
        if !inside {
            return None;
        }
        let i0 = f.floor();
        let t = f - i0;
        let [i, j, k] = i0.to_array().map(|v| v as usize);
        let mut sum = [0.0f64; 4];
        for (dk, wk) in [(0, 1.0 - t.z), (1, t.z)] {
            for (dj, wj) in [(0, 1.0 - t.y), (1, t.y)] {
                for (di, wi) in [(0, 1.0 - t.x), (1, t.x)] {
                    let node = self.nodes[((k + dk) * ny + j + dj) * nx + i + di];
                    let w = wi * wj * wk;
                    for (s, v) in sum.iter_mut().zip(node) {
                        *s += w * f64::from(v);
                    }
                }
            }
        }
        let g = DVec3::new(sum[0], sum[1], sum[2]);
        let w = sum[3];
        if w <= f64::MIN_POSITIVE {
            return None;
        }
        Some(BodyPoint {
            normal: g.try_normalize()?,
            one_sidedness: g.length() / (BODY_SIGMA * w),
        })
    }
}

/// `src` (a grid of `dims`, x fastest) convolved with `kernel` (odd length,
/// centred) along `axis`: `out[i] = Σ_t src[i − (t − reach)] kernel[t]`, so
/// an odd kernel `u K(u)` weighs each source by the offset from it.
fn convolve(src: &[f32], dims: [usize; 3], axis: usize, kernel: &[f32]) -> Vec<f32> {
    let reach = kernel.len() / 2;
    let stride = [1, dims[0], dims[0] * dims[1]][axis];
    let n = dims[axis];
    let mut out = vec![0.0f32; src.len()];
    // Each line along the axis starts where its coordinate on the axis is 0.
    for start in (0..src.len()).filter(|s| (s / stride).is_multiple_of(n)) {
        for i in 0..n {
            let lo = i.saturating_sub(reach);
            let hi = (i + reach).min(n - 1);
            let mut acc = 0.0f32;
            for j in lo..=hi {
                // Offset of the output from the source, in nodes.
                acc += src[start + j * stride] * kernel[i + reach - j];
            }
            out[start + i * stride] = acc;
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The sums the grid approximates, directly over the atoms.
    fn direct(points: &[DVec3], x: DVec3) -> (DVec3, f64) {
        let s2 = 2.0 * BODY_SIGMA * BODY_SIGMA;
        points.iter().fold((DVec3::ZERO, 0.0), |(g, w), q| {
            let k = (-(x - *q).length_squared() / s2).exp();
            (g + (x - *q) * k, w + k)
        })
    }

    /// `n` points drawn uniformly in a ball of `radius` Å at the origin.
    pub(crate) fn blob(rng: &mut Rng, n: usize, radius: f64) -> Vec<DVec3> {
        (0..n)
            .map(|_| {
                loop {
                    let p = rng.in_box(DVec3::ONE);
                    if p.length() <= 1.0 {
                        break p * radius;
                    }
                }
            })
            .collect()
    }

    #[test]
    fn the_grid_matches_the_direct_sums() {
        let mut rng = Rng(7);
        let atoms = blob(&mut rng, 1500, 18.0);
        let shape = BodyShape::build(&atoms).expect("shape");
        for _ in 0..200 {
            let x = rng.in_box(DVec3::splat(30.0));
            let (g, w) = direct(&atoms, x);
            let got = shape.at(x).expect("inside the grid");
            let want = g.normalize();
            assert!(
                got.normal.dot(want) > 0.999 || g.length() < 1e-3 * w * BODY_SIGMA,
                "{x}: {} vs {want}",
                got.normal
            );
            // The kernels stop at 3σ, which the direct sums do not: far
            // out, where one-sidedness runs above 1, that costs a few %.
            let a = g.length() / (BODY_SIGMA * w);
            assert!(
                (got.one_sidedness - a).abs() < 0.01 + 0.03 * a,
                "{x}: {} vs {a}",
                got.one_sidedness
            );
        }
    }

    #[test]
    fn a_ball_is_one_sided_outside_and_not_at_its_centre() {
        let mut rng = Rng(3);
        let atoms = blob(&mut rng, 3000, 20.0);
        let shape = BodyShape::build(&atoms).expect("shape");
        let centre = shape.at(DVec3::new(0.5, -0.3, 0.2)).expect("inside");
        assert!(centre.one_sidedness < 0.1, "{centre:?}");
        let surface = shape.at(DVec3::new(0.0, 0.0, 22.0)).expect("inside");
        assert!(surface.normal.z > 0.99, "{surface:?}");
        assert!(surface.one_sidedness > 0.8, "{surface:?}");
        assert!(shape.at(DVec3::new(0.0, 0.0, 60.0)).is_none());
    }

    #[test]
    fn far_flung_coordinates_coarsen_the_grid_instead_of_growing_it() {
        let atoms = [
            DVec3::ZERO,
            DVec3::splat(9999.0),
            DVec3::new(-9999.0, 5.0, 9999.0),
        ];
        let shape = BodyShape::build(&atoms).expect("shape");
        assert!(shape.nodes.len() <= MAX_NODES);
        assert!(shape.spacing() > SPACING);
        assert!(BodyShape::build(&[]).is_none());
        assert!(BodyShape::build(&[DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0)]).is_none());
    }
}
