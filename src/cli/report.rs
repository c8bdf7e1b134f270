//! Shared output: pairs with the atoms' file identities, as JSON and text.

use bump::collide::{ContactRule, Pair};
use bump::model::Molecule;
use serde::Serialize;

/// One receptor–drug pair as the commands print it.
#[derive(Debug, Serialize)]
pub struct PairReport {
    pub receptor_serial: i64,
    pub receptor_name: String,
    pub receptor_residue: String,
    pub receptor_seq: i64,
    /// Insertion code of the receptor atom's residue, empty when none.
    pub receptor_insertion: String,
    pub receptor_chain: String,
    pub receptor_element: String,
    pub receptor_radius: f32,
    pub drug_serial: i64,
    pub drug_name: String,
    pub drug_residue: String,
    pub drug_seq: i64,
    /// Insertion code of the drug atom's residue, empty when none.
    pub drug_insertion: String,
    pub drug_chain: String,
    pub drug_element: String,
    pub drug_radius: f32,
    /// Centre distance, Å.
    pub distance: f32,
    /// r_i + r_j − d, Å.
    pub overlap: f32,
    /// Overlap at which this pair collides (0.6, or 1.0 for N/O pairs).
    pub allowance: f32,
    /// d − contact distance: ≤ 0 collides.
    pub gap: f32,
}

/// The report for `p`.
pub fn pair_report(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    p: &Pair,
) -> PairReport {
    let a = &receptor.atoms[p.receptor as usize];
    let b = &drug.atoms[p.drug as usize];
    let allowance = rule.allowance(a.polar, b.polar);
    PairReport {
        receptor_serial: a.serial,
        receptor_name: a.name.to_string(),
        receptor_residue: a.residue.to_string(),
        receptor_seq: a.seq,
        receptor_insertion: a.insertion.to_string(),
        receptor_chain: a.chain.to_string(),
        receptor_element: a.element.to_string(),
        receptor_radius: a.radius,
        drug_serial: b.serial,
        drug_name: b.name.to_string(),
        drug_residue: b.residue.to_string(),
        drug_seq: b.seq,
        drug_insertion: b.insertion.to_string(),
        drug_chain: b.chain.to_string(),
        drug_element: b.element.to_string(),
        drug_radius: b.radius,
        distance: p.distance,
        overlap: overlap(a.radius, b.radius, p, allowance),
        allowance,
        gap: p.gap(),
    }
}

/// `r_a + r_b − d` for pair `p`, on the side of `allowance` the rule puts
/// the pair: in f32 the difference can fall a unit short of the allowance
/// for a pair that collides (`d` equal to the contact distance, itself
/// rounded), or reach it for one that does not, and a reader who applies
/// the rule to the printed numbers would then disagree with the verdict.
fn overlap(r_a: f32, r_b: f32, p: &Pair, allowance: f32) -> f32 {
    let raw = r_a + r_b - p.distance;
    if p.collides() {
        raw.max(allowance)
    } else {
        raw.min(allowance.next_down())
    }
}

/// Reports for a list of pairs.
pub fn pair_reports(
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    pairs: &[Pair],
) -> Vec<PairReport> {
    pairs
        .iter()
        .map(|p| pair_report(rule, receptor, drug, p))
        .collect()
}

/// `n` and the noun, plural unless `n` is 1: "1 pair", "2 pairs".
pub fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// A fraction of a motion in [0, 1] to six decimals, or more digits where
/// six would round a partial motion to 0 or to 1 (a step of 10⁹ Å that
/// moves the drug 0.5 Å is t = 5.1e-10, not 0).
pub fn fraction(t: f64) -> String {
    let six = format!("{t:.6}");
    if t > 0.0 && six == "0.000000" {
        format!("{t:.3e}")
    } else if t < 1.0 && six == "1.000000" {
        // Enough decimals to show the first digit that is not 9.
        let decimals = (-(1.0 - t).log10()).ceil() as usize + 2;
        format!("{t:.*}", decimals.min(17))
    } else {
        six
    }
}

/// Prints pairs as an aligned table.
pub fn print_pairs(reports: &[PairReport]) {
    if reports.is_empty() {
        return;
    }
    outln!(
        "  {:>7} {:<4} {:<4} {:>5} {:<2} | {:>6} {:<4} {:<4} | {:>7} {:>7} {:>7}",
        "serial",
        "name",
        "res",
        "seq",
        "ch",
        "serial",
        "name",
        "res",
        "dist",
        "overlap",
        "gap"
    );
    for r in reports {
        outln!(
            "  {:>7} {:<4} {:<4} {:>5} {:<2} | {:>6} {:<4} {:<4} | {:>7.3} {:>7.3} {:>7.3}",
            r.receptor_serial,
            r.receptor_name,
            r.receptor_residue,
            format!("{}{}", r.receptor_seq, r.receptor_insertion),
            r.receptor_chain,
            r.drug_serial,
            r.drug_name,
            r.drug_residue,
            r.distance,
            r.overlap,
            r.gap
        );
    }
}

/// The contact rule and radii as reported.
#[derive(Debug, Serialize)]
pub struct RuleReport {
    pub overlap: f32,
    pub hbond_allowance: f32,
    pub radii: &'static str,
    pub hydrogens: &'static str,
    pub description: &'static str,
}

/// The rule report for a scene's options.
pub fn rule_report(args: &super::SceneArgs, rule: &ContactRule) -> RuleReport {
    RuleReport {
        overlap: rule.overlap,
        hbond_allowance: rule.hbond_allowance,
        radii: args.radii.name(),
        hydrogens: match args.hydrogens {
            bump::model::Hydrogens::Drop => "drop",
            bump::model::Hydrogens::Keep => "keep",
        },
        description: "a pair collides when r_i + r_j - d >= overlap (+ hbond_allowance when both are N/O)",
    }
}

/// A molecule as reported.
#[derive(Debug, Serialize)]
pub struct MoleculeReport {
    pub source: String,
    pub name: String,
    pub atoms: usize,
}

/// Writes the text report's first line: the receptor and the drug, with
/// their atom counts.
pub fn print_molecules(receptor: &MoleculeReport, drug: &MoleculeReport) {
    outln!(
        "receptor {} ({}), drug {} ({})",
        receptor.name,
        counted(receptor.atoms, "atom"),
        drug.name,
        counted(drug.atoms, "atom")
    );
}

/// The report for a molecule.
pub fn molecule_report(source: &str, m: &Molecule) -> MoleculeReport {
    MoleculeReport {
        source: source.to_string(),
        name: m.name.clone(),
        atoms: m.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_never_round_a_partial_motion_to_its_ends() {
        assert_eq!(fraction(0.0), "0.000000");
        assert_eq!(fraction(1.0), "1.000000");
        assert_eq!(fraction(0.25), "0.250000");
        assert_eq!(fraction(5.0914e-10), "5.091e-10");
        assert_eq!(fraction(0.999_999_758), "0.999999758");
        assert_eq!(fraction(1.0 - 1e-16), "0.99999999999999989");
        assert_eq!(fraction(0.999_999_4), "0.999999");
    }

    #[test]
    fn overlaps_say_what_the_rule_says() {
        let rule = ContactRule::default();
        let (r, allowance) = (1.7f32, rule.allowance(false, false));
        let c = rule.contact_distance(r, false, r, false);
        // At contact (2.8000002 Å) the plain difference is 0.5999999.
        assert!(r + r - c < allowance);
        let pair = |distance: f32| Pair {
            receptor: 0,
            drug: 0,
            distance,
            contact: c,
        };
        let mut d = c.next_down().next_down();
        for _ in 0..5 {
            let p = pair(d);
            let o = overlap(r, r, &p, allowance);
            assert_eq!(o >= allowance, p.collides(), "d {d} overlap {o}");
            // Moved by a unit at most.
            assert!((o - (r + r - d)).abs() <= 2.0 * f32::EPSILON, "{o}");
            d = d.next_up();
        }
        // Far from contact: the plain difference.
        assert_eq!(overlap(r, r, &pair(2.0), allowance), r + r - 2.0);
        assert_eq!(overlap(r, r, &pair(3.5), allowance), r + r - 3.5);
    }
}
