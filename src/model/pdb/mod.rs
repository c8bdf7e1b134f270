//! Reading PDB and mmCIF files (plain or gzipped) with bump's own readers:
//! a column reader for PDB records (`records.rs`) and a CIF tokenizer that
//! reads the first data block's `_atom_site` and `_struct_conn` categories
//! (`mmcif.rs`).
//!
//! The file is streamed, never held whole: a gzipped file (recognised by
//! its magic bytes, whatever its name) is decompressed on a thread of its
//! own a chunk ahead of the reader, up to the decompressed-size limit
//! ([`field@LoadOptions::decompressed_limit`]), and lines end with LF, CRLF or a
//! lone CR alike ([`crate::text::LineReader`], at most [`MAX_LINE`] bytes a
//! line). Bytes outside ASCII read as `?`: no field that matters may hold
//! them. Each atom is kept as it is read, in the compact form it keeps
//! ([`AtomInfo`], 56 bytes, and its position), so a structure costs about
//! 80 bytes an atom while it loads, whatever the size of its text.
//!
//! Every problem is a [`LoadError`] naming the file, the line and the
//! column, quoting at most a short excerpt: a record cut short or a field
//! that does not read as a number, a coordinate that is not finite or lies
//! beyond [`MAX_FILE_COORDINATE`], a control character in a name, a label
//! longer than bump keeps ([`super::Label`]).
//!
//! Of the atoms read, the first model's are kept, one per site where there
//! are alternate locations (the highest occupancy, `alternates.rs`), in file
//! order; hydrogens are dropped or kept as asked. Blank element fields get
//! an element guessed from the atom name ([`guess_pdb_element`]); an element
//! field naming no element makes the atom an unknown element (2 Å and a
//! warning). The bonds the file states (`CONECT`, `struct_conn`) become
//! [`Structure::bonds`] (`bonds.rs`), and the formal charges it states (PDB
//! columns 79–80, mmCIF's `pdbx_formal_charge`) the file chemistry's
//! ([`super::FileChemistry::formal_charges`]), as Open Babel reads them: a
//! carboxylate written `1-` gets no hydrogen.

mod alternates;
mod bonds;
mod guess;
mod mmcif;
mod records;
#[cfg(test)]
mod tests;

use std::io::Read;
use std::path::Path;

use glam::DVec3;

use super::element::{self, UNKNOWN_RADIUS};
use super::{
    AtomInfo, FileChemistry, Hydrogens, Label, LoadError, LoadOptions, Loaded, MAX_FILE_COORDINATE,
    RadiiSet, Structure,
};
use crate::model::label::{ChainId, ElementSymbol, InsertionCode, ResidueName};
use crate::text::{LineReader, SourceError, TextSource, lines::LineError};
pub use guess::{guess_pdb_element, is_element_symbol};

/// Longest line a PDB or mmCIF file may hold, bytes (a PDB record is 80;
/// long mmCIF lines hold sequences and strand lists).
pub const MAX_LINE: usize = 16 << 20;

/// The syntax of a coordinate file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// PDB records in fixed columns.
    Pdb,
    /// mmCIF (PDBx/mmCIF), the PDB's own format since 2014.
    Mmcif,
}

impl Format {
    /// The format a file name says: `.cif` or `.mmcif` (optionally `.gz`)
    /// is mmCIF, anything else PDB.
    pub fn of_name(name: &str) -> Self {
        let lower = name.to_ascii_lowercase();
        let stem = lower.strip_suffix(".gz").unwrap_or(&lower);
        if stem.ends_with(".cif") || stem.ends_with(".mmcif") {
            Format::Mmcif
        } else {
            Format::Pdb
        }
    }
}

/// Reads a PDB or mmCIF file, plain or gzipped, keeping the first model.
///
/// The format is chosen by extension ([`Format::of_name`]). Alternate
/// locations are resolved to the highest-occupancy conformer per atom,
/// hydrogens are dropped when `opts.hydrogens` says so, and every atom gets
/// its radius from `opts.radii` ([`UNKNOWN_RADIUS`] and one warning per
/// element the table lacks).
///
/// # Errors
/// [`LoadError::Io`] when the file cannot be read, [`LoadError::TooLarge`]
/// past the decompressed-size limit, [`LoadError::Parse`] for damaged gzip
/// data or text that is not valid (with its line and column),
/// [`LoadError::NoAtoms`] when no atom is left.
pub fn load_pdb_or_mmcif(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let label = path.display().to_string();
    let source = TextSource::open(path, opts.max_decompressed())
        .map_err(|e| LoadError::from_source(&label, e))?;
    parse_source(
        source,
        Format::of_name(&label),
        &label,
        &file_name(path),
        opts,
    )
}

/// Reads PDB or mmCIF text (plain or gzipped) already in memory. `label`
/// names the source in messages; `name` becomes [`Structure::name`].
///
/// # Errors
/// As [`load_pdb_or_mmcif`], less the I/O error.
pub fn parse_bytes(
    bytes: &[u8],
    format: Format,
    label: &str,
    name: &str,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    let source = TextSource::from_bytes(bytes, opts.max_decompressed());
    parse_source(source, format, label, name, opts)
}

/// [`parse_bytes`] of text, for tests.
#[cfg(test)]
fn parse_text(
    text: &str,
    format: Format,
    label: &str,
    name: &str,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    parse_bytes(text.as_bytes(), format, label, name, opts)
}

/// Reads the lines of `source` as `format` and builds the structure.
fn parse_source(
    source: impl Read,
    format: Format,
    label: &str,
    name: &str,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    let mut lines = LineReader::new(source, MAX_LINE);
    let raw = match format {
        Format::Pdb => records::read_pdb(&mut lines, label)?,
        Format::Mmcif => mmcif::read_mmcif(&mut lines, label)?,
    };
    build(raw, label, name, opts)
}

/// The error for a line reader's failure.
pub(crate) fn line_error(label: &str, e: LineError) -> LoadError {
    match e {
        LineError::Io(e) => LoadError::from_source(label, SourceError::from_io(e)),
        LineError::TooLong { line, limit } => LoadError::parse_at(
            label,
            Some(line),
            None,
            format!(
                "the line is longer than {}: not a PDB or mmCIF file?",
                crate::text::format_bytes(limit as u64)
            ),
        ),
    }
}

/// `line` as text: ASCII as it is, any other byte read as `?`, into
/// `scratch` when it has to be copied.
pub(crate) fn ascii_line<'a>(line: &'a [u8], scratch: &'a mut String) -> &'a str {
    if line.is_ascii() {
        // ASCII is UTF-8.
        return std::str::from_utf8(line).unwrap_or_default();
    }
    scratch.clear();
    scratch.extend(
        line.iter()
            .map(|&b| if b.is_ascii() { char::from(b) } else { '?' }),
    );
    scratch
}

/// An element symbol as atoms keep it, the first letter upper case and
/// the rest lower (`CL` → `Cl`); `None` for one longer than the label
/// holds.
pub(crate) fn element_label(symbol: &str) -> Option<ElementSymbol> {
    let t = symbol.trim();
    if t.len() > ElementSymbol::CAPACITY || !t.is_ascii() {
        return Label::new(&element::normalize_symbol(t));
    }
    let mut b = [0u8; ElementSymbol::CAPACITY];
    for (i, c) in t.bytes().enumerate() {
        b[i] = if i == 0 {
            c.to_ascii_uppercase()
        } else {
            c.to_ascii_lowercase()
        };
    }
    Label::new(std::str::from_utf8(&b[..t.len()]).ok()?)
}

/// What a reader found: the atoms of the first model in file order, with
/// what choosing among them needs, and the bonds the file states.
#[derive(Debug, Default)]
struct Raw {
    /// The atoms, radius and polarity still to be set.
    atoms: Vec<AtomInfo>,
    /// Their positions.
    positions: Vec<DVec3>,
    /// Their occupancies.
    occupancy: Vec<f32>,
    /// Their alternate-location codes (0 for none).
    alt: Vec<u8>,
    /// Their formal charges as the file states them (0 where it does not).
    charges: Vec<i8>,
    /// The bonds the file states, by the atoms' serials or names.
    bonds: bonds::Pending,
    /// Warnings, naming the file.
    warnings: Vec<String>,
}

impl Raw {
    /// Adds an atom.
    fn push(&mut self, atom: AtomInfo, position: DVec3, occupancy: f32, alt: u8, charge: i8) {
        self.atoms.push(atom);
        self.positions.push(position);
        self.occupancy.push(occupancy);
        self.alt.push(alt);
        self.charges.push(charge);
    }
}

/// The structure bump keeps of what a reader found: one atom per site,
/// hydrogens dropped or kept, radii and polarity set, bonds between kept
/// atoms.
fn build(mut raw: Raw, label: &str, name: &str, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let mut keep = alternates::one_per_site(&raw.atoms, &raw.occupancy, &raw.alt);
    raw.occupancy = Vec::new();
    let mut dropped = 0;
    // (chain, seq, insertion code, name) of each dropped hydrogen's residue.
    let mut dropped_from = Vec::new();
    let mut lookup = RadiusLookup::new(opts.radii);
    // Per element met: hydrogen, polar (a structure has a few elements).
    let mut seen: Vec<(ElementSymbol, bool, bool)> = Vec::new();
    for (a, kept) in raw.atoms.iter_mut().zip(keep.iter_mut()) {
        if !*kept {
            continue;
        }
        let (hydrogen, polar) = match seen.iter().find(|s| s.0 == a.element) {
            Some(s) => (s.1, s.2),
            None => {
                let e = &a.element;
                let first = (element::is_hydrogen(e), element::is_polar(e));
                seen.push((a.element, first.0, first.1));
                first
            }
        };
        if opts.hydrogens == Hydrogens::Drop && hydrogen {
            *kept = false;
            dropped += 1;
            dropped_from.push((a.chain, a.seq, a.insertion, a.residue));
            continue;
        }
        a.radius = lookup.radius(&a.element);
        a.polar = polar;
    }
    let alt = std::mem::take(&mut raw.alt);
    let bonds = bonds::resolve(&raw.bonds, &raw.atoms, &alt, &keep);
    drop(alt);
    let mut k = 0;
    raw.atoms.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    let mut k = 0;
    raw.positions.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    let mut k = 0;
    raw.charges.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    drop(keep);
    if raw.atoms.is_empty() {
        return Err(LoadError::NoAtoms {
            path: label.to_string(),
            dropped_hydrogens: dropped,
        });
    }
    raw.atoms.shrink_to_fit();
    raw.positions.shrink_to_fit();
    let hydrogen_only = residues_without(&raw.atoms, dropped_from);
    let mut warnings = raw.warnings;
    warnings.extend(lookup.warnings(label));
    Ok(Loaded {
        structure: Structure {
            name: name.to_string(),
            atoms: raw.atoms,
            positions: raw.positions,
            hydrogen_only,
            bonds,
            file_chem: FileChemistry {
                // Only a file that states some charge has charges to keep.
                formal_charges: if raw.charges.iter().any(|&q| q != 0) {
                    raw.charges
                } else {
                    Vec::new()
                },
                ..Default::default()
            },
        },
        warnings,
    })
}

/// Reads a file into memory, decompressing it when it starts with the gzip
/// magic bytes (concatenated gzip members are read to the end), at most
/// `limit` bytes once decompressed.
pub(crate) fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, LoadError> {
    let label = path.display().to_string();
    crate::text::read_limited(path, limit).map_err(|e| LoadError::from_source(&label, e))
}

/// The last component of `path`, for labels (the whole path when it has none).
pub(crate) fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Looks up radii and remembers the elements the table lacks, for one warning each.
pub(crate) struct RadiusLookup {
    radii: RadiiSet,
    /// Elements met that the table knows, with their radii.
    known: Vec<(String, f32)>,
    /// Unknown elements in first-seen order, with their atom counts.
    unknown: Vec<(String, usize)>,
}

impl RadiusLookup {
    /// A lookup in `radii`.
    pub(crate) fn new(radii: RadiiSet) -> Self {
        Self {
            radii,
            known: Vec::new(),
            unknown: Vec::new(),
        }
    }

    /// The radius of `element` (normalised symbol), or [`UNKNOWN_RADIUS`].
    pub(crate) fn radius(&mut self, element: &str) -> f32 {
        if let Some(&(_, r)) = self.known.iter().find(|(e, _)| e == element) {
            return r;
        }
        if let Some(r) = self.radii.radius(element) {
            if self.known.len() < 16 {
                self.known.push((element.to_string(), r));
            }
            return r;
        }
        if let Some(entry) = self.unknown.iter_mut().find(|(e, _)| e == element) {
            entry.1 += 1;
        } else {
            self.unknown.push((element.to_string(), 1));
        }
        UNKNOWN_RADIUS
    }

    /// One warning per unknown element, naming the file.
    pub(crate) fn warnings(&self, label: &str) -> Vec<String> {
        self.unknown
            .iter()
            .map(|(e, n)| {
                let shown = if e.is_empty() { "(none)" } else { e.as_str() };
                format!(
                    "{label}: element {shown} has no van der Waals radius in the {} table; \
                     using {UNKNOWN_RADIUS} Å for its {n} atom{}",
                    self.radii.name(),
                    if *n == 1 { "" } else { "s" }
                )
            })
            .collect()
    }
}

/// The residues among `dropped` (one entry per dropped atom: chain, seq,
/// insertion code, name) that kept no atom in `atoms`, as (name,
/// `chain/seq`), once each, in first-seen order.
fn residues_without(
    atoms: &[AtomInfo],
    dropped: Vec<(ChainId, i64, InsertionCode, ResidueName)>,
) -> Vec<(String, String)> {
    if dropped.is_empty() {
        return Vec::new();
    }
    let kept: std::collections::HashSet<(ChainId, i64, InsertionCode, ResidueName)> = atoms
        .iter()
        .map(|a| (a.chain, a.seq, a.insertion, a.residue))
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for key in dropped {
        if !kept.contains(&key) && seen.insert(key) {
            let (chain, seq, insertion, name) = key;
            out.push((name.to_string(), format!("{chain}/{seq}{insertion}")));
        }
    }
    out
}

/// Checks a position read from a file: finite and within
/// [`MAX_FILE_COORDINATE`]; the message names the atom.
fn check_position(p: DVec3, serial: i64, name: &str) -> Result<DVec3, String> {
    if p.is_finite() && p.abs().max_element() <= MAX_FILE_COORDINATE {
        return Ok(p);
    }
    // Exponent form for the values out of range: 1e300 would
    // otherwise print as 301 digits.
    let shown = |v: f64| {
        if v.abs() <= MAX_FILE_COORDINATE {
            format!("{v}")
        } else {
            format!("{v:.3e}")
        }
    };
    Err(format!(
        "atom {serial} ({name}) is at ({}, {}, {}), not within ±{MAX_FILE_COORDINATE:e} Å",
        shown(p.x),
        shown(p.y),
        shown(p.z)
    ))
}
