//! The docking search and pockets on real complexes: the same seed gives the
//! same poses bit for bit whatever the thread count; every pose is
//! collision-free by brute force (receptor pairs and the drug's own pairs
//! more than three bonds apart); the output files read back; shards add up
//! to the whole run; bad input gets a clear error; the pocket finder finds
//! the crystal ligand's pocket.

#![allow(clippy::unwrap_used)]

mod common;

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use bump::collide::{Collider, ColliderKind, ContactRule};
use bump::dock::{DockOptions, Docking, Target, dock};
use bump::model::{self, LoadOptions, Molecule, receptor_only};
use bump::pocket::{DockBox, PocketOptions, find_pockets};
use bump::score::prepare;
use bump_testkit::data::shared_pdb;
use bump_testkit::oracle::contact;
use common::cli::{bump, json, stderr};
use glam::DVec3;

/// `../shared/dock/ID` when the shared folder is there.
fn complex(id: &str) -> Option<PathBuf> {
    let pdb = shared_pdb()?;
    let d = pdb.parent()?.join("dock").join(id);
    if d.join("protein.pdbqt").is_file() {
        Some(d)
    } else if std::env::var("CI").as_deref() == Ok("true") {
        panic!("{} is missing: CI must have ../shared/dock", d.display());
    } else {
        eprintln!("SKIP: {} not found", d.display());
        None
    }
}

fn load(path: &Path) -> Molecule {
    let m = model::load(path, &LoadOptions::default()).unwrap();
    let mut mol = receptor_only(&m.structure).unwrap();
    mol.name = m.structure.name.clone();
    mol
}

/// A short docking of `id`'s random start in the crystal ligand's box.
fn short_dock(dir: &Path, threads: usize, seed: u64) -> (Molecule, Molecule, Docking) {
    let receptor = load(&dir.join("protein.pdbqt"));
    let drug = load(&dir.join("rand-0.pdbqt"));
    let xray = load(&dir.join("flex-xray.pdbqt"));
    let rule = ContactRule::default();
    let collider = Collider::build_plain(&receptor, &rule, ColliderKind::Hashed);
    let typed = prepare::receptor(&receptor);
    let lig = prepare::ligand(&drug).unwrap();
    let bx = DockBox::around(&xray.file_positions(), 5.0, 20.0).unwrap();
    let target = Target {
        receptor: &typed,
        collider: &collider,
        rule,
        receptor_centre: receptor.centre,
    };
    let opts = DockOptions {
        exhaustiveness: 2,
        threads,
        seed,
        effort: 0.15,
        ..DockOptions::default()
    };
    let d = dock(&target, &drug, &lig, &bx, &opts).unwrap();
    (receptor, drug, d)
}

/// Bonds between heavy atoms of `m` (its chemistry's adjacency), as the
/// number of bonds between every two atoms (breadth first).
fn bond_distances(m: &Molecule) -> Vec<Vec<usize>> {
    let adj = &m.chemistry().adjacency;
    let n = m.len();
    (0..n)
        .map(|s| {
            let mut d = vec![usize::MAX; n];
            d[s] = 0;
            let mut q = VecDeque::from([s]);
            while let Some(i) = q.pop_front() {
                for &(j, _) in adj.of(i) {
                    let j = j as usize;
                    if d[j] == usize::MAX {
                        d[j] = d[i] + 1;
                        q.push_back(j);
                    }
                }
            }
            d
        })
        .collect()
}

#[test]
fn the_same_seed_gives_the_same_poses_on_one_thread_or_two() {
    let Some(dir) = complex("1hnn") else {
        return;
    };
    let (_, _, one) = short_dock(&dir, 1, 5);
    let (_, _, two) = short_dock(&dir, 2, 5);
    assert!(!one.poses.is_empty());
    assert_eq!(one.poses, two.poses, "poses differ between thread counts");
    assert_eq!(one.evaluations, two.evaluations);
    let (_, _, other) = short_dock(&dir, 2, 6);
    assert_ne!(one.poses, other.poses, "another seed searches otherwise");
}

#[test]
fn every_pose_is_collision_free_by_brute_force() {
    let Some(dir) = complex("1p62") else {
        return;
    };
    let (receptor, drug, d) = short_dock(&dir, 0, 3);
    let rule = ContactRule::default();
    let rec_pos = receptor.file_positions();
    let bonds = bond_distances(&drug);
    let lig = prepare::ligand(&drug).unwrap();
    assert!(!d.poses.is_empty());
    for p in &d.poses {
        let x: Vec<DVec3> = p.atoms.iter().map(|a| *a + receptor.centre).collect();
        for (i, xi) in x.iter().enumerate() {
            let a = &drug.atoms[i];
            for (j, q) in rec_pos.iter().enumerate() {
                let c = contact(&rule, &receptor.atoms[j], a);
                assert!(
                    (*xi - *q).length() > c,
                    "pose {}: drug atom {i} collides with receptor atom {j}",
                    p.rank
                );
            }
            for k in i + 1..x.len() {
                // Pairs more than three bonds apart in different rigid
                // pieces (a ring's own atoms never move apart).
                if bonds[i][k] > 3 && lig.fragment_of[i] != lig.fragment_of[k] {
                    let c = contact(&rule, &drug.atoms[k], a);
                    assert!(
                        (*xi - x[k]).length() > c,
                        "pose {}: drug atoms {i} and {k} collide",
                        p.rank
                    );
                }
            }
        }
        // Sorted best first, clustered apart.
        assert!(p.total.is_finite());
    }
    for w in d.poses.windows(2) {
        assert!(w[0].total <= w[1].total);
    }
}

#[test]
fn dock_writes_sdf_and_pdbqt_that_read_back() {
    let Some(dir) = complex("1hnn") else {
        return;
    };
    let tmp = std::env::temp_dir().join(format!("bump-dock-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let (r, l, x) = (
        dir.join("protein.pdbqt"),
        dir.join("rand-0.pdbqt"),
        dir.join("flex-xray.pdbqt"),
    );
    let s = |p: &Path| p.display().to_string();
    let sdf = tmp.join("out.sdf");
    let pdbqt = tmp.join("out.pdbqt");
    let common = [
        "dock",
        &s(&r),
        &s(&l),
        "--box-from",
        &s(&x),
        "--exhaustiveness",
        "2",
        "--effort",
        "0.15",
        "--reference",
        &s(&x),
        "--json",
    ];
    let j = json(&[&common[..], &["-o", &s(&sdf)]].concat());
    let poses = j["molecules"][0]["poses"].as_array().unwrap().clone();
    assert!(!poses.is_empty());
    for p in &poses {
        assert_eq!(p["collides"], false);
        assert!(p["rmsd_to_reference"].as_f64().unwrap() >= 0.0);
        assert!(p["terms"]["gauss1"].is_number());
    }
    assert!(j["elapsed_s"].as_f64().unwrap() > 0.0);
    assert!(j["evaluations"].as_u64().unwrap() > 0);
    assert!(j["box"]["size"][0].as_f64().unwrap() >= 20.0);
    // SDF: one record per pose, with the drug's bonds and the tags.
    let text = std::fs::read_to_string(&sdf).unwrap();
    assert_eq!(text.matches("$$$$").count(), poses.len());
    assert_eq!(text.matches("> <minimizedAffinity>").count(), poses.len());
    assert!(text.contains("> <inter>") && text.contains("> <intra>") && text.contains("> <rank>"));
    let drug = load(&l);
    let first = model::load(&sdf, &LoadOptions::default()).unwrap();
    let back = receptor_only(&first.structure).unwrap();
    assert_eq!(back.len(), drug.len());
    assert!(!back.file_bonds.is_empty());
    let top = poses[0]["total"].as_f64().unwrap();
    assert!(text.contains(&format!("> <minimizedAffinity>\n{top:.3}\n")));
    // PDBQT: one model per pose with Vina's result line, and bump reads each.
    json(&[&common[..], &["-o", &s(&pdbqt)]].concat());
    let text = std::fs::read_to_string(&pdbqt).unwrap();
    assert_eq!(
        text.matches("\nENDMDL").count() + usize::from(text.starts_with("ENDMDL")),
        poses.len()
    );
    assert_eq!(text.matches("REMARK VINA RESULT:").count(), poses.len());
    for k in 1..=poses.len() {
        let m = model::load(
            &pdbqt,
            &LoadOptions {
                sdf_record: Some(k),
                ..LoadOptions::default()
            },
        )
        .unwrap();
        assert_eq!(receptor_only(&m.structure).unwrap().len(), drug.len());
    }
    // The top model scores as reported.
    let one = tmp.join("one.pdbqt");
    let first_model: String = text
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with("ENDMDL"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&one, first_model).unwrap();
    let sc = json(&["score", &s(&r), &s(&one), "--json"]);
    assert!(
        (sc["total"].as_f64().unwrap() - top).abs() < 2e-3,
        "{sc} vs {top}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn shards_add_up_to_the_whole_library() {
    let (Some(pdb), Some(dir)) = (shared_pdb(), complex("1hnn")) else {
        return;
    };
    let tmp = std::env::temp_dir().join(format!("bump-shard-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let lib = tmp.join("lib.sdf");
    // Three molecules of different types: the shared maps grow with them.
    let mut text = String::new();
    for f in [
        "benzamidine_3ptb.sdf",
        "trimethoprim_top_6xg5pose.sdf",
        "methotrexate_mtx_ideal.sdf",
    ] {
        text.push_str(&std::fs::read_to_string(pdb.join(f)).unwrap());
    }
    std::fs::write(&lib, text).unwrap();
    let (rec, xray, lib_s) = (
        dir.join("protein.pdbqt").display().to_string(),
        dir.join("flex-xray.pdbqt").display().to_string(),
        lib.display().to_string(),
    );
    let run = |shard: Option<&str>| {
        let mut args = vec![
            "dock",
            &rec,
            &lib_s,
            "--box-from",
            &xray,
            "--exhaustiveness",
            "1",
            "--effort",
            "0.05",
            "--poses",
            "2",
            "--seed",
            "3",
            "--json",
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        json(&args)
    };
    let recs = |v: &serde_json::Value| -> Vec<(u64, String)> {
        v["molecules"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| (m["record"].as_u64().unwrap(), m["poses"].to_string()))
            .collect()
    };
    let all = run(None);
    // Each molecule is named by its record's title.
    assert_eq!(all["molecules"][0]["name"], "BEN");
    assert_eq!(all["molecules"][2]["name"], "MTX");
    let whole = recs(&all);
    let mut parts = recs(&run(Some("0/2")));
    parts.extend(recs(&run(Some("1/2"))));
    parts.sort();
    assert_eq!(whole.len(), 3);
    assert_eq!(whole.iter().map(|r| r.0).collect::<Vec<_>>(), [1, 2, 3]);
    assert_eq!(parts, whole);
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn from_pose_searches_round_the_drugs_pose() {
    let Some(dir) = complex("1hnn") else {
        return;
    };
    let x = dir.join("flex-xray.pdbqt").display().to_string();
    let r = dir.join("protein.pdbqt").display().to_string();
    let j = json(&[
        "dock",
        &r,
        &x,
        "--from-pose",
        "--radius",
        "2",
        "--exhaustiveness",
        "2",
        "--effort",
        "0.1",
        "--reference",
        &x,
        "--json",
    ]);
    assert!(j["box"]["from"].as_str().unwrap().contains("pose"));
    let poses = j["molecules"][0]["poses"].as_array().unwrap();
    // Started round the crystal pose, the search stays in its pocket: every
    // pose's centre lies within the drug's extent plus the radius.
    let size: Vec<f64> = (0..3)
        .map(|k| j["box"]["size"][k].as_f64().unwrap())
        .collect();
    let centre: Vec<f64> = (0..3)
        .map(|k| j["box"]["center"][k].as_f64().unwrap())
        .collect();
    for p in poses {
        for k in 0..3 {
            let c = p["center"][k].as_f64().unwrap();
            assert!((c - centre[k]).abs() <= size[k] / 2.0 + 1e-6, "{p}");
        }
    }
    assert!(poses[0]["rmsd_to_reference"].as_f64().unwrap() < 2.0);
}

#[test]
fn bad_dock_input_gets_a_clear_error() {
    let Some(dir) = complex("1hnn") else {
        return;
    };
    let s = |p: PathBuf| p.display().to_string();
    let (r, l) = (s(dir.join("protein.pdbqt")), s(dir.join("rand-0.pdbqt")));
    for (extra, says) in [
        (
            vec!["--center", "900,900,900", "--size", "20,20,20"],
            "misses the receptor",
        ),
        (
            vec!["--center", "27.8,44.1,16.5", "--size", "3,3,3"],
            "box's diagonal",
        ),
        (
            vec!["--center", "27.8,44.1,16.5", "--size", "20,20,1e9"],
            "at most 126",
        ),
        (
            vec!["--center", "27.8,44.1,16.5", "--size", "20,-1,20"],
            "above 0",
        ),
        (
            vec!["--exhaustiveness", "0", "--pocket", "1"],
            "exhaustiveness",
        ),
        (
            vec!["--exhaustiveness", "100000000", "--pocket", "1"],
            "exhaustiveness",
        ),
        (vec!["--shard", "2/2", "--pocket", "1"], "0 <= K < N"),
        (vec!["--center", "1,2,3"], "--center and --size"),
        (vec!["--pocket", "99"], "pockets"),
        (
            vec!["--pocket", "1", "--center", "1,2,3", "--size", "20,20,20"],
            "give one box",
        ),
    ] {
        let mut args = vec!["dock", &r, &l];
        args.extend(extra.iter().copied());
        let out = bump(&args);
        assert!(!out.status.success(), "{extra:?} was accepted");
        let e = stderr(&out);
        assert!(e.contains(says), "{extra:?}: {e}");
        assert!(!e.contains("panicked"), "{e}");
    }
    // A ligand with no atoms.
    let empty = std::env::temp_dir().join(format!("bump-empty-{}.sdf", std::process::id()));
    std::fs::write(
        &empty,
        "empty\n  bump\n\n  0  0  0  0  0  0  0  0  0  0999 V2000\nM  END\n$$$$\n",
    )
    .unwrap();
    let out = bump(&["dock", &r, &s(empty.clone()), "--pocket", "1"]);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("bump-empty") && !e.contains("panicked"), "{e}");
    let _ = std::fs::remove_file(&empty);
    // A failed run writes no output file.
    let out_path = std::env::temp_dir().join(format!("bump-bad-{}.sdf", std::process::id()));
    let o = s(out_path.clone());
    let out = bump(&[
        "dock",
        &r,
        &l,
        "--center",
        "900,900,900",
        "--size",
        "20,20,20",
        "-o",
        &o,
    ]);
    assert!(!out.status.success());
    assert!(!out_path.exists());
}

#[test]
fn pockets_find_the_crystal_ligands_pocket_among_the_first_three() {
    let Some(pdb) = shared_pdb() else {
        return;
    };
    for (file, lig) in [
        ("3ptb.pdb", "BEN"),
        ("4dfr.pdb", "MTX"),
        ("1hvr.pdb", "XK2"),
    ] {
        let loaded = model::load(&pdb.join(file), &LoadOptions::default()).unwrap();
        let spec = model::LigandSpec::parse(lig).unwrap();
        let (receptor, ligand) = model::split_complex_owned(loaded.structure, &spec).unwrap();
        let pockets = find_pockets(&receptor, &PocketOptions::default()).unwrap();
        let near = |c: DVec3| {
            ligand
                .file_positions()
                .iter()
                .any(|q| (*q - c).length() <= 4.0)
        };
        assert!(
            pockets.iter().take(3).any(|p| near(p.centre)),
            "{file}: no top-3 pocket centre within 4 Å of {lig}"
        );
        for (k, p) in pockets.iter().enumerate() {
            assert_eq!(p.rank, k + 1);
            assert!(p.volume > 0.0 && !p.residues.is_empty());
            assert!(p.dock_box.contains(p.centre));
        }
        // The same on every run.
        assert_eq!(
            pockets,
            find_pockets(&receptor, &PocketOptions::default()).unwrap()
        );
    }
    let j = json(&[
        "pockets",
        &pdb.join("3ptb.pdb").display().to_string(),
        "--ligand",
        "BEN",
        "--json",
    ]);
    assert!(j["pockets"][0]["residues"].as_array().unwrap().len() > 3);
    assert!(j["pockets"][0]["ligand_distance"].is_number());
}
