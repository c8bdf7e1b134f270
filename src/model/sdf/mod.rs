//! Reading MDL SDF / molfile records (V2000 and V3000), plain or gzipped.
//!
//! A file holds records separated by `$$$$` lines; [`LoadOptions::sdf_record`]
//! picks one (1-based, the first by default). The atom block gives
//! coordinates, element symbols and formal charges (the charge column, or
//! `M  CHG` lines, which replace it; `CHG=` in V3000); the bond block gives
//! [`Structure::bonds`](super::Structure::bonds) with their orders (type 4 aromatic, the query types
//! 5–8 unspecified). A bond naming atom 0, an atom beyond the count or the
//! same atom twice is left out with a warning naming the line. Hydrogens,
//! when dropped, are kept apart with their bonds
//! ([`super::set_hydrogens_apart`]). Properties are skipped.
//!
//! The counts line (record line 4) ends in the version, `V2000` (or nothing,
//! in old files) or `V3000`; another is refused. V2000: the counts line gives
//! the atom count in columns 1–3; each atom line holds x, y, z in columns
//! 1–10, 11–20, 21–30 and the symbol in 32–34. A line that does not fit the columns is read as whitespace-separated
//! fields instead (some writers do not pad). V3000: the `M  V30` lines (with
//! `-` continuation) between `BEGIN ATOM` and `END ATOM`, checked against the
//! `COUNTS` line.
//!
//! Every problem is a [`LoadError::Parse`] carrying the 1-based line number in
//! the file: a malformed counts line, a short atom line, a non-numeric or
//! non-finite coordinate, and an atom count that disagrees with the atom lines
//! present (too few, or an atom line where the block should have ended).
//!
//! Atoms get serial = 1-based order in the record (counted before hydrogens are
//! dropped, so serials match the file), name = element + serial (`C3`),
//! residue = the record's title line trimmed and cut to 8 characters (`LIG`
//! when blank), sequence number 0, no chain, hetero set.
//!
//! This module splits the file into records and builds the structure; the
//! atom blocks are read in `v2000` and `v3000`, the bonds and formal
//! charges in `extras`.

mod extras;
mod v2000;
mod v3000;

use std::path::Path;

use glam::DVec3;

use super::element;
use super::pdb::{RadiusLookup, file_name, read_bytes};
use super::small::{self, Which};
use super::{AtomInfo, FileBond, Label, LoadError, LoadOptions, Loaded};

/// Longest residue label taken from a record's title line.
const MAX_RESIDUE_CHARS: usize = 8;

/// Reads one record of an SDF or MOL file (plain, or gzipped `.sdf.gz`).
///
/// # Errors
/// [`LoadError::Io`] for an unreadable file; [`LoadError::Parse`] with the
/// file's line number for malformed content or a record number past the end;
/// [`LoadError::NoAtoms`] for a file without records or a record without atoms
/// left.
pub fn load_sdf(path: &Path, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let bytes = read_bytes(path, opts.max_decompressed())?;
    let text = String::from_utf8_lossy(&bytes);
    let label = path.display().to_string();
    let mut loaded = parse_sdf(&text, &label, opts)?;
    loaded.structure.name = file_name(path);
    Ok(loaded)
}

/// The title line of each record of an SDF file (plain or gzipped),
/// trimmed: one entry per record, so their count is the file's.
///
/// # Errors
/// [`LoadError::Io`] for an unreadable file.
pub fn record_titles(path: &Path, opts: &LoadOptions) -> Result<Vec<String>, LoadError> {
    let bytes = read_bytes(path, opts.max_decompressed())?;
    let text = String::from_utf8_lossy(&bytes);
    let lines: Vec<&str> = crate::text::lines::split_str(&text).collect();
    Ok(split_records(&lines)
        .into_iter()
        .map(|(start, _)| lines.get(start).map_or("", |l| l.trim()).to_string())
        .collect())
}

/// Parses SDF text already in memory. `path_label` names the source in
/// messages; its last path component becomes [`Structure::name`](super::Structure::name).
///
/// # Errors
/// As [`load_sdf`], less the I/O error.
pub fn parse_sdf(text: &str, path_label: &str, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    let lines: Vec<&str> = crate::text::lines::split_str(text).collect();
    let records = split_records(&lines);
    let err = |line: Option<usize>, reason: String| LoadError::Parse {
        path: path_label.to_string(),
        line,
        column: None,
        reason,
    };
    if records.is_empty() {
        return Err(LoadError::NoAtoms {
            path: path_label.to_string(),
            dropped_hydrogens: 0,
        });
    }
    let wanted = opts.sdf_record.unwrap_or(1);
    if wanted == 0 {
        return Err(err(None, "SDF record numbers start at 1".to_string()));
    }
    let Some(&(start, end)) = records.get(wanted - 1) else {
        return Err(err(
            None,
            format!(
                "asked for SDF record {wanted} but the file has {} record{}",
                records.len(),
                if records.len() == 1 { "" } else { "s" }
            ),
        ));
    };
    let record = Record {
        lines: &lines[start..end],
        first: start,
        total: lines.len(),
        label: path_label,
    };
    let parsed = record.parse()?;
    let extras = record.extras(parsed.len());

    let residue = {
        let t = record.lines.first().map_or("", |l| l.trim());
        if t.is_empty() {
            "LIG".to_string()
        } else {
            t.chars().take(MAX_RESIDUE_CHARS).collect()
        }
    };
    let mut lookup = RadiusLookup::new(opts.radii);
    let mut atoms = Vec::with_capacity(parsed.len());
    let mut positions = Vec::with_capacity(parsed.len());
    for (i, (symbol, pos)) in parsed.into_iter().enumerate() {
        let element = element::normalize_symbol(&symbol);
        let serial = i + 1;
        atoms.push(AtomInfo {
            serial: i64::try_from(serial).unwrap_or(i64::MAX),
            name: format!("{element}{serial}").into(),
            residue: residue.as_str().into(),
            seq: 0,
            insertion: Label::EMPTY,
            chain: Label::EMPTY,
            radius: lookup.radius(&element),
            polar: element::is_polar(&element),
            element: element.as_str().into(),
            hetero: true,
        });
        positions.push(pos);
    }
    let mut bonds: Vec<FileBond> = extras
        .bonds
        .iter()
        .map(|&(a, b, order)| FileBond {
            a: a.min(b),
            b: a.max(b),
            order,
        })
        .collect();
    bonds.sort_unstable();
    bonds.dedup_by_key(|b| (b.a, b.b));
    let record = small::Record {
        atoms,
        positions,
        bonds,
        charges: extras.charges,
        bonds_stated: extras.bond_block,
    };
    let which = Which {
        path_label,
        count: records.len(),
        wanted,
        noun: "record",
    };
    small::loaded(record, &which, opts, &lookup, extras.warnings)
}

/// Record boundaries as `(first, end)` 0-based line indices, `$$$$` excluded.
/// Blank lines after the last `$$$$` make no record.
fn split_records(lines: &[&str]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, line) in lines.iter().enumerate() {
        if line.trim_end() == "$$$$" {
            out.push((start, i));
            start = i + 1;
        }
    }
    if lines[start..].iter().any(|l| !l.trim().is_empty()) {
        out.push((start, lines.len()));
    }
    out
}

/// One record's lines and where they sit in the file.
struct Record<'a> {
    lines: &'a [&'a str],
    /// 0-based index of the record's first line in the file.
    first: usize,
    /// Lines in the file.
    total: usize,
    label: &'a str,
}

/// Atoms as read: element symbol (as written) and position.
type RawAtoms = Vec<(String, DVec3)>;

impl Record<'_> {
    /// The 1-based file line number of record line `i` (0-based), capped at the
    /// file's last line.
    fn line_no(&self, i: usize) -> usize {
        (self.first + i + 1).min(self.total.max(1))
    }

    fn err(&self, i: usize, reason: impl Into<String>) -> LoadError {
        LoadError::Parse {
            path: self.label.to_string(),
            line: Some(self.line_no(i)),
            column: None,
            reason: reason.into(),
        }
    }

    fn parse(&self) -> Result<RawAtoms, LoadError> {
        let Some(counts) = self.lines.get(3) else {
            return Err(self.err(
                self.lines.len(),
                "record ends before its counts line (line 4 of the record)",
            ));
        };
        match version_tag(counts) {
            Some(tag) if tag.eq_ignore_ascii_case("V3000") => self.parse_v3000(),
            Some(tag) if tag.eq_ignore_ascii_case("V2000") => self.parse_v2000(counts),
            None => self.parse_v2000(counts),
            Some(other) => Err(self.err(
                3,
                format!("counts line names molfile version {other}; bump reads V2000 and V3000"),
            )),
        }
    }
}

/// The version tag of a counts line (`V2000`, `V3000`): a `V` and four
/// digits, as its last field (columns 34–39 when aligned); `None` for the
/// old files that have none, which are V2000.
fn version_tag(counts: &str) -> Option<&str> {
    let last = counts.split_whitespace().last()?;
    let tag = last.get(last.len().checked_sub(5)?..)?;
    (tag.starts_with(['V', 'v']) && tag[1..].bytes().all(|b| b.is_ascii_digit())).then_some(tag)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use crate::model::element::UNKNOWN_RADIUS;
    use crate::model::{BondOrder, Hydrogens};

    /// The shared test-data folder, or `None` (after saying so) when it is
    /// missing outside CI. In CI a missing folder fails the test.
    use crate::model::test_data_dir as data_dir;

    fn opts(hydrogens: Hydrogens, record: Option<usize>) -> LoadOptions {
        LoadOptions {
            hydrogens,
            sdf_record: record,
            ..LoadOptions::default()
        }
    }

    fn parse(text: &str) -> Result<Loaded, LoadError> {
        parse_sdf(text, "t.sdf", &LoadOptions::default())
    }

    fn parse_line(text: &str) -> Option<usize> {
        match parse(text) {
            Err(LoadError::Parse { line, .. }) => line,
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    const TWO_RECORDS: &str = "\
first
  test

  2  1  0  0  0  0  0  0  0  0999 V2000
    0.0000    0.0000    0.0000 C   0  0  0  0  0  0  0  0  0  0  0  0
    1.5000    0.0000    0.0000 O   0  0  0  0  0  0  0  0  0  0  0  0
  1  2  1  0
M  END
$$$$
second molecule name that is long
  test

  3  2  0  0  0  0  0  0  0  0999 V2000
    5.0000    0.0000    0.0000 N   0  0  0  0  0  0  0  0  0  0  0  0
    6.0000    0.0000    0.0000 H   0  0  0  0  0  0  0  0  0  0  0  0
    7.0000    0.0000    0.0000 Cl  0  0  0  0  0  0  0  0  0  0  0  0
  1  2  1  0
  1  3  1  0
M  END
$$$$
";

    #[test]
    fn the_counts_lines_version_picks_the_reader() {
        assert_eq!(
            version_tag("  2  1  0  0  0  0  0  0  0  0999 V2000"),
            Some("V2000")
        );
        assert_eq!(
            version_tag("  0  0  0     0  0            999 V3000"),
            Some("V3000")
        );
        assert_eq!(
            version_tag("  2  1  0  0  0  0  0  0  0  0999V2000"),
            Some("V2000")
        );
        assert_eq!(version_tag("  2  1"), None);
        assert_eq!(version_tag(""), None);
        let v9 = "x\n\n\n  1  0  0  0  0  0  0  0  0  0999 V9999\n    0.0000    0.0000    0.0000 C   0  0\nM  END\n";
        let e = parse(v9).expect_err("V9999");
        assert!(
            e.to_string()
                .contains(":4: counts line names molfile version V9999"),
            "{e}"
        );
        // Old files without a tag are V2000.
        let old = "x\n\n\n  1  0\n    0.0000    0.0000    0.0000 C   0  0\nM  END\n";
        assert_eq!(parse(old).expect("untagged").structure.atoms.len(), 1);
    }

    #[test]
    fn shared_sdf_files_load() {
        let Some(dir) = data_dir() else {
            return;
        };
        for (file, heavy, all) in [
            ("trimethoprim_top_6xg5pose.sdf", 21, 39),
            ("methotrexate_mtx_ideal.sdf", 33, 55),
            ("benzamidine_3ptb.sdf", 9, 18),
            ("1s3v_ligand_tqd.sdf", 27, 27),
        ] {
            let path = dir.join(file);
            let h = load_sdf(&path, &opts(Hydrogens::Drop, None)).unwrap();
            assert_eq!(h.structure.atoms.len(), heavy, "{file}");
            assert_eq!(h.structure.name, file);
            let k = load_sdf(&path, &opts(Hydrogens::Keep, None)).unwrap();
            assert_eq!(k.structure.atoms.len(), all, "{file}");
            assert!(h.warnings.is_empty(), "{file}: {:?}", h.warnings);
        }
        let b = load_sdf(&dir.join("benzamidine_3ptb.sdf"), &LoadOptions::default()).unwrap();
        let a = &b.structure.atoms[0];
        assert_eq!((a.serial, a.name.as_str()), (1, "C1"));
        assert_eq!(
            (a.residue.as_str(), a.seq, a.chain.as_str()),
            ("BEN", 0, "")
        );
        assert!(a.hetero);
        assert_eq!(b.structure.positions[0], DVec3::new(-1.853, 14.311, 16.658));
    }

    #[test]
    fn gzipped_sdf_loads() {
        let Some(dir) = data_dir() else {
            return;
        };
        let text = std::fs::read(dir.join("benzamidine_3ptb.sdf")).unwrap();
        let tmp = std::env::temp_dir().join(format!("bump-sdf-{}.sdf.gz", std::process::id()));
        let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        std::io::Write::write_all(&mut enc, &text).unwrap();
        std::fs::write(&tmp, enc.finish().unwrap()).unwrap();
        let l = load_sdf(&tmp, &LoadOptions::default());
        let _ = std::fs::remove_file(&tmp);
        assert_eq!(l.unwrap().structure.atoms.len(), 9);
    }

    #[test]
    fn record_selection() {
        let first = parse(TWO_RECORDS).unwrap();
        assert_eq!(first.structure.atoms.len(), 2);
        assert_eq!(first.structure.atoms[0].residue, "first");
        assert_eq!(first.warnings.len(), 1);
        let second = parse_sdf(TWO_RECORDS, "dir/t.sdf", &opts(Hydrogens::Drop, Some(2))).unwrap();
        let names: Vec<&str> = second
            .structure
            .atoms
            .iter()
            .map(|a| a.name.as_str())
            .collect();
        assert_eq!(names, vec!["N1", "Cl3"]);
        assert_eq!(second.structure.atoms[1].serial, 3);
        assert_eq!(second.structure.atoms[1].residue, "second m");
        assert_eq!(second.structure.name, "t.sdf record 2");
        assert_eq!(first.structure.name, "t.sdf record 1");
        assert_eq!(second.structure.positions[1], DVec3::new(7.0, 0.0, 0.0));
        match parse_sdf(TWO_RECORDS, "t.sdf", &opts(Hydrogens::Drop, Some(3))) {
            Err(LoadError::Parse { reason, .. }) => {
                assert!(reason.contains("2 records"), "{reason}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn v3000_with_continuation() {
        let text = include_str!("../../../tests/data/v3000_continuation.sdf");
        let l = parse_sdf(text, "t.sdf", &opts(Hydrogens::Keep, None)).unwrap();
        let s = &l.structure;
        assert_eq!(s.atoms.len(), 3);
        assert_eq!(s.atoms[1].name, "N2");
        assert_eq!(s.file_chem.formal_charges, vec![0, 1, 0]);
        assert_eq!(
            s.bonds,
            vec![
                FileBond {
                    a: 0,
                    b: 1,
                    order: BondOrder::Single
                },
                FileBond {
                    a: 0,
                    b: 2,
                    order: BondOrder::Single
                }
            ]
        );
        assert!(s.file_chem.bonds_complete);
        // Dropped, the hydrogen is kept apart with its carbon.
        let d = parse_sdf(text, "t.sdf", &opts(Hydrogens::Drop, None)).unwrap();
        let fc = &d.structure.file_chem;
        assert_eq!(d.structure.atoms.len(), 2);
        assert_eq!(fc.hydrogens.len(), 1);
        assert_eq!(
            (fc.hydrogens[0].parent, fc.hydrogens[0].before),
            (Some(0), 2)
        );
        assert_eq!(d.structure.bonds.len(), 1);
        assert!(s.atoms[1].polar);
        assert_eq!(s.positions[1], DVec3::new(4.0, 5.0, 6.0));
        assert_eq!(s.atoms[0].residue, "v3");

        let too_few = text.replace("COUNTS 3 2", "COUNTS 4 2");
        assert_eq!(parse_line(&too_few), Some(12));
        let too_many = text.replace("COUNTS 3 2", "COUNTS 2 2");
        assert_eq!(parse_line(&too_many), Some(11));
        let bad = text.replace("5.0 6.0", "5.0 abc");
        assert_eq!(parse_line(&bad), Some(9));
        let short = text.replace("M  V30 3 H 7.0 8.0 9.0 0", "M  V30 3 H 7.0");
        assert_eq!(parse_line(&short), Some(11));
        let counts = text.replace("COUNTS 3 2", "COUNTS x 2");
        assert_eq!(parse_line(&counts), Some(6));
    }

    #[test]
    fn malformed_v2000_reports_lines() {
        // Record 2 starts at file line 10; its counts line is line 13.
        let bad_counts = TWO_RECORDS.replace("  3  2  0  0", "  x  2  0  0");
        let r = parse_sdf(&bad_counts, "t.sdf", &opts(Hydrogens::Drop, Some(2)));
        assert!(
            matches!(r, Err(LoadError::Parse { line: Some(13), .. })),
            "{r:?}"
        );
        let bad_x = TWO_RECORDS.replace("    1.5000    0.0000", "    1.5z00    0.0000");
        assert_eq!(parse_line(&bad_x), Some(6));
        let nan = TWO_RECORDS.replace("    1.5000    0.0000", "       NaN    0.0000");
        assert_eq!(parse_line(&nan), Some(6));
        let inf = TWO_RECORDS.replace("    1.5000    0.0000", "       inf    0.0000");
        assert_eq!(parse_line(&inf), Some(6));
        let short = TWO_RECORDS.replace(
            "    1.5000    0.0000    0.0000 O   0  0  0  0  0  0  0  0  0  0  0  0",
            "    1.5000    0.0000",
        );
        assert_eq!(parse_line(&short), Some(6));
        // Count too large: the bond line is where atom 3 should be.
        let too_many = TWO_RECORDS.replacen("  2  1  0  0", "  3  1  0  0", 1);
        assert_eq!(parse_line(&too_many), Some(7));
        // Count too large with no bonds: M  END ends the block.
        let no_bonds = "x\n\n\n  2  0  0  0  0  0  0  0  0  0999 V2000\n    0.0000    0.0000    0.0000 C   0  0\nM  END\n";
        assert_eq!(parse_line(no_bonds), Some(6));
        // Count too small: an atom line follows the block.
        let too_few = TWO_RECORDS.replacen("  2  1  0  0", "  1  1  0  0", 1);
        assert_eq!(parse_line(&too_few), Some(6));
        // Truncated record: no counts line.
        assert_eq!(parse_line("name\nprog\n"), Some(2));
    }

    #[test]
    fn empty_inputs_have_no_atoms() {
        assert!(matches!(parse(""), Err(LoadError::NoAtoms { .. })));
        let zero = "empty\n\n\n  0  0  0  0  0  0  0  0  0  0999 V2000\nM  END\n$$$$\n";
        assert!(matches!(parse(zero), Err(LoadError::NoAtoms { .. })));
        let only_h = "h\n\n\n  1  0  0  0  0  0  0  0  0  0999 V2000\n    0.0000    0.0000    0.0000 H   0  0\nM  END\n";
        let e = parse(only_h).unwrap_err();
        assert!(matches!(
            e,
            LoadError::NoAtoms {
                dropped_hydrogens: 1,
                ..
            }
        ));
        assert!(e.to_string().contains("--hydrogens keep"), "{e}");
    }

    #[test]
    fn a_blank_element_column_is_named_as_such() {
        let text = "\n  test\n\n  2  0  0  0  0  0  0  0  0  0999 V2000\n    \
0.0000    0.0000    0.0000     0  0  0  0  0  0  0  0  0  0  0  0\n    \
1.5000    0.0000    0.0000 C   0  0  0  0  0  0  0  0  0  0  0  0\nM  END\n$$$$\n";
        match parse(text) {
            Err(LoadError::Parse { line, reason, .. }) => {
                assert_eq!(line, Some(5));
                assert!(
                    reason.contains("atom 1 of 2 has no element symbol"),
                    "{reason}"
                );
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
        // A line cut short after the coordinates says the same.
        let short = text.replacen("0.0000     0  0  0  0  0  0  0  0  0  0  0  0", "0.0000", 1);
        assert!(
            matches!(parse(&short), Err(LoadError::Parse { line: Some(5), reason, .. })
            if reason.contains("has no element symbol"))
        );
        // A symbol written a few columns late is still read.
        let late = text.replacen("0.0000     0  0", "0.0000      N  0", 1);
        let l = parse(&late).unwrap();
        assert_eq!(l.structure.atoms[0].element, "N");
    }

    #[test]
    fn unpadded_lines_and_unknown_elements() {
        let text = "\n\n\n2 0 0 0 0 0 0 0 0 0999 V2000\n1.0 2.0 3.0 Og 0\n-1.25 2 3 C\nM  END\n";
        let l = parse(text).unwrap();
        let s = &l.structure;
        assert_eq!(s.atoms[0].element, "Og");
        assert_eq!(s.atoms[0].residue, "LIG");
        assert_eq!(s.atoms[0].radius, UNKNOWN_RADIUS);
        assert_eq!(s.positions[1], DVec3::new(-1.25, 2.0, 3.0));
        assert_eq!(l.warnings.len(), 1);
        assert!(l.warnings[0].contains("t.sdf") && l.warnings[0].contains("Og"));
    }
}
