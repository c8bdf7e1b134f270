//! PDBQT files score in bump as AutoDock Vina 1.2.7 scores them: the
//! synthetic pocket and ligands of `tests/data/pdbqt` (written by Open Babel
//! and by Meeko, and a Vina docking's three poses, by
//! `tests/reference/vina/make_pdbqt.py`), every pose and both functions:
//! totals, inter and intra energies to 1e-5 kcal/mol (1e-3 where a pair
//! sits on an edge of Vina's table, see below), Vina's torsion count, and
//! every atom's X-Score type as Vina assigns it from the file.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use bump::model::{LoadOptions, Molecule, load, receptor_only};
use bump::motion::Pose;
use bump::score::{Evaluator, Exact, Scoring, XsType, prepare, score};
use glam::DVec3;
use serde_json::Value;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/pdbqt")
}

fn values() -> Value {
    let text = std::fs::read_to_string(dir().join("values.json")).expect("values.json");
    serde_json::from_str(&text).expect("values.json parses")
}

fn molecule(path: &Path, model: usize) -> Molecule {
    let opts = LoadOptions {
        sdf_record: Some(model),
        ..Default::default()
    };
    let loaded = load(path, &opts).expect("the file loads");
    receptor_only(&loaded.structure).expect("atoms")
}

fn xs(v: &Value) -> XsType {
    XsType::from_name(v.as_str().unwrap()).unwrap()
}

#[test]
fn pdbqt_files_score_as_vina_scores_them() {
    let v = values();
    let receptor_mol = molecule(&dir().join("receptor.pdbqt"), 1);
    let rchem = receptor_mol.chemistry();
    assert!(rchem.warnings.is_empty(), "{:?}", rchem.warnings);
    // Every receptor heavy atom typed as Vina types it (serials repeat in
    // Open Babel's receptor: atoms are named by chain, residue and name).
    let want_rec = v["receptor"]["atoms"].as_array().unwrap();
    assert_eq!(want_rec.len(), receptor_mol.len());
    for (a, w) in receptor_mol.atoms.iter().zip(want_rec) {
        assert_eq!(a.name.as_str(), w["name"].as_str().unwrap());
        assert_eq!(a.seq, w["resnum"].as_i64().unwrap());
    }
    for (i, w) in want_rec.iter().enumerate() {
        assert_eq!(rchem.xs[i], Some(xs(&w["xs"])), "receptor atom {w}");
    }
    let receptor = prepare::receptor(&receptor_mol);
    let mut checked = 0;
    let mut edges = Vec::new();
    for (key, entry) in v["ligands"].as_object().unwrap() {
        let file = key.split('#').next().unwrap();
        let model = entry["model"].as_u64().unwrap() as usize;
        let drug = molecule(&dir().join(file), model);
        let chem = drug.chemistry();
        assert!(chem.warnings.is_empty(), "{key}: {:?}", chem.warnings);
        let atoms = entry["atoms"].as_array().unwrap();
        assert_eq!(atoms.len(), drug.len(), "{key}: heavy atoms");
        for w in atoms {
            let serial = w["serial"].as_i64().unwrap();
            let i = drug.atoms.iter().position(|a| a.serial == serial).unwrap();
            assert_eq!(chem.xs[i], Some(xs(&w["xs"])), "{key}: atom {serial}");
        }
        assert_eq!(
            chem.vina_torsion_count(),
            entry["num_tors"].as_f64().unwrap(),
            "{key}: N_tors"
        );
        let lig = prepare::ligand(&drug).unwrap();
        for pose in entry["poses"].as_array().unwrap() {
            let s = &pose["shift"];
            let shift = DVec3::new(
                s[0].as_f64().unwrap(),
                s[1].as_f64().unwrap(),
                s[2].as_f64().unwrap(),
            );
            let rel = Pose::from_translation(drug.centre - receptor_mol.centre + shift);
            let conf = lig.rigid(rel);
            for sf in [Scoring::Vina, Scoring::Vinardo] {
                let exact = Exact::new(&receptor, sf);
                let got = score(&exact, Evaluator::Exact, &exact, &lig, &conf);
                let want = &pose[sf.name()];
                for (what, g) in [
                    ("total", got.total),
                    ("inter", got.inter),
                    ("intra", got.intra),
                ] {
                    let w = want[what].as_f64().unwrap();
                    let d = (g - w).abs();
                    assert!(
                        d < 1e-3,
                        "{key} shift {shift} {} {what}: bump {g}, Vina {w}",
                        sf.name()
                    );
                    if d >= 1e-5 {
                        edges.push(format!("{key} shift {shift} {} {what}: {d:.1e}", sf.name()));
                    }
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 9 * 6, "{checked} values compared");
    // Only a pair whose r² falls on a sample's edge (32·r² a whole number,
    // which three-decimal coordinates can give) may read the neighbouring
    // sample: bump keeps atoms in f32 about their molecule's centre, Vina in
    // f64. One shift of lig3 (both its files) has such a pair (r² =
    // 15.625 Å²); every other value agrees to 1e-5.
    let shifts: std::collections::BTreeSet<&str> = edges
        .iter()
        .filter_map(|e| e.split(" shift ").nth(1)?.split(']').next())
        .collect();
    assert!(shifts.len() <= 1, "beyond 1e-5 kcal/mol: {edges:?}");
}

#[test]
fn a_pdbqt_keeps_its_charges_and_tree() {
    let lig = molecule(&dir().join("lig3_meeko.pdbqt"), 1);
    let ad = lig
        .autodock
        .as_ref()
        .expect("a PDBQT molecule keeps its AutoDock data");
    assert!(ad.tree);
    let chem = lig.chemistry();
    for (i, a) in ad.atoms.iter().enumerate() {
        assert_eq!(
            chem.charges[i] - a.charge,
            0.0,
            "atom {i}: the file's charge"
        );
    }
    let turned: Vec<[u32; 2]> = chem
        .torsions
        .bonds
        .iter()
        .map(|b| {
            let bond = chem.bonds[b.bond as usize];
            [bond.a, bond.b]
        })
        .collect();
    let mut given: Vec<[u32; 2]> = ad
        .branches
        .iter()
        .map(|&[a, b]| [a.min(b), a.max(b)])
        .collect();
    let mut turned_sorted = turned.clone();
    given.sort_unstable();
    turned_sorted.sort_unstable();
    assert_eq!(
        turned_sorted, given,
        "the rotatable bonds are the file's branches"
    );
}
