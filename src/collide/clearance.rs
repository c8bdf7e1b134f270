//! A clearance map: a lower bound on how far any point is from the receptor.
//!
//! A coarse grid of nodes over the receptor's box (plus a band) stores, per
//! node, a lower bound of `min_j (|p − q_j| − r_j)` — the distance from the
//! node to the nearest receptor atom surface — quantised down to a byte and
//! capped at the band. That function is 1-Lipschitz, so at any point `x` the
//! clearance is at least the nearest node's value minus the node's distance to
//! `x`. A drug atom whose clearance exceeds its own reach (`r_i − allowance`)
//! plus its sweep cannot touch any receptor atom, and its neighbour query is
//! skipped in O(1). In a typical step most drug atoms are such atoms; a query
//! then costs a few lookups instead of a few thousand distance tests (the idea
//! of the precomputed receptor grids in Pattabiraman et al. 1985, which the
//! thesis cites, used only as a conservative bound).

use glam::Vec3;

/// Width of the band the map resolves, in Å; clearances beyond it read as the band.
pub const BAND: f32 = 6.0;

/// Most nodes a map may have (one byte each).
const MAX_NODES: usize = 1 << 23;

/// The clearance map of one receptor.
#[derive(Debug, Clone)]
pub struct ClearanceMap {
    origin: Vec3,
    h: f32,
    inv_h: f32,
    dims: [i32; 3],
    /// Clearance per node, in units of `BAND / 255`, rounded down.
    data: Vec<u8>,
    /// Largest distance from a point to its nearest node: h·√3/2.
    slack: f32,
}

impl ClearanceMap {
    /// Builds the map for atoms at `positions` with `radii` (receptor frame).
    /// Returns `None` for an empty receptor.
    pub fn build(positions: &[Vec3], radii: &[f32]) -> Option<Self> {
        if positions.is_empty() {
            return None;
        }
        let r_max = radii.iter().copied().fold(0.0, f32::max);
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let pad = Vec3::splat(r_max + BAND);
        let (lo, hi) = (lo - pad, hi + pad);
        let extent = hi - lo;
        let volume = f64::from(extent.x) * f64::from(extent.y) * f64::from(extent.z);
        let mut h = 1.0f32.max((volume / MAX_NODES as f64).cbrt() as f32 * 1.01);
        let dims = loop {
            let d = [
                (extent.x / h).ceil() as i32 + 1,
                (extent.y / h).ceil() as i32 + 1,
                (extent.z / h).ceil() as i32 + 1,
            ];
            if d.iter().map(|&v| v as usize).product::<usize>() <= MAX_NODES {
                break d;
            }
            h *= 1.25;
        };
        let inv_h = 1.0 / h;
        let step = BAND / 255.0;
        let mut data = vec![255u8; (dims[0] * dims[1] * dims[2]) as usize];
        for (q, &r) in positions.iter().zip(radii) {
            let reach = r + BAND;
            let a = ((*q - lo - Vec3::splat(reach)) * inv_h)
                .floor()
                .max(Vec3::ZERO);
            let b = ((*q - lo + Vec3::splat(reach)) * inv_h).ceil();
            let (x0, y0, z0) = (a.x as i32, a.y as i32, a.z as i32);
            let x1 = (b.x as i32).min(dims[0] - 1);
            let y1 = (b.y as i32).min(dims[1] - 1);
            let z1 = (b.z as i32).min(dims[2] - 1);
            let inv_step = 1.0 / step;
            for z in z0..=z1 {
                let pz = lo.z + z as f32 * h - q.z;
                for y in y0..=y1 {
                    let py = lo.y + y as f32 * h - q.y;
                    let pyz = py * py + pz * pz;
                    let row = ((z * dims[1] + y) * dims[0]) as usize;
                    let cells = &mut data[row + x0 as usize..=row + x1 as usize];
                    let mut px = lo.x + x0 as f32 * h - q.x;
                    for cell in cells {
                        let d = (px * px + pyz).sqrt() - r;
                        // Truncation rounds positive values down (a lower bound;
                        // the hair subtracted covers f32 rounding); negatives clamp to 0.
                        let v = ((d - 1e-4) * inv_step).clamp(0.0, 255.0) as u8;
                        if v < *cell {
                            *cell = v;
                        }
                        px += h;
                    }
                }
            }
        }
        Some(Self {
            origin: lo,
            h,
            inv_h,
            dims,
            data,
            slack: h * 3f32.sqrt() * 0.5,
        })
    }

    /// A lower bound on the distance from `x` to the nearest receptor atom
    /// surface: at most [`BAND`]; minus infinity near or inside an atom.
    #[inline]
    pub fn clearance(&self, x: Vec3) -> f32 {
        // Nearest node; truncation is floor for the non-negative values kept
        // (round/floor are library calls on baseline x86-64).
        let g = (x - self.origin) * self.inv_h + Vec3::splat(0.5);
        if g.x < 0.0
            || g.y < 0.0
            || g.z < 0.0
            || g.x >= self.dims[0] as f32
            || g.y >= self.dims[1] as f32
            || g.z >= self.dims[2] as f32
        {
            // Outside the padded box every atom surface is at least BAND away.
            return BAND;
        }
        let (ix, iy, iz) = (g.x as i32, g.y as i32, g.z as i32);
        let v = self.data[((iz * self.dims[1] + iy) * self.dims[0] + ix) as usize];
        if v == 0 {
            // At or inside an atom: the byte cannot say how deep, so no bound.
            return f32::NEG_INFINITY;
        }
        f32::from(v) * (BAND / 255.0) - self.slack - 1e-4
    }

    /// Node spacing in Å.
    pub fn spacing(&self) -> f32 {
        self.h
    }

    /// Memory used by the nodes, in bytes.
    pub fn bytes(&self) -> usize {
        self.data.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clearance_is_a_lower_bound_everywhere() {
        let mut seed = 12345u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 10_000) as f32 / 10_000.0
        };
        let pos: Vec<Vec3> = (0..300)
            .map(|_| Vec3::new(rnd(), rnd(), rnd()) * 25.0 - Vec3::splat(12.5))
            .collect();
        let radii: Vec<f32> = (0..300).map(|i| 1.5 + (i % 4) as f32 * 0.1).collect();
        let map = ClearanceMap::build(&pos, &radii).expect("map");
        let mut tight = 0;
        for _ in 0..20_000 {
            let x = Vec3::new(rnd(), rnd(), rnd()) * 50.0 - Vec3::splat(25.0);
            let exact = pos
                .iter()
                .zip(&radii)
                .map(|(q, r)| (x - *q).length() - r)
                .fold(f32::INFINITY, f32::min);
            let bound = map.clearance(x);
            assert!(bound <= exact, "bound {bound} above exact {exact} at {x}");
            if exact < BAND - 2.0 && exact - bound < 1.0 {
                tight += 1;
            }
        }
        assert!(tight > 1000, "the bound should be useful, {tight}");
    }
}
