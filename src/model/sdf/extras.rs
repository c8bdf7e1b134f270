//! What a record says beyond its atoms: the bond block (V2000 bond lines,
//! or the V3000 `BEGIN BOND` block) with MDL bond types as orders, and the
//! formal charges (the V2000 charge column, replaced by `M  CHG` lines, or
//! V3000 `CHG=`). A bond naming atom 0, an atom past the count or the same
//! atom twice is left out with a warning naming the line.

use super::{Record, version_tag};
use crate::model::BondOrder;
use crate::text::excerpt;

/// What a record says beyond its atoms: bonds and formal charges.
#[derive(Debug, Default)]
pub(super) struct Extras {
    /// Bonds as (first atom, second atom) 0-based, with the order.
    pub(super) bonds: Vec<(usize, usize, BondOrder)>,
    /// Formal charge per atom (all atoms of the record).
    pub(super) charges: Vec<i8>,
    /// True when the record has a bond block with at least one bond.
    pub(super) bond_block: bool,
    /// Problems that leave a bond out, naming the line.
    pub(super) warnings: Vec<String>,
}

/// The order of an MDL bond type (1–3 as such, 4 aromatic, the query types
/// 5–8 unspecified).
pub(super) fn mdl_order(code: i64) -> Option<BondOrder> {
    Some(match code {
        1 => BondOrder::Single,
        2 => BondOrder::Double,
        3 => BondOrder::Triple,
        4 => BondOrder::Aromatic,
        5..=8 => BondOrder::Unspecified,
        _ => return None,
    })
}

impl Record<'_> {
    /// A warning naming the file and line of record line `i`.
    pub(super) fn warning(&self, i: usize, what: String) -> String {
        format!("{}:{}: {what}", self.label, self.line_no(i))
    }

    /// Checks a bond's atom numbers (1-based, as written) against the
    /// atom count; the 0-based pair when both are atoms.
    pub(super) fn bond_atoms(
        &self,
        i: usize,
        a: i64,
        b: i64,
        n_atoms: usize,
        out: &mut Extras,
    ) -> Option<(usize, usize)> {
        let ok = |x: i64| x >= 1 && usize::try_from(x).is_ok_and(|x| x <= n_atoms);
        for x in [a, b] {
            if !ok(x) {
                out.warnings.push(self.warning(
                    i,
                    format!(
                        "bond names atom {x}, but the atoms are numbered 1 to {n_atoms}; \
                         the bond is left out"
                    ),
                ));
                return None;
            }
        }
        if a == b {
            out.warnings
                .push(self.warning(i, format!("bond joins atom {a} to itself; it is left out")));
            return None;
        }
        Some((usize::try_from(a - 1).ok()?, usize::try_from(b - 1).ok()?))
    }

    /// Reads the bond block and charges of a record whose atoms `parse`
    /// read (`n_atoms` of them). Never fails: a malformed bond line is
    /// left out with a warning.
    pub(super) fn extras(&self, n_atoms: usize) -> Extras {
        let mut out = Extras {
            charges: vec![0; n_atoms],
            ..Extras::default()
        };
        let v3000 = self
            .lines
            .get(3)
            .and_then(|c| version_tag(c))
            .is_some_and(|t| t.eq_ignore_ascii_case("V3000"));
        if v3000 {
            self.extras_v3000(n_atoms, &mut out);
        } else {
            self.extras_v2000(n_atoms, &mut out);
        }
        out.bond_block = !out.bonds.is_empty();
        out
    }

    pub(super) fn extras_v2000(&self, n_atoms: usize, out: &mut Extras) {
        let counts = self.lines.get(3).copied().unwrap_or("");
        let n_bonds = counts
            .get(3..6)
            .and_then(|f| f.trim().parse::<usize>().ok())
            .or_else(|| {
                counts
                    .split_whitespace()
                    .nth(1)
                    .and_then(|t| t.parse().ok())
            })
            .unwrap_or(0);
        // Atom-block charges (column 37–39: 3 = +1, 5 = -1, ...).
        for k in 0..n_atoms {
            let code = self
                .lines
                .get(4 + k)
                .and_then(|l| l.get(36..39))
                .and_then(|f| f.trim().parse::<i64>().ok())
                .unwrap_or(0);
            out.charges[k] = match code {
                1 => 3,
                2 => 2,
                3 => 1,
                5 => -1,
                6 => -2,
                7 => -3,
                _ => 0,
            };
        }
        let first = 4 + n_atoms;
        for k in 0..n_bonds {
            let i = first + k;
            let Some(line) = self.lines.get(i) else {
                out.warnings.push(self.warning(
                    self.lines.len().saturating_sub(1),
                    format!("counts line says {n_bonds} bonds but the record ends after {k}"),
                ));
                break;
            };
            if line.starts_with("M  ") {
                out.warnings.push(self.warning(
                    i,
                    format!("counts line says {n_bonds} bonds but the bond block ends after {k}"),
                ));
                break;
            }
            let fixed =
                |r: std::ops::Range<usize>| line.get(r).and_then(|f| f.trim().parse::<i64>().ok());
            let fields: Vec<i64> = match (fixed(0..3), fixed(3..6), fixed(6..9)) {
                (Some(a), Some(b), Some(t)) => vec![a, b, t],
                _ => line
                    .split_whitespace()
                    .take(3)
                    .map_while(|f| f.parse::<i64>().ok())
                    .collect(),
            };
            let &[a, b, t] = fields.as_slice() else {
                out.warnings.push(self.warning(
                    i,
                    format!(
                        "malformed bond line {}; it is left out",
                        excerpt(line.trim())
                    ),
                ));
                continue;
            };
            let Some(order) = mdl_order(t) else {
                out.warnings.push(self.warning(
                    i,
                    format!("bond type {t} is not an MDL bond type; read as unspecified"),
                ));
                if let Some((x, y)) = self.bond_atoms(i, a, b, n_atoms, out) {
                    out.bonds.push((x, y, BondOrder::Unspecified));
                }
                continue;
            };
            if let Some((x, y)) = self.bond_atoms(i, a, b, n_atoms, out) {
                out.bonds.push((x, y, order));
            }
        }
        // `M  CHG` lines replace every atom-block charge.
        let mut reset = false;
        for (i, line) in self.lines.iter().enumerate().skip(first) {
            let Some(rest) = line.strip_prefix("M  CHG") else {
                continue;
            };
            if !reset {
                out.charges.iter_mut().for_each(|c| *c = 0);
                reset = true;
            }
            let nums: Vec<i64> = rest
                .split_whitespace()
                .map_while(|f| f.parse::<i64>().ok())
                .collect();
            for pair in nums.get(1..).unwrap_or(&[]).chunks(2) {
                if let &[a, q] = pair {
                    match usize::try_from(a).ok().filter(|&a| a >= 1 && a <= n_atoms) {
                        Some(a) => out.charges[a - 1] = i8::try_from(q).unwrap_or(0),
                        None => out.warnings.push(self.warning(
                            i,
                            format!(
                                "M  CHG names atom {a}, but the atoms are numbered 1 to {n_atoms}"
                            ),
                        )),
                    }
                }
            }
        }
    }

    pub(super) fn extras_v3000(&self, n_atoms: usize, out: &mut Extras) {
        let Ok((logical, _)) = self.v30_logical() else {
            return;
        };
        let upper = |s: &str| s.trim().to_ascii_uppercase();
        let mut block = "";
        let mut atom_k = 0;
        for (i, text) in &logical {
            let u = upper(text);
            match u.as_str() {
                "BEGIN ATOM" => {
                    block = "atom";
                    continue;
                }
                "BEGIN BOND" => {
                    block = "bond";
                    continue;
                }
                _ if u.starts_with("END ") => {
                    block = "";
                    continue;
                }
                _ => {}
            }
            let fields: Vec<&str> = text.split_whitespace().collect();
            if block == "atom" {
                if atom_k < n_atoms {
                    for f in &fields {
                        if let Some(q) = f.strip_prefix("CHG=").and_then(|q| q.parse::<i8>().ok()) {
                            out.charges[atom_k] = q;
                        }
                    }
                }
                atom_k += 1;
            } else if block == "bond" {
                let nums: Vec<i64> = fields
                    .iter()
                    .take(4)
                    .map_while(|f| f.parse::<i64>().ok())
                    .collect();
                let &[_, t, a, b] = nums.as_slice() else {
                    out.warnings.push(self.warning(
                        *i,
                        format!(
                            "malformed bond line {}; it is left out",
                            excerpt(text.trim())
                        ),
                    ));
                    continue;
                };
                let order = mdl_order(t).unwrap_or(BondOrder::Unspecified);
                if let Some((x, y)) = self.bond_atoms(*i, a, b, n_atoms, out) {
                    out.bonds.push((x, y, order));
                }
            }
        }
    }
}
