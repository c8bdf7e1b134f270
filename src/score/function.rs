//! The Vina and Vinardo scoring functions: the terms of one atom pair, their
//! weights, the curl and the torsion divisor, as AutoDock Vina 1.2 defines
//! them (`potentials.h`, `scoring_function.h`, `curl.h`,
//! `conf_independent.cpp`; `docs/vina-scoring.md` §3, §5, §7).
//!
//! A pair of atoms with X-Score types `a`, `b` at centre distance `r` has the
//! surface distance `d = r − (R_a + R_b)` (Vina's or Vinardo's radii) and
//! these unweighted terms, each 0 for `r ≥ 8 Å`:
//!
//! | Vina | Vinardo |
//! |---|---|
//! | gauss1 `exp(−(d/0.5)²)` | gauss `exp(−(d/0.8)²)` |
//! | gauss2 `exp(−((d−3)/2)²)` | |
//! | repulsion `d²` for `d < 0` | repulsion `d²` for `d < 0` |
//! | hydrophobic: 1 for `d ≤ 0.5`, 0 for `d ≥ 1.5`, linear between (both hydrophobic) | 1 for `d ≤ 0`, 0 for `d ≥ 2.5` |
//! | hydrogen: 1 for `d ≤ −0.7`, 0 for `d ≥ 0`, linear between (donor with acceptor) | 1 for `d ≤ −0.6`, 0 for `d ≥ 0` |
//!
//! The pair energy is the weighted sum; Vina never evaluates it directly
//! but reads it from a table ([`super::table`]).

use serde::Serialize;

use crate::chem::XsType;

/// Centre distance (Å) at and beyond which no pair interacts.
pub const CUTOFF: f64 = 8.0;

/// [`CUTOFF`] squared.
pub const CUTOFF2: f64 = CUTOFF * CUTOFF;

/// The weight of the torsion count in the divisor `1 + w·N_tors` (both
/// scoring functions).
pub const ROT_WEIGHT: f64 = 0.05846;

/// Largest number of distance-dependent terms a scoring function has.
pub const MAX_TERMS: usize = 5;

/// Which scoring function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Scoring {
    /// AutoDock Vina's (the default).
    #[default]
    Vina,
    /// Vinardo (Quiroga and Villarreal 2016), as Vina 1.2 implements it.
    Vinardo,
}

/// One distance-dependent term's shape.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// `exp(−((d − offset)/width)²)`.
    Gauss { offset: f64, width: f64 },
    /// `d²` for `d < 0`.
    Repulsion,
    /// Hydrophobic pairs: `slope_step(bad, good, d)`.
    Hydrophobic { good: f64, bad: f64 },
    /// Donor–acceptor pairs: `slope_step(bad, good, d)`.
    HBond { good: f64, bad: f64 },
}

/// A term: its name, shape and default weight.
#[derive(Debug, Clone, Copy)]
struct Term {
    name: &'static str,
    shape: Shape,
    weight: f64,
}

const VINA_TERMS: [Term; 5] = [
    Term {
        name: "gauss1",
        shape: Shape::Gauss {
            offset: 0.0,
            width: 0.5,
        },
        weight: -0.035579,
    },
    Term {
        name: "gauss2",
        shape: Shape::Gauss {
            offset: 3.0,
            width: 2.0,
        },
        weight: -0.005156,
    },
    Term {
        name: "repulsion",
        shape: Shape::Repulsion,
        weight: 0.840245,
    },
    Term {
        name: "hydrophobic",
        shape: Shape::Hydrophobic {
            good: 0.5,
            bad: 1.5,
        },
        weight: -0.035069,
    },
    Term {
        name: "hydrogen",
        shape: Shape::HBond {
            good: -0.7,
            bad: 0.0,
        },
        weight: -0.587439,
    },
];

const VINARDO_TERMS: [Term; 4] = [
    Term {
        name: "gauss",
        shape: Shape::Gauss {
            offset: 0.0,
            width: 0.8,
        },
        weight: -0.045,
    },
    Term {
        name: "repulsion",
        shape: Shape::Repulsion,
        weight: 0.8,
    },
    Term {
        name: "hydrophobic",
        shape: Shape::Hydrophobic {
            good: 0.0,
            bad: 2.5,
        },
        weight: -0.035,
    },
    Term {
        name: "hydrogen",
        shape: Shape::HBond {
            good: -0.6,
            bad: 0.0,
        },
        weight: -0.6,
    },
];

/// Vina's X-Score radii (`atom_constants.h`), by type index.
const VINA_RADIUS: [f64; 19] = [
    1.9, 1.9, 1.8, 1.8, 1.8, 1.8, 1.7, 1.7, 1.7, 1.7, 2.0, 2.1, 1.5, 1.8, 2.0, 2.2, 2.2, 2.3, 1.2,
];

/// Vinardo's radii, by type index.
const VINARDO_RADIUS: [f64; 19] = [
    2.0, 2.0, 1.7, 1.7, 1.7, 1.7, 1.6, 1.6, 1.6, 1.6, 2.0, 2.1, 1.5, 1.8, 2.0, 2.2, 2.2, 2.3, 1.2,
];

/// Vina's `slope_step`: 0 on the bad side of `bad`, 1 on the good side of
/// `good`, linear between.
fn slope_step(bad: f64, good: f64, x: f64) -> f64 {
    if bad < good {
        if x <= bad {
            return 0.0;
        }
        if x >= good {
            return 1.0;
        }
    } else {
        if x >= bad {
            return 0.0;
        }
        if x <= good {
            return 1.0;
        }
    }
    (x - bad) / (good - bad)
}

/// True when `a` and `b` can form a hydrogen bond (one a donor, the other an
/// acceptor, either way round: Vina's `xs_h_bond_possible`).
pub fn hbond_possible(a: XsType, b: XsType) -> bool {
    (a.is_donor() && b.is_acceptor()) || (b.is_donor() && a.is_acceptor())
}

impl Scoring {
    /// Parses `vina` or `vinardo`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "vina" => Some(Self::Vina),
            "vinardo" => Some(Self::Vinardo),
            _ => None,
        }
    }

    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Vina => "vina",
            Self::Vinardo => "vinardo",
        }
    }

    fn terms(self) -> &'static [Term] {
        match self {
            Self::Vina => &VINA_TERMS,
            Self::Vinardo => &VINARDO_TERMS,
        }
    }

    /// Number of distance-dependent terms (5 for Vina, 4 for Vinardo).
    pub fn term_count(self) -> usize {
        self.terms().len()
    }

    /// The terms' names, in Vina's weight order (`gauss1`, `gauss2`,
    /// `repulsion`, `hydrophobic`, `hydrogen`; Vinardo: `gauss`,
    /// `repulsion`, `hydrophobic`, `hydrogen`).
    pub fn term_name(self, k: usize) -> &'static str {
        self.terms()[k].name
    }

    /// The default weight of term `k`.
    pub fn weight(self, k: usize) -> f64 {
        self.terms()[k].weight
    }

    /// Index of the hydrogen-bond term.
    pub fn hbond_term(self) -> usize {
        self.term_count() - 1
    }

    /// The atomic radius of type `t` (Å) in this function.
    pub fn radius(self, t: XsType) -> f64 {
        match self {
            Self::Vina => VINA_RADIUS[t.index()],
            Self::Vinardo => VINARDO_RADIUS[t.index()],
        }
    }

    /// Unweighted terms of a pair of types at centre distance `r` (0 at and
    /// beyond [`CUTOFF`]); entries past [`Self::term_count`] are 0.
    pub fn pair_terms(self, a: XsType, b: XsType, r: f64) -> [f64; MAX_TERMS] {
        let mut out = [0.0; MAX_TERMS];
        if r >= CUTOFF {
            return out;
        }
        let optimal = self.radius(a) + self.radius(b);
        let d = r - optimal;
        for (slot, term) in out.iter_mut().zip(self.terms()) {
            *slot = match term.shape {
                Shape::Gauss { offset, width } => {
                    let x = (r - (optimal + offset)) / width;
                    (-(x * x)).exp()
                }
                Shape::Repulsion => {
                    if d > 0.0 {
                        0.0
                    } else {
                        d * d
                    }
                }
                Shape::Hydrophobic { good, bad } => {
                    if a.is_hydrophobic() && b.is_hydrophobic() {
                        slope_step(bad, good, d)
                    } else {
                        0.0
                    }
                }
                Shape::HBond { good, bad } => {
                    if hbond_possible(a, b) {
                        slope_step(bad, good, d)
                    } else {
                        0.0
                    }
                }
            };
        }
        out
    }

    /// The weighted pair energy `Σ w_k f_k` at centre distance `r`, summed
    /// in Vina's order (`ScoringFunction::eval`).
    pub fn pair_energy(self, a: XsType, b: XsType, r: f64) -> f64 {
        let terms = self.pair_terms(a, b, r);
        let mut e = 0.0;
        for (k, term) in self.terms().iter().enumerate() {
            e += term.weight * terms[k];
        }
        e
    }
}

/// Vina's curl (`curl.h`, v = 1000): positive energies are damped to
/// `e·1000/(1000 + e)`, others are kept.
#[inline]
pub fn curl(e: f64) -> f64 {
    if e > 0.0 {
        e * (1000.0 / (1000.0 + e))
    } else {
        e
    }
}

/// Vina's cap `v` of the curl where it scores (its `authentic_v`).
pub const CURL_CAP: f64 = 1000.0;

/// The curl and its derivative `d curl / d e` (1 for `e ≤ 0`).
#[inline]
pub fn curl_with_slope(e: f64) -> (f64, f64) {
    curl_capped_with_slope(e, CURL_CAP)
}

/// The curl at cap `v` (`e·v/(v + e)` for `e > 0`) and its derivative:
/// Vina's Monte Carlo minimises with lower caps (its `hunt_cap`).
#[inline]
pub fn curl_capped_with_slope(e: f64, v: f64) -> (f64, f64) {
    if e > 0.0 {
        curl_positive(e, v)
    } else {
        (e, 1.0)
    }
}

/// [`curl_capped_with_slope`] of a positive energy: rare (an overlap), and
/// a division, so kept off the common path.
#[cold]
fn curl_positive(e: f64, v: f64) -> (f64, f64) {
    let t = v / (v + e);
    (e * t, t * t)
}

/// Vina's divisor of the intermolecular energy, `1 + 0.05846·N_tors`.
pub fn torsion_divisor(torsion_count: f64) -> f64 {
    1.0 + ROT_WEIGHT * torsion_count
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn terms_match_the_formulas_at_chosen_distances() {
        // C_H–C_H in Vina: optimal distance 3.8 Å.
        let t = Scoring::Vina.pair_terms(XsType::C_H, XsType::C_H, 3.8);
        assert_eq!(t[0], 1.0);
        assert!((t[1] - (-(1.5f64 * 1.5)).exp()).abs() < 1e-15);
        assert_eq!(t[2], 0.0);
        assert_eq!(t[3], 1.0);
        assert_eq!(t[4], 0.0);
        let t = Scoring::Vina.pair_terms(XsType::C_H, XsType::C_H, 4.8);
        assert!((t[3] - 0.5).abs() < 1e-12);
        // N_D–O_A: optimal 3.5 Å; hydrogen-bond term 1 at d ≤ −0.7.
        let t = Scoring::Vina.pair_terms(XsType::N_D, XsType::O_A, 2.7);
        assert_eq!(t[4], 1.0);
        assert!((t[2] - 0.64).abs() < 1e-12);
        let t = Scoring::Vina.pair_terms(XsType::N_D, XsType::O_A, 3.15);
        assert!((t[4] - 0.5).abs() < 1e-12);
        // Donor–donor: no hydrogen bond.
        let t = Scoring::Vina.pair_terms(XsType::N_D, XsType::O_D, 2.7);
        assert_eq!(t[4], 0.0);
        // Nothing at or beyond 8 Å.
        assert_eq!(
            Scoring::Vina.pair_energy(XsType::C_H, XsType::C_H, 8.0),
            0.0
        );
        assert!(Scoring::Vina.pair_energy(XsType::C_H, XsType::C_H, 7.999) < 0.0);
    }

    #[test]
    fn vinardo_uses_its_own_radii_and_terms() {
        // C_H–C_H: optimal 4.0 Å; hydrophobic 1 at d ≤ 0, 0 at d ≥ 2.5.
        let t = Scoring::Vinardo.pair_terms(XsType::C_H, XsType::C_H, 5.25);
        assert!((t[2] - 0.5).abs() < 1e-12);
        assert_eq!(t[0], (-(1.25f64 / 0.8).powi(2)).exp());
        assert_eq!(Scoring::Vinardo.term_count(), 4);
        assert_eq!(Scoring::Vinardo.term_name(3), "hydrogen");
    }

    #[test]
    fn curl_damps_only_positive_energies() {
        assert_eq!(curl(-5.0), -5.0);
        assert!((curl(10.0) - 10.0 * 1000.0 / 1010.0).abs() < 1e-12);
        let (e, s) = curl_with_slope(10.0);
        let h = 1e-6;
        assert!(((curl(10.0 + h) - curl(10.0 - h)) / (2.0 * h) - s).abs() < 1e-8);
        assert_eq!(e, curl(10.0));
    }
}
