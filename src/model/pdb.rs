//! Reading PDB and mmCIF files (plain or gzipped) through `pdbtbx`.
//!
//! The file is read and, when it starts with the gzip magic bytes, decompressed
//! here (so `.pdb.gz`, `.ent.gz` and `.cif.gz` all work, whatever the case of
//! the extension). Bytes outside ASCII are replaced by `?` before parsing:
//! `pdbtbx` slices PDB lines by byte offset and would panic on them, and no
//! coordinate field may contain them.
//!
//! PDB lines are then normalised before `pdbtbx` sees them, one line in, one
//! line out, so every line number it reports is still the file's:
//! - `ATOM`/`HETATM` lines shorter than 80 columns are padded (`pdbtbx` rejects
//!   lines that end before the element column, which many programs write);
//! - a blank occupancy becomes `1.00` and a blank B-factor `0.00`;
//! - a blank element column is filled with the element guessed from the atom
//!   name (see [`guess_pdb_element`]). `pdbtbx` would otherwise take the whole
//!   name as the element, so `CA` (C-alpha) would become calcium.
//!
//! For mmCIF, only the first data block's `_atom_site` loop is handed to
//! `pdbtbx` (it panics on some other categories, e.g. a `_symmetry` block
//! without `Int_Tables_number`, as in 3NZD); mmCIF errors carry no line numbers.
//!
//! `pdbtbx` runs at [`StrictnessLevel::Loose`], reads only the first model and,
//! for PDB files, only the coordinate records (`ATOM`, `HETATM`, `MODEL`,
//! `ENDMDL`, `TER`, `END`: its `only_atomic_coords` option). The other records
//! are not needed, and `pdbtbx` panics or fails on some real ones (a `CRYST1`
//! space group it does not know, such as `H 3` in 1U72; a `REMARK` line without
//! a number).
//! Its non-fatal findings become warnings; a fatal one becomes
//! [`LoadError::Parse`] with the line number where its context has one. A
//! `pdbtbx` panic (it has `expect`s on malformed input) is caught and reported
//! as a parse error too.
//!
//! Alternate locations: `pdbtbx` copies the atoms without an alt-loc into every
//! alternate conformer of their residue (dividing their occupancy). The copies
//! are recognised (same serial, name and position) and kept once. For each atom
//! site (chain, residue number, insertion code, atom name) the alternate with the
//! highest occupancy is kept, ties going to the alt-loc that appears first in the
//! file. Residues whose alternates have different residue names
//! (microheterogeneity) are resolved per atom name in the same way.
//!
//! `pdbtbx` groups atoms by chain; when the serial numbers are all distinct the
//! atoms are put back in serial order, which is file order in any ordinary file.
//!
//! Blank chain identifiers are filled in before `pdbtbx` reads the text, as it
//! would fill them (`A`, the next letter after each `TER`) but with letters no
//! named chain of the file uses (else a blank-chain ligand would join the
//! named chain's residue of its number), and also where a residue number
//! comes back under another residue name: simulation programs number their
//! waters from 1 again, and `pdbtbx` would merge each into the protein residue
//! of that number. Coordinates that are not finite or lie
//! beyond [`MAX_FILE_COORDINATE`] are refused with their line.

use std::collections::{HashMap, HashSet};
use std::io::{BufReader, Read};
use std::path::Path;

use glam::DVec3;
use pdbtbx::{Atom, Context, Format, PDBError, ReadOptions, StrictnessLevel};

use super::element::{self, UNKNOWN_RADIUS};
use super::{
    AtomInfo, Hydrogens, LoadError, LoadOptions, Loaded, MAX_FILE_COORDINATE, RadiiSet, Structure,
};

/// At most this many parser warnings are reported one by one; the rest are counted.
const MAX_PARSER_WARNINGS: usize = 20;

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
    // When pdbtbx refuses a cut-out loop, say what is wrong in the file's
    // own line numbers (pdbtbx's would count the cut-out's lines).
    let refused = |error: LoadError| match &cut_from {
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
    let unknown_elements = match &cut_from {
        Some(_) => unknown_elements_cif(input),
        None if matches!(format, Format::Pdb) => unknown_elements_pdb(input),
        None => HashMap::new(),
    };
    let mut read_options = ReadOptions::new();
    read_options
        .set_format(format)
        .set_level(StrictnessLevel::Loose)
        .set_only_first_model(true)
        .set_only_atomic_coords(true);
    let result = quietly(|| read_options.read_raw(BufReader::new(input.as_bytes())));
    let (pdb, parser_warnings) = match result {
        Ok(Ok(ok)) => ok,
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
            return Err(refused(fatal_error(label, &errors)));
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
            return Err(match line {
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
            });
        }
    };

    let mut warnings = parser_warning_lines(label, &parser_warnings);
    let mut lookup = RadiusLookup::new(opts.radii);
    let mut atoms = Vec::new();
    let mut positions = Vec::new();
    let mut dropped = 0;
    // (chain, seq, insertion code, name) of each dropped hydrogen's residue.
    let mut dropped_from = Vec::new();
    let mut hydrogen_only = Vec::new();
    if let Some(model) = pdb.model(0) {
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
                return Err(LoadError::Parse {
                    path: label.to_string(),
                    line: None,
                    reason: format!(
                        "atom {} ({}) is at ({x}, {y}, {z}), not within ±{MAX_FILE_COORDINATE:e} Å",
                        atom.serial_number(),
                        atom.name()
                    ),
                });
            }
            positions.push(p);
        }
        hydrogen_only = residues_without(&atoms, dropped_from);
    }
    if atoms.is_empty() {
        return Err(LoadError::NoAtoms {
            path: label.to_string(),
            dropped_hydrogens: dropped,
        });
    }
    warnings.extend(lookup.warnings(label));
    Ok(Loaded {
        structure: Structure {
            name: name.to_string(),
            atoms,
            positions,
            hydrogen_only,
        },
        warnings,
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

/// One atom with the hierarchy it came from.
struct Site<'a> {
    atom: &'a Atom,
    chain: &'a str,
    residue: &'a str,
    seq: isize,
    insertion: &'a str,
}

/// Keeps one atom per site among `sites[first..]` (one residue's conformers):
/// copies of shared atoms are dropped, then per atom name the highest
/// occupancy wins, ties to the earliest.
fn resolve_alternates(sites: &mut Vec<Site<'_>>, first: usize) {
    let tail: Vec<Site<'_>> = sites.drain(first..).collect();
    let mut seen: HashSet<(usize, &str, [u64; 3])> = HashSet::new();
    let mut best: Vec<Site<'_>> = Vec::new();
    let mut slot: HashMap<&str, usize> = HashMap::new();
    for site in tail {
        let a = site.atom;
        let (x, y, z) = a.pos();
        if !seen.insert((
            a.serial_number(),
            a.name(),
            [x.to_bits(), y.to_bits(), z.to_bits()],
        )) {
            continue;
        }
        match slot.get(a.name()) {
            Some(&i) => {
                if a.occupancy() > best[i].atom.occupancy() {
                    best[i] = site;
                }
            }
            None => {
                slot.insert(a.name(), best.len());
                best.push(site);
            }
        }
    }
    sites.extend(best);
}

/// Sorts by serial number when the serials are all distinct (file order in an
/// ordinary file); otherwise leaves `pdbtbx`'s chain-grouped order.
fn order_by_serial(sites: &mut [Site<'_>]) {
    if sites
        .windows(2)
        .all(|w| w[0].atom.serial_number() < w[1].atom.serial_number())
    {
        return;
    }
    let mut serials: Vec<usize> = sites.iter().map(|s| s.atom.serial_number()).collect();
    serials.sort_unstable();
    if serials.windows(2).all(|w| w[0] != w[1]) {
        sites.sort_by_key(|s| s.atom.serial_number());
    }
}

/// The error for a failed `pdbtbx` read: the first fatal finding, with its line.
fn fatal_error(label: &str, errors: &[PDBError]) -> LoadError {
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
fn parser_warning_lines(label: &str, warnings: &[PDBError]) -> Vec<String> {
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

/// The first data block's `_atom_site` loop alone, as mmCIF text, with the
/// 1-based line of the original text each of its lines came from; or `None`
/// when it cannot be cut out simply (no such loop, or a `;` text field in it),
/// in which case the whole text goes to `pdbtbx`.
fn mmcif_atom_site_only(text: &str) -> Option<(String, Vec<usize>)> {
    let mut lines = text.lines().map(str::trim).enumerate();
    let (data_at, data) = lines.by_ref().find(|(_, l)| l.starts_with("data_"))?;
    let mut out = String::with_capacity(text.len() / 2);
    let mut from = vec![data_at + 1, data_at + 1];
    out.push_str(data);
    out.push_str("\nloop_\n");
    let mut in_loop = false;
    let mut header = false;
    for (at, line) in lines {
        let lower_start = |p: &str| {
            line.get(..p.len())
                .is_some_and(|s| s.eq_ignore_ascii_case(p))
        };
        if !in_loop {
            if lower_start("data_") {
                return None;
            }
            if line.eq_ignore_ascii_case("loop_") {
                in_loop = true;
                header = true;
                from[1] = at + 1;
            }
            continue;
        }
        if header {
            if lower_start("_atom_site.") {
                out.push_str(line);
                out.push('\n');
                from.push(at + 1);
                continue;
            }
            if !out.ends_with("loop_\n") {
                header = false;
            } else {
                // Another category's loop: look for the next one.
                in_loop = line.eq_ignore_ascii_case("loop_");
                if in_loop {
                    from[1] = at + 1;
                }
                continue;
            }
        }
        if line.starts_with('_')
            || line.starts_with('#')
            || lower_start("loop_")
            || lower_start("data_")
            || lower_start("stop_")
            || lower_start("save_")
            || lower_start("global_")
        {
            break;
        }
        if line.starts_with(';') {
            return None;
        }
        out.push_str(line);
        out.push('\n');
        from.push(at + 1);
    }
    if out.ends_with("loop_\n") {
        None
    } else {
        Some((out, from))
    }
}

/// The values of one line of CIF data: whitespace-separated, a value that
/// opens with a quote running to the same quote followed by a blank (or the
/// line's end), a `#` outside quotes starting a comment.
fn cif_values(line: &str) -> Vec<&str> {
    let bytes = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if bytes[i] == b'#' {
            break;
        }
        let start = i;
        if bytes[i] == b'\'' || bytes[i] == b'"' {
            let quote = bytes[i];
            i += 1;
            while i < bytes.len()
                && !(bytes[i] == quote && bytes.get(i + 1).is_none_or(|b| b.is_ascii_whitespace()))
            {
                i += 1;
            }
            i = (i + 1).min(bytes.len());
        } else {
            while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
                i += 1;
            }
        }
        out.push(line.get(start..i).unwrap_or_default());
    }
    out
}

/// Serial → element field, as written, of the atom records of PDB text
/// whose element field (columns 77-78) names no element `pdbtbx` knows: it
/// would give those atoms one guessed from their names.
fn unknown_elements_pdb(text: &str) -> HashMap<usize, String> {
    let mut out = HashMap::new();
    for line in text.lines() {
        if !(line.starts_with("ATOM  ") || line.starts_with("HETATM")) {
            continue;
        }
        let symbol = line.get(76..78).unwrap_or("").trim();
        if !symbol.is_empty()
            && pdbtbx::Element::from_symbol(symbol).is_none()
            && let Some(serial) = line.get(6..11).and_then(|s| s.trim().parse().ok())
        {
            out.entry(serial).or_insert_with(|| symbol.to_string());
        }
    }
    out
}

/// [`unknown_elements_pdb`] for a cut-out `_atom_site` loop
/// ([`mmcif_atom_site_only`]): its `type_symbol` values by `id`, for rows
/// one per line.
fn unknown_elements_cif(cut: &str) -> HashMap<usize, String> {
    let mut out = HashMap::new();
    // The cut-out is `data_`, `loop_`, the column names, then the rows.
    let mut lines = cut.lines().skip(2).peekable();
    let mut columns: Vec<&str> = Vec::new();
    while let Some(name) = lines.peek().and_then(|l| l.strip_prefix("_atom_site.")) {
        columns.push(name.trim());
        lines.next();
    }
    let column = |name: &str| columns.iter().position(|c| c.eq_ignore_ascii_case(name));
    let (Some(t), Some(i)) = (column("type_symbol"), column("id")) else {
        return out;
    };
    for line in lines {
        let values = cif_values(line);
        if values.len() != columns.len() {
            continue;
        }
        let symbol = values[t].trim_matches(['\'', '"']);
        if !matches!(symbol, "" | "." | "?")
            && pdbtbx::Element::from_symbol(symbol).is_none()
            && let Ok(serial) = values[i].parse()
        {
            out.entry(serial).or_insert_with(|| symbol.to_string());
        }
    }
    out
}

/// What is wrong with a cut-out `_atom_site` loop ([`mmcif_atom_site_only`])
/// that `pdbtbx` refused, said with the original line: a row with the wrong
/// number of values (when rows are one per line, as every mmCIF writer puts
/// them), or a coordinate that is not a number. `None` when neither is found.
fn diagnose_atom_site(cut: &str, from: &[usize]) -> Option<(usize, String)> {
    let mut columns: Vec<&str> = Vec::new();
    let mut rows: Vec<(usize, Vec<&str>)> = Vec::new();
    for (k, line) in cut.lines().enumerate().skip(2) {
        let at = from.get(k).copied().unwrap_or(0);
        if let Some(name) = line.strip_prefix("_atom_site.") {
            columns.push(name.trim());
        } else {
            let values = cif_values(line);
            if !values.is_empty() {
                rows.push((at, values));
            }
        }
    }
    let n = columns.len();
    let full = rows.iter().filter(|(_, v)| v.len() == n).count();
    if n > 0
        && 2 * full >= rows.len()
        && let Some((at, v)) = rows.iter().find(|(_, v)| v.len() != n)
    {
        return Some((
            *at,
            format!(
                "this _atom_site row has {} values; the loop has {n} columns",
                v.len()
            ),
        ));
    }
    let column = |name: &str| columns.iter().position(|c| c.eq_ignore_ascii_case(name));
    let id = column("id");
    for axis in ["Cartn_x", "Cartn_y", "Cartn_z"] {
        let Some(c) = column(axis) else {
            return Some((
                from.get(1).copied().unwrap_or(0),
                format!("the _atom_site loop has no {axis} column"),
            ));
        };
        for (at, v) in rows.iter().filter(|(_, v)| v.len() == n) {
            let value = v[c];
            if value.parse::<f64>().is_err() {
                let atom = id.map_or(String::new(), |i| format!(" of atom {}", v[i]));
                return Some((*at, format!("{axis}{atom} is not a number: {value:?}")));
            }
        }
    }
    None
}

/// Normalises the `ATOM`/`HETATM` lines of PDB text (see the module docs);
/// other lines pass unchanged. Line count and order are kept.
///
/// # Errors
/// [`LoadError::Parse`], naming the line, for an atom record that
/// [`check_atom_fields`] refuses (cut short, a numeric field that is not a
/// number, a coordinate not finite or beyond [`MAX_FILE_COORDINATE`]), and
/// for a residue number that a chain gives to two different residues.
fn normalise_pdb(text: &str, label: &str) -> Result<String, LoadError> {
    if let Some((index, _)) = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.trim().is_empty())
        .filter(|(_, l)| l.trim_start().starts_with("data_"))
    {
        return Err(LoadError::Parse {
            path: label.to_string(),
            line: Some(index + 1),
            reason: "this is mmCIF text (it opens with data_), read as PDB because of its name; name it .cif".into(),
        });
    }
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    let mut chains = ChainNames::new(text);
    for (index, line) in text.lines().enumerate() {
        let at = |reason: String| LoadError::Parse {
            path: label.to_string(),
            line: Some(index + 1),
            reason,
        };
        if line.starts_with("ATOM  ") || line.starts_with("HETATM") {
            check_atom_fields(line).map_err(at)?;
            let chain = chains.chain_of(line, index + 1).map_err(at)?;
            normalise_atom_line(line, chain, &mut out);
        } else {
            chains.other_record(line);
            out.push_str(line);
        }
        out.push('\n');
    }
    Ok(out)
}

/// Refuses an atom record cut before its coordinates end, a numeric field
/// (serial, residue number, coordinates, occupancy, temperature factor) that
/// does not read as a number, naming the field, its columns and its text,
/// and a coordinate that is not finite (on which `pdbtbx` would panic) or
/// lies beyond [`MAX_FILE_COORDINATE`] (which it would keep). Blank serials,
/// residue numbers, occupancies and temperature factors are left to
/// `pdbtbx`.
fn check_atom_fields(line: &str) -> Result<(), String> {
    // pdbtbx would say only "not the right kind (f64)" for any of these,
    // or give up without a line on a record cut short.
    if line.len() < 54 {
        return Err(format!(
            "atom record too short ({} characters): its coordinates take columns 31-54",
            line.len()
        ));
    }
    let field = |range: std::ops::Range<usize>| line.get(range).unwrap_or("").trim();
    for (what, range) in [
        ("atom serial number", 6..11),
        ("residue sequence number", 22..26),
    ] {
        let text = field(range.clone());
        if !text.is_empty() && text.parse::<i64>().is_err() {
            // Files past 99,999 atoms or 9,999 residues may number them so.
            let hybrid36 = text.len() == range.len()
                && text.starts_with(|c: char| c.is_ascii_alphabetic())
                && text.chars().all(|c| c.is_ascii_alphanumeric());
            return Err(format!(
                "{what} (columns {}-{}) is not a whole number: \"{text}\"{}",
                range.start + 1,
                range.end,
                if hybrid36 {
                    " (a hybrid-36 number, which bump does not read: use the structure's mmCIF file)"
                } else {
                    ""
                }
            ));
        }
    }
    for (axis, range) in [("x", 30..38), ("y", 38..46), ("z", 46..54)] {
        let text = field(range.clone());
        let Ok(v) = text.parse::<f64>() else {
            return Err(format!(
                "{axis} coordinate (columns {}-{}) is not a number: \"{text}\"",
                range.start + 1,
                range.end
            ));
        };
        if !v.is_finite() {
            return Err(format!("{axis} coordinate is not finite: {v}"));
        }
        if v.abs() > MAX_FILE_COORDINATE {
            return Err(format!(
                "{axis} coordinate {v} is beyond ±{MAX_FILE_COORDINATE:e} Å"
            ));
        }
    }
    for (what, range) in [("occupancy", 54..60), ("temperature factor", 60..66)] {
        let text = field(range.clone());
        if !text.is_empty() && text.parse::<f64>().is_err() {
            return Err(format!(
                "{what} (columns {}-{}) is not a number: \"{text}\"",
                range.start + 1,
                range.end
            ));
        }
    }
    Ok(())
}

/// Names for blank chain identifiers, as `pdbtbx` gives them (`A`, then the
/// next letter after each `TER`), except that letters a named chain of the
/// file uses are skipped (`pdbtbx` would put a blank-chain ligand numbered
/// 16 into residue 16 of chain `A`), and that a residue number coming back
/// with another residue name also starts a new chain. Files written by
/// simulation programs (chain blank, segments in columns 73–76) number their
/// waters from 1 again, and `pdbtbx` would otherwise merge water 7 into
/// residue 7 of the protein, under the protein residue's name. A chain that
/// is named in the file and numbers two residues alike is refused instead.
struct ChainNames {
    /// Identifiers blank chains may take, in order: those no named chain of
    /// the first model uses.
    free: Vec<u8>,
    /// Letters given to blank chains so far, past the first.
    advanced: usize,
    /// Residue (chain, number, insertion code) of the previous atom line.
    previous: Option<[u8; 6]>,
    /// Residue name and first line of each residue seen in this chain run.
    seen: HashMap<[u8; 6], ([u8; 3], usize)>,
    /// Past the first model: only the first is read, so nothing is checked.
    done: bool,
}

impl ChainNames {
    /// Chain names for PDB `text`, whose named chains are looked up first.
    fn new(text: &str) -> Self {
        let mut taken = [false; 128];
        for line in text.lines() {
            if line.starts_with("ENDMDL") {
                break;
            }
            if (line.starts_with("ATOM  ") || line.starts_with("HETATM"))
                && let Some(&c) = line.as_bytes().get(21)
            {
                taken[usize::from(c & 0x7f)] = true;
            }
        }
        let mut free: Vec<u8> = (b'A'..=b'Z')
            .chain(b'a'..=b'z')
            .chain(b'0'..=b'9')
            .filter(|c| !taken[usize::from(*c)])
            .collect();
        if free.is_empty() {
            free = (b'A'..=b'Z').collect();
        }
        Self {
            free,
            advanced: 0,
            previous: None,
            seen: HashMap::new(),
            done: false,
        }
    }

    /// Notes a record that is not an atom: `TER` starts a new blank chain,
    /// `ENDMDL` ends the first model.
    fn other_record(&mut self, line: &str) {
        if line.starts_with("TER") {
            self.next_blank_chain();
            self.previous = None;
        } else if line.starts_with("ENDMDL") {
            self.done = true;
        }
    }

    /// Blank chains from here on get the next letter: their residue
    /// numbers start afresh (a named chain's do not, in `pdbtbx` either).
    fn next_blank_chain(&mut self) {
        self.advanced = self.advanced.wrapping_add(1);
        self.seen.retain(|key, _| key[0] != b' ');
    }

    /// The chain identifier to write into this atom line (column 22).
    fn chain_of(&mut self, line: &str, number: usize) -> Result<u8, String> {
        let b = line.as_bytes();
        let given = b.get(21).copied().unwrap_or(b' ');
        if self.done || b.len() < 27 {
            return Ok(given);
        }
        let key: [u8; 6] = std::array::from_fn(|k| b[21 + k]);
        let name: [u8; 3] = std::array::from_fn(|k| b[17 + k]);
        let new_residue = self.previous != Some(key);
        self.previous = Some(key);
        if new_residue
            && let Some((other, first)) = self.seen.get(&key).copied()
            && other != name
        {
            if given != b' ' {
                let text = |v: &[u8]| String::from_utf8_lossy(v).trim().to_string();
                return Err(format!(
                    "residue {} {} {} reuses the number of residue {} on line {first}; residues of one chain need their own numbers (or insertion codes)",
                    text(&name),
                    given as char,
                    text(&key[1..]),
                    text(&other),
                ));
            }
            self.next_blank_chain();
        }
        self.seen.entry(key).or_insert((name, number));
        Ok(if given == b' ' {
            self.free[self.advanced % self.free.len()]
        } else {
            given
        })
    }
}

/// Pads an atom line to 80 columns and fills blank occupancy, B-factor and
/// element fields. Lines too short to hold coordinates are left for `pdbtbx`
/// to reject.
fn normalise_atom_line(line: &str, chain: u8, out: &mut String) {
    if line.len() < 54 || !line.is_ascii() {
        out.push_str(line);
        return;
    }
    let mut b: Vec<u8> = line.as_bytes().to_vec();
    if b.len() < 80 {
        b.resize(80, b' ');
    }
    if chain.is_ascii_graphic() {
        b[21] = chain;
    }
    let blank = |b: &[u8], r: std::ops::Range<usize>| b[r].iter().all(|c| *c == b' ');
    if blank(&b, 54..60) {
        b[54..60].copy_from_slice(b"  1.00");
    }
    if blank(&b, 60..66) {
        b[60..66].copy_from_slice(b"  0.00");
    }
    if blank(&b, 76..78) {
        let name = std::str::from_utf8(&b[12..16]).unwrap_or("");
        let residue = std::str::from_utf8(&b[17..20]).unwrap_or("");
        if let Some(e) = guess_pdb_element(name, residue) {
            let e = e.to_ascii_uppercase();
            let bytes = e.as_bytes();
            if bytes.len() == 1 {
                b[77] = bytes[0];
            } else if bytes.len() == 2 {
                b[76..78].copy_from_slice(bytes);
            }
        }
    }
    // Every byte came from an ASCII line or is ASCII padding.
    out.push_str(std::str::from_utf8(&b).unwrap_or(line));
}

/// Residue names whose atoms are only C, N, O, S, P and H: amino acids (with
/// common protonation-state names), nucleotides and caps. Their atom names
/// start with the element letter, whatever the column alignment.
const POLYMER_RESIDUES: &[&str] = &[
    "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE", "LEU", "LYS", "MET",
    "PHE", "PRO", "SER", "THR", "TRP", "TYR", "VAL", "HID", "HIE", "HIP", "HSD", "HSE", "HSP",
    "CYX", "ASH", "GLH", "LYN", "ACE", "NME", "NMA", "DA", "DC", "DG", "DT", "DU", "DI", "A", "C",
    "G", "U", "I",
];

/// Guesses an element from a PDB atom-name field (columns 13–16, unstripped)
/// and its residue name, by the PDB convention that the element symbol is
/// right-justified in columns 13–14:
/// - in standard polymer residues and waters, the first letter of the name;
/// - when column 13 is blank or a digit, the first letter (`" CA "` is carbon);
/// - when column 13 is a letter: a four-character name starting with `H` is
///   hydrogen (`HG21`); a name whose letters are exactly two and form an
///   element symbol, or equal the residue name, is that element (`FE`,
///   `CL1 `, `CA` in residue `CA`); otherwise the first letter.
///
/// `None` when the name has no letter.
pub fn guess_pdb_element(name: &str, residue: &str) -> Option<String> {
    let trimmed = name.trim();
    let letters: String = trimmed
        .chars()
        .skip_while(|c| c.is_ascii_digit())
        .take_while(|c| c.is_ascii_alphabetic())
        .collect();
    let first = letters.chars().next()?.to_ascii_uppercase().to_string();
    let residue = residue.trim().to_ascii_uppercase();
    if POLYMER_RESIDUES.contains(&residue.as_str()) || super::is_water(&residue) {
        return Some(first);
    }
    let col13_letter = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    if !col13_letter || letters.len() < 2 {
        return Some(first);
    }
    if first == "H" && trimmed.len() == 4 {
        return Some(first);
    }
    let upper = letters.to_ascii_uppercase();
    let two = &upper[..2];
    if (letters.len() == 2 || upper == residue) && pdbtbx::Element::from_symbol(two).is_some() {
        return Some(element::normalize_symbol(two));
    }
    Some(first)
}

/// The element for an atom `pdbtbx` could not type: the first letter of its
/// name (after any leading digits), or `X`.
fn guess_from_name(name: &str) -> String {
    name.chars()
        .find(|c| c.is_ascii_alphabetic())
        .map_or_else(|| "X".to_string(), |c| c.to_ascii_uppercase().to_string())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    /// The shared test-data folder, or `None` (after saying so) when it is
    /// missing outside CI. In CI a missing folder fails the test.
    use crate::model::test_data_dir as data_dir;

    fn load(name: &str, hydrogens: Hydrogens) -> Option<Loaded> {
        let dir = data_dir()?;
        let opts = LoadOptions {
            hydrogens,
            ..LoadOptions::default()
        };
        Some(load_pdbtbx(&dir.join(name), &opts).unwrap_or_else(|e| panic!("{name}: {e}")))
    }

    fn parse_pdb_text(text: &str) -> Result<Loaded, LoadError> {
        parse_text(
            text,
            Format::Pdb,
            "inline.pdb",
            "inline.pdb",
            &LoadOptions::default(),
        )
    }

    fn parse_cif_text(text: &str) -> Result<Loaded, LoadError> {
        parse_text(
            text,
            Format::Mmcif,
            "t.cif",
            "t.cif",
            &LoadOptions::default(),
        )
    }

    #[test]
    fn element_guessing_follows_pdb_alignment() {
        let g = |n: &str, r: &str| guess_pdb_element(n, r).unwrap();
        assert_eq!(g(" CA ", "ALA"), "C");
        assert_eq!(g("CA  ", "ALA"), "C"); // left-aligned, but a polymer residue
        assert_eq!(g("CA  ", "CA"), "Ca");
        assert_eq!(g("FE  ", "HEM"), "Fe");
        assert_eq!(g(" C1 ", "TOP"), "C");
        assert_eq!(g("CL1 ", "LIG"), "Cl");
        assert_eq!(g("CAB ", "LIG"), "C");
        assert_eq!(g("HG21", "LIG"), "H");
        assert_eq!(g("1HG2", "LIG"), "H");
        assert_eq!(g(" OH2", "TIP"), "O");
        assert!(guess_pdb_element(" 12 ", "LIG").is_none());
    }

    #[test]
    fn one_ubq_pdb_and_cif_agree() {
        let Some(pdb) = load("1ubq.pdb", Hydrogens::Drop) else {
            return;
        };
        let cif = load("1ubq.cif", Hydrogens::Drop).unwrap();
        assert_eq!(pdb.structure.atoms.len(), 660);
        assert_eq!(pdb.structure.atoms.len(), cif.structure.atoms.len());
        assert_eq!(pdb.structure.name, "1ubq.pdb");
        let a = &pdb.structure.atoms[1];
        assert_eq!((a.name.as_str(), a.residue.as_str()), ("CA", "MET"));
        assert_eq!((a.element.as_str(), a.chain.as_str(), a.seq), ("C", "A", 1));
        assert_eq!(a.serial, 2);
        assert!(!a.hetero);
        assert!(pdb.structure.atoms.last().unwrap().hetero);
        for (p, c) in pdb.structure.positions.iter().zip(&cif.structure.positions) {
            assert!((*p - *c).length() < 1e-3);
        }
    }

    #[test]
    fn file_order_is_kept_across_chains() {
        let Some(l) = load("4dfr.pdb", Hydrogens::Drop) else {
            return;
        };
        let serials: Vec<i64> = l.structure.atoms.iter().map(|a| a.serial).collect();
        assert!(serials.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn real_alt_locs_keep_the_higher_occupancy() {
        // 4dfr SER A 64 and HIS B 45 have A (1.00) and B (< 1) conformers.
        let Some(l) = load("4dfr.pdb", Hydrogens::Drop) else {
            return;
        };
        let ser: Vec<&AtomInfo> = l
            .structure
            .atoms
            .iter()
            .filter(|a| a.chain == "A" && a.seq == 64)
            .collect();
        assert_eq!(ser.len(), 6);
        let serials: Vec<i64> = ser.iter().map(|a| a.serial).collect();
        assert_eq!(serials, vec![498, 500, 502, 504, 506, 508]);
        let his = l
            .structure
            .atoms
            .iter()
            .filter(|a| a.chain == "B" && a.seq == 45)
            .count();
        assert_eq!(his, 10);
    }

    #[test]
    fn inline_alt_locs_pick_highest_occupancy_and_keep_shared_atoms() {
        let text = "\
ATOM      1  N   SER A   1       0.000   0.000   0.000  1.00 10.00           N
ATOM      2  CA  SER A   1       1.000   0.000   0.000  1.00 10.00           C
ATOM      3  CB ASER A   1       2.000   0.000   0.000  0.30 10.00           C
ATOM      4  CB BSER A   1       2.000   1.000   0.000  0.70 10.00           C
ATOM      5  OG ASER A   1       3.000   0.000   0.000  0.50 10.00           O
ATOM      6  OG BSER A   1       3.000   1.000   0.000  0.50 10.00           O
ATOM      7  C   SER A   1       1.000   1.000   1.000  1.00 10.00           C
END
";
        let l = parse_pdb_text(text).unwrap();
        let s = &l.structure;
        let serials: Vec<i64> = s.atoms.iter().map(|a| a.serial).collect();
        assert_eq!(serials, vec![1, 2, 4, 5, 7]);
        assert_eq!(s.positions[2], DVec3::new(2.0, 1.0, 0.0));
    }

    #[test]
    fn short_lines_without_elements_are_read() {
        // Columns end at 66: no element, no segment id.
        let text = "\
ATOM      1  N   MET     1      38.296  20.158  39.260  1.00  0.00
ATOM      2  CA  MET     1      37.000  20.000  39.000
HETATM    3 CA    CA     2      30.000  20.000  39.000  1.00  0.00
HETATM    4  O   HOH     3      31.000  20.000  39.000  1.00  0.00
";
        let l = parse_pdb_text(text).unwrap();
        let els: Vec<&str> = l
            .structure
            .atoms
            .iter()
            .map(|a| a.element.as_str())
            .collect();
        assert_eq!(els, vec!["N", "C", "Ca", "O"]);
    }

    #[test]
    fn solvated_file_without_element_columns_loads() {
        let Some(l) = load("5dfr_solvated.pdb", Hydrogens::Keep) else {
            return;
        };
        assert_eq!(l.structure.atoms.len(), 23558);
        assert!(l.structure.atoms.iter().all(|a| a.radius != UNKNOWN_RADIUS));
        let heavy = load("5dfr_solvated.pdb", Hydrogens::Drop).unwrap();
        assert!(heavy.structure.atoms.iter().all(|a| a.element != "H"));
        // Its 7023 waters are numbered from 1 again in the same blank
        // chain: they must stay waters (7023 of them), and the receptor is
        // DHFR's 159 residues (1268 heavy atoms), not those plus 159 of
        // the waters under protein names.
        let waters = heavy.structure.atoms.iter().filter(|a| a.residue == "HOH");
        assert_eq!(waters.count(), 7023);
        let receptor = crate::model::receptor_only(&heavy.structure).unwrap();
        assert_eq!(receptor.len(), 1268);
    }

    #[test]
    fn bad_coordinate_is_a_parse_error_with_its_line() {
        let text = "\
HEADER    TEST
ATOM      1  N   MET A   1      38.296  20.158  39.260  1.00  0.00           N
ATOM      2  CA  MET A   1      3x.000  20.000  39.000  1.00  0.00           C
";
        match parse_pdb_text(text) {
            Err(LoadError::Parse { line, .. }) => assert_eq!(line, Some(3)),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn only_the_first_model_is_read() {
        let text = "\
MODEL        1
ATOM      1  N   MET A   1       0.000   0.000   0.000  1.00  0.00           N
ATOM      2  CA  MET A   1       1.000   0.000   0.000  1.00  0.00           C
ENDMDL
MODEL        2
ATOM      1  N   MET A   1       5.000   0.000   0.000  1.00  0.00           N
ATOM      2  CA  MET A   1       6.000   0.000   0.000  1.00  0.00           C
ENDMDL
END
";
        let l = parse_pdb_text(text).unwrap();
        assert_eq!(l.structure.atoms.len(), 2);
        assert_eq!(l.structure.positions[1], DVec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn parser_panic_becomes_parse_error() {
        // pdbtbx `expect`s an element: `?` makes it panic.
        let r = parse_cif_text(&mmcif_with_rows(&[
            "ATOM 1 ? N . MET A 1 1 ? 0.0 0.0 0.0 1.0",
        ]));
        assert!(matches!(r, Err(LoadError::Parse { .. })), "{r:?}");
    }

    #[test]
    fn a_bad_numeric_field_is_named_with_its_columns_and_text() {
        let good = atom_line(1, "N", "ALA", 'A', 1, 0.0);
        let cases: [(usize, usize, &str, &str); 7] = [
            (
                30,
                38,
                "    zz.z",
                "x coordinate (columns 31-38) is not a number: \"zz.z\"",
            ),
            (
                54,
                60,
                "  x.00",
                "occupancy (columns 55-60) is not a number: \"x.00\"",
            ),
            (
                60,
                66,
                " 1.0.0",
                "temperature factor (columns 61-66) is not a number",
            ),
            (
                22,
                26,
                "  1x",
                "residue sequence number (columns 23-26) is not a whole number: \"1x\"",
            ),
            (
                6,
                11,
                "    x",
                "atom serial number (columns 7-11) is not a whole number: \"x\"",
            ),
            (6, 11, "A0000", "hybrid-36"),
            (
                40,
                good.trim_end().len(),
                "",
                "atom record too short (40 characters)",
            ),
        ];
        for (from, to, text, says) in cases {
            let mut line = good.trim_end().to_string();
            line.replace_range(from..to, text);
            let file = format!("HEADER    TEST\n{good}{line}\n");
            match parse_pdb_text(&file) {
                Err(LoadError::Parse {
                    line: Some(3),
                    reason,
                    ..
                }) => assert!(reason.contains(says), "{reason}"),
                other => panic!("{says}: {other:?}"),
            }
        }
        // Blank optional fields stay pdbtbx's to judge: this one reads.
        let mut line = good.trim_end().to_string();
        line.replace_range(54..66, &" ".repeat(12));
        assert!(parse_pdb_text(&format!("{line}\n")).is_ok());
    }

    #[test]
    fn a_control_character_in_a_name_is_refused_with_its_line() {
        // pdbtbx panics on it ("Invalid Conformer ID"); the message must
        // still say where.
        let mut text = String::from("HEADER    TEST\n");
        text.push_str(&atom_line(1, "N", "ALA", 'A', 1, 0.0));
        text.push_str(&atom_line(2, "CA", "A\u{1}A", 'A', 1, 1.5));
        match parse_pdb_text(&text) {
            Err(LoadError::Parse {
                line: Some(3),
                reason,
                ..
            }) => assert!(reason.contains("U+0001"), "{reason}"),
            other => panic!("{other:?}"),
        }
    }

    /// A PDB atom line (chain `ch`, one character).
    fn atom_line(serial: usize, name: &str, res: &str, ch: char, seq: i32, x: f64) -> String {
        format!(
            "ATOM  {serial:>5} {name:<4} {res:>3} {ch}{seq:>4}    {x:>8.3}{:>8.3}{:>8.3}  1.00  0.00           {}\n",
            0.0,
            0.0,
            &name[..1]
        )
    }

    #[test]
    fn a_water_reusing_a_residue_number_stays_a_water() {
        // Chains blank, waters numbered from 1 again (as simulation programs
        // write them): pdbtbx would put water 1 into ALA 1, under its name.
        let mut text = String::new();
        text += &atom_line(1, "N", "ALA", ' ', 1, 0.0);
        text += &atom_line(2, "CA", "ALA", ' ', 1, 1.5);
        text += &atom_line(3, "O", "ALA", ' ', 1, 2.5);
        text += &atom_line(4, "N", "GLY", ' ', 2, 4.0);
        text += &atom_line(5, "O", "HOH", ' ', 1, 10.0);
        text += &atom_line(6, "O", "HOH", ' ', 2, 20.0);
        let l = parse_pdb_text(&text).unwrap();
        let names: Vec<(&str, &str, &str)> = l
            .structure
            .atoms
            .iter()
            .map(|a| (a.name.as_str(), a.residue.as_str(), a.chain.as_str()))
            .collect();
        assert_eq!(
            names,
            [
                ("N", "ALA", "A"),
                ("CA", "ALA", "A"),
                ("O", "ALA", "A"),
                ("N", "GLY", "A"),
                ("O", "HOH", "B"),
                ("O", "HOH", "B"),
            ]
        );
        let receptor = crate::model::receptor_only(&l.structure).unwrap();
        assert_eq!(receptor.len(), 4);
        // Alternates of one residue with two names (microheterogeneity,
        // consecutive lines) are not a reuse.
        let micro = "ATOM      1  CA AARG A  10       0.000   0.000   0.000  0.60  0.00           C\n\
                     ATOM      2  CA BLYS A  10       0.100   0.000   0.000  0.40  0.00           C\n";
        let l = parse_pdb_text(micro).unwrap();
        assert_eq!(l.structure.atoms.len(), 1);
        assert_eq!(l.structure.atoms[0].residue, "ARG");
    }

    #[test]
    fn a_blank_chain_takes_a_letter_no_named_chain_uses() {
        // Protein in chains A and B (named); a ligand with a blank chain and
        // a number the protein uses: pdbtbx would put it into ILE A 16.
        let mut text = String::new();
        text += &atom_line(1, "N", "ILE", 'A', 16, 0.0);
        text += &atom_line(2, "CA", "ILE", 'A', 16, 1.5);
        text += &atom_line(3, "N", "GLY", 'B', 16, 5.0);
        text += "TER\n";
        text += &atom_line(4, "C1", "BEN", ' ', 16, 30.0);
        text += &atom_line(5, "C2", "BEN", ' ', 16, 31.5);
        let l = parse_pdb_text(&text).unwrap();
        let ids: Vec<(&str, &str)> = l
            .structure
            .atoms
            .iter()
            .map(|a| (a.residue.as_str(), a.chain.as_str()))
            .collect();
        assert_eq!(
            ids,
            [
                ("ILE", "A"),
                ("ILE", "A"),
                ("GLY", "B"),
                ("BEN", "D"),
                ("BEN", "D")
            ]
        );
        let (_, drug) = crate::model::split_complex(
            &l.structure,
            &crate::model::LigandSpec::parse("BEN").unwrap(),
        )
        .unwrap();
        assert_eq!(drug.len(), 2);
    }

    #[test]
    fn a_hydrogen_only_ligand_says_its_atoms_were_dropped() {
        let mut text = String::new();
        text += &atom_line(1, "N", "ALA", 'A', 1, 0.0);
        text += &atom_line(2, "H", "ALA", 'A', 1, 1.0);
        text += &atom_line(3, "H1", "HHH", 'A', 2, 9.0);
        text += &atom_line(4, "H2", "HHH", 'A', 2, 9.7);
        let l = parse_pdb_text(&text).unwrap();
        // ALA kept its nitrogen, so only HHH is listed, once.
        assert_eq!(
            l.structure.hydrogen_only,
            [("HHH".to_string(), "A/2".to_string())]
        );
        let err = crate::model::split_complex(
            &l.structure,
            &crate::model::LigandSpec::parse("hhh").unwrap(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("residue HHH (A/2) has only hydrogen atoms")
                && err.contains("--hydrogens keep"),
            "{err}"
        );
    }

    #[test]
    fn a_named_chain_reusing_a_residue_number_is_refused_with_its_line() {
        let mut text = String::new();
        text += &atom_line(1, "N", "ALA", 'A', 1, 0.0);
        text += &atom_line(2, "CA", "ALA", 'A', 1, 1.5);
        text += "TER\n";
        text += &atom_line(3, "C1", "LIG", 'A', 1, 30.0);
        match parse_pdb_text(&text) {
            Err(LoadError::Parse {
                line: Some(4),
                reason,
                ..
            }) => assert!(
                reason.contains("LIG A 1") && reason.contains("ALA"),
                "{reason}"
            ),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn coordinates_that_are_not_finite_or_absurd_are_refused_with_their_line() {
        for (bad, what) in [
            ("     nan", "not finite"),
            ("     inf", "not finite"),
            ("  1.0e15", "beyond"),
            ("99999999", "beyond"),
        ] {
            let good = atom_line(1, "N", "ALA", 'A', 1, 0.0);
            let mut line = atom_line(2, "CA", "ALA", 'A', 1, 1.5);
            line.replace_range(38..46, bad);
            match parse_pdb_text(&(good + &line)) {
                Err(LoadError::Parse {
                    line: Some(2),
                    reason,
                    ..
                }) => assert!(reason.contains('y') && reason.contains(what), "{reason}"),
                other => panic!("{bad}: {other:?}"),
            }
        }
        // Within range, far out: kept.
        let mut line = atom_line(1, "CA", "ALA", 'A', 1, 0.0);
        line.replace_range(30..38, "999999.0");
        assert!(parse_pdb_text(&line).is_ok());
    }

    #[test]
    fn no_atoms_is_no_atoms() {
        let r = parse_pdb_text("HEADER    NOTHING HERE\nEND\n");
        assert!(matches!(r, Err(LoadError::NoAtoms { .. })), "{r:?}");
    }

    #[test]
    fn missing_file_is_io() {
        let r = load_pdbtbx(Path::new("/nonexistent/x.pdb"), &LoadOptions::default());
        assert!(matches!(r, Err(LoadError::Io { .. })));
    }

    #[test]
    fn unknown_elements_get_default_radius_and_one_warning_each() {
        let Some(l) = load("1dt6.pdb", Hydrogens::Drop) else {
            return;
        };
        for sym in ["Fe", "Sm"] {
            let atoms: Vec<&AtomInfo> = l
                .structure
                .atoms
                .iter()
                .filter(|a| a.element == sym)
                .collect();
            assert_eq!(atoms.len(), 1, "{sym}");
            assert_eq!(atoms[0].radius, UNKNOWN_RADIUS);
            let n = l
                .warnings
                .iter()
                .filter(|w| w.contains(&format!("element {sym} ")) && w.contains("1dt6.pdb"))
                .count();
            assert_eq!(n, 1, "{sym}: {:?}", l.warnings);
        }
    }

    #[test]
    fn an_element_field_naming_no_element_is_unknown_not_guessed_from_the_name() {
        // pdbtbx would read "QQ" as chlorine, from the atom name CL.
        let mut line = atom_line(2, "CL", "LIG", 'A', 1, 1.5)
            .trim_end()
            .to_string();
        line.replace_range(76..78, "QQ");
        let text = format!("{}{line}\n", atom_line(1, "C1", "LIG", 'A', 1, 0.0));
        let l = parse_pdb_text(&text).expect("loads");
        let c = parse_cif_text(&mmcif_with_rows(&[
            "HETATM 1 C C1 . LIG A 1 1 ? 0.0 0.0 0.0 1.0",
            "HETATM 2 QQ CL . LIG A 1 1 ? 1.5 0.0 0.0 1.0",
        ]))
        .expect("loads");
        for l in [l, c] {
            let a = &l.structure.atoms;
            assert_eq!((a[0].element.as_str(), a[1].element.as_str()), ("C", "Qq"));
            assert_eq!(a[1].radius, UNKNOWN_RADIUS);
            assert_eq!(
                l.warnings
                    .iter()
                    .filter(|w| w.contains("element Qq "))
                    .count(),
                1,
                "{:?}",
                l.warnings
            );
        }
    }

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

    #[test]
    fn mmcif_with_symmetry_pdbtbx_rejects_loads() {
        let Some(l) = load("3nzd.cif", Hydrogens::Drop) else {
            return;
        };
        // 1866 rows, 23 of them the B half of equal-occupancy (0.50) alt-loc pairs.
        assert_eq!(l.structure.atoms.len(), 1866 - 23);
        let ca = l
            .structure
            .atoms
            .iter()
            .position(|a| a.seq == 59 && a.name == "CA")
            .unwrap();
        assert_eq!(l.structure.atoms[ca].serial, 461); // ties go to the first (A)
        assert!((l.structure.positions[ca].x - -9.053).abs() < 1e-9);
        let d2q = l
            .structure
            .atoms
            .iter()
            .filter(|a| a.residue == "D2Q")
            .count();
        assert_eq!(d2q, 32);
    }

    #[test]
    fn atom_site_loop_is_cut_out() {
        let text = "data_X\n#\nloop_\n_cell.a\n1\n#\nloop_\n_atom_site.id\n_atom_site.x\n1 2.0\n2 3.0\n#\n_other.a 1\n";
        let (cut, from) = mmcif_atom_site_only(text).unwrap();
        assert_eq!(
            cut,
            "data_X\nloop_\n_atom_site.id\n_atom_site.x\n1 2.0\n2 3.0\n"
        );
        // The original line of each line of the cut-out.
        assert_eq!(from, [1, 7, 8, 9, 10, 11]);
        assert!(mmcif_atom_site_only("data_X\nloop_\n_cell.a\n1\n").is_none());
    }

    #[test]
    fn cif_values_keep_quoted_values_whole() {
        assert_eq!(
            cif_values("ATOM 1 O \"O5'\" . 'A B' 1.0 # note"),
            ["ATOM", "1", "O", "\"O5'\"", ".", "'A B'", "1.0"]
        );
        assert_eq!(cif_values("  "), Vec::<&str>::new());
    }

    /// A small mmCIF file with `rows` as its atom_site rows, from line 20.
    fn mmcif_with_rows(rows: &[&str]) -> String {
        let mut text = String::from("data_T\n#\n_entry.id T\n#\nloop_\n");
        for c in [
            "group_PDB",
            "id",
            "type_symbol",
            "label_atom_id",
            "label_alt_id",
            "label_comp_id",
            "label_asym_id",
            "label_entity_id",
            "label_seq_id",
            "pdbx_PDB_ins_code",
            "Cartn_x",
            "Cartn_y",
            "Cartn_z",
            "occupancy",
        ] {
            text += &format!("_atom_site.{c}\n");
        }
        for r in rows {
            text += r;
            text += "\n";
        }
        text
    }

    fn mmcif_error(text: &str) -> (Option<usize>, String) {
        match parse_cif_text(text) {
            Err(LoadError::Parse { line, reason, .. }) => (line, reason),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn mmcif_row_errors_name_the_files_line() {
        let good = "ATOM 1 N N . ALA A 1 1 ? 1.0 2.0 3.0 1.0";
        assert!(parse_cif_text(&mmcif_with_rows(&[good])).is_ok());
        // A short row: its own line (21), not the loop's.
        let (line, reason) = mmcif_error(&mmcif_with_rows(&[
            good,
            "ATOM 2 C CA . ALA A 1 1 ? 2.0 3.0",
        ]));
        assert_eq!(line, Some(21), "{reason}");
        assert!(
            reason.contains("has 12 values; the loop has 14 columns"),
            "{reason}"
        );
        // A coordinate that is not a number, named with its atom.
        let (line, reason) = mmcif_error(&mmcif_with_rows(&[
            good,
            "ATOM 2 C CA . ALA A 1 1 ? abc 3.0 4.0 1.0",
        ]));
        assert_eq!(line, Some(21), "{reason}");
        assert_eq!(reason, "Cartn_x of atom 2 is not a number: \"abc\"");
    }

    #[test]
    fn gzipped_pdb_loads() {
        let Some(l) = load("2btv.pdb.gz", Hydrogens::Drop) else {
            return;
        };
        assert_eq!(l.structure.atoms.len(), 49061);
    }

    #[test]
    fn large_gzipped_mmcif_loads() {
        let Some(l) = load("1f2n_assembly1.cif.gz", Hydrogens::Drop) else {
            return;
        };
        assert_eq!(l.structure.atoms.len(), 271_860);
    }

    #[test]
    fn hydrogens_kept_or_dropped() {
        let Some(keep) = load("6xg5_tmp_prepared.pdb", Hydrogens::Keep) else {
            return;
        };
        let drop = load("6xg5_tmp_prepared.pdb", Hydrogens::Drop).unwrap();
        assert_eq!(keep.structure.atoms.len(), 2491 + 39);
        assert_eq!(drop.structure.atoms.len(), 1268 + 21);
    }
}
