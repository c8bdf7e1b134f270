//! The V3000 atom block: the `M  V30` lines (with `-` continuation) joined
//! into logical lines, and the atoms between `BEGIN ATOM` and `END ATOM`
//! checked against the `COUNTS` line.

use super::{RawAtoms, Record};
use crate::model::LoadError;
use crate::text::excerpt;

impl Record<'_> {
    /// The record's logical `M  V30` lines (continuations joined), each
    /// with the record line index of its first physical line, and the
    /// index of the `M  END` line.
    pub(super) fn v30_logical(&self) -> Result<(Vec<(usize, String)>, usize), LoadError> {
        // Logical V30 lines: (record line index of the first physical line, text).
        let mut logical: Vec<(usize, String)> = Vec::new();
        let mut pending: Option<(usize, String)> = None;
        let mut end_at = self.lines.len();
        for (i, line) in self.lines.iter().enumerate().skip(4) {
            if line.starts_with("M  END") {
                end_at = i;
                break;
            }
            let Some(body) = line.strip_prefix("M  V30") else {
                if let Some(p) = pending.take() {
                    return Err(self.err(
                        p.0,
                        "V3000 line ends with '-' but no continuation line follows",
                    ));
                }
                continue;
            };
            let body = body.strip_prefix(' ').unwrap_or(body);
            let (start, mut text) = pending.take().unwrap_or((i, String::new()));
            let trimmed = body.trim_end();
            if let Some(cont) = trimmed.strip_suffix('-') {
                text.push_str(cont);
                pending = Some((start, text));
            } else {
                text.push_str(trimmed);
                logical.push((start, text));
            }
        }
        if let Some(p) = pending {
            return Err(self.err(
                p.0,
                "V3000 line ends with '-' but no continuation line follows",
            ));
        }
        Ok((logical, end_at))
    }

    pub(super) fn parse_v3000(&self) -> Result<RawAtoms, LoadError> {
        let (logical, end_at) = self.v30_logical()?;

        let upper = |s: &str| s.trim().to_ascii_uppercase();
        let Some((counts_i, counts)) = logical.iter().find(|(_, t)| upper(t).starts_with("COUNTS"))
        else {
            return Err(self.err(3, "V3000 record has no COUNTS line"));
        };
        let n_atoms = counts
            .split_whitespace()
            .nth(1)
            .and_then(|t| t.parse::<usize>().ok())
            .ok_or_else(|| {
                self.err(
                    *counts_i,
                    format!("malformed COUNTS line: {}", excerpt(counts.trim())),
                )
            })?;
        let Some(begin) = logical.iter().position(|(_, t)| upper(t) == "BEGIN ATOM") else {
            if n_atoms == 0 {
                return Ok(Vec::new());
            }
            return Err(self.err(
                end_at,
                format!("COUNTS says {n_atoms} atoms but there is no BEGIN ATOM block"),
            ));
        };
        // Not sized by COUNTS: it may claim 10^18 atoms.
        let mut atoms = Vec::new();
        for (i, text) in &logical[begin + 1..] {
            if upper(text) == "END ATOM" {
                if atoms.len() != n_atoms {
                    return Err(self.err(
                        *i,
                        format!(
                            "COUNTS says {n_atoms} atoms but the atom block holds {}",
                            atoms.len()
                        ),
                    ));
                }
                return Ok(atoms);
            }
            if atoms.len() == n_atoms {
                return Err(self.err(
                    *i,
                    format!(
                        "COUNTS says {n_atoms} atoms but this is atom {}",
                        n_atoms + 1
                    ),
                ));
            }
            let fields: Vec<&str> = text.split_whitespace().collect();
            if fields.len() < 5 {
                return Err(self.err(
                    *i,
                    format!(
                        "atom line too short (need index, type, x, y, z): {}",
                        excerpt(text.trim())
                    ),
                ));
            }
            let pos = self.coords(*i, &fields[2..5])?;
            atoms.push((fields[1].trim_matches('"').to_string(), pos));
        }
        Err(self.err(end_at, "V3000 atom block has no END ATOM line"))
    }
}
