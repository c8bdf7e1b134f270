//! The V2000 atom block: the atom count from the counts line, then one
//! line per atom read by its fixed columns (x, y, z in 1–10, 11–20, 21–30,
//! the symbol in 32–34), or as whitespace-separated fields where a writer
//! does not pad; every coordinate checked as a finite number in range.

use glam::DVec3;

use super::{RawAtoms, Record};
use crate::model::{LoadError, MAX_FILE_COORDINATE};
use crate::text::excerpt;

impl Record<'_> {
    pub(super) fn parse_v2000(&self, counts: &str) -> Result<RawAtoms, LoadError> {
        let n_atoms = counts
            .get(0..3)
            .and_then(|f| f.trim().parse::<usize>().ok())
            .or_else(|| {
                counts
                    .split_whitespace()
                    .next()
                    .and_then(|t| t.parse::<usize>().ok())
            })
            .ok_or_else(|| {
                self.err(
                    3,
                    format!(
                        "malformed counts line (no atom count): {}",
                        excerpt(counts.trim())
                    ),
                )
            })?;
        // Not sized by the count: a counts line may claim 10^18 atoms.
        let mut atoms = Vec::new();
        for k in 0..n_atoms {
            let i = 4 + k;
            let Some(line) = self.lines.get(i) else {
                return Err(self.err(
                    3,
                    format!(
                        "counts line says {n_atoms} atoms but the record ends after {k} atom lines"
                    ),
                ));
            };
            if line.starts_with("M  ") {
                return Err(self.err(
                    i,
                    format!("counts line says {n_atoms} atoms but the atom block ends after {k}"),
                ));
            }
            atoms.push(self.v2000_atom(i, line, k, n_atoms)?);
        }
        if let Some(next) = self.lines.get(n_atoms.saturating_add(4))
            && looks_like_v2000_atom(next)
        {
            return Err(self.err(
                4 + n_atoms,
                format!("counts line says {n_atoms} atoms but this line is another atom line"),
            ));
        }
        Ok(atoms)
    }

    /// One V2000 atom line: fixed columns, else whitespace fields.
    pub(super) fn v2000_atom(
        &self,
        i: usize,
        line: &str,
        k: usize,
        n_atoms: usize,
    ) -> Result<(String, DVec3), LoadError> {
        if let Some(atom) = fixed_v2000_atom(line) {
            return Ok(atom);
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        // Coordinates in their columns and a blank symbol field, with no
        // symbol further on either: say so, rather than "not a symbol".
        let no_symbol = fields
            .get(3)
            .is_none_or(|f| !f.starts_with(|c: char| c.is_ascii_alphabetic() || c == '*'))
            && fixed_v2000_coords(line).is_some()
            && line
                .get(31..line.len().min(34))
                .is_none_or(|f| f.trim().is_empty());
        if no_symbol {
            return Err(self.err(
                i,
                format!(
                    "atom {} of {n_atoms} has no element symbol (columns 32–34 are blank)",
                    k + 1
                ),
            ));
        }
        if fields.len() < 4 {
            return Err(self.err(
                i,
                format!(
                    "atom line too short (need x, y, z and an element): {}",
                    excerpt(line.trim())
                ),
            ));
        }
        let pos = self.coords(i, &fields[0..3])?;
        if !fields[3].starts_with(|c: char| c.is_ascii_alphabetic() || c == '*') {
            return Err(self.err(
                i,
                format!(
                    "atom {} of {n_atoms}: {} is not an element symbol \
                     (is the atom count on the counts line right?)",
                    k + 1,
                    excerpt(fields[3])
                ),
            ));
        }
        Ok((fields[3].to_string(), pos))
    }

    /// Parses three coordinate fields, rejecting non-numbers and non-finite values.
    pub(super) fn coords(&self, i: usize, fields: &[&str]) -> Result<DVec3, LoadError> {
        let mut v = [0.0_f64; 3];
        for (axis, (slot, text)) in v.iter_mut().zip(fields).enumerate() {
            let name = ["x", "y", "z"][axis];
            let value: f64 = text.trim().parse().map_err(|_| {
                self.err(
                    i,
                    format!(
                        "{name} coordinate is not a number: {}",
                        excerpt(text.trim())
                    ),
                )
            })?;
            if !value.is_finite() {
                return Err(self.err(
                    i,
                    format!("{name} coordinate is not finite: {}", excerpt(text.trim())),
                ));
            }
            if value.abs() > MAX_FILE_COORDINATE {
                return Err(self.err(
                    i,
                    format!(
                        "{name} coordinate {} is beyond ±{MAX_FILE_COORDINATE:e} Å",
                        text.trim()
                    ),
                ));
            }
            *slot = value;
        }
        Ok(DVec3::from_array(v))
    }
}

/// A V2000 atom line read by its fixed columns, if it fits them.
pub(super) fn fixed_v2000_atom(line: &str) -> Option<(String, DVec3)> {
    let pos = fixed_v2000_coords(line)?;
    let symbol = line.get(31..line.len().min(34))?.trim();
    if symbol.is_empty() || symbol.contains(char::is_whitespace) {
        return None;
    }
    Some((symbol.to_string(), pos))
}

/// The coordinates of a V2000 atom line in its fixed columns (1–10, 11–20,
/// 21–30), when all three are finite numbers in range.
pub(super) fn fixed_v2000_coords(line: &str) -> Option<DVec3> {
    let num = |r: std::ops::Range<usize>| {
        line.get(r)
            .and_then(|f| f.trim().parse::<f64>().ok())
            // Anything else is read (and refused, naming it) field by field.
            .filter(|v| v.is_finite() && v.abs() <= MAX_FILE_COORDINATE)
    };
    Some(DVec3::new(num(0..10)?, num(10..20)?, num(20..30)?))
}

/// True when a line reads as a V2000 atom line (three numbers with a decimal
/// point, then a symbol starting with a letter). Bond lines hold integers.
pub(super) fn looks_like_v2000_atom(line: &str) -> bool {
    let fields: Vec<&str> = line.split_whitespace().collect();
    fields.len() >= 4
        && fields[..3]
            .iter()
            .all(|f| f.contains('.') && f.parse::<f64>().is_ok())
        && fields[3].starts_with(|c: char| c.is_ascii_alphabetic())
}
