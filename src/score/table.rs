//! The precalculated pair-energy table Vina reads every pair energy from,
//! even when it scores "exactly" (`precalculate.h`; `docs/vina-scoring.md`
//! §4).
//!
//! For each pair of X-Score types the weighted pair energy is sampled at
//! `r² = k/32` Å² (`smooth_k`); Vina's score reads
//! `fast_k = (smooth_k + smooth_{k+1})/2` at `k = ⌊32·r²⌋`: piecewise
//! constant in r². Evaluating the formulas directly differs from Vina by
//! 5·10⁻⁴ to 0.02 kcal/mol on crystal poses and up to 0.4 on clashes, so
//! bump reads the same table. Gradients use the continuous energy
//! `smooth_k + (32·r² − k)(smooth_{k+1} − smooth_k)`, linear in r² between
//! samples (Vina's optimiser interpolates the same samples), whose
//! derivative `dE/d(r²) = 32 (smooth_{k+1} − smooth_k)` is exact.
//!
//! The tables cover `r² < 64` (`k ≤ 2047`); one per scoring function, built
//! on first use (190 type pairs × 2 × 2050 samples, about 6 MB, a few ms).
//! The terms one by one ([`fast_terms`], for a score's term-by-term report)
//! are sampled the same way, one type pair's row when that pair is first
//! asked for (82 kB and about 0.1 ms a pair), so a report reads two samples
//! per term instead of evaluating the terms' exponentials twice.

use std::sync::OnceLock;

use super::function::{CUTOFF2, MAX_TERMS, Scoring};
use crate::chem::XsType;

/// Samples per Å² of r².
pub const FACTOR: f64 = 32.0;

/// Samples kept per type pair: `k = 0 … 2049` (only `k ≤ 2048` are ever
/// non-zero or read).
pub const STRIDE: usize = 2050;

/// Largest index read: `r² ≥ 64` reads sample 2048, whose value is 0.
const LAST: i32 = 2048;

/// Number of X-Score types.
const TYPES: usize = XsType::ALL.len();

/// One type pair's samples.
pub type Row = [f64; STRIDE];

/// One type pair's unweighted terms at the samples `k = 0 … 2048`.
type TermRow = Box<[[f64; MAX_TERMS]]>;

/// The sampled pair energies of one scoring function.
#[derive(Debug)]
pub struct Table {
    scoring: Scoring,
    /// Per type pair, `fast_k`.
    fast: Vec<Row>,
    /// Per type pair, `smooth_k`.
    smooth: Vec<Row>,
    /// Each ordered type pair's row (symmetric).
    pair: [[u16; TYPES]; TYPES],
    /// Per type pair, the unweighted terms at the samples, made on first use.
    terms: Vec<OnceLock<TermRow>>,
}

/// `r_k = √(k/32)`, as Vina's `calculate_rs`.
#[inline]
fn sample_r(k: usize) -> f64 {
    (k as f64 / FACTOR).sqrt()
}

/// The table index of `r2`, `⌊32·r²⌋` (truncation toward zero, as Vina's
/// `sz(32·r²)`), clamped to 2048, whose samples are 0: so `r² ≥ 64` needs
/// no test of its own.
#[inline]
pub fn index(r2: f64) -> usize {
    ((FACTOR * r2) as i32).clamp(0, LAST) as usize
}

impl Table {
    fn build(scoring: Scoring) -> Self {
        let mut fast = Vec::with_capacity(TYPES * (TYPES + 1) / 2);
        let mut smooth = Vec::with_capacity(TYPES * (TYPES + 1) / 2);
        let mut pair = [[0u16; TYPES]; TYPES];
        // Both halves of the symmetric index are written at once.
        #[allow(clippy::needless_range_loop)]
        for a in 0..TYPES {
            for b in a..TYPES {
                pair[a][b] = fast.len() as u16;
                pair[b][a] = fast.len() as u16;
                let (ta, tb) = (XsType::ALL[a], XsType::ALL[b]);
                let mut s = [0.0; STRIDE];
                // From k = 2048 (r = 8 Å) on, every term is 0.
                for (k, v) in s.iter_mut().enumerate().take(LAST as usize) {
                    *v = scoring.pair_energy(ta, tb, sample_r(k));
                }
                let mut f = [0.0; STRIDE];
                for k in 0..STRIDE - 1 {
                    f[k] = (s[k] + s[k + 1]) / 2.0;
                }
                f[STRIDE - 1] = s[STRIDE - 1] / 2.0;
                fast.push(f);
                smooth.push(s);
            }
        }
        let terms = (0..fast.len()).map(|_| OnceLock::new()).collect();
        Self {
            scoring,
            fast,
            smooth,
            pair,
            terms,
        }
    }

    /// The table of `scoring`, built on first use.
    pub fn of(scoring: Scoring) -> &'static Table {
        static VINA: OnceLock<Table> = OnceLock::new();
        static VINARDO: OnceLock<Table> = OnceLock::new();
        match scoring {
            Scoring::Vina => VINA.get_or_init(|| Table::build(Scoring::Vina)),
            Scoring::Vinardo => VINARDO.get_or_init(|| Table::build(Scoring::Vinardo)),
        }
    }

    /// The scoring function sampled.
    pub fn scoring(&self) -> Scoring {
        self.scoring
    }

    /// Vina's pair energy of types `a`, `b` at squared distance `r2`
    /// (`eval_fast`); 0 for `r2 ≥ 64`.
    #[inline]
    pub fn fast(&self, a: XsType, b: XsType, r2: f64) -> f64 {
        self.fast_row(a, b)[index(r2)]
    }

    /// The samples `fast_k` of the pair `a`, `b`.
    #[inline]
    pub fn fast_row(&self, a: XsType, b: XsType) -> &Row {
        &self.fast[usize::from(self.pair[a.index()][b.index()])]
    }

    /// The samples `smooth_k` of the pair `a`, `b`.
    #[inline]
    pub fn smooth_row(&self, a: XsType, b: XsType) -> &Row {
        &self.smooth[usize::from(self.pair[a.index()][b.index()])]
    }

    /// The `fast` rows of type `a` with every type, by type index: for loops
    /// that look up many pairs of one drug atom.
    #[inline]
    pub fn fast_rows(&self, a: XsType) -> [&Row; TYPES] {
        let p = &self.pair[a.index()];
        std::array::from_fn(|b| &self.fast[usize::from(p[b])])
    }

    /// The `smooth` rows of type `a` with every type, by type index.
    #[inline]
    pub fn smooth_rows(&self, a: XsType) -> [&Row; TYPES] {
        let p = &self.pair[a.index()];
        std::array::from_fn(|b| &self.smooth[usize::from(p[b])])
    }

    /// The unweighted terms of the pair `a`, `b` at the samples `k = 0 …
    /// 2048` (the formulas' values at `r_k`), sampled on first use.
    fn terms_row(&self, a: XsType, b: XsType) -> &[[f64; MAX_TERMS]] {
        let p = usize::from(self.pair[a.index()][b.index()]);
        // Sampled in one order of the two, whichever pair asks first.
        let (a, b) = if a.index() <= b.index() {
            (a, b)
        } else {
            (b, a)
        };
        self.terms[p].get_or_init(|| {
            (0..=LAST as usize)
                .map(|k| self.scoring.pair_terms(a, b, sample_r(k)))
                .collect()
        })
    }

    /// The continuous pair energy of types `a`, `b` and its derivative with
    /// respect to r²; 0 for `r2 ≥ 64`.
    #[inline]
    pub fn smooth(&self, a: XsType, b: XsType, r2: f64) -> (f64, f64) {
        smooth_at(self.smooth_row(a, b), r2)
    }
}

/// The continuous energy of a `smooth` row at `r2` and `dE/d(r²)`: linear
/// between the samples around it (0 for `r2 ≥ 64`).
#[inline]
pub fn smooth_at(row: &Row, r2: f64) -> (f64, f64) {
    let k = index(r2);
    smooth_from(row, k, FACTOR * r2 - k as f64)
}

/// [`smooth_at`] from `k = index(r²)` and `rem = 32·r² − k`.
#[inline]
pub fn smooth_from(row: &Row, k: usize, rem: f64) -> (f64, f64) {
    let (s0, s1) = (row[k], row[k + 1]);
    let slope = s1 - s0;
    (s0 + rem * slope, FACTOR * slope)
}

/// The unweighted terms of a pair as Vina's table gives them: each term's
/// own `fast` value, `(f(r_k) + f(r_{k+1}))/2` at `k = ⌊32·r²⌋` (the table
/// is linear in the weights, so the weighted terms sum to [`Table::fast`]
/// up to rounding). Zero for `r2 ≥ 64`.
pub fn fast_terms(scoring: Scoring, a: XsType, b: XsType, r2: f64) -> [f64; MAX_TERMS] {
    let mut out = [0.0; MAX_TERMS];
    if r2 >= CUTOFF2 {
        return out;
    }
    let k = index(r2);
    let row = Table::of(scoring).terms_row(a, b);
    let (lo, hi) = (row[k], row[k + 1]);
    for t in 0..MAX_TERMS {
        out[t] = (lo[t] + hi[t]) / 2.0;
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn fast_is_the_mean_of_the_samples_around_r2() {
        let t = Table::of(Scoring::Vina);
        let (a, b) = (XsType::C_H, XsType::O_A);
        let r2 = 13.3;
        let k = (32.0 * r2) as usize;
        let want = (Scoring::Vina.pair_energy(a, b, sample_r(k))
            + Scoring::Vina.pair_energy(a, b, sample_r(k + 1)))
            / 2.0;
        assert_eq!(t.fast(a, b, r2), want);
        assert_eq!(t.fast(b, a, r2), want);
        assert_eq!(t.fast(a, b, 64.0), 0.0);
        // The last interval before the cutoff: half of its left sample.
        let last = t.fast(a, b, 63.99);
        assert_eq!(last, Scoring::Vina.pair_energy(a, b, sample_r(2047)) / 2.0);
    }

    #[test]
    fn weighted_fast_terms_sum_to_the_table() {
        for s in [Scoring::Vina, Scoring::Vinardo] {
            let t = Table::of(s);
            for &(a, b) in &[(XsType::N_D, XsType::O_A), (XsType::C_H, XsType::Cl_H)] {
                for r2 in [4.0, 9.7, 12.25, 20.0, 50.0] {
                    let terms = fast_terms(s, a, b, r2);
                    let sum: f64 = (0..s.term_count()).map(|k| s.weight(k) * terms[k]).sum();
                    assert!((sum - t.fast(a, b, r2)).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn sampled_terms_are_the_formulas_at_the_samples_either_way_round() {
        for s in [Scoring::Vina, Scoring::Vinardo] {
            for &(a, b) in &[(XsType::N_D, XsType::O_A), (XsType::C_H, XsType::Cl_H)] {
                for r2 in [0.0, 4.0, 9.7, 12.25, 20.0, 63.99, 64.0, 70.0] {
                    let got = fast_terms(s, b, a, r2);
                    assert_eq!(got, fast_terms(s, a, b, r2));
                    if r2 >= CUTOFF2 {
                        assert_eq!(got, [0.0; MAX_TERMS]);
                        continue;
                    }
                    let k = index(r2);
                    let (lo, hi) = (
                        s.pair_terms(a, b, sample_r(k)),
                        s.pair_terms(a, b, sample_r(k + 1)),
                    );
                    for t in 0..MAX_TERMS {
                        let want = (lo[t] + hi[t]) / 2.0;
                        assert!((got[t] - want).abs() <= 1e-15 * want.abs().max(1.0));
                    }
                }
            }
        }
    }

    #[test]
    fn the_smooth_slope_is_the_derivative_of_the_smooth_energy() {
        let t = Table::of(Scoring::Vina);
        let (a, b) = (XsType::C_H, XsType::C_H);
        for r2 in [10.01, 14.4, 30.3] {
            let (e, de) = t.smooth(a, b, r2);
            let h = 1e-7;
            let num = (t.smooth(a, b, r2 + h).0 - t.smooth(a, b, r2 - h).0) / (2.0 * h);
            assert!((num - de).abs() < 1e-6, "{num} vs {de}");
            // Close to the analytic energy.
            assert!((e - Scoring::Vina.pair_energy(a, b, r2.sqrt())).abs() < 1e-3);
        }
    }
}
