//! Reading Tripos MOL2 files (plain or gzipped), as docking sets and
//! ChimeraX, PyMOL and Open Babel write them.
//!
//! A file holds molecules, each starting at a `@<TRIPOS>MOLECULE` line;
//! [`LoadOptions::sdf_record`] picks one (1-based, the first by default).
//! Of a molecule's sections this reader uses:
//!
//! - `MOLECULE`: the name (line 1) and the counts line (line 2), whose atom
//!   count the `ATOM` section must match (a cut file is an error, not a
//!   smaller molecule);
//! - `ATOM`: `id name x y z type [subst_id [subst_name [charge …]]]`; the
//!   element is the SYBYL type's part before the dot (`C.ar` → C, `Cl` →
//!   Cl); dummy atoms and lone pairs (`Du`, `LP`) are left out with a
//!   warning; the residue is `subst_name` and its number `subst_id`;
//! - `BOND`: `id a b type`, with `1`, `2`, `3`, `ar` (aromatic), `am`
//!   (amide: single) and `du` / `un` (an order the file does not say); `nc`
//!   (not connected) is no bond. A bond naming an atom that is not there is
//!   left out with a warning naming the line;
//! - `UNITY_ATOM_ATTR`: `charge N` attributes are formal charges.
//!
//! Partial charges are not read: the chemistry computes Gasteiger charges
//! from the bonds, as for every other format. Every problem in what is read
//! (a short line, a coordinate that is not a number or lies beyond
//! [`MAX_FILE_COORDINATE`], an unknown bond type, an atom count the section
//! does not hold) is a [`LoadError::Parse`] naming the file's line. Nothing
//! is sized by a count read from the file.

use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;

use super::element;
use super::pdb::{RadiusLookup, read_bytes};
use super::small::{self, Record, Which};
use super::{
    AtomInfo, BondOrder, FileBond, Label, LoadError, LoadOptions, Loaded, MAX_FILE_COORDINATE,
};
use crate::text::excerpt;

/// Longest residue label taken from a substructure or molecule name.
const MAX_RESIDUE_CHARS: usize = 8;

/// The line that starts a molecule.
const MOLECULE: &str = "@<TRIPOS>MOLECULE";

/// Reads one molecule of a MOL2 file (plain, or gzipped `.mol2.gz`).
///
/// # Errors
/// [`LoadError::Io`] for an unreadable file; [`LoadError::Parse`] with the
/// file's line number for malformed content or a molecule number past the
/// end; [`LoadError::NoAtoms`] for a molecule without atoms left.
pub fn load_mol2(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let bytes = read_bytes(path, opts.max_decompressed())?;
    let text = String::from_utf8_lossy(&bytes);
    parse_mol2(&text, &path.display().to_string(), opts)
}

/// One atom line as read: its id, name, element, residue and position.
struct RawAtom {
    id: i64,
    name: String,
    element: String,
    residue: Option<(String, i64)>,
    position: DVec3,
}

/// Parses MOL2 text already in memory. `path_label` names the source in
/// messages; its last path component becomes [`Structure::name`](super::Structure::name).
///
/// # Errors
/// As [`load_mol2`], less the I/O error.
pub fn parse_mol2(text: &str, path_label: &str, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let lines: Vec<&str> = crate::text::lines::split_str(text).collect();
    let err = |line: Option<usize>, reason: String| LoadError::Parse {
        path: path_label.to_string(),
        line: line.map(|i| i + 1),
        column: None,
        reason,
    };
    let starts: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].trim() == MOLECULE)
        .collect();
    if starts.is_empty() {
        return Err(err(None, format!("no {MOLECULE} line: not a MOL2 file")));
    }
    let wanted = opts.sdf_record.unwrap_or(1);
    if wanted == 0 {
        return Err(err(None, "MOL2 molecule numbers start at 1".to_string()));
    }
    let Some(&start) = starts.get(wanted - 1) else {
        return Err(err(
            None,
            format!(
                "asked for molecule {wanted} but the file has {} molecule{}",
                starts.len(),
                if starts.len() == 1 { "" } else { "s" }
            ),
        ));
    };
    let end = starts.get(wanted).copied().unwrap_or(lines.len());
    let name = lines.get(start + 1).map_or("", |l| l.trim()).to_string();
    let counts_at = start + 2;
    let counts = lines.get(counts_at).copied().unwrap_or("");
    let declared: usize = counts
        .split_whitespace()
        .next()
        .and_then(|f| f.parse().ok())
        .ok_or_else(|| {
            err(
                Some(counts_at),
                format!(
                    "the counts line should start with the atom count: {}",
                    excerpt(counts)
                ),
            )
        })?;

    // The sections of this molecule: header line index → its lines' range.
    let mut sections: Vec<(&str, usize, usize)> = Vec::new();
    for (i, line) in lines.iter().enumerate().take(end).skip(start + 1) {
        let l = line.trim();
        if let Some(tag) = l.strip_prefix("@<TRIPOS>") {
            if let Some(last) = sections.last_mut() {
                last.2 = i;
            }
            sections.push((tag, i + 1, end));
        }
    }
    let section = |tag: &str| sections.iter().find(|s| s.0 == tag).map(|s| (s.1, s.2));
    let Some((a0, a1)) = section("ATOM") else {
        return Err(err(
            Some(start),
            format!("molecule {wanted} has no @<TRIPOS>ATOM section"),
        ));
    };

    let mut warnings = Vec::new();
    let mut raw: Vec<RawAtom> = Vec::new();
    let mut skipped = 0usize;
    for (i, &line) in lines.iter().enumerate().take(a1).skip(a0) {
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() < 6 {
            return Err(err(
                Some(i),
                format!(
                    "an atom line needs id, name, x, y, z and type: {}",
                    excerpt(line)
                ),
            ));
        }
        let id: i64 = f[0].parse().map_err(|_| {
            err(
                Some(i),
                format!("atom id is not a number: {}", excerpt(f[0])),
            )
        })?;
        let mut xyz = [0.0f64; 3];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let v: f64 = f[2 + k].parse().map_err(|_| {
                err(
                    Some(i),
                    format!("{axis} coordinate is not a number: {}", excerpt(f[2 + k])),
                )
            })?;
            if !v.is_finite() {
                return Err(err(
                    Some(i),
                    format!("{axis} coordinate is not finite: {}", excerpt(f[2 + k])),
                ));
            }
            if v.abs() > MAX_FILE_COORDINATE {
                return Err(err(
                    Some(i),
                    format!(
                        "{axis} coordinate {} is beyond ±{MAX_FILE_COORDINATE:e} Å",
                        excerpt(f[2 + k])
                    ),
                ));
            }
            xyz[k] = v;
        }
        let sybyl = f[5];
        let base = sybyl.split('.').next().unwrap_or(sybyl);
        if base.eq_ignore_ascii_case("du") || base.eq_ignore_ascii_case("lp") {
            skipped += 1;
            continue;
        }
        let residue = match (f.get(6), f.get(7)) {
            (Some(id), Some(name)) if !name.starts_with('<') && !name.starts_with('*') => {
                Some(((*name).to_string(), id.parse().unwrap_or(0)))
            }
            _ => None,
        };
        raw.push(RawAtom {
            id,
            name: f[1].to_string(),
            element: element::normalize_symbol(base),
            residue,
            position: DVec3::from_array(xyz),
        });
    }
    if raw.len() + skipped != declared {
        return Err(err(
            Some(counts_at),
            format!(
                "the counts line says {declared} atoms but the ATOM section has {}",
                raw.len() + skipped
            ),
        ));
    }
    if skipped > 0 {
        warnings.push(format!(
            "{path_label}: {skipped} dummy atom{} or lone pair{} (Du, LP) left out",
            if skipped == 1 { "" } else { "s" },
            if skipped == 1 { "" } else { "s" }
        ));
    }
    let mut index: BTreeMap<i64, usize> = BTreeMap::new();
    for (k, a) in raw.iter().enumerate() {
        if index.insert(a.id, k).is_some() {
            return Err(err(
                Some(a0),
                format!("atom id {} appears twice in the ATOM section", a.id),
            ));
        }
    }

    let mut bonds: Vec<FileBond> = Vec::new();
    let bond_section = section("BOND");
    if let Some((b0, b1)) = bond_section {
        for (i, &line) in lines.iter().enumerate().take(b1).skip(b0) {
            if line.trim().is_empty() || line.trim_start().starts_with('#') {
                continue;
            }
            let f: Vec<&str> = line.split_whitespace().collect();
            if f.len() < 4 {
                return Err(err(
                    Some(i),
                    format!(
                        "a bond line needs id, two atom ids and a type: {}",
                        excerpt(line)
                    ),
                ));
            }
            let order = match f[3].to_ascii_lowercase().as_str() {
                "1" | "am" => BondOrder::Single,
                "2" => BondOrder::Double,
                "3" => BondOrder::Triple,
                "ar" => BondOrder::Aromatic,
                "du" | "un" => BondOrder::Unspecified,
                "nc" => continue,
                _ => {
                    return Err(err(Some(i), format!("unknown bond type {}", excerpt(f[3]))));
                }
            };
            let ends: Vec<Option<usize>> = f[1..3]
                .iter()
                .map(|v| v.parse::<i64>().ok().and_then(|id| index.get(&id).copied()))
                .collect();
            match (ends[0], ends[1]) {
                (Some(a), Some(b)) if a != b => bonds.push(FileBond {
                    a: a.min(b),
                    b: a.max(b),
                    order,
                }),
                _ => warnings.push(format!(
                    "{path_label}:{}: bond {} names no atom of the molecule, or one atom twice; \
                     the bond is left out",
                    i + 1,
                    excerpt(line.trim())
                )),
            }
        }
    }
    bonds.sort_unstable();
    bonds.dedup_by_key(|b| (b.a, b.b));

    let mut charges = vec![0i8; raw.len()];
    if let Some((u0, u1)) = section("UNITY_ATOM_ATTR") {
        // `id count`, then `count` lines of `name value`; only the lines
        // present are read.
        let mut i = u0;
        while i < u1 {
            let f: Vec<&str> = lines[i].split_whitespace().collect();
            i += 1;
            let (Some(id), Some(n)) = (
                f.first().and_then(|v| v.parse::<i64>().ok()),
                f.get(1).and_then(|v| v.parse::<usize>().ok()),
            ) else {
                continue;
            };
            let last = i.saturating_add(n).min(u1);
            for line in &lines[i..last] {
                let g: Vec<&str> = line.split_whitespace().collect();
                if let (Some(&"charge"), Some(q)) = (g.first(), g.get(1))
                    && let (Some(&k), Ok(q)) = (index.get(&id), q.parse::<i8>())
                {
                    charges[k] = q;
                }
            }
            i = last;
        }
    }

    let molecule_residue: String = if name.is_empty() {
        "LIG".to_string()
    } else {
        name.chars().take(MAX_RESIDUE_CHARS).collect()
    };
    let mut lookup = RadiusLookup::new(opts.radii);
    let mut atoms = Vec::with_capacity(raw.len());
    let mut positions = Vec::with_capacity(raw.len());
    for a in &raw {
        let (residue, seq) = a.residue.clone().unwrap_or((molecule_residue.clone(), 0));
        let residue: String = residue.chars().take(MAX_RESIDUE_CHARS).collect();
        atoms.push(AtomInfo {
            serial: a.id,
            name: a.name.as_str().into(),
            residue: residue.as_str().into(),
            seq,
            insertion: Label::EMPTY,
            chain: Label::EMPTY,
            radius: lookup.radius(&a.element),
            polar: element::is_polar(&a.element),
            element: a.element.as_str().into(),
            hetero: true,
        });
        positions.push(a.position);
    }
    let record = Record {
        atoms,
        positions,
        bonds,
        charges,
        bonds_stated: bond_section.is_some(),
    };
    let which = Which {
        path_label,
        count: starts.len(),
        wanted,
        noun: "molecule",
    };
    small::loaded(record, &which, opts, &lookup, warnings)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// Eleven atoms, eleven bonds, a charge, a hydrogen and a dummy atom.
    const BEN: &str = include_str!("../../tests/data/amidine.mol2");

    fn opts() -> LoadOptions {
        LoadOptions::default()
    }

    #[test]
    fn atoms_bonds_and_charges_are_read() {
        let l = parse_mol2(BEN, "ben.mol2", &opts()).unwrap();
        let s = &l.structure;
        // The dummy atom is left out and the hydrogen kept apart.
        assert_eq!(s.atoms.len(), 9);
        assert_eq!(s.atoms[7].element.as_str(), "N");
        assert_eq!(s.atoms[0].residue.as_str(), "BEN1");
        assert_eq!(s.atoms[0].seq, 1);
        assert_eq!(s.atoms[8].name.as_str(), "N2");
        assert!((s.positions[6] - DVec3::new(2.89, 0.0, 0.0)).length() < 1e-12);
        let order = |a: usize, b: usize| {
            s.bonds
                .iter()
                .find(|x| x.a == a && x.b == b)
                .map(|x| x.order)
        };
        assert_eq!(order(0, 1), Some(BondOrder::Aromatic));
        assert_eq!(order(6, 7), Some(BondOrder::Double));
        assert_eq!(order(6, 8), Some(BondOrder::Single));
        assert_eq!(s.bonds.len(), 9, "the bonds of the heavy atoms");
        assert!(s.file_chem.bonds_complete && s.file_chem.from_sdf);
        assert_eq!(s.file_chem.formal_charges[7], 1);
        assert_eq!(s.file_chem.hydrogens.len(), 1);
        assert!(l.warnings.iter().any(|w| w.contains("dummy")));
        assert!(
            l.warnings
                .iter()
                .any(|w| w.contains("ben.mol2:") && w.contains("left out")),
            "{:?}",
            l.warnings
        );
    }

    #[test]
    fn molecules_are_records() {
        let two = format!("{BEN}{}", BEN.replace("\nBEN\n 11", "\nSECOND\n 11"));
        let o = LoadOptions {
            sdf_record: Some(2),
            ..opts()
        };
        let l = parse_mol2(&two, "two.mol2", &o).unwrap();
        assert_eq!(l.structure.name, "two.mol2 record 2");
        let o = LoadOptions {
            sdf_record: Some(3),
            ..opts()
        };
        let e = parse_mol2(&two, "two.mol2", &o).unwrap_err().to_string();
        assert!(e.contains("2 molecules"), "{e}");
    }

    #[test]
    fn bad_input_names_the_line() {
        let cases = [
            (
                BEN.replace("-0.6950    1.2040", "nan    1.2040"),
                ":12:",
                "not finite",
            ),
            (
                BEN.replace("-0.6950    1.2040", "x1    1.2040"),
                ":12:",
                "not a number",
            ),
            (
                BEN.replace(" 11 11 0", " 12 11 0"),
                ":5:",
                "counts line says 12",
            ),
            (BEN.replace(" 11 11 0", " lots"), ":5:", "atom count"),
            (
                BEN.replace("   am\n", "   zz\n"),
                ":33:",
                "unknown bond type",
            ),
            (
                BEN.replace(
                    "-0.6950   -1.2040    0.0000 C.ar    1  BEN1        0.0",
                    "-0.6950",
                ),
                ":14:",
                "needs id",
            ),
            ("@<TRIPOS>ATOM\n".to_string(), "", "not a MOL2 file"),
            (
                BEN.replace("@<TRIPOS>ATOM", "@<TRIPOS>ATOMS"),
                "",
                "no @<TRIPOS>ATOM",
            ),
        ];
        for (text, line, what) in cases {
            let e = parse_mol2(&text, "bad.mol2", &opts())
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("bad.mol2") && e.contains(line) && e.contains(what),
                "{e}"
            );
        }
    }
}
