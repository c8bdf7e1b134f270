//! The fuzz harness: every reader bump has (PDB, gzipped PDB, mmCIF, SDF
//! V2000 and V3000, MOL2, PDBQT, session logs, joystick maps) is called
//! in-process on seeded mutants of small seed inputs (written here, the
//! committed PDBQT test files, and slices of the shared structures in
//! `../shared/pdb`), and must neither panic nor use
//! memory out of proportion to its input.
//!
//! - Each input runs under `catch_unwind`; a panic is a failure.
//! - A counting global allocator records each input's peak heap use; a
//!   peak above [`BOUND_PER_BYTE`] bytes per input byte (decompressed
//!   bytes, up to the limit, for gzip) plus [`BOUND_FIXED`] is a failure.
//! - Every failure is reported with the reader, the seed, the input's
//!   number and its mutations, and the input is saved under the test
//!   target's temporary folder, to be read again with
//!   `BUMP_FUZZ_REPLAY=FILE`.
//!
//! `cargo test --test fuzz` runs [`DEFAULT_INPUTS`] inputs per reader
//! (about two minutes in the test profile on a busy two-core machine);
//! `BUMP_FUZZ_INPUTS=N` runs N, and
//! `cargo test --test fuzz -- --ignored` runs 10⁶ per reader.
//! `BUMP_FUZZ_SEED` changes the seed (each reader's generator starts from
//! it and the reader's name). A new reader is one more line in [`readers`].

// The counting allocator implements `GlobalAlloc`, which is unsafe to
// implement; it only forwards to the system allocator and counts.
#![allow(unsafe_code)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod fuzz_support;

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use bump::input::JoystickMap;
use bump::model::mol2::parse_mol2;
use bump::model::pdb::{Format, parse_bytes};
use bump::model::pdbqt::parse_pdbqt;
use bump::model::sdf::parse_sdf;
use bump::model::{LigandSpec, LoadOptions, receptor_only, split_complex};
use bump::rng::Rng;
use bump::session::log::SessionLog;
use bump::text::TextSource;
use fuzz_support::{Mutation, below, gzip, mutate, one_in};

/// Inputs per reader in an ordinary test run.
const DEFAULT_INPUTS: usize = 10_000;

/// Inputs per reader in the long run (`--ignored`).
const LONG_INPUTS: usize = 1_000_000;

/// Decompressed-size limit the readers run under here: bombs are refused
/// after 1 MiB rather than 2 GiB (the limit itself is tested too).
const FUZZ_DECOMPRESSED_LIMIT: u64 = 1 << 20;

/// Heap bytes an input may use per byte of input.
const BOUND_PER_BYTE: usize = 100;

/// Heap bytes any input may use: line and gzip buffers.
const BOUND_FIXED: usize = 3 << 20;

struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(n: usize) {
    let now = CURRENT.fetch_add(n, Ordering::Relaxed) + n;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

fn shrank(n: usize) {
    CURRENT.fetch_sub(n, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded; `ptr` came from this allocator with `layout`.
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded; `ptr` came from this allocator with `layout`.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            grew(new_size);
            shrank(layout.size());
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One test of this binary at a time: the allocator's counts are global.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// A reader under test: its name, its seed inputs, and how to call it.
struct Reader {
    name: &'static str,
    seeds: Vec<Vec<u8>>,
    read: fn(&[u8]) -> Result<(), String>,
    /// Repairs done after mutating, so that mutants get past checks that
    /// would otherwise stop nearly all of them (a log's line checksums),
    /// or the form the reader takes its input in (gzip).
    repair: Option<fn(&mut Rng, &mut Vec<u8>)>,
}

/// Gzips a mutant that is not gzip data already: the damage is done to
/// the text, as to a file before it was compressed.
fn gzip_text(_: &mut Rng, data: &mut Vec<u8>) {
    if !data.starts_with(&[0x1f, 0x8b]) {
        *data = gzip(data);
    }
}

fn opts() -> LoadOptions {
    LoadOptions {
        decompressed_limit: Some(FUZZ_DECOMPRESSED_LIMIT),
        ..LoadOptions::default()
    }
}

/// A coordinate file read, then split as the commands split it.
fn coordinates(bytes: &[u8], format: Format) -> Result<(), String> {
    let loaded = parse_bytes(bytes, format, "fuzz", "fuzz", &opts()).map_err(|e| e.to_string())?;
    let s = &loaded.structure;
    assert_eq!(s.atoms.len(), s.positions.len());
    for b in &s.bonds {
        assert!(b.a < b.b && b.b < s.atoms.len(), "{b:?}");
    }
    assert!(
        s.bonds
            .windows(2)
            .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b))
    );
    let _ = receptor_only(s);
    if let Ok(spec) = LigandSpec::parse("auto") {
        let _ = split_complex(s, &spec);
    }
    Ok(())
}

fn read_pdb(bytes: &[u8]) -> Result<(), String> {
    coordinates(bytes, Format::Pdb)
}

fn read_mmcif(bytes: &[u8]) -> Result<(), String> {
    coordinates(bytes, Format::Mmcif)
}

/// As `model::load` reads an SDF file: decompressed under the limit, read
/// lossily as UTF-8; the first record, or another.
fn read_sdf(bytes: &[u8]) -> Result<(), String> {
    let text = TextSource::from_bytes(bytes, FUZZ_DECOMPRESSED_LIMIT)
        .read_all()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&text);
    let first = parse_sdf(&text, "fuzz.sdf", &opts()).map_err(|e| e.to_string());
    let second = LoadOptions {
        sdf_record: Some(2),
        ..opts()
    };
    let _ = parse_sdf(&text, "fuzz.sdf", &second);
    first.map(|_| ())
}

/// As `model::load` reads a PDBQT file: the first model, or another; then
/// split as the commands split it, and the drug's chemistry (the file's
/// types and tree) perceived.
fn read_pdbqt(bytes: &[u8]) -> Result<(), String> {
    let text = TextSource::from_bytes(bytes, FUZZ_DECOMPRESSED_LIMIT)
        .read_all()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&text);
    let second = LoadOptions {
        sdf_record: Some(2),
        ..opts()
    };
    let _ = parse_pdbqt(&text, "fuzz.pdbqt", "fuzz.pdbqt", &second);
    let mut loaded =
        parse_pdbqt(&text, "fuzz.pdbqt", "fuzz.pdbqt", &opts()).map_err(|e| e.to_string())?;
    bump::model::set_hydrogens_apart(&mut loaded.structure);
    if let Ok(mol) = receptor_only(&loaded.structure) {
        let chem = mol.chemistry();
        assert_eq!(chem.xs.len(), mol.len());
    }
    Ok(())
}

/// As `model::load` reads a MOL2 file: the first molecule, or another.
fn read_mol2(bytes: &[u8]) -> Result<(), String> {
    let text = TextSource::from_bytes(bytes, FUZZ_DECOMPRESSED_LIMIT)
        .read_all()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&text);
    let first = parse_mol2(&text, "fuzz.mol2", &opts()).map_err(|e| e.to_string());
    let second = LoadOptions {
        sdf_record: Some(2),
        ..opts()
    };
    let _ = parse_mol2(&text, "fuzz.mol2", &second);
    first.map(|_| ())
}

fn read_log(bytes: &[u8]) -> Result<(), String> {
    let log = SessionLog::parse_bytes(bytes, Path::new("fuzz.log")).map_err(|e| e.to_string())?;
    assert!(log.duration().is_finite());
    Ok(())
}

fn read_map(bytes: &[u8]) -> Result<(), String> {
    JoystickMap::parse_bytes(bytes, Path::new("fuzz.toml"))
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// FNV-1a, 32-bit, as session logs check their lines.
fn fnv1a(s: &[u8]) -> u32 {
    s.iter().fold(0x811c_9dc5, |h: u32, &b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

/// Gives every log line that has a ` ~` check value the right one (but
/// one time in eight, so that damaged lines are read too).
fn recheck_log(rng: &mut Rng, data: &mut Vec<u8>) {
    if one_in(rng, 8) || data.starts_with(&[0x1f, 0x8b]) {
        return;
    }
    let mut out = Vec::with_capacity(data.len());
    for line in data.split(|&b| b == b'\n') {
        match line.windows(2).rposition(|w| w == b" ~") {
            Some(at) if !line.starts_with(b"meta") => {
                out.extend_from_slice(&line[..at]);
                out.extend_from_slice(format!(" ~{:08x}", fnv1a(&line[..at])).as_bytes());
            }
            _ => out.extend_from_slice(line),
        }
        out.push(b'\n');
    }
    out.pop();
    *data = out;
}

/// `../shared/pdb`, or `None` with a message; under `CI=true` its absence
/// fails.
fn shared_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if dir.join("MANIFEST.md").is_file() {
        return Some(dir);
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "test data folder {} is missing (CI must have ../shared/pdb)",
        dir.display()
    );
    eprintln!("SKIP: seeds from {} (not found)", dir.display());
    None
}

fn read_shared(name: &str) -> Option<Vec<u8>> {
    let path = shared_dir()?.join(name);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(bytes.as_slice())
            .read_to_end(&mut out)
            .unwrap();
        Some(out)
    } else {
        Some(bytes)
    }
}

/// A PDB file's first `atoms` atom records, the lines between them, and
/// its `CONECT`, `TER`, `MODEL`/`ENDMDL` and `END` records.
/// The committed PDBQT test files: two ligands (Meeko's and Open Babel's
/// trees), a docking's three models, and the receptor's first 60 lines.
fn pdbqt_seeds() -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pdbqt");
    let mut seeds = Vec::new();
    for name in ["lig1_meeko.pdbqt", "lig3_obabel.pdbqt", "dock_out.pdbqt"] {
        if let Ok(b) = std::fs::read(dir.join(name)) {
            seeds.push(b);
        }
    }
    if let Ok(b) = std::fs::read(dir.join("receptor.pdbqt")) {
        let head: Vec<u8> = b
            .split_inclusive(|&c| c == b'\n')
            .take(60)
            .flatten()
            .copied()
            .collect();
        seeds.push(head);
    }
    seeds
}

fn pdb_slice(text: &[u8], atoms: usize) -> Vec<u8> {
    let mut out = Vec::new();
    let mut n = 0;
    for line in text.split(|&b| b == b'\n') {
        let atom = line.starts_with(b"ATOM") || line.starts_with(b"HETATM");
        let keep = if atom {
            n += 1;
            n <= atoms
        } else {
            n <= atoms || line.starts_with(b"CONECT") || line.starts_with(b"END")
        };
        if keep && !line.starts_with(b"REMARK") {
            out.extend_from_slice(line);
            out.push(b'\n');
        }
    }
    out
}

/// An mmCIF file cut down to its first `rows` rows of each loop, and its
/// single items (text fields kept whole).
fn cif_slice(text: &[u8], rows: usize) -> Vec<u8> {
    let mut out = Vec::new();
    let mut in_rows = 0;
    let mut in_text = false;
    for line in text.split(|&b| b == b'\n') {
        if line.starts_with(b";") {
            in_text = !in_text;
            out.extend_from_slice(line);
            out.push(b'\n');
            continue;
        }
        if in_text
            || line.starts_with(b"_")
            || line.starts_with(b"loop_")
            || line.starts_with(b"#")
            || line.starts_with(b"data_")
        {
            in_rows = 0;
        } else {
            in_rows += 1;
            if in_rows > rows {
                continue;
            }
        }
        out.extend_from_slice(line);
        out.push(b'\n');
    }
    out
}

const PDB_SEED: &str = "\
HEADER    TEST
ATOM      1  N   SER A   1       0.000   0.000   0.000  1.00 10.00           N
ATOM      2  CA  SER A   1       1.000   0.000   0.000  1.00 10.00           C
ATOM      3  CB ASER A   1       2.000   0.000   0.000  0.30 10.00           C
ATOM      4  CB BSER A   1       2.000   1.000   0.000  0.70 10.00           C
ATOM      5  OG ASER A   1       3.000   0.000   0.000  0.50 10.00           O
ATOM      6  OG BSER A   1       3.000   1.000   0.000  0.50 10.00           O
ATOM      7  H   SER A   1       1.000   1.000   1.000  1.00 10.00           H
TER
HETATM    8  C1  LIG     2      10.000   0.000   0.000  1.00 10.00           C
HETATM    9  C2  LIG     2      11.500   0.000   0.000
HETATM   10 CL   LIG     2      12.500   0.000   0.000  1.00 10.00          CL
HETATM   11  O   HOH     1      20.000   0.000   0.000  1.00 10.00           O
CONECT    8    9
CONECT    9    8   10
END
";

const CIF_SEED: &str = "\
data_T
#
_entry.id T
_struct.title
;A title
in a text field
;
loop_
_struct_conn.id
_struct_conn.conn_type_id
_struct_conn.ptnr1_auth_asym_id
_struct_conn.ptnr1_auth_seq_id
_struct_conn.ptnr1_label_atom_id
_struct_conn.ptnr1_label_comp_id
_struct_conn.ptnr2_auth_asym_id
_struct_conn.ptnr2_auth_seq_id
_struct_conn.ptnr2_label_atom_id
_struct_conn.ptnr2_label_comp_id
_struct_conn.pdbx_value_order
covale1 covale A 2 C1 LIG A 1 CA ALA sing
loop_
_atom_site.group_PDB
_atom_site.id
_atom_site.type_symbol
_atom_site.label_atom_id
_atom_site.label_alt_id
_atom_site.label_comp_id
_atom_site.label_asym_id
_atom_site.label_seq_id
_atom_site.pdbx_PDB_ins_code
_atom_site.Cartn_x
_atom_site.Cartn_y
_atom_site.Cartn_z
_atom_site.occupancy
_atom_site.auth_seq_id
_atom_site.auth_asym_id
_atom_site.pdbx_PDB_model_num
ATOM 1 N N . ALA A 1 ? 1.0 2.0 3.0 1.0 1 A 1
ATOM 2 C CA A ALA A 1 ? 2.0 2.0 3.0 0.6 1 A 1
ATOM 3 C CA B ALA A 1 ? 2.1 2.0 3.0 0.4 1 A 1
HETATM 4 C C1 . LIG B . ? 5.0 2.0 3.0 1.0 2 A 1
HETATM 5 O O . HOH C . ? 9.0 2.0 3.0 1.0 3 A 1
ATOM 6 N N . ALA A 1 ? 1.0 2.0 3.0 1.0 1 A 2
#
";

const SDF_V2000_SEED: &str = "\
first
  test

  3  2  0  0  0  0  0  0  0  0999 V2000
    0.0000    0.0000    0.0000 C   0  0  0  0  0  0  0  0  0  0  0  0
    1.5000    0.0000    0.0000 O   0  0  0  0  0  0  0  0  0  0  0  0
    2.0000    1.0000    0.0000 H   0  0  0  0  0  0  0  0  0  0  0  0
  1  2  1  0
  2  3  1  0
M  END
$$$$
second
  test

  1  0  0  0  0  0  0  0  0  0999 V2000
    5.0000    0.0000    0.0000 N   0  0  0  0  0  0  0  0  0  0  0  0
M  END
$$$$
";

/// A V3000 molfile with a continued atom line (shared with the reader's
/// unit test).
const SDF_V3000_SEED: &str = include_str!("data/v3000_continuation.sdf");

const MOL2_SEED: &str = include_str!("data/amidine.mol2");

#[path = "common/mol2.rs"]
mod mol2_text;

/// A short session log, its lines checked.
fn log_seed() -> Vec<u8> {
    let mut text = b"bump-log 2\n# a comment\nmeta file x.pdb\n".to_vec();
    for line in [
        "f 0.016666666666666666",
        "f 0.016666666666666666 v=0.0,0.0,1.5,0.0,0.4363323129985824,0.0 z=-2.5",
        "f 0.017 n=1.0,2.0,3.0,0.0,0.0,0.0 c=mode c=select:1 c=response:slide",
        "f 0.0 c=move:1.5,-2.0,1e-9,0.0,1.0,0.0,0.1 c=undo c=rock",
        "f 0.02 c=fit-all k=down:tx+:coarse:0.0123 k=up:rz-:normal:0.015",
        "final 0 1.0 2.0 3.0 0.0 0.0 0.0 1.0",
    ] {
        text.extend_from_slice(format!("{line} ~{:08x}\n", fnv1a(line.as_bytes())).as_bytes());
    }
    text.extend_from_slice(b"end 5\n");
    text
}

/// The readers and their seeds. A new reader is one more entry here.
fn readers() -> Vec<Reader> {
    let mut pdb = vec![PDB_SEED.as_bytes().to_vec()];
    let mut cif = vec![CIF_SEED.as_bytes().to_vec()];
    let mut v2000 = vec![SDF_V2000_SEED.as_bytes().to_vec()];
    let mut logs = vec![log_seed()];
    for (file, atoms) in [
        ("4dfr.pdb", 40),
        ("1ubq.pdb", 20),
        ("5dfr_solvated.pdb", 30),
        ("1dt6.pdb", 25),
    ] {
        if let Some(text) = read_shared(file) {
            pdb.push(pdb_slice(&text, atoms));
        }
    }
    // The ends of files: hetero groups, waters, CONECT records.
    if let Some(text) = read_shared("4dfr.pdb") {
        let at = text.len() - 6000.min(text.len());
        let tail = &text[at..];
        let start = tail.iter().position(|&b| b == b'\n').map_or(0, |i| i + 1);
        pdb.push(tail[start..].to_vec());
    }
    for (file, rows) in [("1ubq.cif", 30), ("3nzd.cif", 20), ("1ehz.cif", 20)] {
        if let Some(text) = read_shared(file) {
            cif.push(cif_slice(&text, rows));
        }
    }
    let mut mol2 = vec![MOL2_SEED.as_bytes().to_vec()];
    for file in ["benzamidine_3ptb.sdf", "trimethoprim_top_6xg5pose.sdf"] {
        if let Some(text) = read_shared(file) {
            mol2.push(mol2_text::from_sdf(&String::from_utf8_lossy(&text)).into_bytes());
            v2000.push(text);
        }
    }
    let sessions = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/sessions/tmp-dhfr.bumplog"
    );
    if let Ok(text) = std::fs::read(sessions) {
        // Its head (meta lines, frames), its final poses and a fitting end.
        let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
        let mut cut = Vec::new();
        let head = lines.iter().take(40);
        let finals = lines.iter().filter(|l| l.starts_with(b"final"));
        for l in head.chain(finals) {
            cut.extend_from_slice(l);
            cut.push(b'\n');
        }
        let frames = lines
            .iter()
            .take(40)
            .filter(|l| l.starts_with(b"f "))
            .count();
        cut.extend_from_slice(format!("end {frames}\n").as_bytes());
        logs.push(cut);
    }
    let gz = pdb.clone();
    vec![
        Reader {
            name: "pdb",
            seeds: pdb,
            read: read_pdb,
            repair: None,
        },
        Reader {
            name: "pdb.gz",
            seeds: gz,
            read: read_pdb,
            repair: Some(gzip_text),
        },
        Reader {
            name: "mmcif",
            seeds: cif,
            read: read_mmcif,
            repair: None,
        },
        Reader {
            name: "sdf-v2000",
            seeds: v2000,
            read: read_sdf,
            repair: None,
        },
        Reader {
            name: "sdf-v3000",
            seeds: vec![SDF_V3000_SEED.as_bytes().to_vec()],
            read: read_sdf,
            repair: None,
        },
        Reader {
            name: "mol2",
            seeds: mol2,
            read: read_mol2,
            repair: None,
        },
        Reader {
            name: "pdbqt",
            seeds: pdbqt_seeds(),
            read: read_pdbqt,
            repair: None,
        },
        Reader {
            name: "session-log",
            seeds: logs,
            read: read_log,
            repair: Some(recheck_log),
        },
        Reader {
            name: "joystick-map",
            seeds: vec![bump::input::map::DEFAULT_MAP.as_bytes().to_vec()],
            read: read_map,
            repair: None,
        },
    ]
}

/// How much text the reader sees of `input`: its length, or for gzip its
/// decompressed length up to the limit.
fn text_size(input: &[u8]) -> usize {
    if !input.starts_with(&[0x1f, 0x8b]) {
        return input.len();
    }
    let mut decoder = flate2::read::MultiGzDecoder::new(input).take(FUZZ_DECOMPRESSED_LIMIT + 1);
    let mut sink = [0u8; 1 << 16];
    let mut n = 0;
    while let Ok(k) = decoder.read(&mut sink) {
        if k == 0 {
            break;
        }
        n += k;
    }
    n.max(input.len())
}

/// A failed input.
struct Failure {
    reader: &'static str,
    index: usize,
    mutations: Vec<Mutation>,
    what: String,
    saved: PathBuf,
}

/// Runs `input` through `reader`: the failure, if any (a panic, an error
/// message that quotes too much, or a peak heap use above the bound), and
/// whether the reader refused the input.
fn run_one(reader: &Reader, input: &[u8]) -> (Option<String>, bool) {
    let before = CURRENT.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let outcome = std::panic::catch_unwind(|| (reader.read)(input));
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(before);
    match outcome {
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            (Some(format!("panicked: {what}")), true)
        }
        Ok(result) => {
            if let Err(message) = &result
                && message.len() > 600
            {
                return (
                    Some(format!(
                        "an error message of {} bytes: {}…",
                        message.len(),
                        message.chars().take(200).collect::<String>()
                    )),
                    true,
                );
            }
            let bound = BOUND_PER_BYTE * text_size(input) + BOUND_FIXED;
            let failed =
                (peak > bound).then(|| format!("peak heap {peak} bytes, above the bound {bound}"));
            (failed, result.is_err())
        }
    }
}

/// The seed of `reader`'s generator.
fn seed_of(name: &str) -> u64 {
    let base: u64 = std::env::var("BUMP_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    (base ^ u64::from(fnv1a(name.as_bytes()))).max(1)
}

/// Runs `inputs` mutants through every reader; panics listing the failures.
fn fuzz(inputs: usize) {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let out_dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
    let mut failures: Vec<Failure> = Vec::new();
    for reader in readers() {
        let seed = seed_of(reader.name);
        let mut rng = Rng(seed);
        let start = std::time::Instant::now();
        let (mut slowest, mut rejected) = (0.0f64, 0usize);
        // The seeds themselves read.
        for s in &reader.seeds {
            if let Err(e) = (reader.read)(s) {
                panic!("{}: a seed input is refused: {e}", reader.name);
            }
        }
        for index in 0..inputs {
            let s = &reader.seeds[below(&mut rng, reader.seeds.len())];
            let (mut input, mutations) = mutate(&mut rng, s);
            if let Some(repair) = reader.repair {
                repair(&mut rng, &mut input);
            }
            let t = std::time::Instant::now();
            let (failed, refused) = run_one(&reader, &input);
            slowest = slowest.max(t.elapsed().as_secs_f64());
            rejected += usize::from(refused);
            if let Some(what) = failed {
                let _ = std::fs::create_dir_all(&out_dir);
                let saved = out_dir.join(format!("{}-seed{seed}-{index}.bin", reader.name));
                let _ = std::fs::write(&saved, &input);
                failures.push(Failure {
                    reader: reader.name,
                    index,
                    mutations,
                    what,
                    saved,
                });
            }
        }
        eprintln!(
            "fuzz {}: {inputs} inputs in {:.1} s ({rejected} refused with an error), slowest {:.1} ms",
            reader.name,
            start.elapsed().as_secs_f64(),
            slowest * 1e3
        );
    }
    if !failures.is_empty() {
        let report: Vec<String> = failures
            .iter()
            .take(20)
            .map(|f| {
                format!(
                    "{} input {} ({:?}): {} [saved as {}]",
                    f.reader,
                    f.index,
                    f.mutations,
                    f.what,
                    f.saved.display()
                )
            })
            .collect();
        panic!("{} failing inputs:\n{}", failures.len(), report.join("\n"));
    }
}

#[test]
fn every_reader_survives_mutated_inputs() {
    if let Ok(file) = std::env::var("BUMP_FUZZ_REPLAY") {
        // One saved input, through the reader its name says.
        let bytes = std::fs::read(&file).unwrap();
        let name = Path::new(&file)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let reader = readers()
            .into_iter()
            .find(|r| name.starts_with(&format!("{}-seed", r.name)))
            .expect("the file name starts with a reader's name");
        assert_eq!(run_one(&reader, &bytes).0, None);
        return;
    }
    let inputs = std::env::var("BUMP_FUZZ_INPUTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_INPUTS);
    fuzz(inputs);
}

#[test]
#[ignore = "10^6 inputs per reader: an hour or more"]
fn every_reader_survives_a_million_mutated_inputs() {
    fuzz(LONG_INPUTS);
}

#[test]
fn gzip_bombs_stop_at_the_limit_with_bounded_memory() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // 64 MiB of spaces, then of atom records, gzipped to a few hundred KiB.
    let atom = "ATOM      1  N   MET A   1      38.296  20.158  39.260  1.00  0.00           N\n";
    for (what, text) in [
        ("spaces", vec![b' '; 64 << 20]),
        (
            "atoms",
            atom.as_bytes()
                .iter()
                .copied()
                .cycle()
                .take(64 << 20)
                .collect(),
        ),
    ] {
        let z = gzip(&text);
        drop(text);
        for limit in [1u64 << 20, 8 << 20] {
            let o = LoadOptions {
                decompressed_limit: Some(limit),
                ..LoadOptions::default()
            };
            let before = CURRENT.load(Ordering::Relaxed);
            PEAK.store(before, Ordering::Relaxed);
            let r = parse_bytes(&z, Format::Pdb, "bomb.pdb.gz", "bomb.pdb.gz", &o);
            let peak = PEAK.load(Ordering::Relaxed) - before;
            let e = r.expect_err(what).to_string();
            assert!(
                e.starts_with("bomb.pdb.gz: decompresses to more than"),
                "{what}: {e}"
            );
            let bound = BOUND_PER_BYTE * limit as usize + BOUND_FIXED;
            assert!(peak < bound, "{what}, limit {limit}: peak {peak} > {bound}");
        }
    }
}
