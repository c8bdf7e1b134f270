//! PDB atom records, checked and normalised before `pdbtbx` sees them, one
//! line in, one line out, so every line number it reports is still the
//! file's:
//! - a record cut before its coordinates end, or with a serial, residue
//!   number, coordinate, occupancy or B-factor that does not read as a
//!   number, is refused, naming the field, its columns and its text
//!   ([`check_atom_fields`]);
//! - lines shorter than 80 columns are padded (`pdbtbx` rejects lines that
//!   end before the element column, which many programs write);
//! - a blank occupancy becomes `1.00` and a blank B-factor `0.00`;
//! - a blank element column is filled with the element guessed from the atom
//!   name ([`guess_pdb_element`]);
//! - blank chain identifiers get letters no named chain uses, and a residue
//!   number that comes back under another residue name starts a new chain
//!   ([`ChainNames`]).

use std::collections::HashMap;

use super::guess::guess_pdb_element;
use crate::model::{LoadError, MAX_FILE_COORDINATE};

/// Normalises the `ATOM`/`HETATM` lines of PDB text (see the module docs);
/// other lines pass unchanged. Line count and order are kept.
///
/// # Errors
/// [`LoadError::Parse`], naming the line, for an atom record that
/// [`check_atom_fields`] refuses (cut short, a numeric field that is not a
/// number, a coordinate not finite or beyond [`MAX_FILE_COORDINATE`]), and
/// for a residue number that a chain gives to two different residues.
pub(super) fn normalise_pdb(text: &str, label: &str) -> Result<String, LoadError> {
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
                "{axis} coordinate {text} is beyond ±{MAX_FILE_COORDINATE:e} Å"
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

/// Serial → element field, as written, of the atom records of PDB text
/// whose element field (columns 77-78) names no element `pdbtbx` knows: it
/// would give those atoms one guessed from their names.
pub(super) fn unknown_elements_pdb(text: &str) -> HashMap<usize, String> {
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
