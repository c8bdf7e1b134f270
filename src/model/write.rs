//! Writing a molecule at a pose: PDB, SDF (V2000, or V3000 past 999 atoms
//! or bonds), and PDBQT for a molecule read from one ([`pdbqt_text`]).
//!
//! Coordinates are the molecule's atoms placed by a pose — for a docked drug,
//! its pose in the receptor file's frame, so the file lines up with the
//! receptor. The file's hydrogens are written too, placed by the same pose,
//! in the file's order, with their names. Atom names are written as read.
//! Bonds are the molecule's real bonds: the file's own, with their orders,
//! when it stated them all (an SDF), otherwise the perceived ones
//! ([`crate::chem`]) with their Kekulé orders; each hydrogen is bonded to
//! its heavy atom. A PDB file gets `CONECT` records for the bonds of hetero
//! atoms. Files are written to a temporary name and renamed into place, so a
//! failure never leaves half a file.

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;
use thiserror::Error;

use super::{AtomInfo, BondOrder, Molecule};
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

/// One atom to write: a heavy atom or a kept hydrogen.
#[derive(Clone, Copy)]
enum Entry {
    Heavy(usize),
    Hydrogen(usize),
}

/// Heavy atoms and hydrogens in the file's order.
fn file_order(mol: &Molecule) -> Vec<Entry> {
    let h = &mol.hydrogens;
    let mut out = Vec::with_capacity(mol.len() + h.len());
    let mut next_h = 0;
    // Hydrogens are kept in file order, so their `before` never decreases
    // in a file; sort anyway so an odd input still writes every atom once.
    let mut hs: Vec<usize> = (0..h.len()).collect();
    hs.sort_by_key(|&k| (h.before[k], k));
    for i in 0..mol.len() {
        while next_h < hs.len() && (h.before[hs[next_h]] as usize) <= i {
            out.push(Entry::Hydrogen(hs[next_h]));
            next_h += 1;
        }
        out.push(Entry::Heavy(i));
    }
    out.extend(hs[next_h..].iter().map(|&k| Entry::Hydrogen(k)));
    out
}

/// The bonds to write, as positions in `order` with the order: the file's
/// bonds when it stated them all, else the perceived ones; hydrogens bonded
/// to their heavy atoms.
fn written_bonds(mol: &Molecule, order: &[Entry]) -> Vec<(usize, usize, BondOrder)> {
    let mut slot_heavy = vec![0usize; mol.len()];
    let mut slot_h = vec![0usize; mol.hydrogens.len()];
    for (k, e) in order.iter().enumerate() {
        match *e {
            Entry::Heavy(i) => slot_heavy[i] = k,
            Entry::Hydrogen(h) => slot_h[h] = k,
        }
    }
    let heavy: Vec<(u32, u32, BondOrder)> = if mol.bonds_complete {
        mol.file_bonds.iter().map(|b| (b.a, b.b, b.order)).collect()
    } else {
        mol.chemistry()
            .bonds
            .iter()
            .map(|b| (b.a, b.b, b.order))
            .collect()
    };
    let mut out: Vec<(usize, usize, BondOrder)> = heavy
        .into_iter()
        .filter(|&(a, b, _)| (a as usize) < mol.len() && (b as usize) < mol.len())
        .map(|(a, b, o)| (slot_heavy[a as usize], slot_heavy[b as usize], o))
        .collect();
    for (h, &p) in mol.hydrogens.parent.iter().enumerate() {
        if (p as usize) < mol.len() {
            out.push((slot_heavy[p as usize], slot_h[h], BondOrder::Single));
        }
    }
    for b in &mut out {
        if b.0 > b.1 {
            std::mem::swap(&mut b.0, &mut b.1);
        }
    }
    out.sort_unstable_by_key(|b| (b.0, b.1));
    out
}

/// The placed position of an entry.
fn placed(mol: &Molecule, pose: &Pose, e: Entry) -> DVec3 {
    match e {
        Entry::Heavy(i) => pose.transform_point(mol.local[i].as_dvec3()),
        Entry::Hydrogen(h) => pose.transform_point(mol.hydrogens.local[h].as_dvec3()),
    }
}

/// Columns 1–66 of a PDB (or PDBQT) atom record for atom `a` (or one of
/// its hydrogens, named `name`): record name, serial, name, residue, chain,
/// number, insertion code, position `p`, occupancy 1 and temperature
/// factor 0.
fn atom_columns(out: &mut String, a: &AtomInfo, serial: i64, name: &str, element: &str, p: DVec3) {
    let record = if a.hetero { "HETATM" } else { "ATOM  " };
    // Names of one-letter elements start in column 14, as the format wants.
    let name = if name.len() < 4 && element.len() == 1 {
        format!(" {name:<3}")
    } else {
        format!("{name:<4}")
    };
    let chain = a.chain.chars().next().unwrap_or(' ');
    let ins = a.insertion.chars().next().unwrap_or(' ');
    let _ = write!(
        out,
        "{record}{serial:>5} {name:.4} {:>3} {chain}{:>4}{ins}   {:>8.3}{:>8.3}{:>8.3}{:>6.2}{:>6.2}",
        a.residue.chars().take(3).collect::<String>(),
        a.seq.rem_euclid(10_000),
        p.x,
        p.y,
        p.z,
        1.0,
        0.0,
    );
}

/// PDB text for `mol` placed by `pose`: its atoms and hydrogens in the
/// file's order, then `CONECT` records for the bonds of hetero atoms.
pub fn pdb_text(mol: &Molecule, pose: &Pose) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "REMARK   1 WRITTEN BY BUMP: {}", mol.name);
    let order = file_order(mol);
    let mut serials = Vec::with_capacity(order.len());
    let mut hetero = Vec::with_capacity(order.len());
    for &e in &order {
        let (a, name, serial, element, charge) = match e {
            Entry::Heavy(i) => {
                let a = &mol.atoms[i];
                let q = mol.formal_charges.get(i).copied().unwrap_or(0);
                (a, a.name.as_str(), a.serial, a.element.as_str(), q)
            }
            Entry::Hydrogen(h) => {
                let p = mol.hydrogens.parent[h] as usize;
                let Some(a) = mol.atoms.get(p) else { continue };
                (a, mol.hydrogens.name(h), mol.hydrogens.serial[h], "H", 0)
            }
        };
        // Columns 79-80 as the format writes a charge (`1-`, `2+`), so the
        // file reads back with the chemistry it was written from.
        let charge = match charge {
            0 => String::new(),
            q => format!("{}{}", q.unsigned_abs(), if q > 0 { '+' } else { '-' }),
        };
        let serial = serial.rem_euclid(100_000);
        serials.push(serial);
        hetero.push(a.hetero);
        atom_columns(&mut out, a, serial, name, element, placed(mol, pose, e));
        let _ = writeln!(out, "          {:>2}{charge}", element.to_ascii_uppercase());
    }
    // CONECT: each hetero atom's bonded partners, four to a record.
    let bonds = written_bonds(mol, &order);
    let mut partners: Vec<Vec<i64>> = vec![Vec::new(); order.len()];
    for &(a, b, _) in &bonds {
        if hetero.get(a).copied().unwrap_or(false) || hetero.get(b).copied().unwrap_or(false) {
            partners[a].push(serials[b]);
            partners[b].push(serials[a]);
        }
    }
    for (k, list) in partners.iter().enumerate() {
        for chunk in list.chunks(4) {
            let _ = write!(out, "CONECT{:>5}", serials[k]);
            for s in chunk {
                let _ = write!(out, "{s:>5}");
            }
            out.push('\n');
        }
    }
    out.push_str("END\n");
    out
}

/// The MDL bond type of an order.
fn mdl_type(order: BondOrder) -> u8 {
    match order {
        BondOrder::Single => 1,
        BondOrder::Double => 2,
        BondOrder::Triple => 3,
        BondOrder::Aromatic => 4,
        BondOrder::Unspecified => 8,
    }
}

/// SDF text for `mol` placed by `pose`: V2000, or V3000 when it has more
/// than 999 atoms or bonds.
pub fn sdf_text(mol: &Molecule, pose: &Pose) -> String {
    let order = file_order(mol);
    let bonds = written_bonds(mol, &order);
    let element = |e: Entry| match e {
        Entry::Heavy(i) => mol.atoms[i].element.as_str(),
        Entry::Hydrogen(_) => "H",
    };
    let charge = |e: Entry| match e {
        Entry::Heavy(i) => mol.formal_charges.get(i).copied().unwrap_or(0),
        Entry::Hydrogen(_) => 0,
    };
    let mut out = String::new();
    let _ = writeln!(out, "{}", mol.name.lines().next().unwrap_or(""));
    let _ = writeln!(out, "  bump      3D");
    let _ = writeln!(out, "docked pose written by bump");
    if order.len() > 999 || bonds.len() > 999 {
        let _ = writeln!(out, "  0  0  0     0  0            999 V3000");
        let _ = writeln!(out, "M  V30 BEGIN CTAB");
        let _ = writeln!(out, "M  V30 COUNTS {} {} 0 0 0", order.len(), bonds.len());
        let _ = writeln!(out, "M  V30 BEGIN ATOM");
        for (k, &e) in order.iter().enumerate() {
            let p = placed(mol, pose, e);
            let q = charge(e);
            let chg = if q != 0 {
                format!(" CHG={q}")
            } else {
                String::new()
            };
            let _ = writeln!(
                out,
                "M  V30 {} {} {:.4} {:.4} {:.4} 0{chg}",
                k + 1,
                element(e),
                p.x,
                p.y,
                p.z
            );
        }
        let _ = writeln!(out, "M  V30 END ATOM");
        let _ = writeln!(out, "M  V30 BEGIN BOND");
        for (k, &(a, b, o)) in bonds.iter().enumerate() {
            let _ = writeln!(out, "M  V30 {} {} {} {}", k + 1, mdl_type(o), a + 1, b + 1);
        }
        let _ = writeln!(out, "M  V30 END BOND");
        let _ = writeln!(out, "M  V30 END CTAB");
    } else {
        let _ = writeln!(
            out,
            "{:>3}{:>3}  0  0  0  0  0  0  0  0999 V2000",
            order.len(),
            bonds.len()
        );
        for &e in &order {
            let p = placed(mol, pose, e);
            let _ = writeln!(
                out,
                "{:>10.4}{:>10.4}{:>10.4} {:<3} 0  0  0  0  0  0  0  0  0  0  0  0",
                p.x,
                p.y,
                p.z,
                element(e)
            );
        }
        for &(a, b, o) in &bonds {
            let _ = writeln!(
                out,
                "{:>3}{:>3}{:>3}  0  0  0  0",
                a + 1,
                b + 1,
                mdl_type(o)
            );
        }
        let charged: Vec<(usize, i8)> = order
            .iter()
            .enumerate()
            .filter_map(|(k, &e)| (charge(e) != 0).then_some((k + 1, charge(e))))
            .collect();
        for chunk in charged.chunks(8) {
            let _ = write!(out, "M  CHG{:>3}", chunk.len());
            for (k, q) in chunk {
                let _ = write!(out, " {k:>3} {q:>3}");
            }
            out.push('\n');
        }
    }
    out.push_str("M  END\n$$$$\n");
    out
}

/// PDBQT text for `mol` placed by `pose`, for a molecule read from a PDBQT
/// file: each atom with the AutoDock type and charge the file gave it, and,
/// when the file had a torsion tree, the tree of the molecule's rotatable
/// bonds (`ROOT`, nested `BRANCH` records, `TORSDOF`), so that AutoDock Vina
/// reads back what bump scored. Atoms are numbered afresh in the order
/// written (each node's atoms in the file's order, a branch's axis atom
/// first). `None` for a molecule without AutoDock types (another format:
/// its polar hydrogens may not be in the file, and Vina needs them placed;
/// prepare it with Meeko or Open Babel). A macrocycle Meeko opened is
/// written as bump holds it: without its `G` pseudo-atoms and with its ring
/// rigid, so Vina reads fewer torsions from it than from the original file.
pub fn pdbqt_text(mol: &Molecule, pose: &Pose) -> Option<String> {
    let ad = mol.autodock.as_ref()?;
    if ad.atoms.len() != mol.len() || ad.hydrogens.len() != mol.hydrogens.len() {
        return None;
    }
    let order = file_order(mol);
    let mut rank_heavy = vec![0usize; mol.len()];
    let mut rank_h = vec![0usize; mol.hydrogens.len()];
    for (k, e) in order.iter().enumerate() {
        match *e {
            Entry::Heavy(i) => rank_heavy[i] = k,
            Entry::Hydrogen(h) => rank_h[h] = k,
        }
    }
    let mut out = String::new();
    let _ = writeln!(out, "REMARK  Name = {}", mol.name);
    let _ = writeln!(out, "REMARK  written by bump, in the receptor's frame");
    // One atom record numbered `serial`; false for a hydrogen without its
    // heavy atom (not written).
    let line = |out: &mut String, e: Entry, serial: usize| -> bool {
        let (a, name, ad_atom) = match e {
            Entry::Heavy(i) => (&mol.atoms[i], mol.atoms[i].name.as_str(), ad.atoms[i]),
            Entry::Hydrogen(h) => {
                let p = mol.hydrogens.parent[h] as usize;
                let Some(a) = mol.atoms.get(p) else {
                    return false;
                };
                (a, mol.hydrogens.name(h), ad.hydrogens[h])
            }
        };
        let element = ad_atom.ad.element().unwrap_or("X");
        let serial = i64::try_from(serial % 100_000).unwrap_or(0);
        atom_columns(out, a, serial, name, element, placed(mol, pose, e));
        // Columns 71-76 the charge, 78-79 the type.
        let _ = writeln!(out, "    {:>+6.3} {}", ad_atom.charge, ad_atom.ad.name());
        true
    };
    let mut serial_of = vec![0usize; mol.len()];
    let mut next = 1usize;
    let mut atom_line = |out: &mut String, e: Entry, serial_of: &mut [usize]| {
        if line(out, e, next) {
            if let Entry::Heavy(i) = e {
                serial_of[i] = next;
            }
            next += 1;
        }
    };
    if !ad.tree {
        // A rigid molecule (a receptor): its atoms as they were.
        for &e in &order {
            atom_line(&mut out, e, &mut serial_of);
        }
        return Some(out);
    }
    let tree = &mol.chemistry().torsions;
    // A node's members in the file's order, `first` (a branch's axis atom)
    // before the rest.
    let members = |n: usize, first: Option<u32>| -> Vec<Entry> {
        let node = &tree.nodes[n];
        let mut m: Vec<(usize, Entry)> = node
            .atoms
            .iter()
            .map(|&i| (rank_heavy[i as usize], Entry::Heavy(i as usize)))
            .chain(
                node.hydrogens
                    .iter()
                    .map(|&h| (rank_h[h as usize], Entry::Hydrogen(h as usize))),
            )
            .collect();
        m.sort_by_key(|&(r, e)| (!matches!(e, Entry::Heavy(i) if Some(i as u32) == first), r));
        m.into_iter().map(|(_, e)| e).collect()
    };
    out.push_str("ROOT\n");
    let roots: Vec<usize> = (0..tree.nodes.len())
        .filter(|&n| tree.nodes[n].parent.is_none())
        .collect();
    for &r in &roots {
        for e in members(r, None) {
            atom_line(&mut out, e, &mut serial_of);
        }
    }
    out.push_str("ENDROOT\n");
    // Depth first: (node, entering) pairs, a branch closed when left.
    let mut branch = String::new();
    let mut stack: Vec<(usize, bool)> = roots
        .iter()
        .rev()
        .flat_map(|&r| {
            tree.nodes[r]
                .children
                .iter()
                .rev()
                .map(|&c| (c as usize, true))
        })
        .collect();
    while let Some((n, entering)) = stack.pop() {
        let Some(b) = tree.nodes[n].bond.and_then(|b| tree.bonds.get(b as usize)) else {
            continue;
        };
        if entering {
            let from = serial_of[b.parent_atom as usize];
            let mut first = true;
            for e in members(n, Some(b.child_atom)) {
                atom_line(&mut branch, e, &mut serial_of);
                if first {
                    // The axis atom leads (members puts it first).
                    let _ = writeln!(
                        out,
                        "BRANCH {from:>3} {:>3}",
                        serial_of[b.child_atom as usize]
                    );
                    first = false;
                }
                out.push_str(&branch);
                branch.clear();
            }
            stack.push((n, false));
            for &c in tree.nodes[n].children.iter().rev() {
                stack.push((c as usize, true));
            }
        } else {
            let _ = writeln!(
                out,
                "ENDBRANCH {:>3} {:>3}",
                serial_of[b.parent_atom as usize], serial_of[b.child_atom as usize]
            );
        }
    }
    let _ = writeln!(out, "TORSDOF {}", tree.bonds.len());
    Some(out)
}

/// Writes `mol` placed by `pose` as PDBQT to `path` ([`pdbqt_text`]).
///
/// # Errors
/// [`WriteError`] naming the file, also for a molecule that has no
/// AutoDock types to write.
pub fn write_pdbqt(mol: &Molecule, pose: &Pose, path: &Path) -> Result<(), WriteError> {
    let text = pdbqt_text(mol, pose).ok_or_else(|| WriteError {
        path: path.display().to_string(),
        reason: "PDBQT is written only for a molecule read from a PDBQT file (its AutoDock \
                 types and charges); write SDF and prepare it with Meeko or Open Babel"
            .into(),
    })?;
    write_atomically(path, text.as_bytes())
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
    write_atomically(path, sdf_text(mol, pose).as_bytes())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

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
        // Trimethoprim: 21 heavy atoms, 22 bonds between them (two rings, a
        // CH2 bridge, three methoxy groups, two amines), and 18 hydrogens.
        let text = std::fs::read_to_string(&sdf).expect("sdf text");
        let counts = text.lines().nth(3).expect("counts line");
        assert_eq!(counts[0..3].trim(), "39", "{counts}");
        assert_eq!(counts[3..6].trim(), "40", "{counts}");
        let _ = std::fs::remove_dir_all(&tmp);
    }

    /// Reads `text` as SDF keeping hydrogens.
    fn sdf_back(text: &str) -> crate::model::Structure {
        let keep = LoadOptions {
            hydrogens: crate::model::Hydrogens::Keep,
            ..LoadOptions::default()
        };
        crate::model::sdf::parse_sdf(text, "back.sdf", &keep)
            .expect("read back")
            .structure
    }

    #[test]
    fn shared_sdfs_round_trip_at_the_identity_pose() {
        let Some(dir) = test_data_dir() else { return };
        let keep = LoadOptions {
            hydrogens: crate::model::Hydrogens::Keep,
            ..LoadOptions::default()
        };
        for file in [
            "trimethoprim_top_6xg5pose.sdf",
            "methotrexate_mtx_ideal.sdf",
            "benzamidine_3ptb.sdf",
            "1s3v_ligand_tqd.sdf",
        ] {
            let original = load(&dir.join(file), &keep).expect(file).structure;
            let loaded = load(&dir.join(file), &LoadOptions::default()).expect(file);
            let mol = crate::model::receptor_only(&loaded.structure).expect(file);
            let pose = Pose::new(DQuat::IDENTITY, mol.centre);
            let back = sdf_back(&sdf_text(&mol, &pose));
            assert_eq!(back.atoms.len(), original.atoms.len(), "{file}");
            for (i, (a, b)) in original.atoms.iter().zip(&back.atoms).enumerate() {
                assert_eq!(
                    (&a.name, &a.element),
                    (&b.name, &b.element),
                    "{file} atom {i}"
                );
                let d = (original.positions[i] - back.positions[i])
                    .abs()
                    .max_element();
                assert!(d <= 1e-4, "{file} atom {i}: {d}");
            }
            assert_eq!(back.bonds, original.bonds, "{file}: bonds and orders");
            assert_eq!(
                back.file_chem.formal_charges, original.file_chem.formal_charges,
                "{file}: charges"
            );
        }
    }

    #[test]
    fn the_6xg5_ligand_round_trips_through_pdb() {
        let Some(dir) = test_data_dir() else { return };
        let keep = LoadOptions {
            hydrogens: crate::model::Hydrogens::Keep,
            ..LoadOptions::default()
        };
        let spec = LigandSpec::parse("TOP").expect("spec");
        let path = dir.join("6xg5_tmp_prepared.pdb");
        let full = load(&path, &keep).expect("load").structure;
        let (_, with_h) = split_complex(&full, &spec).expect("split");
        let (_, drug) = split_complex(
            &load(&path, &LoadOptions::default())
                .expect("load")
                .structure,
            &spec,
        )
        .expect("split");
        assert_eq!(drug.hydrogens.len(), 18);
        let pose = Pose::new(DQuat::IDENTITY, drug.centre);
        let tmp = std::env::temp_dir().join(format!("bump-top-{}.pdb", std::process::id()));
        write_pdb(&drug, &pose, &tmp).expect("write");
        let text = std::fs::read_to_string(&tmp).expect("text");
        let back = load(&tmp, &keep).expect("read back").structure;
        let _ = std::fs::remove_file(&tmp);
        assert_eq!(back.atoms.len(), with_h.len());
        for (i, (a, b)) in with_h.atoms.iter().zip(&back.atoms).enumerate() {
            assert_eq!(
                (&a.name, &a.element, a.serial),
                (&b.name, &b.element, b.serial),
                "atom {i}"
            );
            let d = (with_h.file_position(i) - back.positions[i])
                .abs()
                .max_element();
            assert!(d <= 1e-3, "atom {i}: {d}");
        }
        // CONECT records: every heavy bond and every hydrogen's bond, both ways.
        let conect = text.lines().filter(|l| l.starts_with("CONECT")).count();
        assert!(conect >= 39, "{conect} CONECT records");
        // The same bonds and orders are perceived from the written file.
        let again = crate::model::receptor_only(&load_text_as_pdb(&text)).expect("molecule");
        assert_eq!(again.chemistry().bonds, drug.chemistry().bonds);
    }

    /// A drug read with charges (benzoate's `1-`) is written with them, and
    /// reads back as the same anion.
    #[test]
    fn formal_charges_round_trip_through_pdb() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let path = dir.join("tests/data/perception/benzoate.pdb");
        let loaded = load(&path, &LoadOptions::default()).expect("load");
        let drug = crate::model::receptor_only(&loaded.structure).expect("molecule");
        assert!(
            drug.formal_charges.contains(&-1),
            "{:?}",
            drug.formal_charges
        );
        let text = pdb_text(&drug, &Pose::new(DQuat::IDENTITY, drug.centre));
        assert!(
            text.lines()
                .any(|l| l.starts_with("HETATM") && l.ends_with(" O1-")),
            "{text}"
        );
        let again = crate::model::receptor_only(&load_text_as_pdb(&text)).expect("molecule");
        assert_eq!(again.formal_charges, drug.formal_charges);
        assert_eq!(again.chemistry().xs, drug.chemistry().xs);
    }

    /// Loads PDB text through a temporary file.
    fn load_text_as_pdb(text: &str) -> crate::model::Structure {
        let tmp = std::env::temp_dir().join(format!("bump-again-{}.pdb", std::process::id()));
        std::fs::write(&tmp, text).expect("write");
        let s = load(&tmp, &LoadOptions::default()).expect("load").structure;
        let _ = std::fs::remove_file(&tmp);
        s
    }

    #[test]
    fn large_molecules_are_written_as_v3000() {
        let Some(dir) = test_data_dir() else { return };
        let s = load(&dir.join("1ubq.pdb"), &LoadOptions::default())
            .expect("1ubq")
            .structure;
        let rec = crate::model::receptor_only(&s).expect("receptor");
        // Ubiquitin's 602 atoms fit V2000; DHFR's 2577 do not.
        let pose = Pose::new(DQuat::IDENTITY, rec.centre);
        let text = sdf_text(&rec, &pose);
        assert!(text.lines().nth(3).is_some_and(|l| l.ends_with("V2000")));
        let s = load(&dir.join("4dfr.pdb"), &LoadOptions::default())
            .expect("4dfr")
            .structure;
        let rec = crate::model::receptor_only(&s).expect("receptor");
        let pose = Pose::new(DQuat::IDENTITY, rec.centre);
        let text = sdf_text(&rec, &pose);
        assert!(text.lines().nth(3).is_some_and(|l| l.ends_with("V3000")));
        let back = sdf_back(&text);
        assert_eq!(back.atoms.len(), rec.len());
        assert_eq!(back.bonds.len(), rec.chemistry().bonds.len());
        for (b, c) in back.bonds.iter().zip(&rec.chemistry().bonds) {
            assert_eq!((b.a, b.b, b.order), (c.a as usize, c.b as usize, c.order));
        }
    }

    #[test]
    fn unwritable_paths_are_errors_and_leave_nothing() {
        let mol = Molecule::new("x", vec![], &[]);
        let e = write_pdb(&mol, &Pose::IDENTITY, Path::new("/nonexistent/dir/x.pdb"));
        assert!(e.is_err_and(|e| e.to_string().contains("/nonexistent/dir/x.pdb")));
    }

    /// Each file of `tests/data/pdbqt` written back as PDBQT (its models
    /// too) reads as the same atoms, AutoDock types, charges, rotatable
    /// bonds and Vina types, with the tree written in nested branches.
    #[test]
    fn pdbqt_files_round_trip() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pdbqt");
        let read = |path: &Path, text: Option<&str>, model: usize| {
            let opts = LoadOptions {
                sdf_record: Some(model),
                ..Default::default()
            };
            let loaded = match text {
                None => load(path, &opts).unwrap(),
                Some(t) => {
                    let mut l = crate::model::pdbqt::parse_pdbqt(t, "back", "back", &opts).unwrap();
                    crate::model::set_hydrogens_apart(&mut l.structure);
                    l
                }
            };
            crate::model::receptor_only(&loaded.structure).unwrap()
        };
        // (name, residue number) -> (position, type, charge, Vina type).
        let summary = |m: &Molecule| {
            let c = m.chemistry();
            let ad = m.autodock.as_ref().unwrap();
            let mut v: Vec<_> = (0..m.len())
                .map(|i| {
                    let a = &m.atoms[i];
                    let p = m.file_position(i);
                    (
                        format!("{} {} {}", a.chain, a.seq, a.name),
                        [p.x, p.y, p.z].map(|x| (x * 1000.0).round() as i64),
                        ad.atoms[i].ad,
                        (f64::from(ad.atoms[i].charge) * 1000.0).round() as i64,
                        c.xs[i],
                    )
                })
                .collect();
            v.sort_by(|a, b| (&a.0, a.1).cmp(&(&b.0, b.1)));
            let mut hd: Vec<_> = ad
                .hydrogens
                .iter()
                .map(|h| (h.ad.name(), (f64::from(h.charge) * 1000.0).round() as i64))
                .collect();
            hd.sort_unstable();
            (v, hd, c.torsions.bonds.len(), c.vina_torsion_count())
        };
        let mut files = 0;
        for (name, model) in [
            ("receptor.pdbqt", 1),
            ("lig1_meeko.pdbqt", 1),
            ("lig1_obabel.pdbqt", 1),
            ("lig2_obabel.pdbqt", 1),
            ("lig3_meeko.pdbqt", 1),
            ("dock_out.pdbqt", 3),
        ] {
            let path = dir.join(name);
            let mol = read(&path, None, model);
            let text = pdbqt_text(&mol, &Pose::from_translation(mol.centre)).unwrap();
            let tree = mol.autodock.as_ref().unwrap().tree;
            assert_eq!(text.contains("ROOT"), tree, "{name}");
            let turned = if tree {
                mol.chemistry().torsions.bonds.len()
            } else {
                0
            };
            assert_eq!(text.matches("\nBRANCH").count(), turned, "{name}");
            let back = read(&path, Some(&text), 1);
            assert_eq!(summary(&back), summary(&mol), "{name}");
            files += 1;
        }
        assert_eq!(files, 6);
        // Another format has no AutoDock types to write.
        let plain = Molecule::new(
            "x",
            vec![crate::model::molecule::test_carbon(1)],
            &[DVec3::ZERO],
        );
        assert!(pdbqt_text(&plain, &Pose::IDENTITY).is_none());
    }
}
