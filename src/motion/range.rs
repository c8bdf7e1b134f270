//! The one range check for what moves a molecule and for how long: every
//! command (`check`, `touch`, `render`, `devices`) and the session-log
//! reader take positions, displacements and times through it, so that a
//! number one of them accepts none of the others refuses, and a message
//! about one prints it short ([`crate::text::short_number`]).
//!
//! - A position (a pose's centre) lies within [`MAX_COORDINATE`] of the
//!   origin on every axis ([`check_position`]).
//! - A displacement or velocity (a move, a nudge, Å per second) is at most
//!   twice that on every axis ([`check_displacement`]): the most that takes
//!   one position in range to another.
//! - A time (a frame's step, a duration to watch) is a finite number of
//!   seconds from 0 to [`MAX_SECONDS`] ([`check_seconds`]).

use glam::DVec3;
use thiserror::Error;

pub use super::pose::MAX_COORDINATE;
use crate::text::short_number;

/// Longest time step or duration, seconds (about 11.6 days): far beyond any
/// frame or watch, small enough that sums of many stay finite and that
/// `Duration` and `Instant` arithmetic cannot overflow.
pub const MAX_SECONDS: f64 = 1e6;

/// Largest displacement or velocity along an axis, Å (or Å per second).
pub const MAX_DISPLACEMENT: f64 = 2.0 * MAX_COORDINATE;

/// A number outside its range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RangeError {
    /// NaN or infinite.
    #[error("{} is not a finite number", short_number(*.0))]
    NotFinite(f64),
    /// A negative time.
    #[error("{} s is negative", short_number(*.0))]
    Negative(f64),
    /// A time beyond [`MAX_SECONDS`].
    #[error("{} s, beyond the {MAX_SECONDS:e} s a time may last", short_number(*.0))]
    TooLong(f64),
    /// A position beyond [`MAX_COORDINATE`].
    #[error(
        "{} Å from the origin along an axis, beyond the {MAX_COORDINATE:e} Å a position may reach",
        short_number(*.0)
    )]
    TooFar(f64),
    /// A displacement beyond [`MAX_DISPLACEMENT`].
    #[error(
        "{} Å along an axis, beyond the {MAX_DISPLACEMENT:e} Å a move may span",
        short_number(*.0)
    )]
    TooLarge(f64),
}

/// Checks a time in seconds: finite, from 0 to [`MAX_SECONDS`].
///
/// # Errors
/// [`RangeError::NotFinite`], [`RangeError::Negative`] or [`RangeError::TooLong`].
pub fn check_seconds(t: f64) -> Result<f64, RangeError> {
    if !t.is_finite() {
        Err(RangeError::NotFinite(t))
    } else if t < 0.0 {
        Err(RangeError::Negative(t))
    } else if t > MAX_SECONDS {
        Err(RangeError::TooLong(t))
    } else {
        Ok(t)
    }
}

/// The component of `v` farthest from zero (NaN first).
fn extreme(v: DVec3) -> f64 {
    let mut out = 0.0_f64;
    for c in v.to_array() {
        if c.is_nan() {
            return c;
        }
        if c.abs() > out.abs() {
            out = c;
        }
    }
    out
}

/// Checks a position: finite, within [`MAX_COORDINATE`] on every axis.
///
/// # Errors
/// [`RangeError::NotFinite`] or [`RangeError::TooFar`], with the component
/// farthest out.
pub fn check_position(p: DVec3) -> Result<DVec3, RangeError> {
    let c = extreme(p);
    if !c.is_finite() {
        Err(RangeError::NotFinite(c))
    } else if c.abs() > MAX_COORDINATE {
        Err(RangeError::TooFar(c))
    } else {
        Ok(p)
    }
}

/// Checks a displacement or velocity: finite, within [`MAX_DISPLACEMENT`]
/// on every axis.
///
/// # Errors
/// [`RangeError::NotFinite`] or [`RangeError::TooLarge`], with the
/// component farthest out.
pub fn check_displacement(d: DVec3) -> Result<DVec3, RangeError> {
    let c = extreme(d);
    if !c.is_finite() {
        Err(RangeError::NotFinite(c))
    } else if c.abs() > MAX_DISPLACEMENT {
        Err(RangeError::TooLarge(c))
    } else {
        Ok(d)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn times_run_from_zero_to_the_limit() {
        assert_eq!(check_seconds(0.0), Ok(0.0));
        assert_eq!(check_seconds(MAX_SECONDS), Ok(MAX_SECONDS));
        assert_eq!(check_seconds(-1.0), Err(RangeError::Negative(-1.0)));
        assert!(matches!(
            check_seconds(f64::NAN),
            Err(RangeError::NotFinite(_))
        ));
        let e = check_seconds(1e308).unwrap_err().to_string();
        assert_eq!(e, "1e308 s, beyond the 1e6 s a time may last");
        assert!(check_seconds(1e19).is_err());
    }

    #[test]
    fn positions_and_displacements_name_the_component_farthest_out() {
        assert!(check_position(DVec3::splat(MAX_COORDINATE)).is_ok());
        assert_eq!(
            check_position(DVec3::new(1.0, -3e9, 2e9)),
            Err(RangeError::TooFar(-3e9))
        );
        assert!(matches!(
            check_position(DVec3::new(1.0, f64::NAN, 2e9)),
            Err(RangeError::NotFinite(_))
        ));
        assert!(matches!(
            check_position(DVec3::new(1.0, 2e9, f64::INFINITY)),
            Err(RangeError::NotFinite(_))
        ));
        assert!(check_displacement(DVec3::new(1.5e9, 0.0, 0.0)).is_ok());
        let e = check_displacement(DVec3::new(1e308, 0.0, 0.0)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "1e308 Å along an axis, beyond the 2e9 Å a move may span"
        );
    }
}
