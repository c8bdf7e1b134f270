//! Writing a molecule at a pose: PDB and SDF (V2000).
//!
//! Coordinates are the molecule's atoms placed by a pose — for a docked drug,
//! its pose in the receptor file's frame, so the file lines up with the
//! receptor. Files are written to a temporary name and renamed into place, so
//! a failure never leaves half a file. The loader keeps no bonds, so the SDF's
//! bonds are perceived from distances (single bonds between atoms closer than
//! the sum of their covalent radii plus 0.45 Å); bond orders and dropped
//! hydrogens are not restored.

use std::fmt::Write as _;
use std::path::Path;

use thiserror::Error;

use super::Molecule;
use crate::motion::Pose;

/// A file that could not be written.
#[derive(Debug, Error)]
#[error("{path}: cannot write: {reason}")]
pub struct WriteError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub reason: String,
}

/// Writes `bytes` to `path` through a temporary file in the same folder that
/// is renamed into place, so a failure never leaves a partial file.
///
/// # Errors
/// [`WriteError`] naming the file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let err = |reason: String| WriteError {
        path: path.display().to_string(),
        reason,
    };
    let name = path
        .file_name()
        .ok_or_else(|| err("not a file name".into()))?
        .to_string_lossy()
        .into_owned();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| err(e.to_string()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e.to_string())
    })
}

/// PDB text for `mol` placed by `pose`.
pub fn pdb_text(mol: &Molecule, pose: &Pose) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "REMARK   1 WRITTEN BY BUMP: {}", mol.name);
    for (i, a) in mol.atoms.iter().enumerate() {
        let p = pose.transform_point(mol.local[i].as_dvec3());
        let record = if a.hetero { "HETATM" } else { "ATOM  " };
        // Names of one-letter elements start in column 14, as the format wants.
        let name = if a.name.len() < 4 && a.element.len() == 1 {
            format!(" {:<3}", a.name)
        } else {
            format!("{:<4}", a.name)
        };
        let chain = a.chain.chars().next().unwrap_or(' ');
        let ins = a.insertion.chars().next().unwrap_or(' ');
        let _ = writeln!(
            out,
            "{record}{:>5} {name:.4} {:>3} {chain}{:>4}{ins}   {:>8.3}{:>8.3}{:>8.3}{:>6.2}{:>6.2}          {:>2}",
            a.serial.rem_euclid(100_000),
            a.residue.chars().take(3).collect::<String>(),
            a.seq.rem_euclid(10_000),
            p.x,
            p.y,
            p.z,
            1.0,
            0.0,
            a.element.to_ascii_uppercase()
        );
    }
    out.push_str("END\n");
    out
}

/// Covalent radius for bond perception (Å).
fn covalent(element: &str) -> f64 {
    match element {
        "H" | "D" => 0.31,
        "C" => 0.76,
        "N" => 0.71,
        "O" => 0.66,
        "F" => 0.57,
        "P" => 1.07,
        "S" => 1.05,
        "Cl" => 1.02,
        "Br" => 1.20,
        "I" => 1.39,
        "Se" => 1.20,
        _ => 1.5,
    }
}

/// SDF (V2000) text for `mol` placed by `pose`.
pub fn sdf_text(mol: &Molecule, pose: &Pose) -> String {
    let pos: Vec<_> = (0..mol.len())
        .map(|i| pose.transform_point(mol.local[i].as_dvec3()))
        .collect();
    let mut bonds = Vec::new();
    for i in 0..mol.len() {
        for j in i + 1..mol.len() {
            let limit = covalent(&mol.atoms[i].element) + covalent(&mol.atoms[j].element) + 0.45;
            if (pos[i] - pos[j]).length() < limit {
                bonds.push((i + 1, j + 1));
            }
        }
    }
    let mut out = String::new();
    let _ = writeln!(out, "{}", mol.name);
    let _ = writeln!(out, "  bump      3D");
    let _ = writeln!(
        out,
        "docked pose written by bump (bonds perceived from distances)"
    );
    let _ = writeln!(
        out,
        "{:>3}{:>3}  0  0  0  0  0  0  0  0999 V2000",
        mol.len().min(999),
        bonds.len().min(999)
    );
    for (p, a) in pos.iter().zip(&mol.atoms) {
        let _ = writeln!(
            out,
            "{:>10.4}{:>10.4}{:>10.4} {:<3} 0  0  0  0  0  0  0  0  0  0  0  0",
            p.x, p.y, p.z, a.element
        );
    }
    for (i, j) in &bonds {
        let _ = writeln!(out, "{i:>3}{j:>3}  1  0  0  0  0");
    }
    out.push_str("M  END\n$$$$\n");
    out
}

/// Writes `mol` placed by `pose` as PDB to `path`.
///
/// # Errors
/// [`WriteError`] naming the file.
pub fn write_pdb(mol: &Molecule, pose: &Pose, path: &Path) -> Result<(), WriteError> {
    write_atomically(path, pdb_text(mol, pose).as_bytes())
}

/// Writes `mol` placed by `pose` as SDF to `path`.
///
/// # Errors
/// [`WriteError`] naming the file.
pub fn write_sdf(mol: &Molecule, pose: &Pose, path: &Path) -> Result<(), WriteError> {
    if mol.len() > 999 {
        return Err(WriteError {
            path: path.display().to_string(),
            reason: format!("{} atoms: SDF V2000 holds at most 999", mol.len()),
        });
    }
    write_atomically(path, sdf_text(mol, pose).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{LigandSpec, LoadOptions, load, split_complex, test_data_dir};
    use glam::{DQuat, DVec3};

    #[test]
    fn pdb_and_sdf_round_trip_through_the_readers() {
        let Some(dir) = test_data_dir() else { return };
        let loaded =
            load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default()).expect("load");
        let spec = LigandSpec::parse("TOP").expect("spec");
        let (_, drug) = split_complex(&loaded.structure, &spec).expect("split");
        let pose = Pose::new(
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.8),
            drug.centre + DVec3::new(3.0, -1.0, 2.0),
        );
        let tmp = std::env::temp_dir().join(format!("bump-write-{}", std::process::id()));
        std::fs::create_dir_all(&tmp).expect("tmp");
        let pdb = tmp.join("top.pdb");
        let sdf = tmp.join("top.sdf");
        write_pdb(&drug, &pose, &pdb).expect("pdb");
        write_sdf(&drug, &pose, &sdf).expect("sdf");
        for path in [&pdb, &sdf] {
            let back = load(path, &LoadOptions::default()).expect("read back");
            assert_eq!(back.structure.atoms.len(), drug.len(), "{}", path.display());
            for (i, p) in back.structure.positions.iter().enumerate() {
                let want = pose.transform_point(drug.local[i].as_dvec3());
                assert!((*p - want).length() < 1e-3, "{}: atom {i}", path.display());
                assert_eq!(back.structure.atoms[i].element, drug.atoms[i].element);
            }
        }
        let pdb_back = load(&pdb, &LoadOptions::default()).expect("pdb");
        assert_eq!(pdb_back.structure.atoms[0].name, drug.atoms[0].name);
        assert_eq!(pdb_back.structure.atoms[0].residue, "TOP");
        // Trimethoprim: 21 heavy atoms, 22 bonds (two rings, a CH2 bridge,
        // three methoxy groups, two amines).
        let text = std::fs::read_to_string(&sdf).expect("sdf text");
        let counts = text.lines().nth(3).expect("counts line");
        assert_eq!(counts[3..6].trim(), "22", "{counts}");
        let _ = std::fs::remove_dir_all(&tmp);
    }

    #[test]
    fn unwritable_paths_are_errors_and_leave_nothing() {
        let mol = Molecule::new("x", vec![], &[]);
        let e = write_pdb(&mol, &Pose::IDENTITY, Path::new("/nonexistent/dir/x.pdb"));
        assert!(e.is_err_and(|e| e.to_string().contains("/nonexistent/dir/x.pdb")));
    }
}
