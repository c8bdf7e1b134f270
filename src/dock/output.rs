//! A docking run's poses as files: SDF with the drug's bonds, bond orders
//! and hydrogens as read and the scores as SD tags (`minimizedAffinity`, as
//! smina and gnina write it, then `inter`, `intra`, `rank`), and PDBQT with
//! one `MODEL` per pose and Vina's `REMARK VINA RESULT` line, in the atom
//! order the PDBQT writer gives (the input's tree, node by node), so that
//! Vina's own tools read it.

use std::fmt::Write as _;

use glam::DVec3;

use super::DockedPose;
use crate::chem::symmetry::rmsd_over;
use crate::model::Molecule;
use crate::model::write::{pdbqt_text, sdf_text};
use crate::motion::Pose;
use crate::score::Ligand;
use crate::score::settle::settled_molecule;

/// The drug at `pose`'s torsions, and its world pose, for a receptor whose
/// centre (file coordinates) is `receptor_centre`.
pub fn posed(
    drug: &Molecule,
    lig: &Ligand,
    pose: &DockedPose,
    receptor_centre: DVec3,
) -> (Molecule, Pose) {
    let mol = settled_molecule(drug, lig, &pose.conf.torsions);
    let world = Pose::from_translation(receptor_centre).compose(&pose.conf.pose);
    (mol, world)
}

/// One SDF record of `pose`, its scores as SD tags.
pub fn sdf_record(
    drug: &Molecule,
    lig: &Ligand,
    pose: &DockedPose,
    receptor_centre: DVec3,
) -> String {
    let (mol, world) = posed(drug, lig, pose, receptor_centre);
    let text = sdf_text(&mol, &world);
    let body = text.strip_suffix("$$$$\n").unwrap_or(&text);
    let mut out = body.to_string();
    for (tag, value) in [
        ("minimizedAffinity", format!("{:.3}", pose.total)),
        ("inter", format!("{:.3}", pose.energies.inter)),
        ("intra", format!("{:.3}", pose.energies.intra)),
        ("rank", pose.rank.to_string()),
    ] {
        let _ = write!(out, "> <{tag}>\n{value}\n\n");
    }
    out.push_str("$$$$\n");
    out
}

/// The PDBQT models of `poses` (`MODEL k` … `ENDMDL`), each with Vina's
/// result line: the total and the RMSD to the first pose, symmetry-aware
/// (`swaps`) then plain. `None` when the drug was not read from a PDBQT
/// (it has no AutoDock types to write).
pub fn pdbqt_models(
    drug: &Molecule,
    lig: &Ligand,
    poses: &[DockedPose],
    swaps: &[Vec<u32>],
    receptor_centre: DVec3,
) -> Option<String> {
    let mut out = String::new();
    let first = poses.first()?;
    for p in poses {
        let (mol, world) = posed(drug, lig, p, receptor_centre);
        let text = pdbqt_text(&mol, &world)?;
        let lb = rmsd_over(swaps, &first.atoms, &p.atoms);
        let ub = crate::score::settle::rmsd(&first.atoms, &p.atoms);
        let _ = writeln!(out, "MODEL {}", p.rank);
        let _ = writeln!(
            out,
            "REMARK VINA RESULT: {:>9.3} {:>10.3} {:>10.3}",
            p.total, lb, ub
        );
        out.push_str(&text);
        if !text.ends_with('\n') {
            out.push('\n');
        }
        out.push_str("ENDMDL\n");
    }
    Some(out)
}
