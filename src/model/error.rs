//! Errors from reading and splitting molecule files. Every message names the
//! file, and the line (and column) where the reader knows it, and quotes at
//! most a short excerpt of the input ([`crate::text::excerpt`]).

use thiserror::Error;

/// Why a molecule could not be loaded or split.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    // The I/O error is part of the message, not a `source`: reporters that
    // print the chain of causes would print it twice.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The extension names no format bump reads.
    #[error(
        "{path}: unknown format (expected .pdb, .ent, .cif, .mmcif, .pdbqt, .sdf, .mol or .mol2, optionally .gz)"
    )]
    UnknownFormat {
        /// The file.
        path: String,
    },
    /// The file is not valid in its format.
    #[error("{path}{}{}: {reason}",
        line.map(|l| format!(":{l}")).unwrap_or_default(),
        line.and(*column).map(|c| format!(":{c}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// 1-based column (in characters) on that line, when it helps.
        column: Option<usize>,
        /// What is wrong.
        reason: String,
    },
    /// The file decompresses to more than the limit
    /// ([`field@super::LoadOptions::decompressed_limit`]).
    #[error("{path}: {}", crate::text::SourceError::TooLarge { limit: *limit })]
    TooLarge {
        /// The file.
        path: String,
        /// The limit, bytes.
        limit: u64,
    },
    /// Every atom kept was a water's.
    #[error("{path}: only waters ({waters} atoms), which are never part of a receptor or a drug")]
    OnlyWaters {
        /// The file.
        path: String,
        /// Water atoms it had.
        waters: usize,
    },
    /// A record number was asked of a file that has no records (not SDF,
    /// MOL2 or PDBQT).
    #[error(
        "{path}: record {record} was asked for, but only SDF, MOL2 and PDBQT files hold several records; a PDB or mmCIF file is read whole (its first model)"
    )]
    NotRecords {
        /// The file.
        path: String,
        /// The record asked for (1-based).
        record: usize,
    },
    /// The file parsed but holds no atoms (after dropping hydrogens, if asked).
    #[error("{path}: no atoms{}", if *dropped_hydrogens > 0 {
        format!(" but {dropped_hydrogens} hydrogens, which are dropped by default (--hydrogens keep keeps them)")
    } else {
        String::new()
    })]
    NoAtoms {
        /// The file.
        path: String,
        /// Hydrogens it had, all dropped.
        dropped_hydrogens: usize,
    },
    /// The ligand asked for is not in the file, or the split left nothing.
    #[error("{path}: {reason}")]
    Ligand {
        /// The file.
        path: String,
        /// What is wrong.
        reason: String,
    },
}

impl LoadError {
    /// A [`LoadError::Parse`] at `line` (and `column`) of `path`.
    pub fn parse_at(
        path: &str,
        line: Option<usize>,
        column: Option<usize>,
        reason: impl Into<String>,
    ) -> Self {
        LoadError::Parse {
            path: path.to_string(),
            line,
            column,
            reason: reason.into(),
        }
    }

    /// The error for a file whose bytes could not be had.
    pub fn from_source(path: &str, e: crate::text::SourceError) -> Self {
        use crate::text::SourceError;
        match e {
            SourceError::Io(error) => LoadError::Io {
                path: path.to_string(),
                error,
            },
            SourceError::TooLarge { limit } => LoadError::TooLarge {
                path: path.to_string(),
                limit,
            },
            gzip @ SourceError::Gzip(_) => LoadError::parse_at(path, None, None, gzip.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn parse_errors_name_line_and_column() {
        let e = LoadError::parse_at("f.cif", Some(3), Some(27), "bad");
        assert_eq!(e.to_string(), "f.cif:3:27: bad");
        let e = LoadError::parse_at("f.cif", Some(3), None, "bad");
        assert_eq!(e.to_string(), "f.cif:3: bad");
        let e = LoadError::parse_at("f.cif", None, Some(1), "bad");
        assert_eq!(e.to_string(), "f.cif: bad");
        let e = LoadError::TooLarge {
            path: "b.pdb.gz".into(),
            limit: 1 << 20,
        };
        assert!(
            e.to_string()
                .starts_with("b.pdb.gz: decompresses to more than 1 MiB"),
            "{e}"
        );
    }
}
