//! `bump score` and `bump settle` end to end: Vina's numbers for a shared
//! complex, the report's parts adding up, a settled drug that an independent
//! `bump check` finds clear, and a drug whose chemistry cannot be perceived
//! scored with a warning naming the atom, and a Vina docking's PDBQT poses
//! scored as Vina scores them.

#![allow(clippy::unwrap_used)]

mod common;

use std::path::{Path, PathBuf};

use common::cli::{bump, json};
use serde_json::Value;

fn f(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

/// Vina 1.2.7's score of 1s3v's TQD at the crystal pose
/// (`tests/reference/vina/values.json`).
fn vina_1s3v(scoring: &str) -> Value {
    let text = std::fs::read_to_string("tests/reference/vina/values.json").unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    v["complexes"]["1s3v_TQD"]["poses"][0][scoring]["score"].clone()
}

fn files(dir: &Path) -> (String, String) {
    (
        dir.join("1s3v_protein.pdb").display().to_string(),
        dir.join("1s3v_ligand_tqd.sdf").display().to_string(),
    )
}

#[test]
fn score_reports_vinas_numbers_term_by_term() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let (rec, lig) = files(&dir);
    for scoring in ["vina", "vinardo"] {
        let v = json(&["score", &rec, &lig, "--scoring", scoring, "--json"]);
        let want = vina_1s3v(scoring);
        assert_eq!(v["scoring"], scoring);
        assert_eq!(v["evaluator"], "exact");
        // Same molecules, same typing, same table: Vina's numbers.
        for (ours, theirs) in [
            ("total", "total"),
            ("inter", "lig_inter"),
            ("intra", "lig_intra"),
        ] {
            assert!(
                (f(&v[ours]) - f(&want[theirs])).abs() < 2e-3,
                "{scoring} {ours}: {} vs Vina {}",
                v[ours],
                want[theirs]
            );
        }
        assert_eq!(v["rotatable_bonds"], 7);
        assert_eq!(f(&v["torsion_count"]), 6.5);
        // The atoms' shares add up to inter; the weighted terms to about
        // inter (the curl only damps positive atoms).
        let atoms = v["atoms"].as_array().unwrap();
        assert_eq!(atoms.len(), 27);
        assert!(atoms.iter().all(|a| a["vina_type"].is_string()));
        let shares: f64 = atoms.iter().map(|a| f(&a["contribution"])).sum();
        assert!((shares - f(&v["inter"])).abs() < 1e-6);
        let terms: f64 = v["terms"].as_object().unwrap().values().map(f).sum();
        assert!(
            (terms - f(&v["inter"])).abs() < 0.05,
            "{terms} vs {}",
            v["inter"]
        );
        // Hydrogen bonds: N/O pairs within the sum of their radii.
        let hb = v["hbonds"].as_array().unwrap();
        assert!(!hb.is_empty());
        for h in hb {
            assert!(f(&h["distance"]) < 3.5 && f(&h["energy"]) < 0.0, "{h}");
            for side in ["donor", "acceptor"] {
                assert!(
                    ["N", "O"].contains(&h[side]["element"].as_str().unwrap()),
                    "{h}"
                );
            }
        }
        assert!(f(&v["coulomb"]).is_finite() && f(&v["elapsed_us"]) > 0.0);
    }
    // Maps: the same score within their interpolation error.
    let v = json(&["score", &rec, &lig, "--evaluator", "maps", "--json"]);
    assert_eq!(v["evaluator"], "maps");
    assert!(f(&v["maps_build_ms"]) > 0.0);
    assert!((f(&v["inter"]) - f(&vina_1s3v("vina")["lig_inter"])).abs() < 1.5);
    // Far from the receptor: nothing.
    let v = json(&["score", &rec, &lig, "--move", "0,0,60", "--json"]);
    assert_eq!(f(&v["inter"]), 0.0);
    assert!(v["hbonds"].as_array().unwrap().is_empty());
    // Human output.
    let out = bump(&["score", &rec, &lig]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("vina score -8.96") && text.contains("hydrogen bond"),
        "{text}"
    );
}

#[test]
fn settle_lowers_the_score_and_writes_a_drug_that_does_not_collide() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let (rec, lig) = files(&dir);
    let out_dir = tempdir("settle");
    let out = out_dir.join("settled.sdf");
    let out_s = out.display().to_string();
    // Off the crystal pose, clear of the receptor.
    let start = ["--move", "0.3,-0.2,0.2", "--turn", "1,1,0,8"];
    let check = json(&[&["check", &rec, &lig, "--json"][..], &start].concat());
    let v = json(
        &[
            &[
                "settle",
                &rec,
                &lig,
                "--evaluator",
                "exact",
                "-o",
                &out_s,
                "--json",
            ][..],
            &start,
        ]
        .concat(),
    );
    assert_eq!(
        v["start_collisions"].as_array().unwrap().len(),
        check["clash_count"].as_u64().unwrap() as usize
    );
    assert!(f(&v["after"]["total"]) < f(&v["before"]["total"]), "{v}");
    assert!(v["end_collisions"].as_array().unwrap().is_empty());
    assert!(f(&v["rmsd"]) > 0.0 && v["steps"].as_u64().unwrap() > 0);
    assert_eq!(v["torsions_deg"].as_array().unwrap().len(), 7);
    // The written drug, read back: clear of the receptor, and scored as
    // settle says (the file keeps 4 decimals).
    let c = json(&["check", &rec, &out_s, "--json"]);
    assert_eq!(c["clash_count"], 0, "{c}");
    let s = json(&["score", &rec, &out_s, "--json"]);
    assert!(
        (f(&s["total"]) - f(&v["after"]["total"])).abs() < 0.01,
        "{s} {v}"
    );
    assert_eq!(s["atoms"].as_array().unwrap().len(), 27);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("V2000") && text.lines().count() > 27 + 4);
    // Human output says before and after.
    let out = bump(&[&["settle", &rec, &lig, "--evaluator", "exact"][..], &start].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains(" -> ") && text.contains("RMSD"),
        "{text}"
    );
}

/// Settle on the maps reports Vina's exact score before and after, as
/// `bump score` gives it for the start and for the written drug, and the
/// maps' own energies (what it minimised) beside them.
#[test]
fn settle_on_the_maps_reports_the_exact_score() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let (rec, lig) = files(&dir);
    let out_dir = tempdir("settle_maps");
    let out = out_dir.join("settled.sdf");
    let out_s = out.display().to_string();
    let start = ["--move", "0.3,-0.2,0.2", "--turn", "1,1,0,8"];
    let v = json(&[&["settle", &rec, &lig, "-o", &out_s, "--json"][..], &start].concat());
    assert_eq!(v["evaluator"], "maps");
    let at_start = json(&[&["score", &rec, &lig, "--json"][..], &start].concat());
    for key in ["total", "inter", "intra"] {
        assert!(
            (f(&v["before"][key]) - f(&at_start[key])).abs() < 1e-9,
            "{key}: settle {} score {}",
            v["before"][key],
            at_start[key]
        );
    }
    let written = json(&["score", &rec, &out_s, "--json"]);
    assert!(
        (f(&written["total"]) - f(&v["after"]["total"])).abs() < 0.01,
        "{written} {v}"
    );
    // The maps' energies, what settle minimised, went down.
    let m = &v["minimised"];
    assert!(f(&m["after"][0]) < f(&m["before"][0]), "{v}");
    assert_ne!(f(&m["before"][0]), f(&v["before"]["total"]));
    let out = bump(&[&["settle", &rec, &lig][..], &start].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("minimised on the maps"), "{text}");
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// A fresh directory under the target's temporary folder.
fn tempdir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("score_cli_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A small receptor: one alanine and one serine.
const RECEPTOR: &str = "\
ATOM      1  N   ALA A   1       0.000   0.000   0.000  1.00  0.00           N
ATOM      2  CA  ALA A   1       1.458   0.000   0.000  1.00  0.00           C
ATOM      3  C   ALA A   1       2.009   1.420   0.000  1.00  0.00           C
ATOM      4  O   ALA A   1       1.251   2.390   0.000  1.00  0.00           O
ATOM      5  CB  ALA A   1       1.988  -0.773  -1.199  1.00  0.00           C
ATOM      6  N   SER A   2       3.332   1.536   0.000  1.00  0.00           N
ATOM      7  CA  SER A   2       3.970   2.845   0.000  1.00  0.00           C
ATOM      8  C   SER A   2       5.485   2.729   0.000  1.00  0.00           C
ATOM      9  O   SER A   2       6.051   1.634   0.000  1.00  0.00           O
ATOM     10  CB  SER A   2       3.516   3.648   1.216  1.00  0.00           C
ATOM     11  OG  SER A   2       3.963   4.988   1.187  1.00  0.00           O
END
";

/// An SDF record of `atoms` and 1-based `bonds`.
fn sdf(atoms: &[(&str, [f64; 3])], bonds: &[(usize, usize, u8)]) -> String {
    let mut t = format!(
        "bad\n  test\n\n{:>3}{:>3}  0  0  0  0  0  0  0  0999 V2000\n",
        atoms.len(),
        bonds.len()
    );
    for (e, p) in atoms {
        t += &format!(
            "{:>10.4}{:>10.4}{:>10.4} {:<3} 0  0  0  0  0  0  0  0  0  0  0  0\n",
            p[0], p[1], p[2], e
        );
    }
    for (a, b, o) in bonds {
        t += &format!("{a:>3}{b:>3}{o:>3}  0\n");
    }
    t + "M  END\n$$$$\n"
}

#[test]
fn a_drug_that_cannot_be_perceived_is_scored_with_a_warning_naming_the_atom() {
    let dir = tempdir("bad");
    let rec = dir.join("rec.pdb");
    std::fs::write(&rec, RECEPTOR).unwrap();
    let rec = rec.display().to_string();
    // A carbon with five bonds, an unknown element and an ordinary oxygen,
    // 4 Å above the serine.
    let z = 5.5;
    let cases = [
        (
            "valence.sdf",
            sdf(
                &[
                    ("C", [4.0, 3.0, z]),
                    ("C", [5.5, 3.0, z]),
                    ("C", [2.5, 3.0, z]),
                    ("C", [4.0, 4.5, z]),
                    ("C", [4.0, 1.5, z]),
                    ("O", [4.0, 3.0, z + 1.5]),
                ],
                &[(1, 2, 1), (1, 3, 1), (1, 4, 1), (1, 5, 1), (1, 6, 1)],
            ),
            "odd valence",
        ),
        (
            "element.sdf",
            sdf(
                &[
                    ("C", [4.0, 3.0, z]),
                    ("Xx", [5.5, 3.0, z]),
                    ("O", [4.0, 4.4, z]),
                ],
                &[(1, 2, 1), (1, 3, 1)],
            ),
            "unknown element",
        ),
    ];
    for (name, text, what) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let lig = path.display().to_string();
        for cmd in ["score", "settle"] {
            let out = bump(&[cmd, &rec, &lig, "--evaluator", "exact", "--json"]);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "{cmd} {name}: {err}");
            assert!(
                err.contains("drug chemistry") && err.contains(what) && err.contains(name),
                "{cmd} {name}: {err}"
            );
            assert!(!err.contains("panicked"), "{err}");
            let v: Value = serde_json::from_slice(&out.stdout).unwrap();
            let warnings = v["warnings"].as_array().unwrap();
            assert!(
                warnings.iter().any(|w| w.as_str().unwrap().contains(what)),
                "{v}"
            );
            if cmd == "score" {
                assert!(f(&v["total"]).is_finite() && f(&v["coulomb"]).is_finite());
                if what == "unknown element" {
                    // Not typed, so not scored, but listed.
                    let xx = &v["atoms"][1];
                    assert_eq!(xx["element"], "Xx", "{v}");
                    assert!(xx["vina_type"].is_null() && f(&xx["contribution"]) == 0.0);
                }
            } else {
                assert!(f(&v["after"]["total"]) <= f(&v["before"]["total"]) + 1e-9);
            }
        }
    }
}

/// A drug read from MOL2 scores exactly as the same drug read from SDF:
/// every shared SDF, each against a shared receptor.
#[test]
fn a_mol2_drug_scores_as_its_sdf() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let tmp = tempdir("mol2");
    for (receptor, drug) in [
        ("1s3v_protein.pdb", "1s3v_ligand_tqd.sdf"),
        ("6xg5_tmp_prepared.pdb", "trimethoprim_top_6xg5pose.sdf"),
        ("1s3v_protein.pdb", "benzamidine_3ptb.sdf"),
        ("1s3v_protein.pdb", "methotrexate_mtx_ideal.sdf"),
    ] {
        let sdf_path = dir.join(drug);
        let text = std::fs::read_to_string(&sdf_path).unwrap();
        let mol2 = tmp.join(drug.replace(".sdf", ".mol2"));
        std::fs::write(&mol2, common::mol2::from_sdf(&text)).unwrap();
        let rec = dir.join(receptor).display().to_string();
        let a = json(&["score", &rec, &sdf_path.display().to_string(), "--json"]);
        let b = json(&["score", &rec, &mol2.display().to_string(), "--json"]);
        for k in ["total", "inter", "intra", "coulomb", "torsion_count"] {
            assert_eq!(a[k], b[k], "{drug}: {k}");
        }
        assert_eq!(a["rotatable_bonds"], b["rotatable_bonds"], "{drug}");
        // The same bonds (the drug's residue is named by each file).
        let hbonds = |v: &Value| -> Vec<Value> {
            v["hbonds"]
                .as_array()
                .unwrap()
                .iter()
                .map(|h| {
                    serde_json::json!([
                        h["donor"]["serial"],
                        h["acceptor"]["serial"],
                        h["distance"],
                        h["energy"]
                    ])
                })
                .collect()
        };
        assert_eq!(hbonds(&a), hbonds(&b), "{drug}");
        assert!(!hbonds(&a).is_empty() || drug != "1s3v_ligand_tqd.sdf");
        let types = |v: &Value| -> Vec<Value> {
            v["atoms"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x["vina_type"].clone())
                .collect()
        };
        assert_eq!(types(&a), types(&b), "{drug}");
    }
}

/// A Vina docking's output read by its models: `--record N` scores pose N
/// against the PDBQT receptor as Vina scores it (`tests/data/pdbqt`).
#[test]
fn score_reads_a_dockings_poses_from_pdbqt() {
    let text = std::fs::read_to_string("tests/data/pdbqt/values.json").unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    for model in 1..=3 {
        let want = &v["ligands"][format!("dock_out.pdbqt#{model}")]["poses"][0]["vina"];
        let got = json(&[
            "score",
            "tests/data/pdbqt/receptor.pdbqt",
            "tests/data/pdbqt/dock_out.pdbqt",
            "--record",
            &model.to_string(),
            "--json",
        ]);
        for what in ["total", "inter", "intra"] {
            assert!(
                (f(&got[what]) - f(&want[what])).abs() < 1e-5,
                "model {model} {what}: bump {}, Vina {}",
                got[what],
                want[what]
            );
        }
    }
    let out = bump(&[
        "score",
        "tests/data/pdbqt/receptor.pdbqt",
        "tests/data/pdbqt/dock_out.pdbqt",
        "--record",
        "4",
    ]);
    let err = common::cli::stderr(&out);
    assert!(!out.status.success() && err.contains("model 4"), "{err}");
}

/// `bump settle -o OUT.pdbqt` on a PDBQT drug writes it with its torsion
/// tree, types and charges: read back, it has the same rotatable bonds and
/// scores what settle reported (exact evaluator; coordinates to 3 decimals).
#[test]
fn settle_writes_a_pdbqt_drug_as_pdbqt() {
    let dir = tempdir("pdbqt");
    let out = dir.join("settled.pdbqt");
    let out_s = out.display().to_string();
    let rec = "tests/data/pdbqt/receptor.pdbqt";
    let settled = json(&[
        "settle",
        rec,
        "tests/data/pdbqt/lig3_meeko.pdbqt",
        "--move",
        "0.6,-0.4,0.3",
        "--evaluator",
        "exact",
        "-o",
        &out_s,
        "--json",
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("ROOT") && text.contains("TORSDOF 9"),
        "{text}"
    );
    let back = json(&["score", rec, &out_s, "--json"]);
    let original = json(&["score", rec, "tests/data/pdbqt/lig3_meeko.pdbqt", "--json"]);
    assert_eq!(back["rotatable_bonds"], original["rotatable_bonds"]);
    assert_eq!(back["torsion_count"], original["torsion_count"]);
    let (got, want) = (f(&back["total"]), f(&settled["after"]["total"]));
    assert!((got - want).abs() < 0.01, "written {got}, settled {want}");
    let _ = std::fs::remove_dir_all(&dir);
}
