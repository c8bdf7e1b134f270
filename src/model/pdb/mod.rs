//! Reading PDB and mmCIF files (plain or gzipped) through `pdbtbx`.
//!
//! The file is read and, when it starts with the gzip magic bytes, decompressed
//! here (so `.pdb.gz`, `.ent.gz` and `.cif.gz` all work, whatever the case of
//! the extension). Bytes outside ASCII are replaced by `?` before parsing:
//! `pdbtbx` slices PDB lines by byte offset and would panic on them, and no
//! coordinate field may contain them.
//!
//! Before `pdbtbx` sees the text, PDB atom records are checked and
//! normalised one line in, one line out, so every line number it reports is
//! still the file's (`records.rs`: padded short lines, filled occupancy,
//! B-factor and element fields, chain letters for blank chains, numeric
//! fields refused by name and column); an mmCIF file is cut down to its
//! first `_atom_site` loop (`mmcif.rs`). Blank element fields get an element
//! guessed from the atom name ([`guess_pdb_element`]); `pdbtbx` would
//! otherwise take the whole name as the element, so `CA` (C-alpha) would
//! become calcium. An element field naming no element makes the atom an
//! unknown element (2 Å and a warning), where `pdbtbx` would guess again.
//!
//! `pdbtbx` runs at [`StrictnessLevel::Loose`], reads only the first model and,
//! for PDB files, only the coordinate records (`ATOM`, `HETATM`, `MODEL`,
//! `ENDMDL`, `TER`, `END`: its `only_atomic_coords` option). The other records
//! are not needed, and `pdbtbx` panics or fails on some real ones (a `CRYST1`
//! space group it does not know, such as `H 3` in 1U72; a `REMARK` line without
//! a number). Its findings become warnings or a [`LoadError::Parse`] with
//! their line (`findings.rs`); a `pdbtbx` panic (it has `expect`s on malformed
//! input) is caught and reported as a parse error too.
//!
//! Of the atoms it returns, one per site is kept where there are alternate
//! locations (the highest occupancy, `alternates.rs`), in serial order, which
//! is file order in any ordinary file (`pdbtbx` groups atoms by chain).
//! Coordinates that are not finite or lie beyond [`MAX_FILE_COORDINATE`] are
//! refused with their line.

mod alternates;
mod findings;
mod guess;
mod mmcif;
mod records;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::io::{BufReader, Read};
use std::path::Path;

use glam::DVec3;
use pdbtbx::{Format, PDB, PDBError, ReadOptions, StrictnessLevel};

use super::element::{self, UNKNOWN_RADIUS};
use super::{
    AtomInfo, Hydrogens, LoadError, LoadOptions, Loaded, MAX_FILE_COORDINATE, RadiiSet, Structure,
};
use alternates::{Site, order_by_serial, resolve_alternates};
use findings::{fatal_error, parser_warning_lines};
use guess::guess_from_name;
pub use guess::guess_pdb_element;
use mmcif::{atom_site_line, diagnose_atom_site, mmcif_atom_site_only, unknown_elements_cif};
use records::{normalise_pdb, unknown_elements_pdb};

/// Reads a PDB or mmCIF file, plain or gzipped, keeping the first model.
///
/// The format is chosen by extension (`.cif`/`.mmcif`, optionally followed by
/// `.gz`, is mmCIF; anything else is PDB). Alternate locations are resolved to
/// the highest-occupancy conformer per atom, hydrogens are dropped when
/// `opts.hydrogens` says so, and every atom gets its radius from `opts.radii`
/// ([`UNKNOWN_RADIUS`] and one warning per element the table lacks).
///
/// # Errors
/// [`LoadError::Io`] when the file cannot be read, [`LoadError::Parse`] when it
/// is not valid gzip or `pdbtbx` rejects it, [`LoadError::NoAtoms`] when no atom
/// is left.
pub fn load_pdbtbx(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let label = path.display().to_string();
    let bytes = read_bytes(path)?;
    let text = ascii_text(bytes);
    let format = if is_mmcif_name(&label) {
        Format::Mmcif
    } else {
        Format::Pdb
    };
    parse_text(&text, format, &label, &file_name(path), opts)
}

/// Reads a file into memory, decompressing it when it starts with the gzip
/// magic bytes (concatenated gzip members are read to the end).
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, LoadError> {
    let label = path.display().to_string();
    let raw = std::fs::read(path).map_err(|error| LoadError::Io {
        path: label.clone(),
        error,
    })?;
    if raw.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::with_capacity(raw.len() * 4);
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| LoadError::Parse {
                path: label,
                line: None,
                reason: format!("cannot decompress gzip data: {e}"),
            })?;
        Ok(out)
    } else {
        Ok(raw)
    }
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
    /// Unknown elements in first-seen order, with their atom counts.
    unknown: Vec<(String, usize)>,
}

impl RadiusLookup {
    /// A lookup in `radii`.
    pub(crate) fn new(radii: RadiiSet) -> Self {
        Self {
            radii,
            unknown: Vec::new(),
        }
    }

    /// The radius of `element` (normalised symbol), or [`UNKNOWN_RADIUS`].
    pub(crate) fn radius(&mut self, element: &str) -> f32 {
        if let Some(r) = self.radii.radius(element) {
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

/// True when the (possibly gzipped) name ends in `.cif` or `.mmcif`.
fn is_mmcif_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    let stem = lower.strip_suffix(".gz").unwrap_or(&lower);
    stem.ends_with(".cif") || stem.ends_with(".mmcif")
}

/// The bytes as text, every non-ASCII byte replaced by `?`.
fn ascii_text(mut bytes: Vec<u8>) -> String {
    for b in &mut bytes {
        if !b.is_ascii() {
            *b = b'?';
        }
    }
    // Every byte is ASCII now, so this cannot fail; keep a lossy path anyway.
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// Parses PDB or mmCIF text already in memory. `label` names the source in
/// messages; `name` becomes [`Structure::name`].
fn parse_text(
    text: &str,
    format: Format,
    label: &str,
    name: &str,
    opts: &LoadOptions,
) -> Result<Loaded, LoadError> {
    let normalised;
    // For a cut-out atom_site loop: the original line of each of its lines.
    let mut cut_from: Option<Vec<usize>> = None;
    let input = if matches!(format, Format::Pdb) {
        normalised = normalise_pdb(text, label)?;
        normalised.as_str()
    } else if let Some((atoms_only, from)) = mmcif_atom_site_only(text) {
        normalised = atoms_only;
        cut_from = Some(from);
        normalised.as_str()
    } else {
        text
    };
    let unknown_elements = match &cut_from {
        Some(_) => unknown_elements_cif(input),
        None if matches!(format, Format::Pdb) => unknown_elements_pdb(input),
        None => HashMap::new(),
    };
    let (pdb, parser_warnings) = read_pdbtbx(text, input, format, label, cut_from.as_deref())?;
    let mut warnings = parser_warning_lines(label, &parser_warnings);
    let mut lookup = RadiusLookup::new(opts.radii);
    // A PDB file's coordinates were checked record by record (the
    // normalisation); an mmCIF atom is found by its id in the cut-out rows.
    let row_line = |serial: usize| {
        cut_from
            .as_deref()
            .and_then(|from| atom_site_line(input, from, serial))
    };
    let structure = first_model(
        &pdb,
        &unknown_elements,
        &mut lookup,
        (label, name),
        opts,
        &row_line,
    )?;
    warnings.extend(lookup.warnings(label));
    Ok(Loaded {
        structure,
        warnings,
    })
}

/// Runs `pdbtbx` on `input` (the normalised PDB text or cut-out mmCIF loop
/// of `text`; `cut_from` maps a cut-out's lines to the file's) and turns its
/// refusal or panic into a [`LoadError`] that names the file's line.
fn read_pdbtbx(
    text: &str,
    input: &str,
    format: Format,
    label: &str,
    cut_from: Option<&[usize]>,
) -> Result<(PDB, Vec<PDBError>), LoadError> {
    // When pdbtbx refuses a cut-out loop, say what is wrong in the file's
    // own line numbers (pdbtbx's would count the cut-out's lines).
    let refused = |error: LoadError| match cut_from {
        None => error,
        Some(from) => match diagnose_atom_site(input, from) {
            Some((line, reason)) => LoadError::Parse {
                path: label.to_string(),
                line: Some(line),
                reason,
            },
            None => match error {
                LoadError::Parse { path, line, reason } => LoadError::Parse {
                    path,
                    line: line.and_then(|l| from.get(l.checked_sub(1)?).copied()),
                    reason,
                },
                other => other,
            },
        },
    };
    let mut read_options = ReadOptions::new();
    read_options
        .set_format(format)
        .set_level(StrictnessLevel::Loose)
        .set_only_first_model(true)
        .set_only_atomic_coords(true);
    match quietly(|| read_options.read_raw(BufReader::new(input.as_bytes()))) {
        Ok(Ok(ok)) => Ok(ok),
        Ok(Err(errors)) => {
            // pdbtbx's own validation refuses a file without atoms.
            let mut fatal = errors
                .iter()
                .filter(|e| e.fails(StrictnessLevel::Loose))
                .peekable();
            if fatal.peek().is_some() && fatal.all(|e| e.short_description() == "No Atoms") {
                return Err(LoadError::NoAtoms {
                    path: label.to_string(),
                    dropped_hydrogens: 0,
                });
            }
            Err(refused(fatal_error(label, &errors)))
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown failure".to_string());
            // pdbtbx panics on a name holding a control character; say
            // where the first atom record with one is.
            let line = text
                .lines()
                .enumerate()
                .filter(|(_, l)| {
                    let l = l.trim_start();
                    l.starts_with("ATOM") || l.starts_with("HETATM")
                })
                .find_map(|(k, l)| l.chars().find(|c| c.is_ascii_control()).map(|c| (k + 1, c)));
            Err(match line {
                Some((line, c)) => LoadError::Parse {
                    path: label.to_string(),
                    line: Some(line),
                    reason: format!(
                        "control character U+{:04X} in an atom record (names must be printable); \
                         the PDB/mmCIF parser gave up: {what}",
                        u32::from(c)
                    ),
                },
                None => refused(LoadError::Parse {
                    path: label.to_string(),
                    line: None,
                    reason: format!("the PDB/mmCIF parser gave up: {what}"),
                }),
            })
        }
    }
}

/// The atoms of `pdb`'s first model that bump keeps: one per site where
/// there are alternate locations, in serial order, hydrogens dropped or
/// kept as `opts` says, each with its element (`unknown_elements`: serial →
/// an element field naming no element) and radius (`lookup`). `label` names
/// the file in messages, `name` the structure.
///
/// # Errors
/// [`LoadError::Parse`] for a coordinate that is not finite or lies beyond
/// [`MAX_FILE_COORDINATE`], at the line `row_line` gives the atom's serial;
/// [`LoadError::NoAtoms`] when no atom is kept.
fn first_model(
    pdb: &PDB,
    unknown_elements: &HashMap<usize, String>,
    lookup: &mut RadiusLookup,
    (label, name): (&str, &str),
    opts: &LoadOptions,
    row_line: &dyn Fn(usize) -> Option<usize>,
) -> Result<Structure, LoadError> {
    let mut atoms = Vec::new();
    let mut positions = Vec::new();
    let mut dropped = 0;
    // (chain, seq, insertion code, name) of each dropped hydrogen's residue.
    let mut dropped_from = Vec::new();
    let no_atoms = |dropped_hydrogens| LoadError::NoAtoms {
        path: label.to_string(),
        dropped_hydrogens,
    };
    let Some(model) = pdb.model(0) else {
        return Err(no_atoms(0));
    };
    let mut sites = Vec::new();
    for chain in model.chains() {
        for residue in chain.residues() {
            let (seq, icode) = residue.id();
            let first = sites.len();
            for conformer in residue.conformers() {
                for atom in conformer.atoms() {
                    sites.push(Site {
                        atom,
                        chain: chain.id(),
                        residue: conformer.name(),
                        seq,
                        insertion: icode.unwrap_or(""),
                    });
                }
            }
            if residue.conformer_count() > 1 {
                resolve_alternates(&mut sites, first);
            }
        }
    }
    order_by_serial(&mut sites);
    for site in sites {
        let atom = site.atom;
        // An element field naming no element makes the atom unknown (a
        // warning and 2 Å), where pdbtbx would guess from its name.
        let element = match (unknown_elements.get(&atom.serial_number()), atom.element()) {
            (Some(symbol), _) => element::normalize_symbol(symbol),
            (None, Some(e)) => element::normalize_symbol(e.symbol()),
            (None, None) => guess_from_name(atom.name()),
        };
        if opts.hydrogens == Hydrogens::Drop && element::is_hydrogen(&element) {
            dropped += 1;
            dropped_from.push((site.chain, site.seq, site.insertion, site.residue));
            continue;
        }
        let radius = lookup.radius(&element);
        atoms.push(AtomInfo {
            serial: i64::try_from(atom.serial_number()).unwrap_or(i64::MAX),
            name: atom.name().to_string(),
            residue: site.residue.to_string(),
            seq: i64::try_from(site.seq).unwrap_or(0),
            insertion: site.insertion.to_string(),
            chain: site.chain.to_string(),
            polar: element::is_polar(&element),
            element,
            radius,
            hetero: atom.hetero(),
        });
        let (x, y, z) = atom.pos();
        let p = DVec3::new(x, y, z);
        if !p.is_finite() || p.abs().max_element() > MAX_FILE_COORDINATE {
            // Out-of-range values in exponent form, not 300 digits.
            let shown = |v: f64| {
                if v.abs() <= MAX_FILE_COORDINATE {
                    format!("{v}")
                } else {
                    format!("{v:.3e}")
                }
            };
            let (x, y, z) = (shown(x), shown(y), shown(z));
            return Err(LoadError::Parse {
                path: label.to_string(),
                line: row_line(atom.serial_number()),
                reason: format!(
                    "atom {} ({}) is at ({x}, {y}, {z}), not within ±{MAX_FILE_COORDINATE:e} Å",
                    atom.serial_number(),
                    atom.name()
                ),
            });
        }
        positions.push(p);
    }
    if atoms.is_empty() {
        return Err(no_atoms(dropped));
    }
    let hydrogen_only = residues_without(&atoms, dropped_from);
    Ok(Structure {
        name: name.to_string(),
        atoms,
        positions,
        hydrogen_only,
        bonds: Vec::new(),
        file_chem: Default::default(),
    })
}

/// The residues among `dropped` (one entry per dropped atom: chain, seq,
/// insertion code, name) that kept no atom in `atoms`, as (name,
/// `chain/seq`), once each, in first-seen order.
fn residues_without(
    atoms: &[AtomInfo],
    dropped: Vec<(&str, isize, &str, &str)>,
) -> Vec<(String, String)> {
    if dropped.is_empty() {
        return Vec::new();
    }
    let kept: std::collections::HashSet<(&str, i64, &str, &str)> = atoms
        .iter()
        .map(|a| {
            (
                a.chain.as_str(),
                a.seq,
                a.insertion.as_str(),
                a.residue.as_str(),
            )
        })
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for (chain, seq, insertion, name) in dropped {
        let key = (chain, i64::try_from(seq).unwrap_or(0), insertion, name);
        if !kept.contains(&key) && seen.insert(key) {
            out.push((name.to_string(), format!("{chain}/{seq}{insertion}")));
        }
    }
    out
}

thread_local! {
    /// Set while this thread runs `pdbtbx`, whose panics are caught and
    /// reported as parse errors, so the panic hook prints nothing for them.
    static QUIET_PANICS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, catching a panic without the panic hook's message on stderr
/// (the caller reports it as an error). The hook installed once here defers
/// to the previous one on every other thread, and on this one outside `f`.
fn quietly<R>(f: impl FnOnce() -> R) -> std::thread::Result<R> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET_PANICS.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET_PANICS.with(|q| q.set(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET_PANICS.with(|q| q.set(false));
    result
}
