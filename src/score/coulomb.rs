//! The thesis's electrostatics beside Vina's score (never part of it):
//! Coulomb's law between partial charges with AutoDock 4's
//! distance-dependent dielectric (Mehler and Solmajer 1991).
//!
//! `E = Σ 332.06363 · q_i q_j / (r · ε(r))` over receptor–drug pairs closer
//! than 20.48 Å (AutoDock 4's cutoff for electrostatics), with
//! `ε(r) = A + B / (1 + k·exp(−λ B r))`, `A = −8.5525`, `B = 78.4 − A`,
//! `λ = 0.003627`, `k = 7.7839` (ε(0) = 1.35, ε(∞) = 78.4), and `r` taken as at
//! least 0.5 Å (AutoDock 4's `elec_min_distance`). The energy is reported in
//! kcal/mol as is; AutoDock 4's free-energy model weights it by 0.1406
//! ([`AD4_WEIGHT`]). Charges are the chemistry's Gasteiger charges.
//!
//! [`CoulombMap`] holds the receptor's potential `φ(x) = Σ_j 332.06363 q_j /
//! (r ε(r))` on a lattice (the drug's energy is `Σ q_i φ(x_i)`), read by
//! trilinear interpolation with its gradient; atoms outside it are summed
//! exactly. The potential is sampled from a table of the kernel in r²
//! (linear between samples 1/32 Å² apart) while building.

use glam::DVec3;

use super::maps::{Lattice, MapBox, MapsError};
use super::receptor::Receptor;

/// e²/(4π ε0) in kcal·Å/mol (AutoDock's `ELEC_SCALE_FACTOR`).
pub const ELEC_SCALE: f64 = 332.06363;

/// AutoDock 4.2's weight of the electrostatic term in its free-energy model.
pub const AD4_WEIGHT: f64 = 0.1406;

/// Centre distance (Å) beyond which pairs are not counted.
pub const COULOMB_CUTOFF: f64 = 20.48;

/// Smallest distance (Å) the kernel is evaluated at.
pub const MIN_DISTANCE: f64 = 0.5;

const A: f64 = -8.5525;
const B: f64 = 78.4 - A;
const LAMBDA: f64 = 0.003627;
const K: f64 = 7.7839;

/// Mehler and Solmajer's dielectric at distance `r` (Å).
pub fn dielectric(r: f64) -> f64 {
    A + B / (1.0 + K * (-LAMBDA * B * r).exp())
}

/// The kernel `332.06363 / (r ε(r))` and its derivative in `r` (0 beyond the
/// cutoff; constant below [`MIN_DISTANCE`]).
pub fn kernel(r: f64) -> (f64, f64) {
    if r >= COULOMB_CUTOFF {
        return (0.0, 0.0);
    }
    let rc = r.max(MIN_DISTANCE);
    let e = (-LAMBDA * B * rc).exp();
    let eps = A + B / (1.0 + K * e);
    // dε/dr = B·k·λB·e / (1 + k e)²
    let deps = B * K * LAMBDA * B * e / ((1.0 + K * e) * (1.0 + K * e));
    let v = ELEC_SCALE / (rc * eps);
    let dv = if r < MIN_DISTANCE {
        0.0
    } else {
        -v * (1.0 / rc + deps / eps)
    };
    (v, dv)
}

/// The receptor's electrostatic potential at `x` (kcal/mol/e) and its
/// gradient, summed exactly over the receptor atoms within the cutoff.
pub fn potential(receptor: &Receptor, x: DVec3) -> (f64, DVec3) {
    let (mut phi, mut g) = (0.0, DVec3::ZERO);
    let c2 = COULOMB_CUTOFF * COULOMB_CUTOFF;
    receptor.cells().visit(x, COULOMB_CUTOFF, |a| {
        let d = x - a.position;
        let r2 = d.length_squared();
        let q = receptor.charges[a.atom as usize];
        if r2 < c2 && q != 0.0 {
            let r = r2.sqrt();
            let (v, dv) = kernel(r);
            phi += q * v;
            if r > 0.0 {
                g += d * (q * dv / r);
            }
        }
    });
    (phi, g)
}

/// The Coulomb energy of drug atoms with `charges` at `positions` (receptor
/// frame) and each atom's gradient, written into `gradients` (kcal/mol/Å).
pub fn energy(
    receptor: &Receptor,
    positions: &[DVec3],
    charges: &[f64],
    map: Option<&CoulombMap>,
    gradients: &mut Vec<DVec3>,
) -> f64 {
    gradients.clear();
    let mut e = 0.0;
    for (x, &q) in positions.iter().zip(charges) {
        if q == 0.0 {
            gradients.push(DVec3::ZERO);
            continue;
        }
        let (phi, g) = map
            .and_then(|m| m.sample(*x))
            .unwrap_or_else(|| potential(receptor, *x));
        e += q * phi;
        gradients.push(g * q);
    }
    e
}

/// Samples of the kernel per 1/32 Å² of r², to the cutoff.
fn kernel_table() -> Vec<f64> {
    let n = (32.0 * COULOMB_CUTOFF * COULOMB_CUTOFF) as usize + 2;
    (0..n).map(|k| kernel((k as f64 / 32.0).sqrt()).0).collect()
}

/// The receptor's electrostatic potential on a lattice.
#[derive(Debug, Clone)]
pub struct CoulombMap {
    lattice: Lattice,
    values: Vec<f32>,
}

impl CoulombMap {
    /// Builds the potential of `receptor` over `bx` on up to `threads`
    /// threads.
    ///
    /// # Errors
    /// For a box that is not a usable lattice.
    pub fn build(receptor: &Receptor, bx: &MapBox, threads: usize) -> Result<Self, MapsError> {
        let lattice = Lattice::new(bx)?;
        let table = kernel_table();
        let cut = COULOMB_CUTOFF;
        let c2 = cut * cut;
        let (lo, hi) = (lattice.origin - cut, lattice.end() + cut);
        let near: Vec<usize> = (0..receptor.len())
            .filter(|&j| {
                let p = receptor.positions[j];
                receptor.charges[j] != 0.0 && p.cmpge(lo).all() && p.cmple(hi).all()
            })
            .collect();
        let [nx, ny, nz] = lattice.points;
        let mut values = vec![0.0f32; lattice.len()];
        let threads = threads.clamp(1, nz);
        let per = nz.div_ceil(threads);
        let h = lattice.spacing;
        let inv = 1.0 / h;
        let work = |z0: usize, out: &mut [f32]| {
            let z1 = z0 + out.len() / (nx * ny);
            for &j in &near {
                let p = receptor.positions[j];
                let q = receptor.charges[j];
                let g = (p - lattice.origin) * inv;
                let reach = cut * inv;
                let zlo = (g.z - reach).ceil().max(z0 as f64) as usize;
                let zhi = (g.z + reach).floor().min((z1 - 1) as f64);
                let ylo = (g.y - reach).ceil().max(0.0) as usize;
                let yhi = (g.y + reach).floor().min((ny - 1) as f64);
                if zhi < zlo as f64 || yhi < ylo as f64 {
                    continue;
                }
                for z in zlo..=zhi as usize {
                    let dz = lattice.origin.z + z as f64 * h - p.z;
                    for y in ylo..=yhi as usize {
                        let dy = lattice.origin.y + y as f64 * h - p.y;
                        let dyz2 = dy * dy + dz * dz;
                        if dyz2 >= c2 {
                            continue;
                        }
                        let half = (c2 - dyz2).sqrt();
                        let xlo = ((p.x - half - lattice.origin.x) * inv).ceil().max(0.0);
                        let xhi = ((p.x + half - lattice.origin.x) * inv)
                            .floor()
                            .min((nx - 1) as f64);
                        if xhi < xlo {
                            continue;
                        }
                        let row = ((z - z0) * ny + y) * nx;
                        for x in xlo as usize..=xhi as usize {
                            let dx = lattice.origin.x + x as f64 * h - p.x;
                            let s = 32.0 * (dx * dx + dyz2);
                            let k = s as usize;
                            if k + 1 < table.len() {
                                let v = table[k] + (s - k as f64) * (table[k + 1] - table[k]);
                                out[row + x] += (q * v) as f32;
                            }
                        }
                    }
                }
            }
        };
        let chunks: Vec<(usize, &mut [f32])> = values
            .chunks_mut(per * nx * ny)
            .enumerate()
            .map(|(c, s)| (c * per, s))
            .collect();
        if chunks.len() == 1 {
            for (z0, s) in chunks {
                work(z0, s);
            }
        } else {
            std::thread::scope(|sc| {
                for (z0, s) in chunks {
                    let work = &work;
                    sc.spawn(move || work(z0, s));
                }
            });
        }
        Ok(Self { lattice, values })
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// The interpolated potential at `x` and its gradient; `None` outside.
    pub fn sample(&self, x: DVec3) -> Option<(f64, DVec3)> {
        self.lattice.interpolate(&self.values, x)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::rng::Rng;
    use crate::score::XsType;

    #[test]
    fn the_dielectric_runs_from_one_to_water() {
        assert!((dielectric(0.0) - (A + B / (1.0 + K))).abs() < 1e-12);
        assert!((dielectric(0.0) - 1.3466).abs() < 1e-4);
        assert!((dielectric(1e3) - 78.4).abs() < 1e-9);
        let (v, dv) = kernel(4.0);
        let h = 1e-6;
        let num = (kernel(4.0 + h).0 - kernel(4.0 - h).0) / (2.0 * h);
        assert!((num - dv).abs() < 1e-6 * v.abs().max(1.0));
        // Below the smallest distance: constant.
        assert_eq!(kernel(0.1), (kernel(MIN_DISTANCE).0, 0.0));
    }

    #[test]
    fn the_map_agrees_with_the_exact_potential() {
        let mut rng = Rng(9);
        let n = 300;
        let pos: Vec<DVec3> = (0..n).map(|_| rng.in_box(DVec3::splat(15.0))).collect();
        let q: Vec<f64> = (0..n).map(|_| rng.range(-0.5, 0.5)).collect();
        let r = Receptor::new(&pos, &vec![Some(XsType::C_P); n], &q);
        let map = CoulombMap::build(&r, &MapBox::cube(DVec3::ZERO, 6.0, 0.375), 2).unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..200 {
            let x = rng.in_box(DVec3::splat(2.9));
            // Away from the receptor atoms, where the potential is smooth.
            if pos.iter().any(|p| (*p - x).length() < 2.5) {
                continue;
            }
            let (m, _) = map.sample(x).unwrap();
            let (e, _) = potential(&r, x);
            worst = worst.max((m - e).abs() / (1.0 + e.abs()));
        }
        // Trilinear interpolation of a 1/r-like kernel 2.5 Å from its
        // charges, at 0.375 Å: a few per cent.
        assert!(worst < 0.1, "{worst}");
    }
}
