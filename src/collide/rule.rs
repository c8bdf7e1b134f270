//! The contact rule: when two atoms collide. This is the one place it is defined.
//!
//! A receptor atom `j` and a drug atom `i` collide when their overlap
//! `r_i + r_j − d` is at least the allowance: `overlap` (0.6 Å), or
//! `overlap + hbond_allowance` (0.6 + 0.4 Å) when both atoms are N or O and
//! could be hydrogen-bonded. These are ChimeraX's `clashes` defaults. The rule is
//! evaluated as `d ≤ c` with the contact distance `c = r_i + r_j − allowance`,
//! in squared form `d² ≤ c²` (and `c ≥ 0`), so "exactly touching" collides.
//! A pair reports its distance so that `distance ≤ contact` says the same
//! ([`reported_distance`]).

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
        within(d2, self.contact_distance(r_a, polar_a, r_b, polar_b))
    }
}

/// The rule's test on a squared centre distance `d2` (f32, as the colliders
/// compute it): `d² ≤ c²` with `c ≥ 0`, for a contact distance `c` (a
/// collision) or `c + extra` (within `extra` of one).
#[inline(always)]
pub fn within(d2: f32, c: f32) -> bool {
    c >= 0.0 && d2 <= c * c
}

/// The centre distance a pair at squared distance `d2` with contact
/// distance `c` reports: `√d2` in f32, moved by at most one unit in the last
/// place so that `distance ≤ c` holds exactly when the pair collides
/// ([`within`]`(d2, c)`). The square root alone can round onto `c` from a
/// `d2` one unit above `c²` (a pair the rule finds clear would read as
/// colliding); the other way, `√d2` of a `d2 ≤ c²` lies within half a unit
/// of `c`, so only a tie could round it above.
#[inline]
pub fn reported_distance(d2: f32, c: f32) -> f32 {
    let d = d2.sqrt();
    if within(d2, c) {
        d.min(c)
    } else if d <= c {
        c.next_up()
    } else {
        d
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
    fn reported_distances_say_what_the_rule_says() {
        let mut checked = 0;
        for c in [0.0f32, 1e-3, 0.9, 2.8, 2.8000002, 3.07, 4.5] {
            // Squared distances a few units either side of c² (rounded).
            let mut d2 = (c * c).max(f32::MIN_POSITIVE);
            for _ in 0..8 {
                d2 = d2.next_down().max(0.0);
            }
            for _ in 0..16 {
                let d = reported_distance(d2, c);
                assert_eq!(d <= c, within(d2, c), "c {c} d2 {d2} d {d}");
                // Never more than a unit from the square root.
                let s = d2.sqrt();
                assert!(d == s || d == s.next_up() || d == s.next_down(), "{d} {s}");
                checked += usize::from(d != s);
                d2 = d2.next_up();
            }
        }
        // Some of them needed the nudge (c = 2.8 does).
        assert!(checked > 0);
        // A negative contact distance never collides.
        assert!(!within(0.0, -0.1) && reported_distance(0.0, -0.1) == 0.0);
    }

    #[test]
    fn rejects_non_finite() {
        assert!(ContactRule::new(f32::NAN, 0.4).is_err());
        assert!(ContactRule::new(0.6, 99.0).is_err());
        assert!(ContactRule::new(0.5, 0.0).is_ok());
    }
}
