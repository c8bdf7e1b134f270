//! A pose's score term by term: Vina's total, the intermolecular and
//! intramolecular energies, each term weighted and unweighted, each drug
//! atom's contribution and the hydrogen bonds.
//!
//! The totals and the per-atom contributions come from the evaluator asked
//! for (exact or maps); the terms and the hydrogen bonds need the atom pairs,
//! so they always come from the exact evaluator. Term sums are plain sums of
//! the pairs' table values (as Vina's `terms_raw` with weight −1): the curl,
//! which damps a drug atom's positive sum, is applied to the totals only, so
//! on a clashing pose the weighted terms add up to a little more than
//! `inter`.
//!
//! A **hydrogen bond** is a receptor–drug pair whose hydrogen-bond term is
//! not zero: one atom a donor and the other an acceptor (by X-Score type)
//! and the centre distance below the sum of their radii (3.5 Å for N–O in
//! Vina, 3.3 Å in Vinardo), which is where Vina's term starts to count; it
//! counts fully 0.7 Å closer (0.6 in Vinardo).

use serde::Serialize;

use super::exact::Exact;
use super::field::{Field, Workspace};
use super::function::{CUTOFF2, MAX_TERMS, Scoring, curl, hbond_possible, torsion_divisor};
use super::ligand::{Conformation, Ligand};
use super::table::{Table, fast_terms, index};
use crate::chem::XsType;

/// Which evaluator gave a score's totals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Evaluator {
    /// Pairwise over the receptor atoms within 8 Å.
    Exact,
    /// Interpolated grid maps.
    Maps,
}

impl Evaluator {
    /// Parses `exact` or `maps`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "exact" => Some(Self::Exact),
            "maps" | "map" | "grid" => Some(Self::Maps),
            _ => None,
        }
    }

    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Maps => "maps",
        }
    }
}

/// One term's sums over a pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TermScore {
    /// The term's name (`gauss1`, `repulsion`, …).
    pub name: &'static str,
    /// Its weight.
    pub weight: f64,
    /// Unweighted sum over the receptor–drug pairs.
    pub inter_raw: f64,
    /// Weighted sum over the receptor–drug pairs (kcal/mol).
    pub inter: f64,
    /// Unweighted sum over the intramolecular pairs.
    pub intra_raw: f64,
    /// Weighted sum over the intramolecular pairs (kcal/mol).
    pub intra: f64,
}

/// One drug atom's share of the intermolecular energy.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AtomScore {
    /// Heavy-atom index in the drug.
    pub atom: u32,
    /// Its X-Score type.
    pub xs: XsType,
    /// Its intermolecular energy after the curl (kcal/mol); these sum to
    /// the score's `inter`.
    pub inter: f64,
    /// Its weighted terms, in the scoring function's order (kcal/mol).
    pub terms: Vec<f64>,
}

/// Which atom of a hydrogen bond donates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Donor {
    /// The drug atom donates, the receptor atom accepts.
    Drug,
    /// The receptor atom donates.
    Receptor,
    /// Both atoms can donate and accept (two hydroxyls, say).
    Either,
}

/// A receptor–drug pair with a non-zero hydrogen-bond term.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HBond {
    /// Heavy-atom index in the drug.
    pub drug_atom: u32,
    /// Index of the receptor atom in the list the receptor was built from
    /// ([`super::Receptor::source`]).
    pub receptor_atom: u32,
    /// Which one donates.
    pub donor: Donor,
    /// Centre distance (Å).
    pub distance: f64,
    /// The weighted hydrogen-bond term of the pair (kcal/mol).
    pub energy: f64,
}

/// A pose's score.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Score {
    /// The scoring function.
    pub scoring: Scoring,
    /// The evaluator that gave `inter` and the atoms' shares.
    pub evaluator: Evaluator,
    /// Vina's reported affinity: `inter / divisor` (kcal/mol).
    pub total: f64,
    /// Intermolecular energy, before the torsion division (kcal/mol).
    pub inter: f64,
    /// Intramolecular energy (kcal/mol; not part of `total`, as in Vina's
    /// `score()`).
    pub intra: f64,
    /// Vina's torsion count.
    pub torsion_count: f64,
    /// `1 + 0.05846 · torsion_count`.
    pub divisor: f64,
    /// The terms.
    pub terms: Vec<TermScore>,
    /// Each scored drug atom's share.
    pub atoms: Vec<AtomScore>,
    /// Hydrogen bonds, by drug atom then receptor atom.
    pub hbonds: Vec<HBond>,
}

/// Scores `conf`: totals and atoms' shares from `field` (reported as
/// `evaluator`), terms and hydrogen bonds from `exact`.
pub fn score<F: Field + ?Sized>(
    field: &F,
    evaluator: Evaluator,
    exact: &Exact<'_>,
    lig: &Ligand,
    conf: &Conformation,
) -> Score {
    score_collecting(field, evaluator, exact, lig, conf, None)
}

/// [`score`], and each receptor atom's share of the intermolecular energy
/// (as [`super::contrib::receptor_contributions`] gives it, to the bit),
/// collected during the score's own walk over the pairs.
pub fn score_with_contributions<F: Field + ?Sized>(
    field: &F,
    evaluator: Evaluator,
    exact: &Exact<'_>,
    lig: &Ligand,
    conf: &Conformation,
) -> (Score, Vec<(u32, f64)>) {
    let mut pairs = Vec::new();
    let s = score_collecting(field, evaluator, exact, lig, conf, Some(&mut pairs));
    (s, super::contrib::merge(pairs))
}

/// [`score`]; with `pairs`, each receptor–drug pair's table energy
/// `(receptor atom, energy)` too, in the walk's order.
fn score_collecting<F: Field + ?Sized>(
    field: &F,
    evaluator: Evaluator,
    exact: &Exact<'_>,
    lig: &Ligand,
    conf: &Conformation,
    mut pairs: Option<&mut Vec<(u32, f64)>>,
) -> Score {
    let scoring = exact.scoring();
    let table = Table::of(scoring);
    let nt = scoring.term_count();
    let mut ws = Workspace::default();
    let energies = super::field::energies(field, lig, conf, &mut ws);
    let x = std::mem::take(&mut ws.positions);
    // Each scored atom's intermolecular energy before the curl, as `field`
    // gave it for the total.
    let inter_energy = ws.inter_energy();
    let receptor = exact.receptor();
    let mut terms: Vec<TermScore> = (0..nt)
        .map(|k| TermScore {
            name: scoring.term_name(k),
            weight: scoring.weight(k),
            inter_raw: 0.0,
            inter: 0.0,
            intra_raw: 0.0,
            intra: 0.0,
        })
        .collect();
    let mut atoms = Vec::with_capacity(lig.scored.len());
    let mut hbonds = Vec::new();
    for (at, (&i, &t)) in lig.scored.iter().zip(&lig.xs).enumerate() {
        let xi = x[i as usize];
        let mut raw = [0.0; MAX_TERMS];
        let rows = table.fast_rows(t);
        exact.neighbours(xi, |j, r2| {
            let u = receptor.xs[j];
            if let Some(p) = pairs.as_deref_mut() {
                p.push((receptor.source[j], rows[u.index()][index(r2)]));
            }
            let f = fast_terms(scoring, t, u, r2);
            for k in 0..nt {
                raw[k] += f[k];
            }
            // The distance only for pairs that can H-bond.
            let r = if hbond_possible(t, u) {
                r2.sqrt()
            } else {
                f64::INFINITY
            };
            if r < scoring.radius(t) + scoring.radius(u) {
                let donor = match (
                    t.is_donor() && u.is_acceptor(),
                    u.is_donor() && t.is_acceptor(),
                ) {
                    (true, true) => Donor::Either,
                    (true, false) => Donor::Drug,
                    _ => Donor::Receptor,
                };
                hbonds.push(HBond {
                    drug_atom: i,
                    receptor_atom: receptor.source[j],
                    donor,
                    distance: r,
                    energy: scoring.weight(nt - 1) * f[nt - 1],
                });
            }
        });
        for k in 0..nt {
            terms[k].inter_raw += raw[k];
        }
        atoms.push(AtomScore {
            atom: i,
            xs: t,
            inter: curl(inter_energy.get(at).copied().unwrap_or(0.0)),
            terms: (0..nt).map(|k| scoring.weight(k) * raw[k]).collect(),
        });
    }
    for &[a, b] in &lig.pairs {
        let (i, j) = (
            lig.scored[a as usize] as usize,
            lig.scored[b as usize] as usize,
        );
        let r2 = (x[i] - x[j]).length_squared();
        if r2 < CUTOFF2 {
            let f = fast_terms(scoring, lig.xs[a as usize], lig.xs[b as usize], r2);
            for k in 0..nt {
                terms[k].intra_raw += f[k];
            }
        }
    }
    for t in &mut terms {
        t.inter = t.weight * t.inter_raw;
        t.intra = t.weight * t.intra_raw;
    }
    hbonds.sort_by_key(|h| (h.drug_atom, h.receptor_atom));
    let divisor = torsion_divisor(lig.torsion_count);
    Score {
        scoring,
        evaluator,
        total: energies.inter / divisor,
        inter: energies.inter,
        intra: energies.intra,
        torsion_count: lig.torsion_count,
        divisor,
        terms,
        atoms,
        hbonds,
    }
}

/// The table index of `r2` (re-exported for callers that bin distances as
/// Vina does).
pub fn table_index(r2: f64) -> usize {
    index(r2)
}
