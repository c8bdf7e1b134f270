//! Each failure of the hostile-input round (issue 47), at its cause: counts
//! in files that lie, gzip bombs, errors that echo their input, line
//! endings, invalid UTF-8, numbers beyond the shared ranges, and oversized
//! joystick maps. The fuzz harness (`tests/fuzz.rs`) throws mutants at the
//! same readers; these are the cases named.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use bump::input::JoystickMap;
use bump::model::pdb::{Format, parse_bytes};
use bump::model::sdf::parse_sdf;
use bump::model::{BondOrder, LoadError, LoadOptions, load};
use bump::session::log::SessionLog;
use common::cli::{bump, stderr};

/// A fresh folder for this test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bump-robust-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn gzip(data: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

const V3000: &str = "v3\n  test\n\n  0  0  0     0  0            999 V3000\nM  V30 BEGIN CTAB\n\
M  V30 COUNTS 2 0 0 0 0\nM  V30 BEGIN ATOM\nM  V30 1 C 1.0 2.0 3.0 0\nM  V30 2 N 4.0 5.0 6.0 0\n\
M  V30 END ATOM\nM  V30 END CTAB\nM  END\n$$$$\n";

#[test]
fn sdf_counts_that_lie_are_refused_without_reserving_memory() {
    for claim in ["1000000000", "1000000000000000000", "18446744073709551615"] {
        let text = V3000.replace("COUNTS 2 0", &format!("COUNTS {claim} 0"));
        let e = parse_sdf(&text, "t.sdf", &LoadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(&format!("COUNTS says {claim} atoms")), "{e}");
    }
    // V2000 counts are three columns: at most 999, still not believed.
    let v2000 =
        "x\n\n\n999 0 0 0 0 0 0 0 0 0999 V2000\n    0.0000    0.0000    0.0000 C   0  0\nM  END\n";
    let e = parse_sdf(v2000, "t.sdf", &LoadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("says 999 atoms"), "{e}");
}

#[test]
fn every_line_ending_reads_alike() {
    let pdb = "HEADER    T\nATOM      1  N   ALA A   1       0.000   0.000   0.000  1.00  0.00           N\n\
               ATOM      2  CA  ALA A   1       1.500   0.000   0.000  1.00  0.00           C\n\
               ATOM      3  X   ALA A   1       1.500   x.000   0.000  1.00  0.00           C\n";
    let cif = "data_T\nloop_\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n\
               _atom_site.label_comp_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n\
               1 N N ALA 0 0 0\n2 C CA ALA 1.5 0 0\n3 C X ALA 1.5 x 0\n";
    let sdf = V3000.replace("5.0 6.0", "5.0 x");
    for (text, format) in [
        (pdb, Some(Format::Pdb)),
        (cif, Some(Format::Mmcif)),
        (&sdf, None),
    ] {
        let read = |t: &str| match format {
            Some(f) => parse_bytes(t.as_bytes(), f, "t", "t", &LoadOptions::default()).map(|_| ()),
            None => parse_sdf(t, "t", &LoadOptions::default()).map(|_| ()),
        };
        let lf = read(text).unwrap_err().to_string();
        for ending in ["\r\n", "\r"] {
            let e = read(&text.replace('\n', ending)).unwrap_err().to_string();
            assert_eq!(e, lf, "{ending:?}");
        }
        // Without the bad line, each reads.
        let good: String = text
            .split_inclusive('\n')
            .filter(|l| !l.contains(" X ") && !l.contains("5.0 x"))
            .collect();
        let good = good.replace("COUNTS 2", "COUNTS 1");
        assert!(read(&good.replace('\n', "\r")).is_ok(), "{good}");
    }
}

#[test]
fn errors_quote_short_excerpts_with_line_and_column() {
    let huge = "z".repeat(5_000_000);
    // An SDF field.
    let sdf = V3000.replace("COUNTS 2 0 0 0 0", &format!("COUNTS {huge}"));
    let e = parse_sdf(&sdf, "t.sdf", &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.len() < 300 && e.contains("(5000007 bytes)"),
        "{}",
        &e[..300.min(e.len())]
    );
    // A PDB coordinate, named by column.
    let pdb = format!(
        "ATOM      1  N   ALA A   1    {}   0.000   0.000  1.00  0.00           N\n",
        "é".repeat(4)
    );
    let e = parse_bytes(
        pdb.as_bytes(),
        Format::Pdb,
        "t.pdb",
        "t.pdb",
        &LoadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("t.pdb:1:31: x coordinate (columns 31-38)"),
        "{e}"
    );
    // An mmCIF value on a line of 5 MB.
    let cif = format!(
        "data_T\nloop_\n_atom_site.id\n_atom_site.label_atom_id\n_atom_site.label_comp_id\n\
         _atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n1 N ALA 0 {huge} 0\n"
    );
    let e = parse_bytes(
        cif.as_bytes(),
        Format::Mmcif,
        "t.cif",
        "t.cif",
        &LoadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("t.cif:9:11: Cartn_y of atom 1 is not a number: \"zzz"),
        "{}",
        &e[..200]
    );
    assert!(e.len() < 300, "{}", e.len());
    // A log line.
    let log = format!("bump-log 1\n{huge}\nend 0\n");
    let e = SessionLog::parse(&log, Path::new("x.log"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("x.log:2: unknown line kind \"zzz"),
        "{}",
        &e[..100]
    );
    assert!(e.len() < 300, "{}", e.len());
    // A joystick map value.
    let map =
        format!("version = 1\ntranslate_speed = 1\nrotate_speed = 1\nrotation = \"{huge}\"\n");
    let e = JoystickMap::parse(&map, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.len() < 600 && e.contains("line 4"),
        "{}",
        &e[..600.min(e.len())]
    );
}

#[test]
fn session_logs_read_any_line_ending_and_name_bad_bytes() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/sessions/tmp-dhfr.bumplog"
    ))
    .unwrap();
    let lf = SessionLog::parse(&text, Path::new("s.log")).unwrap();
    for ending in ["\r\n", "\r"] {
        let other = SessionLog::parse(&text.replace('\n', ending), Path::new("s.log")).unwrap();
        assert_eq!(other, lf, "{ending:?}");
    }
    let mut bytes = text.clone().into_bytes();
    let at = text.match_indices('\n').nth(14).unwrap().0 + 4;
    bytes[at] = 0xff;
    let e = SessionLog::parse_bytes(&bytes, Path::new("s.log"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.log:16: not UTF-8 text: byte 0xFF at column 4"),
        "{e}"
    );
}

/// A log line with its check value.
fn checked(body: &str) -> String {
    let h = body.bytes().fold(0x811c_9dc5u32, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    });
    format!("{body} ~{h:08x}")
}

#[test]
fn log_time_steps_and_moves_share_the_commands_range() {
    for (line, says) in [
        ("f 1e308", "time step 1e308 s, beyond the 1e6 s"),
        ("f -0.5", "time step -0.5 s is negative"),
        (
            "f 0.1 v=1e308,0,0,0,0,0",
            "translation 1e308 Å along an axis, beyond",
        ),
        (
            "f 0 c=move:3e9,0,0,0,0,1,0",
            "move 3e9 Å along an axis, beyond the 2e9 Å",
        ),
        (
            "final 0 2e9 0 0 0 0 0 1",
            "2e9 Å from the origin along an axis, beyond the 1e9 Å",
        ),
        ("final 0 0 0 0 0 0 0 0", "quaternion"),
    ] {
        let text = format!("bump-log 1\n{}\nend 1\n", checked(line));
        let e = SessionLog::parse(&text, Path::new("x.log"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("x.log:2: ") && e.contains(says),
            "{line}: {e}"
        );
    }
    let ok = format!("bump-log 1\n{}\nend 1\n", checked("f 1000000"));
    let log = SessionLog::parse(&ok, Path::new("x.log")).unwrap();
    assert_eq!(log.duration(), 1e6);
}

#[test]
fn a_gzip_bomb_is_refused_at_the_limit_naming_the_file() {
    let dir = scratch("bomb");
    let bomb = dir.join("bomb.pdb.gz");
    std::fs::write(&bomb, gzip(&vec![b' '; 64 << 20])).unwrap();
    let opts = LoadOptions {
        decompressed_limit: Some(16 << 20),
        ..LoadOptions::default()
    };
    let e = load(&bomb, &opts).unwrap_err();
    assert!(
        matches!(e, LoadError::TooLarge { limit, .. } if limit == 16 << 20),
        "{e}"
    );
    assert!(
        e.to_string().starts_with(&format!(
            "{}: decompresses to more than 16 MiB",
            bomb.display()
        )),
        "{e}"
    );
    // The command line's option and environment variable set the limit.
    let path = bomb.to_str().unwrap();
    let out = bump(&["check", path, "--max-decompressed", "1M"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("decompresses to more than 1 MiB"),
        "{}",
        stderr(&out)
    );
    let out = Command::new(env!("CARGO_BIN_EXE_bump"))
        .args(["check", path])
        .env("BUMP_MAX_DECOMPRESSED", "2MiB")
        .output()
        .unwrap();
    assert!(
        stderr(&out).contains("decompresses to more than 2 MiB"),
        "{}",
        stderr(&out)
    );
    let out = Command::new(env!("CARGO_BIN_EXE_bump"))
        .args(["check", path])
        .env("BUMP_MAX_DECOMPRESSED", "lots")
        .output()
        .unwrap();
    assert!(
        stderr(&out).contains("BUMP_MAX_DECOMPRESSED: `lots`"),
        "{}",
        stderr(&out)
    );
    // Within the default limit, 64 MiB of spaces is no atoms, not 4 GB.
    let e = load(&bomb, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("line is longer than"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_oversized_joystick_map_is_refused_before_it_is_parsed() {
    let dir = scratch("map");
    let map = dir.join("big.toml");
    let mut f = std::fs::File::create(&map).unwrap();
    for _ in 0..1000 {
        f.write_all(&vec![b'#'; 100_000]).unwrap();
        f.write_all(b"\n").unwrap();
    }
    drop(f);
    let e = JoystickMap::read(&map).unwrap_err().to_string();
    assert!(e.contains("longer than 1 MiB"), "{e}");
    // Classic Mac line endings and nesting too deep to recurse into.
    let cr = bump::input::map::DEFAULT_MAP.replace('\n', "\r");
    assert!(JoystickMap::parse_bytes(cr.as_bytes(), Path::new("cr.toml")).is_ok());
    let deep = format!("x = {}{}\n", "[".repeat(100_000), "]".repeat(100_000));
    let e = JoystickMap::parse(&deep, Path::new("d.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nest deeper"), "{e}");
    let e = JoystickMap::parse_bytes(b"version = 1\n\xff = 2\n", Path::new("u.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 2, column 1: not UTF-8"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn conect_and_struct_conn_bonds_join_kept_atoms() {
    let pdb = "\
ATOM      1  N   ALA A   1       0.000   0.000   0.000  1.00  0.00           N
ATOM      2  CA AALA A   1       1.500   0.000   0.000  0.60  0.00           C
ATOM      3  CA BALA A   1       1.500   0.100   0.000  0.40  0.00           C
ATOM      4  H   ALA A   1      -1.000   0.000   0.000  1.00  0.00           H
HETATM    5  C1  LIG B   1       5.000   0.000   0.000  1.00  0.00           C
HETATM    6  C2  LIG B   1       6.500   0.000   0.000  1.00  0.00           C
CONECT    5    6
CONECT    6    5    2
CONECT    3    1
CONECT    1    4
";
    let l = parse_bytes(
        pdb.as_bytes(),
        Format::Pdb,
        "t.pdb",
        "t.pdb",
        &LoadOptions::default(),
    )
    .unwrap();
    let pairs: Vec<(usize, usize)> = l.structure.bonds.iter().map(|b| (b.a, b.b)).collect();
    // Kept: N, CA A, C1, C2 (indices 0-3); CA B and H are not.
    assert_eq!(pairs, [(1, 3), (2, 3)]);
    assert!(
        l.structure
            .bonds
            .iter()
            .all(|b| b.order == BondOrder::Unspecified)
    );
}

#[test]
fn real_files_give_their_bonds() {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if !dir.join("MANIFEST.md").is_file() {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "../shared/pdb is missing"
        );
        eprintln!("SKIP: ../shared/pdb not found");
        return;
    }
    for file in [
        "4dfr.pdb",
        "1ubq.cif",
        "3nzd.cif",
        "1ehz.cif",
        "1f2n_assembly1.cif.gz",
    ] {
        let l = load(&dir.join(file), &LoadOptions::default()).unwrap();
        let s = &l.structure;
        for b in &s.bonds {
            assert!(b.a < b.b && b.b < s.atoms.len());
            let d = (s.positions[b.a] - s.positions[b.b]).length();
            assert!(
                d < 3.0,
                "{file}: {:?} {:?} {d} Å apart",
                s.atoms[b.a],
                s.atoms[b.b]
            );
        }
        assert!(
            s.bonds
                .windows(2)
                .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b))
        );
        eprintln!("{file}: {} bonds", s.bonds.len());
        if file == "4dfr.pdb" || file == "1ehz.cif" {
            assert!(!s.bonds.is_empty(), "{file}");
        }
    }
}

#[cfg(feature = "app")]
#[test]
fn command_line_numbers_beyond_range_are_refused_briefly() {
    for (args, says) in [
        (
            &["devices", "--seconds", "1e308"][..],
            "--seconds: 1e308 s, beyond the 1e6 s",
        ),
        (
            &["devices", "--seconds", "1e19"][..],
            "--seconds: 1e19 s, beyond",
        ),
        (
            &["devices", "--seconds", "nan"][..],
            "--seconds: NaN is not a finite number",
        ),
        (
            &["render", "-o", "/nonexistent/x.png", "--move", "1e308,0,0"][..],
            "--move: the drug's centre would be 1e308 Å from the origin along an axis, beyond the 1e9 Å",
        ),
        (
            &["render", "-o", "/nonexistent/x.png", "--eye-sep", "1e308"][..],
            "--eye-sep must be between 0 and 1, got 1e308",
        ),
    ] {
        let out = bump(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let e = stderr(&out);
        assert!(
            e.contains(says) && !e.contains("panicked") && e.len() < 300,
            "{args:?}: {e}"
        );
    }
}

#[test]
fn owned_splits_equal_borrowed_ones() {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if !dir.join("MANIFEST.md").is_file() {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "../shared/pdb is missing"
        );
        return;
    }
    let same = |a: &bump::model::Molecule, b: &bump::model::Molecule| {
        assert_eq!(a.name, b.name);
        assert_eq!(a.atoms, b.atoms);
        assert_eq!(a.local, b.local);
        assert_eq!(a.centre, b.centre);
    };
    let spec = bump::model::LigandSpec::parse("auto").unwrap();
    for file in ["4dfr.pdb", "6xg5_tmp_prepared.pdb", "3nzd.cif"] {
        let s = load(&dir.join(file), &LoadOptions::default())
            .unwrap()
            .structure;
        let (r, d) = bump::model::split_complex(&s, &spec).unwrap();
        let r1 = bump::model::receptor_only(&s).unwrap();
        let (r2, d2) = bump::model::split_complex_owned(s.clone(), &spec).unwrap();
        same(&r, &r2);
        same(&d, &d2);
        same(&r1, &bump::model::receptor_only_owned(s).unwrap());
    }
}
