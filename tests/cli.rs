//! The command line end to end: `check`, `touch` and `stats` with `--json`,
//! and clear errors for bad input.

mod common;

use common::cli::{bump, json, stderr};
use serde_json::Value;

#[test]
fn builtin_scene_docks_by_a_straight_push() {
    let v = json(&["touch", "builtin", "--move", "0,0,25", "--json"]);
    assert_eq!(v["t"], 1.0);
    assert_eq!(v["contacts"].as_array().map(Vec::len), Some(0));
    let v = json(&[
        "touch", "builtin", "--start", "0,5,0", "--move", "0,0,25", "--json",
    ]);
    let t = v["t"].as_f64().expect("t");
    assert!(t > 0.0 && t < 1.0);
    assert!(!v["contacts"].as_array().expect("contacts").is_empty());
    assert!(v["elapsed_us"].as_f64().expect("time") > 0.0);
    // The E pushed off-centre into the rings (it touches), under `response`.
    let misaligned = |response: &str, json: bool| {
        let mut args = vec![
            "touch",
            "builtin",
            "--start",
            "0,5,0",
            "--move",
            "0,0,25",
            "--response",
        ];
        args.push(response);
        if json {
            args.push("--json");
        }
        bump(&args)
    };
    for response in ["stop", "slide", "pass"] {
        let out = misaligned(response, true);
        assert!(out.status.success(), "{response}: {}", stderr(&out));
        let v: Value = serde_json::from_slice(&out.stdout).expect("JSON output");
        assert_eq!(v["response"], response);
        // `stop` stays put and says its contacts are where the step ran in.
        assert_eq!(v["step_rejected"], response == "stop", "{response}");
    }
    let plain = misaligned("touch", false);
    let plain = String::from_utf8_lossy(&plain.stdout).into_owned();
    assert!(!plain.contains("rejected") && plain.contains("in contact"));
    let stop = misaligned("stop", false);
    let stop = String::from_utf8_lossy(&stop.stdout).into_owned();
    assert!(stop.contains("the step was rejected"), "{stop}");
    // A turn past half a revolution says how it will run.
    let out = bump(&["touch", "--move", "0,0,25", "--turn", "0,0,1,270"]);
    assert!(out.status.success());
    assert!(stderr(&out).contains("as -90°"), "{}", stderr(&out));
    // The built-in scene is the default: no file needed.
    let plain = bump(&["touch", "--move", "0,0,25"]);
    assert!(String::from_utf8_lossy(&plain.stdout).contains("t = 1.000000"));
    // An axis of any finite size turns; a tolerance too fine is raised, and said.
    let v = json(&[
        "touch",
        "--move",
        "0,0,-5",
        "--turn",
        "1e300,1e300,0,30",
        "--json",
    ]);
    let turned = v["final_pose"]["angle_deg"].as_f64().expect("angle");
    assert!((turned - 30.0).abs() < 1e-9, "{turned}");
    let out = bump(&["touch", "--move", "0,0,1", "--tolerance", "1e-12", "--json"]);
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON output");
    assert_eq!(v["tolerance"], 1e-5);
    assert!(stderr(&out).contains("raised to 1e-5"), "{}", stderr(&out));
    // One so large every pair would be "in contact" is refused, naming it.
    let out = bump(&["touch", "--move", "0,0,1", "--tolerance", "1e300"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--tolerance must be at most 1 Å, got 1e300"),
        "{}",
        stderr(&out)
    );
    // A negative one is read as a value (not an option) and refused, named.
    let out = bump(&["touch", "--move", "0,0,1", "--tolerance", "-1e-3"]);
    assert!(
        stderr(&out).contains("--tolerance must be a positive number of Å, got -0.001"),
        "{}",
        stderr(&out)
    );
}

/// The smallest gap is reported however far the drug ends from the
/// receptor (beyond the grid's 4 Å look-up every pair is measured): the E
/// started 10 Å farther back along its approach ends 10 Å farther away,
/// less the little its nearest pair's sideways offset takes off.
#[test]
fn touch_reports_the_smallest_gap_far_from_the_receptor() {
    let gap_with = |start: &str, more: &[&str]| {
        let mut args = vec![
            "touch", "builtin", "--start", start, "--move", "0,0,1", "--json",
        ];
        args.extend_from_slice(more);
        let v = json(&args);
        assert_eq!(v["t"], 1.0);
        let g = v["min_gap"].as_f64().expect("min_gap is a number");
        assert!(v["nearest"].is_object(), "{v}");
        g
    };
    let gap = |start: &str| gap_with(start, &[]);
    let (near, far) = (gap("0,0,-100"), gap("0,0,-110"));
    // Every collider finds the same pair; under the largest overlap
    // allowance its gap is 5 − 0.6 Å larger than under the default rule.
    for collider in ["brute", "grid", "hashed"] {
        assert_eq!(
            gap_with("0,0,-100", &["--collider", collider]),
            near,
            "{collider}"
        );
    }
    let loose = gap_with("0,0,-100", &["--overlap", "5"]);
    assert!((loose - near - 4.4).abs() < 1e-3, "{near} {loose}");
    assert!(near > 100.0, "{near}");
    let d = far - near;
    assert!(d > 9.9 && d <= 10.0 + 1e-3, "{near} {far}");
    let out = bump(&["touch", "builtin", "--start", "0,0,-100", "--move", "0,0,1"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains(&format!("smallest gap {near:.4}")), "{text}");
}

#[test]
fn check_reports_serials_and_the_rule() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let f = dir.join("6xg5_tmp_prepared.pdb");
    let f = f.to_str().expect("path");
    let v = json(&["check", f, "--ligand", "TOP", "--json"]);
    assert_eq!(v["clash_count"], 0);
    assert_eq!(v["drug"]["atoms"], 21);
    assert_eq!(v["receptor"]["atoms"], 1268);
    assert_eq!(
        v["rule"]["overlap"].as_f64().map(|x| (x * 10.0).round()),
        Some(6.0)
    );
    assert_eq!(v["collider"], "hashed");
    // Pushed 2 Å along x the drug hits the pocket wall.
    for collider in ["brute", "grid", "hashed"] {
        let v = json(&[
            "check",
            f,
            "--ligand",
            "TOP",
            "--move",
            "2,0,0",
            "--collider",
            collider,
            "--json",
        ]);
        let clashes = v["clashes"].as_array().expect("clashes");
        assert!(!clashes.is_empty(), "{collider}");
        let c = &clashes[0];
        assert!(c["receptor_serial"].as_i64().expect("serial") > 0);
        assert!(c["drug_serial"].as_i64().expect("serial") > 0);
        assert_eq!(c["drug_residue"], "TOP");
        assert!(c["overlap"].as_f64().expect("overlap") >= 0.6 - 1e-6);
        for k in [
            "receptor_name",
            "receptor_chain",
            "receptor_element",
            "drug_name",
            "distance",
            "receptor_radius",
        ] {
            assert!(!c[k].is_null(), "{k}");
        }
    }
    // A separate SDF drug: serials are 1-based record order.
    let sdf = dir.join("trimethoprim_top_6xg5pose.sdf");
    let sdf = sdf.to_str().expect("path");
    let r = dir.join("1rx1.pdb");
    let v = json(&[
        "check",
        r.to_str().expect("path"),
        sdf,
        "--move",
        "0,0,0",
        "--json",
    ]);
    assert_eq!(v["drug"]["atoms"], 21);
    let quiet = bump(&["check", r.to_str().expect("path"), sdf]);
    assert!(!stderr(&quiet).contains("lie within"), "{}", stderr(&quiet));
    // The drug given again beside the complex that still holds it: said,
    // with the split that was meant.
    let complex = dir.join("6xg5_tmp_prepared.pdb");
    let out = bump(&["check", complex.to_str().expect("path"), sdf]);
    assert!(out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("21 of 21 drug atoms lie within 0.5 Å") && e.contains("--ligand TOP"),
        "{e}"
    );
    // There every drug atom collides with its copy: each clash's
    // drug_serial is the atom's 1-based place in the SDF record, whose
    // element it must carry.
    let v = json(&["check", complex.to_str().expect("path"), sdf, "--json"]);
    let text = std::fs::read_to_string(dir.join("trimethoprim_top_6xg5pose.sdf")).expect("sdf");
    let lines: Vec<&str> = text.lines().collect();
    let clashes = v["clashes"].as_array().expect("clashes");
    let mut serials: Vec<u64> = clashes
        .iter()
        .map(|c| c["drug_serial"].as_u64().expect("drug_serial"))
        .collect();
    for (c, &k) in clashes.iter().zip(&serials) {
        // Atom k is on line 4 + k (three header lines, then the counts line).
        let element = lines[3 + k as usize]
            .split_whitespace()
            .nth(3)
            .expect("element");
        assert!((1..=39).contains(&k) && element != "H", "{k}");
        assert_eq!(c["drug_element"].as_str(), Some(element), "serial {k}");
    }
    serials.sort_unstable();
    serials.dedup();
    // The 21 heavy atoms come first in this record.
    assert_eq!(serials, (1..=21).collect::<Vec<u64>>());
}

/// Residues with insertion codes (trypsin's 184A, 188A, 221A) are named
/// with them, in the table and in JSON.
#[test]
fn pairs_name_insertion_codes() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let f = dir.join("3ptb.pdb");
    let f = f.to_str().expect("path");
    // Benzamidine pushed into the pocket wall at ALA 221A.
    let args = ["check", f, "--ligand", "BEN", "--move=-3.42,0.287,-1.074"];
    let v = json(&[&args[..], &["--json"]].concat());
    let clashes = v["clashes"].as_array().expect("clashes");
    let ala = clashes
        .iter()
        .find(|c| c["receptor_serial"] == 1423)
        .expect("N ALA 221A (serial 1423) clashes");
    assert_eq!(ala["receptor_seq"], 221);
    assert_eq!(ala["receptor_insertion"], "A");
    assert_eq!(ala["drug_insertion"], "");
    assert!(clashes.iter().any(|c| c["receptor_insertion"] == ""));
    let out = bump(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.lines().any(|l| l.contains(" 1423 N    ALA   221A A ")),
        "{text}"
    );
}

#[test]
fn touch_from_outside_the_pocket() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let f = dir.join("3ptb.pdb");
    let f = f.to_str().expect("path");
    let v = json(&[
        "touch", f, "--ligand", "BEN", "--start", "0,12,0", "--move", "0,-12,0", "--turn",
        "0,1,0,20", "--json",
    ]);
    let t = v["t"].as_f64().expect("t");
    assert!((0.0..=1.0).contains(&t));
    assert_eq!(v["start_collides"], false);
    assert!(v["final_pose"]["centre"].is_array());
    assert!(v["final_pose"]["angle_deg"].as_f64().is_some());
    let thesis = json(&[
        "touch", f, "--ligand", "BEN", "--start", "0,12,0", "--move", "0,-12,0", "--method",
        "thesis", "--json",
    ]);
    assert_eq!(thesis["method"], "thesis");
    // Slide: t is its first leg's; the text says how far all legs went.
    let out = bump(&[
        "touch",
        f,
        "--ligand",
        "BEN",
        "--start",
        "0,12,0",
        "--move",
        "0,-12,0",
        "--response",
        "slide",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("of its first leg;") && text.contains("legs moved the centre"),
        "{text}"
    );
    // A colliding start: pass says it lets the drug move, the others that
    // they refuse to deepen the overlap.
    for (response, says) in [
        ("pass", "pass lets the drug move anyway"),
        ("touch", "only motions that do not deepen them are allowed"),
    ] {
        let out = bump(&[
            "touch",
            f,
            "--ligand",
            "BEN",
            "--start",
            "0,1.5,0",
            "--move",
            "0,0.3,0",
            "--response",
            response,
        ]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.contains("already collides (1 pair)") && text.contains(says),
            "{text}"
        );
    }
}

#[test]
fn stats_reproduces_table_1_columns() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let files: Vec<String> = ["4dfr.pdb", "1bna.pdb", "3ptb.pdb"]
        .iter()
        .map(|f| dir.join(f).display().to_string())
        .collect();
    let mut args = vec!["stats", "--json"];
    args.extend(files.iter().map(String::as_str));
    let v = json(&args);
    let rows = v.as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    for r in rows {
        let hashed = r["hashed_overlap"]["atoms_per_cell"]
            .as_f64()
            .expect("hashed");
        let grid = r["grid_overlap"]["atoms_per_cell"].as_f64().expect("grid");
        let centre = r["grid_centre"]["atoms_per_cell"].as_f64().expect("centre");
        assert!(hashed >= grid * 0.99, "hashing cannot lower the density");
        assert!(grid > centre, "overlap counting exceeds centre counting");
        assert!((3.0..30.0).contains(&grid), "{grid}");
        assert_eq!(r["hash_cells"], 4096);
        assert!(r["cell_size"].as_f64().expect("cell") > 3.0);
    }
    // Hydrogens are spelt as in check and touch (the old flag still works).
    let h = dir.join("6xg5_tmp_prepared.pdb").display().to_string();
    let atoms = |extra: &[&str]| {
        let mut args = vec!["stats", "--json", h.as_str()];
        args.extend(extra);
        json(&args)[0]["atoms"].as_u64().expect("atoms")
    };
    let (dropped, kept) = (atoms(&[]), atoms(&["--hydrogens", "keep"]));
    assert!(kept > dropped, "{kept} {dropped}");
    assert_eq!(atoms(&["--keep-hydrogens"]), kept);
    assert_eq!(atoms(&["--hydrogens", "drop", "--radii", "bondi"]), dropped);
    // Cells so small that counting would take minutes are refused.
    let out = bump(&["stats", files[0].as_str(), "--cell", "0.11"]);
    assert_eq!(out.status.code(), Some(2));
    let e = stderr(&out);
    assert!(
        e.contains("4dfr.pdb") && e.contains("choose a larger --cell"),
        "{e}"
    );
}

#[test]
fn bad_input_gets_clear_errors() {
    let out = bump(&["check", "/nonexistent/x.pdb"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("/nonexistent/x.pdb"),
        "{}",
        stderr(&out)
    );
    // The operating system's reason, once.
    assert_eq!(
        stderr(&out).matches("os error").count(),
        1,
        "{}",
        stderr(&out)
    );

    let dir = std::env::temp_dir().join(format!("bump-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let bad = dir.join("bad.sdf");
    std::fs::write(&bad, "name\n  prog\n\n  2  0  0  0  0  0  0  0  0  0999 V2000\n    0.0000    0.0000    0.0000 C   0  0\n    x.0000    0.0000    0.0000 C   0  0\nM  END\n$$$$\n").expect("write");
    let out = bump(&["check", "builtin"]);
    assert!(out.status.success());
    let out = bump(&["stats", bad.to_str().expect("path")]);
    assert_eq!(out.status.code(), Some(2));
    let e = stderr(&out);
    assert!(e.contains("bad.sdf") && e.contains(":6"), "{e}");
    let empty = dir.join("empty.pdb");
    std::fs::write(&empty, "REMARK nothing here\nEND\n").expect("write");
    let out = bump(&["stats", empty.to_str().expect("path")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("empty.pdb"), "{}", stderr(&out));
    let out = bump(&["touch", "builtin", "--move", "1,2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("X,Y,Z"), "{}", stderr(&out));
    let out = bump(&["check", "builtin", "--collider", "octree"]);
    assert!(stderr(&out).contains("brute, grid or hashed"));
    let out = bump(&["touch", "builtin", "--move", "0,0,1", "--overlap", "nan"]);
    assert_eq!(out.status.code(), Some(2));
    // Poses beyond the range the collision math is exact in are refused.
    for args in [
        &["touch", "--move", "1e155,0,0"][..],
        &["touch", "--start", "0,-2e9,0", "--move", "0,0,1"][..],
        &["check", "--move", "0,0,3e9"][..],
    ] {
        let out = bump(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&out).contains("beyond the 1e9 Å"),
            "{}",
            stderr(&out)
        );
    }
    // A parser that panics on bad values (pdbtbx does) is an error like any
    // other: no panic message, the file named, and the line where known.
    let cif = dir.join("unknown-element.cif");
    std::fs::write(
        &cif,
        "data_T\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n\
         _atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.label_asym_id\n\
         _atom_site.label_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n\
         ATOM 1 ? N MET A 1 0.0 0.0 0.0\n",
    )
    .expect("write");
    let nan = dir.join("nan.pdb");
    std::fs::write(
        &nan,
        "ATOM      1  N   MET A   1      38.296  20.158  39.260  1.00  0.00           N\n\
         ATOM      2  CA  MET A   1         nan  20.000  39.000  1.00  0.00           C\n",
    )
    .expect("write");
    for (file, at) in [(&cif, "unknown-element.cif"), (&nan, "nan.pdb:2")] {
        let out = bump(&["stats", file.to_str().expect("path")]);
        assert_eq!(out.status.code(), Some(2));
        let e = stderr(&out);
        assert!(e.contains(at) && !e.contains("panicked"), "{e}");
    }
    // A record number only means something for SDF.
    let tiny = dir.join("tiny.pdb");
    std::fs::write(
        &tiny,
        "ATOM      1  N   MET A   1      38.296  20.158  39.260  1.00  0.00           N\n",
    )
    .expect("write");
    let tiny = tiny.to_str().expect("path");
    let out = bump(&["check", tiny, tiny, "--record", "2"]);
    assert_eq!(out.status.code(), Some(2));
    let e = stderr(&out);
    assert!(e.contains("tiny.pdb: record 2 was asked for"), "{e}");
    // mmCIF text under a .pdb name, and numbers single precision cannot hold.
    let cif_as_pdb = dir.join("cif-text.pdb");
    std::fs::write(&cif_as_pdb, "\ndata_1ABC\n_entry.id 1ABC\n").expect("write");
    let out = bump(&["stats", cif_as_pdb.to_str().expect("path")]);
    assert_eq!(out.status.code(), Some(2));
    let e = stderr(&out);
    assert!(e.contains("cif-text.pdb:2: this is mmCIF text"), "{e}");
    for args in [
        &["check", "--overlap", "1e300"][..],
        &["check", "--hbond-allowance", "1e-300"][..],
    ] {
        let out = bump(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains("out of range"), "{}", stderr(&out));
    }
    let out = bump(&["check", "unknown.xyz"]);
    assert!(stderr(&out).contains("unknown format"), "{}", stderr(&out));
    // Negative numbers are values, refused by the option's own check (clap
    // would call them unknown arguments and suggest `-- -1`).
    for (args, says) in [
        (
            &["check", tiny, tiny, "--record", "-1"][..],
            "`-1` is not a whole number",
        ),
        (
            &["stats", tiny, "--cell", "-1"][..],
            "--cell must be a cell edge above 0.1 Å, got -1",
        ),
        (
            &["stats", tiny, "--hash-cells", "-4096"][..],
            "`-4096` is not a whole number",
        ),
    ] {
        let out = bump(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(says), "{}", stderr(&out));
    }
    // An absurd coordinate is quoted as written, not in 300 digits.
    let huge = dir.join("huge.pdb");
    std::fs::write(
        &huge,
        "ATOM      1  N   MET A   1    1.0e300  20.158  39.260  1.00  0.00           N\n",
    )
    .expect("write");
    let out = bump(&["stats", huge.to_str().expect("path")]);
    let e = stderr(&out);
    assert!(
        e.contains("huge.pdb:1:31: x coordinate 1.0e300 is beyond"),
        "{e}"
    );
    assert!(e.len() < 200, "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(feature = "app")]
#[test]
fn without_a_display_the_window_fails_cleanly() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bump"))
        .arg("/nonexistent/receptor.pdb")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run bump");
    assert_eq!(out.status.code(), Some(2));
    let e = stderr(&out);
    assert!(
        e.contains("cannot open a window") && e.contains("bump render"),
        "{e}"
    );
}

#[test]
fn steer_reports_the_run_as_json_and_refuses_a_zero_direction() {
    let v = json(&[
        "steer",
        "builtin",
        "--direction",
        "1,0,0",
        "--response",
        "pass",
        "--json",
    ]);
    assert_eq!(v["reached"], true);
    assert_eq!(v["response"], "pass");
    assert!(v["start_distance"].as_f64().expect("start") >= 8.0);
    assert!(v["final_rmsd"].as_f64().expect("final") < 1e-6);
    // At the file pose there is no push left to measure against a surface.
    assert!(v["end_push_into_surface"].is_null(), "{v}");
    // The path pressed deeper than the soft limit is there exactly when the
    // run went deeper than the limit at all.
    let beyond = v["path_beyond_limit"].as_f64().expect("beyond");
    let deepest = v["deepest_overlap"].as_f64().expect("deepest");
    assert_eq!(beyond > 0.0, deepest > 1.0 + 1e-6, "{v}");
    // At the default limit both lengths are the same.
    assert_eq!(
        v["path_beyond_default_limit"], v["path_beyond_limit"],
        "{v}"
    );
    // A looser soft limit lets benzamidine through trypsin from the far
    // side: nothing beyond that limit, but a long path beyond the default.
    if let Some(dir) = common::shared_pdb() {
        let rec = dir.join("3ptb.pdb").display().to_string();
        let v = json(&[
            "steer",
            &rec,
            "--ligand",
            "BEN",
            "--direction",
            "1,0,0",
            "--response",
            "soft",
            "--soft-limit",
            "2.5",
            "--json",
        ]);
        let deepest = v["deepest_overlap"].as_f64().expect("deepest");
        assert!(deepest > 1.0 && deepest <= 2.5 + 1e-4, "{v}");
        assert_eq!(v["path_beyond_limit"], 0.0, "{v}");
        let beyond = v["path_beyond_default_limit"].as_f64().expect("beyond");
        assert!(beyond > 5.0, "{v}");
    }
    let v = json(&[
        "steer",
        "builtin",
        "--direction",
        "0,-1,0.2",
        "--response",
        "soft",
        "--json",
    ]);
    let deepest = v["deepest_overlap"].as_f64().expect("deepest");
    assert!((0.0..=1.0 + 1e-4).contains(&deepest), "{v}");
    assert_eq!(v["path_beyond_limit"], 0.0, "{v}");
    let frames = v["frames"].as_u64().expect("frames");
    assert!((1..=3000).contains(&frames));
    assert!(v["best_rmsd"].as_f64() <= v["final_rmsd"].as_f64());
    let out = bump(&["steer", "builtin", "--direction", "0,0,0"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("direction"), "{}", stderr(&out));
    for bad in ["8/8", "1/0", "x/2", "-1/4"] {
        let out = bump(&["steer", "builtin", "--direction", bad]);
        assert!(!out.status.success(), "{bad}");
        assert!(stderr(&out).contains(bad), "{bad}: {}", stderr(&out));
    }
}

/// `--direction K/N` is the report's run K of N: its direction and its
/// seed, the same run as the vector with `--seed K+1`.
#[test]
fn steer_direction_k_of_n_is_the_reports_run() {
    let d = bump::rng::sphere_directions(8)[3];
    let vector = format!("{},{},{}", d.x, d.y, d.z);
    let run = |scene: &[&str], direction: &str, extra: &[&str]| {
        let mut args = vec!["steer"];
        args.extend_from_slice(scene);
        args.extend(["--direction", direction, "--json"]);
        args.extend_from_slice(extra);
        let mut v = json(&args);
        for timing in ["step_us_median", "step_us_p99"] {
            v[timing] = serde_json::Value::Null;
        }
        v
    };
    let builtin = ["builtin"];
    let of = run(&builtin, "3/8", &[]);
    assert_eq!(of, run(&builtin, &vector, &[]));
    assert_ne!(of["direction"], run(&builtin, "2/8", &[])["direction"]);
    // The seed shows in the start's torsion turns, so a drug with
    // rotatable bonds, flexible (its seeds 3, 4 and 1 turn them
    // differently).
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let file = dir.join("6xg5_tmp_prepared.pdb");
    let top = [file.to_str().expect("path"), "--ligand", "TOP"];
    let flexible = ["--flexible", "--response", "pass"];
    let of = run(&top, "3/8", &flexible);
    let seeded = |seed: &str| {
        let mut extra = flexible.to_vec();
        extra.extend(["--seed", seed]);
        run(&top, &vector, &extra)
    };
    assert_eq!(of, seeded("4"));
    assert_ne!(of["start_torsions"], seeded("3")["start_torsions"], "{of}");
    assert_ne!(of["start_torsions"], seeded("1")["start_torsions"], "{of}");
    // An explicit seed still wins.
    let mut extra = flexible.to_vec();
    extra.extend(["--seed", "1"]);
    assert_eq!(run(&top, "3/8", &extra), seeded("1"));
}

/// `bump steer --json` of the drug `ligand` split from `file`, flexible,
/// from `direction` with the start torsions of `seed`, through `response`.
fn steer_flexible(
    file: &str,
    ligand: &str,
    direction: &str,
    seed: u64,
    response: &str,
    extra: &[&str],
) -> serde_json::Value {
    let seed = seed.to_string();
    let mut args = vec![
        "steer",
        file,
        "--ligand",
        ligand,
        "--direction",
        direction,
        "--response",
        response,
        "--flexible",
        "--seed",
        &seed,
        "--json",
    ];
    args.extend_from_slice(extra);
    json(&args)
}

#[test]
fn steer_soft_goes_round_the_receptor_from_its_far_side() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let file = dir.join("6xg5_tmp_prepared.pdb");
    let file = file.to_str().expect("path");
    // The dockability report's fifth direction: the receptor's body lies
    // between this start and the pocket, and the straight path in presses
    // 1.5 Å and more past the contact rule (`pass`, below), beyond the
    // 1 Å soft limit. `soft` keeps to the limit and gets there round the
    // body.
    let run = |response: &str| steer_flexible(file, "TOP", "4/32", 5, response, &[]);
    let straight = run("pass");
    assert!(
        straight["deepest_overlap"].as_f64().expect("deepest") > 1.5,
        "{straight}"
    );
    let soft = run("soft");
    assert_eq!(soft["reached"], true, "{soft}");
    assert!(
        soft["deepest_overlap"].as_f64().expect("deepest") <= 1.0 + 1e-4,
        "{soft}"
    );
    assert_eq!(soft["path_beyond_limit"], 0.0, "{soft}");
}

#[test]
fn steer_starts_with_the_drugs_own_atoms_clear_of_each_other() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let turns = |v: &serde_json::Value| -> Vec<f64> {
        v["start_torsions"]
            .as_array()
            .expect("start_torsions")
            .iter()
            .map(|t| t.as_f64().expect("turn"))
            .collect()
    };
    let overlap = |v: &serde_json::Value, k: &str| v[k].as_f64().expect("overlap");
    // The dockability report's fourth direction: the seeded draw of
    // methotrexate's turns would press its halves 1.7 Å into each other.
    // The start turns those bonds the other way, or not at all; `soft` then
    // presses nothing past the limit and settles free of overlaps, and
    // `slide` presses nothing.
    let file = dir.join("4dfr.pdb");
    let file = file.to_str().expect("path");
    let direction = "3/32";
    let run = |response: &str| steer_flexible(file, "MTX", direction, 4, response, &["--settle"]);
    let soft = run("soft");
    let t = turns(&soft);
    assert_eq!(
        t.len(),
        soft["torsions"].as_u64().expect("torsions") as usize
    );
    assert!(t.iter().all(|t| [-60.0, 0.0, 60.0].contains(t)), "{soft}");
    assert_eq!(overlap(&soft, "start_inner_overlap"), 0.0, "{soft}");
    assert!(
        overlap(&soft, "deepest_inner_overlap") <= 1.0 + 1e-4,
        "{soft}"
    );
    assert!(overlap(&soft, "deepest_overlap") <= 1.0 + 1e-4, "{soft}");
    assert_eq!(soft["settled"]["collides"], false, "{soft}");
    let slide = run("slide");
    assert_eq!(overlap(&slide, "deepest_inner_overlap"), 0.0, "{slide}");
    assert_eq!(overlap(&slide, "deepest_overlap"), 0.0, "{slide}");
    // One of trimethoprim's methoxy groups, turned 60° either way, presses
    // its methyl into the next methoxy's oxygen: that bond starts at its
    // file angle, the others 60° off.
    let file = dir.join("6xg5_tmp_prepared.pdb");
    let file = file.to_str().expect("path");
    let top = steer_flexible(file, "TOP", direction, 1, "slide", &[]);
    let t = turns(&top);
    assert_eq!(t.iter().filter(|t| **t == 0.0).count(), 1, "{top}");
    assert_eq!(t.iter().filter(|t| t.abs() == 60.0).count(), t.len() - 1);
    assert_eq!(overlap(&top, "start_inner_overlap"), 0.0, "{top}");
}

/// `--escape` runs the controller from the file pose and file torsions out
/// to the start, its pose and turned bonds: collision off it gets there
/// exactly; under `soft` nothing presses past the limit on the way.
#[test]
fn steer_escape_runs_from_the_file_pose_out_to_the_start() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let file = dir.join("4dfr.pdb");
    let file = file.to_str().expect("path");
    let direction = "3/32";
    let num = |v: &serde_json::Value, k: &str| v[k].as_f64().expect(k);
    let free = steer_flexible(file, "MTX", direction, 4, "pass", &["--escape"]);
    assert_eq!(free["escape"], true, "{free}");
    assert_eq!(free["reached"], true, "{free}");
    for k in [
        "final_rmsd",
        "final_offset",
        "final_turn",
        "final_torsion_rms",
    ] {
        assert!(num(&free, k) < 1e-3, "{k}: {free}");
    }
    let turned = free["start_torsions"].as_array().expect("start_torsions");
    assert!(turned.iter().any(|t| t.as_f64() != Some(0.0)), "{free}");
    // The run in from the same start: the same start, the other way.
    let back = steer_flexible(file, "MTX", direction, 4, "pass", &[]);
    assert_eq!(back["escape"], false);
    assert_eq!(back["start_torsions"], free["start_torsions"]);
    assert_eq!(back["start_distance"], free["start_distance"]);
    let soft = steer_flexible(file, "MTX", direction, 4, "soft", &["--escape"]);
    assert!(num(&soft, "deepest_overlap") <= 1.0 + 1e-4, "{soft}");
    assert!(num(&soft, "deepest_inner_overlap") <= 1.0 + 1e-4, "{soft}");
    assert!(num(&soft, "best_rmsd") <= num(&soft, "final_rmsd") + 1e-12);
}

#[test]
fn steer_flexible_turns_the_torsions_home_and_settles_free_of_overlaps() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let file = dir.join("6xg5_tmp_prepared.pdb");
    let file = file.to_str().expect("path");
    let args = [
        "steer",
        file,
        "--ligand",
        "TOP",
        "--direction",
        "0,1,0",
        "--response",
        "soft",
        "--flexible",
        "--settle",
        "--json",
    ];
    let v = json(&args);
    assert_eq!(v["flexible"], true);
    assert!(v["torsions"].as_u64().expect("torsions") > 0, "{v}");
    assert_eq!(v["reached"], true, "{v}");
    assert!(v["deepest_overlap"].as_f64().expect("deepest") <= 1.0 + 1e-4);
    let settled = &v["settled"];
    assert_eq!(settled["applied"], true, "{v}");
    assert_eq!(settled["collides"], false, "{v}");
    assert!(settled["rmsd"].as_f64().expect("rmsd") < 2.0, "{v}");
    assert!(settled["score"].as_f64().expect("score") < 0.0, "{v}");
    // Seeded: the same run again is the same, bit for bit.
    let again = json(&args);
    assert_eq!(v["best_rmsd"], again["best_rmsd"]);
    assert_eq!(v["settled"], again["settled"]);
}

/// Soft contacts leave the drug up to the soft limit inside the contact
/// rule; settle after a soft flexible run pushes it out and always ends free
/// of overlaps, from every start the report's dockability table uses, even
/// where the energy alone would hold the drug in the overlap.
#[test]
fn steer_soft_flexible_settles_free_of_overlaps_from_every_direction() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let p = |f: &str| dir.join(f).to_str().expect("path").to_owned();
    let complexes = [
        (p("1s3v_protein.pdb"), vec![p("1s3v_ligand_tqd.sdf")]),
        (p("3nzd.cif"), vec!["--ligand".to_owned(), "D2Q".to_owned()]),
    ];
    for (receptor, drug) in &complexes {
        for (k, d) in bump::rng::sphere_directions(32).iter().enumerate() {
            let direction = format!("{},{},{}", d.x, d.y, d.z);
            let seed = (k + 1).to_string();
            let mut args = vec!["steer", receptor.as_str()];
            args.extend(drug.iter().map(String::as_str));
            args.extend([
                "--direction",
                &direction,
                "--response",
                "soft",
                "--flexible",
                "--settle",
                "--seed",
                &seed,
                "--json",
            ]);
            let v = json(&args);
            let settled = &v["settled"];
            assert_eq!(settled["collides"], false, "{receptor} direction {k}: {v}");
        }
    }
}
