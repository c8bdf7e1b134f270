//! Errors from reading and splitting molecule files. Every message names the
//! file, and the line where the reader knows it.

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
        "{path}: unknown format (expected .pdb, .ent, .cif, .mmcif, .sdf or .mol, optionally .gz)"
    )]
    UnknownFormat {
        /// The file.
        path: String,
    },
    /// The file is not valid in its format.
    #[error("{path}{}: {reason}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },
    /// Every atom kept was a water's.
    #[error("{path}: only waters ({waters} atoms), which are never part of a receptor or a drug")]
    OnlyWaters {
        /// The file.
        path: String,
        /// Water atoms it had.
        waters: usize,
    },
    /// A record number was asked of a file that has no records (not SDF).
    #[error(
        "{path}: record {record} was asked for, but only SDF files hold several records; a PDB or mmCIF file is read whole (its first model)"
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
