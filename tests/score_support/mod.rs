//! Reading `tests/reference/vina/values.json` (AutoDock Vina 1.2.7's own
//! numbers, see `make_reference.py` beside it) for the scoring tests.

#![allow(dead_code)] // Each test binary uses its own part of this module.
#![allow(clippy::unwrap_used)] // A malformed reference file should fail the test loudly.

use std::collections::HashMap;
use std::path::PathBuf;

use bump::score::{Fragment, Ligand, Receptor, XsType};
use glam::DVec3;
use serde_json::Value;

/// The reference file.
pub fn values() -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/vina/values.json");
    let text = std::fs::read_to_string(&path).expect("values.json is committed");
    serde_json::from_str(&text).expect("values.json parses")
}

/// Three numbers as a vector.
pub fn vec3(v: &Value) -> DVec3 {
    DVec3::new(
        v[0].as_f64().expect("x"),
        v[1].as_f64().expect("y"),
        v[2].as_f64().expect("z"),
    )
}

/// The X-Score type Vina recorded.
pub fn xs(v: &Value) -> XsType {
    XsType::from_name(v.as_str().expect("a type name")).expect("a known type")
}

/// The receptor atoms Vina scored against (every heavy atom within 8 Å of
/// any pose), with Vina's types, in the file's frame.
pub fn receptor_from_values(cx: &Value) -> (Receptor, Vec<DVec3>) {
    let atoms = cx["receptor"]["atoms_near"].as_array().expect("atoms_near");
    let pos: Vec<DVec3> = atoms
        .iter()
        .map(|a| {
            DVec3::new(
                a[4].as_f64().unwrap(),
                a[5].as_f64().unwrap(),
                a[6].as_f64().unwrap(),
            )
        })
        .collect();
    let types: Vec<Option<XsType>> = atoms.iter().map(|a| Some(xs(&a[8]))).collect();
    let charges: Vec<f64> = atoms.iter().map(|a| a[9].as_f64().unwrap()).collect();
    (Receptor::new(&pos, &types, &charges), pos)
}

/// The torsion tree of the ligand's PDBQT: one fragment per `ROOT` and
/// `BRANCH`, heavy atoms only (indices into `heavy_atoms`).
pub fn fragments(cx: &Value) -> Vec<Fragment> {
    let lig = &cx["ligand"];
    let heavy = lig["heavy_atoms"].as_array().unwrap();
    let by_serial: HashMap<i64, u32> = heavy
        .iter()
        .enumerate()
        .map(|(i, a)| (a[7].as_i64().unwrap(), i as u32))
        .collect();
    let mut frags: Vec<Fragment> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    for line in lig["pdbqt"].as_array().unwrap() {
        let line = line.as_str().unwrap();
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first().copied() {
            Some("ROOT") => {
                frags.push(Fragment {
                    parent: None,
                    bond: None,
                    atoms: vec![],
                });
                stack.push(frags.len() - 1);
            }
            Some("BRANCH") => {
                let a: i64 = words[1].parse().unwrap();
                let b: i64 = words[2].parse().unwrap();
                let parent = *stack.last().unwrap();
                frags.push(Fragment {
                    parent: Some(parent as u32),
                    bond: Some([by_serial[&a], by_serial[&b]]),
                    atoms: vec![],
                });
                stack.push(frags.len() - 1);
            }
            Some("ENDBRANCH") => {
                stack.pop();
            }
            Some("ATOM") | Some("HETATM") => {
                let serial: i64 = line[6..11].trim().parse().unwrap();
                if let Some(&i) = by_serial.get(&serial) {
                    frags[*stack.last().unwrap()].atoms.push(i);
                }
            }
            _ => {}
        }
    }
    frags
}

/// The ligand at one pose's coordinates (as Vina read them), with Vina's
/// types, tree, pairs and torsion count; its frame is the file's.
pub fn ligand_at(cx: &Value, xyz: &[DVec3]) -> Ligand {
    let lig = &cx["ligand"];
    let heavy = lig["heavy_atoms"].as_array().unwrap();
    let types: Vec<Option<XsType>> = heavy.iter().map(|a| Some(xs(&a[5]))).collect();
    let charges: Vec<f64> = heavy.iter().map(|a| a[6].as_f64().unwrap()).collect();
    let pairs: Vec<[u32; 2]> = lig["intra_pairs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [p[0].as_u64().unwrap() as u32, p[1].as_u64().unwrap() as u32])
        .collect();
    Ligand::from_parts(
        xyz.to_vec(),
        fragments(cx),
        &types,
        charges,
        &pairs,
        lig["vina_num_tors"].as_f64().unwrap(),
    )
    .expect("the reference tree is valid")
}

/// A pose's ligand heavy-atom coordinates as Vina scored them.
pub fn pose_xyz(pose: &Value) -> Vec<DVec3> {
    pose["ligand_heavy_xyz_as_scored"]
        .as_array()
        .unwrap()
        .iter()
        .map(vec3)
        .collect()
}

/// Sorted complex names.
pub fn complex_names(v: &Value) -> Vec<String> {
    let mut names: Vec<String> = v["complexes"]
        .as_object()
        .unwrap()
        .keys()
        .cloned()
        .collect();
    names.sort();
    names
}

/// The shared complexes of the reference and how they are loaded, shared
/// with the report's settle rates.
pub use bump_testkit::vina_reference::{COMPLEXES, load_complex};

/// `../shared/pdb`, or `None` (with a message) when it is absent outside CI.
pub fn shared_pdb() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/pdb");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "../shared/pdb is missing (required under CI=true)"
    );
    eprintln!("skipping: ../shared/pdb is missing");
    None
}

/// A pose of the reference as a relative pose of bump's drug against
/// bump's receptor: `x' = c + R(x − c) + shift` about the recorded centroid.
pub fn relative_pose(
    pose: &Value,
    receptor: &bump::model::Molecule,
    drug: &bump::model::Molecule,
) -> bump::motion::Pose {
    let t = &pose["transform"];
    let c = vec3(&t["centroid"]);
    let axis = vec3(&t["axis"]).normalize_or_zero();
    let angle = t["angle_deg"].as_f64().unwrap().to_radians();
    let rot = if axis == DVec3::ZERO {
        glam::DQuat::IDENTITY
    } else {
        glam::DQuat::from_axis_angle(axis, angle)
    };
    let shift = vec3(&t["shift"]);
    bump::motion::Pose::new(rot, c + rot * (drug.centre - c) + shift - receptor.centre)
}

/// A position rounded to the file's 3 decimals, to match atoms.
pub fn key(p: DVec3) -> (i64, i64, i64) {
    (
        (p.x * 1000.0).round() as i64,
        (p.y * 1000.0).round() as i64,
        (p.z * 1000.0).round() as i64,
    )
}
