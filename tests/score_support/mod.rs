//! Reading `tests/reference/vina/values.json` (AutoDock Vina 1.2.7's own
//! numbers, see `make_reference.py` beside it) for the scoring tests.

#![allow(dead_code)] // Each test binary uses its own part of this module.

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
pub fn receptor(cx: &Value) -> (Receptor, Vec<DVec3>) {
    let atoms = cx["receptor"]["atoms_near"].as_array().expect("atoms_near");
    let pos: Vec<DVec3> = atoms
        .iter()
        .map(|a| DVec3::new(a[4].as_f64().unwrap(), a[5].as_f64().unwrap(), a[6].as_f64().unwrap()))
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
    let mut names: Vec<String> = v["complexes"].as_object().unwrap().keys().cloned().collect();
    names.sort();
    names
}
