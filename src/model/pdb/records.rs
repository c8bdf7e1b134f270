//! PDB records read by their columns, one line at a time:
//! - `ATOM`/`HETATM` records are checked ([`check_atom_fields`]): a record
//!   cut before its coordinates end, a serial, residue number, coordinate,
//!   occupancy or B-factor that does not read as a number, a coordinate not
//!   finite or beyond [`MAX_FILE_COORDINATE`], or a control character in a
//!   name is refused, naming the field, its columns and its text. Records
//!   of every model are checked; the first model's are kept.
//! - A blank occupancy reads 1; a blank element column gets the element
//!   guessed from the atom name ([`guess_pdb_element`]).
//! - Blank chain identifiers get letters no named chain uses, and a residue
//!   number that comes back under another residue name starts a new chain
//!   ([`ChainNames`]).
//! - `CONECT` records give the bonds (their first four bonded atoms, the
//!   covalent ones); `TER` and `ENDMDL` end chains and the first model.

use std::collections::HashMap;
use std::io::Read;

use glam::DVec3;

use super::guess::{guess_from_name, guess_pdb_element};
use super::{Raw, ascii_line, element_label, line_error};
use crate::model::label::ElementSymbol;
use crate::model::{AtomInfo, Label, LoadError, MAX_FILE_COORDINATE};
use crate::text::{LineReader, excerpt};

/// At most this many warnings about `CONECT` records are given one by one.
const MAX_CONECT_WARNINGS: usize = 5;

/// Reads the atoms of PDB text's first model and its `CONECT` bonds.
///
/// # Errors
/// [`LoadError::Parse`] naming the line and column of a record that
/// [`check_atom_fields`] refuses, of a residue number that a named chain
/// gives to two residues, or of mmCIF text read as PDB; a line reader's
/// failure ([`super::line_error`]).
pub(super) fn read_pdb<R: Read>(lines: &mut LineReader<R>, label: &str) -> Result<Raw, LoadError> {
    let mut raw = Raw::default();
    let mut chains = ChainNames::default();
    // Blank-chain atoms: (index, run), for letters given at the end.
    let mut blank: Vec<(usize, usize)> = Vec::new();
    let mut looked_at_start = false;
    let mut scratch = String::new();
    let mut conect_warnings = 0;
    // The first unreadable charge field (line, text) and how many there were.
    let mut odd_charges: (Option<(usize, String)>, usize) = (None, 0);
    while let Some((number, bytes)) = lines.next_line().map_err(|e| line_error(label, e))? {
        let line = ascii_line(bytes, &mut scratch);
        let at = |column: usize, reason: String| {
            LoadError::parse_at(label, Some(number), Some(column), reason)
        };
        if !looked_at_start && !line.trim().is_empty() {
            looked_at_start = true;
            if line.trim_start().starts_with("data_") {
                return Err(LoadError::parse_at(
                    label,
                    Some(number),
                    None,
                    "this is mmCIF text (it opens with data_), read as PDB because of its name; name it .cif",
                ));
            }
        }
        if line.starts_with("ATOM  ") || line.starts_with("HETATM") {
            let fields = check_atom_fields(line).map_err(|(c, r)| at(c, r))?;
            if chains.done {
                continue;
            }
            let charge = formal_charge(line).unwrap_or_else(|| {
                if odd_charges.0.is_none() {
                    odd_charges.0 = Some((number, excerpt(line.get(78..80).unwrap_or(""))));
                }
                odd_charges.1 += 1;
                0
            });
            let chain = chains.chain_of(line, number).map_err(|r| at(22, r))?;
            if let Chain::Blank(run) = chain {
                blank.push((raw.atoms.len(), run));
            }
            let given = match chain {
                Chain::Named(c) => Label::truncated(char::from(c).encode_utf8(&mut [0; 4])),
                Chain::Blank(_) => Label::EMPTY,
            };
            raw.push(
                AtomInfo {
                    serial: fields.serial,
                    name: Label::truncated(line[12..16].trim()),
                    residue: Label::truncated(line[17..20].trim()),
                    seq: fields.seq,
                    insertion: Label::truncated(line[26..27].trim()),
                    chain: given,
                    element: fields.element,
                    radius: 0.0,
                    polar: false,
                    hetero: line.starts_with("HETATM"),
                },
                fields.position,
                fields.occupancy,
                match line.as_bytes()[16] {
                    b' ' => 0,
                    c => c,
                },
                charge,
            );
        } else if line.starts_with("TER") {
            chains.next_blank_chain();
            chains.previous = None;
        } else if line.starts_with("ENDMDL") {
            chains.done = true;
        } else if line.starts_with("CONECT") {
            match conect(line) {
                Ok(pairs) => raw.bonds.serials.extend(pairs),
                Err((column, reason)) => {
                    conect_warnings += 1;
                    if conect_warnings <= MAX_CONECT_WARNINGS {
                        raw.warnings.push(format!(
                            "{label}:{number}:{column}: {reason}; the record is skipped"
                        ));
                    }
                }
            }
        }
    }
    if conect_warnings > MAX_CONECT_WARNINGS {
        raw.warnings.push(format!(
            "{label}: ... and {} more CONECT records skipped",
            conect_warnings - MAX_CONECT_WARNINGS
        ));
    }
    if let (Some((line, text)), n) = odd_charges {
        raw.warnings.push(format!(
            "{label}:{line}:79: the charge field (columns 79-80) reads {text}, not a charge \
             such as 1- or 2+; {n} such record(s) read as uncharged"
        ));
    }
    let free = chains.free_letters();
    for (i, run) in blank {
        let letter = free[run % free.len()];
        raw.atoms[i].chain = Label::truncated(char::from(letter).encode_utf8(&mut [0; 4]));
    }
    Ok(raw)
}

/// The fields of an atom record that are numbers, or that are worked out.
struct AtomFields {
    serial: i64,
    seq: i64,
    position: DVec3,
    occupancy: f32,
    element: ElementSymbol,
}

/// Checks and reads an atom record. Refuses a record cut before its
/// coordinates end, a numeric field (serial, residue number, coordinates,
/// occupancy, temperature factor) that does not read as a number, naming
/// the field, its columns and its text, a coordinate that is not finite or
/// lies beyond [`MAX_FILE_COORDINATE`], and a control character in a name.
/// Blank serials and residue numbers read 0, a blank occupancy 1. The error
/// is the column it points at and the message.
fn check_atom_fields(line: &str) -> Result<AtomFields, (usize, String)> {
    if line.len() < 54 {
        return Err((
            1,
            format!(
                "atom record too short ({} characters): its coordinates take columns 31-54",
                line.len()
            ),
        ));
    }
    if let Some((at, c)) = line
        .char_indices()
        .take(80)
        .find(|(_, c)| c.is_ascii_control())
    {
        return Err((
            at + 1,
            format!(
                "control character U+{:04X} in an atom record (names must be printable)",
                u32::from(c)
            ),
        ));
    }
    let field = |range: std::ops::Range<usize>| line.get(range).unwrap_or("").trim();
    let mut whole = [0i64; 2];
    for (slot, (what, range)) in whole.iter_mut().zip([
        ("atom serial number", 6..11),
        ("residue sequence number", 22..26),
    ]) {
        let text = field(range.clone());
        if text.is_empty() {
            continue;
        }
        let Ok(v) = text.parse::<i64>() else {
            // Files past 99,999 atoms or 9,999 residues may number them so.
            let hybrid36 = text.len() == range.len()
                && text.starts_with(|c: char| c.is_ascii_alphabetic())
                && text.chars().all(|c| c.is_ascii_alphanumeric());
            return Err((
                range.start + 1,
                format!(
                    "{what} (columns {}-{}) is not a whole number: {}{}",
                    range.start + 1,
                    range.end,
                    excerpt(text),
                    if hybrid36 {
                        " (a hybrid-36 number, which bump does not read: use the structure's mmCIF file)"
                    } else {
                        ""
                    }
                ),
            ));
        };
        *slot = v;
    }
    let mut xyz = [0.0; 3];
    for (slot, (axis, range)) in xyz
        .iter_mut()
        .zip([("x", 30..38), ("y", 38..46), ("z", 46..54)])
    {
        let text = field(range.clone());
        let Ok(v) = text.parse::<f64>() else {
            return Err((
                range.start + 1,
                format!(
                    "{axis} coordinate (columns {}-{}) is not a number: {}",
                    range.start + 1,
                    range.end,
                    excerpt(text)
                ),
            ));
        };
        if !v.is_finite() {
            return Err((
                range.start + 1,
                format!("{axis} coordinate is not finite: {v}"),
            ));
        }
        if v.abs() > MAX_FILE_COORDINATE {
            return Err((
                range.start + 1,
                format!("{axis} coordinate {text} is beyond ±{MAX_FILE_COORDINATE:e} Å"),
            ));
        }
        *slot = v;
    }
    let mut occupancy = 1.0;
    for (what, range) in [("occupancy", 54..60), ("temperature factor", 60..66)] {
        let text = field(range.clone());
        if text.is_empty() {
            continue;
        }
        match text.parse::<f64>() {
            Ok(v) if range.start == 54 => occupancy = v as f32,
            Ok(_) => {}
            Err(_) => {
                return Err((
                    range.start + 1,
                    format!(
                        "{what} (columns {}-{}) is not a number: {}",
                        range.start + 1,
                        range.end,
                        excerpt(text)
                    ),
                ));
            }
        }
    }
    let symbol = field(76..78);
    let element = if symbol.is_empty() {
        let name = line.get(12..16).unwrap_or("");
        let residue = line.get(17..20).unwrap_or("");
        let guess =
            guess_pdb_element(name, residue).unwrap_or_else(|| guess_from_name(name.trim()));
        Label::truncated(&guess)
    } else {
        // A symbol naming no element stays as written: an unknown element.
        element_label(symbol).unwrap_or_default()
    };
    Ok(AtomFields {
        serial: whole[0],
        seq: whole[1],
        position: DVec3::from_array(xyz),
        occupancy,
        element,
    })
}

/// The formal charge in columns 79–80 of an atom record: blank is 0, and
/// the format's `1-` or `2+` (or `-1`, `+2`, a bare digit) the charge; None
/// for anything else.
fn formal_charge(line: &str) -> Option<i8> {
    let text = line.get(78..80).unwrap_or("").trim();
    let b = text.as_bytes();
    let digit = |c: u8| c.is_ascii_digit().then(|| (c - b'0') as i8);
    match b {
        [] => Some(0),
        [d] => digit(*d),
        [d, b'+'] | [b'+', d] => digit(*d),
        [d, b'-'] | [b'-', d] => digit(*d).map(|v| -v),
        _ => None,
    }
}

/// The bonded pairs of a `CONECT` record: the atom in columns 7–11 with
/// each of those in columns 12–31 (later columns held hydrogen bonds and
/// salt bridges in old files). The error is a column and a message.
fn conect(line: &str) -> Result<Vec<(i64, i64)>, (usize, String)> {
    let serial = |start: usize| -> Result<Option<i64>, (usize, String)> {
        let text = line
            .get(start..(start + 5).min(line.len()))
            .unwrap_or("")
            .trim();
        if text.is_empty() {
            return Ok(None);
        }
        text.parse().map(Some).map_err(|_| {
            (
                start + 1,
                format!(
                    "CONECT serial (columns {}-{}) is not a whole number: {}",
                    start + 1,
                    start + 5,
                    excerpt(text)
                ),
            )
        })
    };
    let Some(from) = serial(6)? else {
        return Err((7, "CONECT record without an atom serial".to_string()));
    };
    let mut out = Vec::new();
    for start in [11, 16, 21, 26] {
        if let Some(to) = serial(start)? {
            out.push((from, to));
        }
    }
    Ok(out)
}

/// A chain as an atom record gives it: a letter, or blank (a letter to be
/// chosen once every named chain is known).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Chain {
    /// Named in the file.
    Named(u8),
    /// Blank, in the `run`th blank chain.
    Blank(usize),
}

/// Names for blank chain identifiers: `A`, then the next letter after each
/// `TER`, skipping letters a named chain of the first model uses (else a
/// blank-chain ligand numbered 16 would join residue 16 of chain `A`); a
/// residue number coming back with another residue name also starts a new
/// chain. Files written by simulation programs (chain blank, segments in
/// columns 73–76) number their waters from 1 again, which must not merge
/// water 7 into residue 7 of the protein. A chain that is named in the file
/// and numbers two residues alike is refused instead.
struct ChainNames {
    /// Letters named chains of the first model use.
    taken: [bool; 128],
    /// Blank chains started so far, past the first.
    advanced: usize,
    /// Residue (chain, number, insertion code) of the previous atom line.
    previous: Option<[u8; 6]>,
    /// Residue name and first line of each residue of a named chain.
    seen: HashMap<[u8; 6], ([u8; 3], usize)>,
    /// The same for the blank chain of this run (forgotten at its end).
    seen_blank: HashMap<[u8; 6], ([u8; 3], usize)>,
    /// Past the first model: only the first is read.
    done: bool,
}

impl Default for ChainNames {
    fn default() -> Self {
        Self {
            taken: [false; 128],
            advanced: 0,
            previous: None,
            seen: HashMap::new(),
            seen_blank: HashMap::new(),
            done: false,
        }
    }
}

impl ChainNames {
    /// Blank chains from here on get the next letter: their residue
    /// numbers start afresh (a named chain's do not).
    fn next_blank_chain(&mut self) {
        self.advanced = self.advanced.wrapping_add(1);
        if !self.seen_blank.is_empty() {
            // A fresh map: clearing would cost its capacity at every TER.
            self.seen_blank = HashMap::new();
        }
    }

    /// The chain of this atom record (at least 54 columns, ASCII), line
    /// `number`.
    fn chain_of(&mut self, line: &str, number: usize) -> Result<Chain, String> {
        let b = line.as_bytes();
        let given = b[21];
        self.taken[usize::from(given & 0x7f)] = true;
        let key: [u8; 6] = std::array::from_fn(|k| b[21 + k]);
        let name: [u8; 3] = std::array::from_fn(|k| b[17 + k]);
        let new_residue = self.previous != Some(key);
        self.previous = Some(key);
        let seen = if given == b' ' {
            &mut self.seen_blank
        } else {
            &mut self.seen
        };
        if new_residue
            && let Some((other, first)) = seen.get(&key).copied()
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
        let seen = if given == b' ' {
            &mut self.seen_blank
        } else {
            &mut self.seen
        };
        seen.entry(key).or_insert((name, number));
        Ok(if given == b' ' {
            Chain::Blank(self.advanced)
        } else {
            Chain::Named(given)
        })
    }

    /// The letters blank chains take, in order: those no named chain uses
    /// (all of `A`–`Z` when every one is used).
    fn free_letters(&self) -> Vec<u8> {
        let free: Vec<u8> = (b'A'..=b'Z')
            .chain(b'a'..=b'z')
            .chain(b'0'..=b'9')
            .filter(|c| !self.taken[usize::from(*c)])
            .collect();
        if free.is_empty() {
            (b'A'..=b'Z').collect()
        } else {
            free
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    #[test]
    fn conect_records_give_pairs_of_serials() {
        assert_eq!(
            conect("CONECT    1    2    3                                                 "),
            Ok(vec![(1, 2), (1, 3)])
        );
        assert_eq!(
            conect("CONECT  413  412  414  415  416  417"),
            Ok(vec![(413, 412), (413, 414), (413, 415), (413, 416)])
        );
        assert_eq!(conect("CONECT    7"), Ok(vec![]));
        let (column, reason) = conect("CONECT    1   x2").unwrap_err();
        assert_eq!(column, 12);
        assert!(reason.contains("\"x2\""), "{reason}");
        assert!(conect("CONECT").is_err());
    }
}
