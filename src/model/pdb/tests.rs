//! Tests of PDB and mmCIF loading: real files from `../shared/pdb` and
//! small inline texts for each rule and error.

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
    Some(load_pdb_or_mmcif(&dir.join(name), &opts).unwrap_or_else(|e| panic!("{name}: {e}")))
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
    let r = load_pdb_or_mmcif(Path::new("/nonexistent/x.pdb"), &LoadOptions::default());
    assert!(matches!(r, Err(LoadError::Io { .. })));
}

#[test]
fn metals_take_ionic_radii_without_a_warning() {
    let Some(l) = load("1dt6.pdb", Hydrogens::Drop) else {
        return;
    };
    for (sym, radius) in [("Fe", 0.78), ("Sm", 0.958)] {
        let atoms: Vec<&AtomInfo> = l
            .structure
            .atoms
            .iter()
            .filter(|a| a.element == sym)
            .collect();
        assert_eq!(atoms.len(), 1, "{sym}");
        assert_eq!(atoms[0].radius, radius);
    }
    assert!(
        !l.warnings.iter().any(|w| w.contains("radius")),
        "{:?}",
        l.warnings
    );
}

#[test]
fn unknown_elements_get_default_radius_and_one_warning_each() {
    let mut text = atom_line(1, "C1", "LIG", 'A', 1, 0.0);
    for (serial, x) in [(2, 1.5), (3, 3.0)] {
        let mut line = atom_line(serial, "X1", "LIG", 'A', 1, x)
            .trim_end()
            .to_string();
        line.replace_range(76..78, "OG");
        text += &format!("{line}\n");
    }
    let l = parse_pdb_text(&text).expect("loads");
    let a = &l.structure.atoms;
    assert_eq!((a[1].element.as_str(), a[2].element.as_str()), ("Og", "Og"));
    assert_eq!((a[1].radius, a[2].radius), (UNKNOWN_RADIUS, UNKNOWN_RADIUS));
    let about: Vec<&String> = l
        .warnings
        .iter()
        .filter(|w| w.contains("element Og ") && w.contains("2 atoms") && w.contains("inline.pdb"))
        .collect();
    assert_eq!(about.len(), 1, "{:?}", l.warnings);
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
fn mmcif_tags_are_read_whatever_their_case() {
    // CIF tags are case-insensitive: `pdbtbx` found no atoms in this file.
    let upper = mmcif_with_rows(&[
        "HETATM 1 C C1 . LIG A 1 1 ? 0.0 0.0 0.0 1.0",
        "HETATM 2 QQ CL . LIG A 1 1 ? 1.5 0.0 0.0 1.0",
        "HETATM 3 C C2 . LIG A 1 1 ? 1e300 0.0 0.0 1.0",
    ])
    .replace("_atom_site.Cartn", "_ATOM_SITE.CARTN")
    .replace("_atom_site.", "_Atom_Site.")
    .replace("_Atom_Site.type_symbol", "_ATOM_SITE.TYPE_SYMBOL");
    assert!(!upper.contains("_atom_site."));
    // The out-of-range coordinate is found by its line (22) through the
    // same tags.
    let (line, reason) = mmcif_error(&upper);
    assert_eq!(line, Some(22), "{reason}");
    let last_row = upper.rfind("HETATM 3").unwrap();
    let l = parse_cif_text(&upper[..last_row]).expect("loads");
    let a = &l.structure.atoms;
    assert_eq!(a.len(), 2);
    assert_eq!((a[0].element.as_str(), a[1].element.as_str()), ("C", "Qq"));
    assert_eq!(a[1].radius, UNKNOWN_RADIUS);
    assert!((l.structure.positions[1].x - 1.5).abs() < 1e-12);
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
    // A number out of range, on the third row: that row's line (22).
    let (line, reason) = mmcif_error(&mmcif_with_rows(&[
        good,
        "ATOM 2 C CA . ALA A 1 1 ? 2.0 3.0 4.0 1.0",
        "ATOM 3 C C . ALA A 1 1 ? 2.0 -1e300 4.0 1.0",
    ]));
    assert_eq!(line, Some(22), "{reason}");
    assert!(
        reason.contains("atom 3 (C) is at (2, -1.000e300, 4), not within"),
        "{reason}"
    );
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

/// Columns 79-80 give formal charges as PDB writes them (`1-`, `2+`) and as
/// some programs do (`-1`, `+2`); blank is 0; a field that is not a charge
/// reads 0 with one warning naming its line; a file with no charge keeps
/// none.
#[test]
fn formal_charges_are_read_from_columns_79_to_80() {
    let line = |serial: usize, name: &str, element: &str, charge: &str| {
        format!(
            "HETATM{serial:5} {name:<4} LIG A   1    {:8.3}{:8.3}{:8.3}  1.00  0.00          {element:>2}{charge}",
            serial as f64 * 1.5,
            0.0,
            0.0
        )
    };
    let text = [
        line(1, "O1", "O", "1-"),
        line(2, "C2", "C", ""),
        line(3, "N3", "N", "1+"),
        line(4, "O4", "O", "-1"),
        line(5, "N5", "N", "+2"),
        line(6, "C6", "C", "x?"),
        line(7, "C7", "C", " 0"),
    ]
    .join("\n");
    let loaded = parse_pdb_text(&text).expect("parses");
    assert_eq!(
        loaded.structure.file_chem.formal_charges,
        vec![-1, 0, 1, -1, 2, 0, 0]
    );
    let warned: Vec<&String> = loaded
        .warnings
        .iter()
        .filter(|w| w.contains("charge field"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", loaded.warnings);
    assert!(
        warned[0].contains("inline.pdb:6:79") && warned[0].contains("x?"),
        "{}",
        warned[0]
    );
    let plain = [line(1, "O1", "O", ""), line(2, "C2", "C", "")].join("\n");
    let loaded = parse_pdb_text(&plain).expect("parses");
    assert!(loaded.structure.file_chem.formal_charges.is_empty());
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

/// mmCIF's `pdbx_formal_charge` gives formal charges (`?` is 0); a value
/// that is not a small whole number is refused, naming the atom.
#[test]
fn formal_charges_are_read_from_pdbx_formal_charge() {
    let cif = |charges: [&str; 3]| {
        let mut t = String::from(
            "data_t\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n\
             _atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.auth_asym_id\n\
             _atom_site.auth_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n\
             _atom_site.pdbx_formal_charge\n",
        );
        for (k, q) in charges.iter().enumerate() {
            t += &format!(
                "HETATM {} O O{} LIG A 1 {}.0 0.0 0.0 {q}\n",
                k + 1,
                k + 1,
                2 * k
            );
        }
        t
    };
    let loaded = parse_cif_text(&cif(["-1", "?", "2"])).expect("parses");
    assert_eq!(loaded.structure.file_chem.formal_charges, vec![-1, 0, 2]);
    let loaded = parse_cif_text(&cif(["?", ".", "0"])).expect("parses");
    assert!(loaded.structure.file_chem.formal_charges.is_empty());
    let err = parse_cif_text(&cif(["0", "half", "0"])).expect_err("refused");
    let msg = err.to_string();
    assert!(
        msg.contains("formal charge of atom 2") && msg.contains("half"),
        "{msg}"
    );
}
