//! A tiny seeded random generator (xorshift64*): the same seed gives the
//! same draws on every machine, with no seed crate. `bump steer`'s seeded
//! torsions, the tests and the benchmarks use it; and
//! [`sphere_directions`], evenly spread directions to start, search or
//! sample along.

use glam::DVec3;

/// xorshift64*; the state must not be zero.
#[derive(Debug, Clone)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[0, 1)`.
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }

    /// Uniform in the box `[-half, half)` (x, y, z drawn in that order).
    pub fn in_box(&mut self, half: DVec3) -> DVec3 {
        let x = self.range(-half.x, half.x);
        let y = self.range(-half.y, half.y);
        DVec3::new(x, y, self.range(-half.z, half.z))
    }

    /// A uniformly random unit vector (rejection sampling in the ball).
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = self.in_box(DVec3::ONE);
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// `n` unit vectors spread evenly over the sphere (a Fibonacci lattice),
/// in a fixed order.
pub fn sphere_directions(n: usize) -> Vec<DVec3> {
    (0..n).map(|i| sphere_direction(i, n)).collect()
}

/// The `i`-th of [`sphere_directions`]`(n)`, without the others.
pub fn sphere_direction(i: usize, n: usize) -> DVec3 {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
    let r = (1.0 - y * y).sqrt();
    let phi = golden * i as f64;
    DVec3::new(r * phi.cos(), y, r * phi.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeded_draws_repeat_and_stay_in_range() {
        let (mut a, mut b) = (Rng(7), Rng(7));
        for _ in 0..1000 {
            let x = a.range(-2.0, 3.0);
            assert_eq!(x, b.range(-2.0, 3.0));
            assert!((-2.0..3.0).contains(&x));
            assert!((a.unit().length() - 1.0).abs() < 1e-12);
            b.unit();
        }
        assert_ne!(Rng(1).next_u64(), Rng(2).next_u64());
    }

    #[test]
    fn sphere_directions_are_unit_and_spread_evenly() {
        let d = super::sphere_directions(300);
        assert_eq!(d.len(), 300);
        assert!(d.iter().all(|v| (v.length() - 1.0).abs() < 1e-12));
        // Evenly spread: their mean is near the centre, and no two coincide.
        let mean = d.iter().copied().sum::<DVec3>() / 300.0;
        assert!(mean.length() < 1e-2, "{mean}");
        let closest = (0..300)
            .flat_map(|i| (0..i).map(move |j| (i, j)))
            .map(|(i, j)| d[i].distance(d[j]))
            .fold(f64::INFINITY, f64::min);
        assert!(closest > 0.1, "{closest}");
        assert!(super::sphere_directions(0).is_empty());
    }
}
