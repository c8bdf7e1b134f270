//! `pdbtbx`'s findings as bump's messages: a fatal one becomes a
//! [`LoadError::Parse`] with the line its context points at, non-fatal ones
//! become warnings (at most [`MAX_PARSER_WARNINGS`], then a count).

use pdbtbx::{Context, PDBError, StrictnessLevel};

use crate::model::LoadError;

/// At most this many parser warnings are reported one by one; the rest are counted.
const MAX_PARSER_WARNINGS: usize = 20;

/// The error for a failed `pdbtbx` read: the first fatal finding, with its line.
pub(super) fn fatal_error(label: &str, errors: &[PDBError]) -> LoadError {
    let fatal: Vec<&PDBError> = errors
        .iter()
        .filter(|e| e.fails(StrictnessLevel::Loose))
        .collect();
    let Some(first) = fatal.first().copied().or(errors.first()) else {
        return LoadError::Parse {
            path: label.to_string(),
            line: None,
            reason: "the PDB/mmCIF parser failed without saying why".to_string(),
        };
    };
    let mut reason = describe(first);
    if fatal.len() > 1 {
        reason.push_str(&format!(" (and {} more errors)", fatal.len() - 1));
    }
    LoadError::Parse {
        path: label.to_string(),
        line: context_line(first.context()),
        reason,
    }
}

/// `short: long`, on one line.
fn describe(e: &PDBError) -> String {
    let long = e.long_description().trim();
    let short = e.short_description().trim();
    let mut text = if long.is_empty() {
        short.to_string()
    } else {
        format!("{short}: {long}")
    };
    if let Context::Show { line } = e.context()
        && !line.trim().is_empty()
    {
        text.push_str(&format!(" [{}]", line.trim()));
    }
    text.replace('\n', " ")
}

/// The 1-based line number a `pdbtbx` context points at, if any.
fn context_line(c: &Context) -> Option<usize> {
    match c {
        Context::FullLine { linenumber, .. } | Context::Line { linenumber, .. } => {
            Some(*linenumber)
        }
        Context::Range {
            start_linenumber, ..
        }
        | Context::RangeHighlights {
            start_linenumber, ..
        } => Some(*start_linenumber),
        Context::Multiple { contexts } => contexts.iter().find_map(|(_, c)| context_line(c)),
        Context::None | Context::Show { .. } => None,
    }
}

/// The parser's non-fatal findings as messages, at most [`MAX_PARSER_WARNINGS`].
pub(super) fn parser_warning_lines(label: &str, warnings: &[PDBError]) -> Vec<String> {
    let mut out: Vec<String> = warnings
        .iter()
        .take(MAX_PARSER_WARNINGS)
        .map(|w| match context_line(w.context()) {
            Some(l) => format!("{label}:{l}: {}", describe(w)),
            None => format!("{label}: {}", describe(w)),
        })
        .collect();
    if warnings.len() > MAX_PARSER_WARNINGS {
        out.push(format!(
            "{label}: ... and {} more parser warnings",
            warnings.len() - MAX_PARSER_WARNINGS
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn parser_warnings_are_capped() {
        let warnings: Vec<PDBError> = (0..30)
            .map(|i| {
                PDBError::new(
                    pdbtbx::ErrorLevel::GeneralWarning,
                    "w",
                    "x",
                    Context::full_line(i + 1, "L"),
                )
            })
            .collect();
        let lines = parser_warning_lines("f.pdb", &warnings);
        assert_eq!(lines.len(), MAX_PARSER_WARNINGS + 1);
        assert_eq!(lines[0], "f.pdb:1: w: x");
        assert!(lines[MAX_PARSER_WARNINGS].contains("10 more"));
    }
}
