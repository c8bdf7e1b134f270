//! The contact rule: when two atoms collide. This is the one place it is defined.
//!
//! A receptor atom `j` and a drug atom `i` collide when their overlap
//! `r_i + r_j − d` is at least the allowance: `overlap` (0.6 Å), or
//! `overlap + hbond_allowance` (0.6 + 0.4 Å) when both atoms are N or O and
//! could be hydrogen-bonded. These are ChimeraX's `clashes` defaults. The rule is
//! evaluated as `d ≤ c` with the contact distance `c = r_i + r_j − allowance`,
//! in squared form `d² ≤ c²` (and `c ≥ 0`), so "exactly touching" collides.

use serde::Serialize;
use thiserror::Error;

/// The overlap thresholds that decide a collision.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactRule {
    /// Minimum overlap `r_i + r_j − d` that counts as a collision, in Å.
    pub overlap: f32,
    /// Extra overlap allowed between two N/O atoms (a possible hydrogen bond), in Å.
    pub hbond_allowance: f32,
}

impl Default for ContactRule {
    fn default() -> Self {
        Self {
            overlap: 0.6,
            hbond_allowance: 0.4,
        }
    }
}

/// A contact rule with a value that is not a finite number of ångströms.
#[derive(Debug, Error, PartialEq)]
#[error("contact rule: {what} must be a finite number of Å between -5 and 5, got {value}")]
pub struct RuleError {
    /// Which parameter.
    pub what: &'static str,
    /// Its value.
    pub value: f32,
}

impl ContactRule {
    /// A rule with the given thresholds.
    ///
    /// # Errors
    /// When a value is not finite or outside ±5 Å.
    pub fn new(overlap: f32, hbond_allowance: f32) -> Result<Self, RuleError> {
        for (what, value) in [("overlap", overlap), ("hbond allowance", hbond_allowance)] {
            if !value.is_finite() || value.abs() > 5.0 {
                return Err(RuleError { what, value });
            }
        }
        Ok(Self {
            overlap,
            hbond_allowance,
        })
    }

    /// The overlap a pair must reach to collide.
    #[inline]
    pub fn allowance(&self, polar_a: bool, polar_b: bool) -> f32 {
        if polar_a && polar_b {
            self.overlap + self.hbond_allowance
        } else {
            self.overlap
        }
    }

    /// The smallest allowance any pair can get.
    pub fn min_allowance(&self) -> f32 {
        self.overlap.min(self.overlap + self.hbond_allowance)
    }

    /// Contact distance `r_a + r_b − allowance`: the pair collides at or below it.
    #[inline]
    pub fn contact_distance(&self, r_a: f32, polar_a: bool, r_b: f32, polar_b: bool) -> f32 {
        r_a + r_b - self.allowance(polar_a, polar_b)
    }

    /// True when atoms with these radii and polarity collide at distance² `d2`.
    #[inline]
    pub fn collides(&self, r_a: f32, polar_a: bool, r_b: f32, polar_b: bool, d2: f32) -> bool {
        let c = self.contact_distance(r_a, polar_a, r_b, polar_b);
        c >= 0.0 && d2 <= c * c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_chimerax_clash_values() {
        let r = ContactRule::default();
        assert_eq!(r.allowance(false, true), 0.6);
        assert_eq!(r.allowance(true, true), 0.6 + 0.4);
        // C–C at 2.8 Å: overlap 1.7 + 1.7 − 2.8 = 0.6 → collides (at least).
        assert!(r.collides(1.7, false, 1.7, false, 2.8 * 2.8));
        assert!(!r.collides(1.7, false, 1.7, false, 2.81 * 2.81));
        // N–O at 2.9 Å (a hydrogen bond): overlap 0.17 < 1.0 → no collision.
        assert!(!r.collides(1.55, true, 1.52, true, 2.9 * 2.9));
    }

    #[test]
    fn rejects_non_finite() {
        assert!(ContactRule::new(f32::NAN, 0.4).is_err());
        assert!(ContactRule::new(0.6, 99.0).is_err());
        assert!(ContactRule::new(0.5, 0.0).is_ok());
    }
}
