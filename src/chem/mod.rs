//! Chemistry of a molecule: bonds, bond orders and aromaticity, hydrogen
//! counts, AutoDock Vina's atom types, rotatable bonds and the torsion
//! tree, and Gasteiger partial charges.
//!
//! [`perceive`] computes a [`Chemistry`] from a [`Molecule`] in one pass
//! that is linear in the atom count:
//! 1. bonds ([`connect`]): the file's complete bond block (SDF), residue
//!    templates ([`templates`]) with their peptide and phosphodiester links,
//!    the file's `CONECT`/`struct_conn`, and distances for everything else;
//! 2. bond orders for bonds that have none ([`orders`]), from hydrogen
//!    counts or geometry, and aromatic rings ([`aromatic`]);
//! 3. hydrogens per heavy atom: the file's, when the residue has any, else
//!    implicit from valence and formal charge;
//! 4. Vina's X-Score atom types ([`typing`]);
//! 5. rotatable bonds, the torsion tree, Vina's torsion count and the
//!    intramolecular pairs ([`torsions`]);
//! 6. Gasteiger–Marsili charges as Open Babel computes them ([`gasteiger`]).
//!
//! A molecule read from a PDBQT file keeps what the file states
//! ([`autodock`]): Vina's types from its AutoDock types, the rotatable bonds
//! of its torsion tree, its partial charges; and, as the file merges
//! non-polar hydrogens into their carbons, a carbon's hydrogens are implicit.
//!
//! A molecule computes its chemistry when first asked
//! ([`Molecule::chemistry`]), not when it is loaded. Nothing here panics on
//! odd input: an atom whose chemistry cannot be perceived is reported in
//! [`Chemistry::warnings`], naming it by file, serial and name.

pub mod aromatic;
pub mod autodock;
pub mod connect;
pub mod elements;
pub mod gasteiger;
pub mod graph;
pub mod grid;
pub mod orders;
pub mod rings;
pub mod symmetry;
pub mod templates;
pub mod torsions;
pub mod typing;

use std::collections::BTreeMap;

pub use graph::{Adjacency, Bond};
pub use torsions::{RotatableBond, TorsionNode, TorsionTree};
pub use typing::{Hybridisation, XsType};

use crate::model::Molecule;

/// Everything perceived about a molecule's chemistry. Per-atom arrays are
/// indexed like [`Molecule::atoms`] (heavy atoms); per-hydrogen arrays like
/// [`Molecule::hydrogens`].
#[derive(Debug, Clone)]
pub struct Chemistry {
    /// Bonds between heavy atoms, each pair once with `a < b`, sorted, with
    /// Kekulé orders.
    pub bonds: Vec<Bond>,
    /// Neighbours of each heavy atom (through `bonds`).
    pub adjacency: Adjacency,
    /// Per bond: in a ring.
    pub bond_in_ring: Vec<bool>,
    /// Per bond: in an aromatic ring.
    pub bond_aromatic: Vec<bool>,
    /// Per atom: in an aromatic ring.
    pub aromatic: Vec<bool>,
    /// Per atom: formal charge (the file's, a template's, or implied by a
    /// valence beyond the neutral one, as in a quaternary nitrogen).
    pub formal_charges: Vec<i8>,
    /// Per atom: hydrogens bonded to it (the file's, implicit, or hydrogens
    /// loaded as atoms); 0 for a hydrogen atom.
    pub hydrogen_count: Vec<u8>,
    /// Per atom: true when its hydrogens are implicit (the file had none
    /// for its residue).
    pub implicit_hydrogens: Vec<bool>,
    /// Per atom: hybridisation as Open Babel assigns it.
    pub hybridisation: Vec<Hybridisation>,
    /// Per atom: Vina's X-Score type; `None` for an element Vina has no
    /// type for (reported in `warnings`).
    pub xs: Vec<Option<XsType>>,
    /// Per atom: Gasteiger partial charge (e) with its non-polar
    /// hydrogens' charges added, as AutoDock's PDBQT has them.
    pub charges: Vec<f32>,
    /// Per atom: the summed charge of its polar hydrogens (bonded to N, O,
    /// S or P). They are separate atoms in a PDBQT file; where the molecule
    /// keeps them, their charges are also in `hydrogen_charges`.
    pub polar_hydrogen_charge: Vec<f32>,
    /// Per kept hydrogen ([`Molecule::hydrogens`]): its Gasteiger charge
    /// (non-polar ones are already merged into their carbon's `charges`).
    pub hydrogen_charges: Vec<f32>,
    /// Rotatable bonds and the torsion tree.
    pub torsions: TorsionTree,
    /// What could not be perceived, naming the atom (file, serial, name).
    pub warnings: Vec<String>,
}

impl Chemistry {
    /// Vina's torsion count `N_tors` (each rotatable bond counts ½ per
    /// side whose other atom has more than one heavy neighbour); the score's
    /// divisor is `1 + 0.05846 · N_tors`.
    pub fn vina_torsion_count(&self) -> f64 {
        self.torsions.vina_count
    }

    /// Gasteiger charge per heavy atom with all its hydrogens' charges
    /// added (a united-atom charge, for a molecule whose hydrogens are not
    /// kept).
    pub fn united_charges(&self) -> Vec<f32> {
        self.charges
            .iter()
            .zip(&self.polar_hydrogen_charge)
            .map(|(q, h)| q + h)
            .collect()
    }
}

/// Collects warnings, one per atom and kind, in atom order.
#[derive(Debug, Default)]
pub(crate) struct Warnings {
    by_atom: BTreeMap<(usize, String), ()>,
    general: Vec<String>,
}

impl Warnings {
    /// A warning about atom `i` of `mol`.
    pub(crate) fn atom(&mut self, mol: &Molecule, i: usize, what: String) {
        let a = &mol.atoms[i];
        let chain = if a.chain.is_empty() {
            String::new()
        } else {
            format!("{}/", a.chain)
        };
        let text = format!(
            "{}: atom {} ({} {} {}{}): {what}",
            mol.name,
            a.serial,
            a.name,
            a.residue,
            chain,
            a.residue_number()
        );
        self.by_atom.insert((i, text), ());
    }

    /// A warning about the molecule.
    pub(crate) fn general(&mut self, what: String) {
        self.general.push(what);
    }

    fn into_vec(self) -> Vec<String> {
        self.general
            .into_iter()
            .chain(self.by_atom.into_keys().map(|(_, t)| t))
            .collect()
    }
}

/// Perceives `mol`'s chemistry (see the module docs). Linear in the atom
/// count; never panics.
pub fn perceive(mol: &Molecule) -> Chemistry {
    let mut warn = Warnings::default();
    let n = mol.len();
    // Explicit hydrogens per atom, for residues that have any.
    let residues = connect::residue_ranges(&mol.atoms);
    let mut residue_of = vec![0u32; n];
    for (r, &(s, e)) in residues.iter().enumerate() {
        residue_of[s as usize..e as usize].fill(connect::idx(r));
    }
    let mut h_of = vec![0u8; n];
    let mut residue_has_h = vec![false; residues.len()];
    for &p in &mol.hydrogens.parent {
        if let Some(slot) = h_of.get_mut(p as usize) {
            *slot = slot.saturating_add(1);
            residue_has_h[residue_of[p as usize] as usize] = true;
        }
    }
    // A PDBQT merges its non-polar hydrogens into their carbons: where it
    // has none, a carbon's hydrogens are not the file's to count.
    let united = mol.autodock.as_ref().is_some_and(|ad| {
        !ad.hydrogens
            .iter()
            .chain(&ad.atoms)
            .any(|a| a.ad == autodock::AdType::H)
    });
    let explicit_h: Vec<Option<u8>> = (0..n)
        .map(|i| {
            let merged = united && mol.atoms[i].element.as_str() == "C";
            (residue_has_h[residue_of[i] as usize] && !merged).then_some(h_of[i])
        })
        .collect();

    let mut conn = connect::connect(mol, &explicit_h, &mut warn);
    if !mol.bonds_complete && mol.file_bonds.is_empty() && mol.from_sdf && n > 1 {
        warn.general(format!(
            "{}: the file has no bonds; bonds and orders are perceived from distances",
            mol.name
        ));
    }
    let adjacency = Adjacency::new(n, &conn.bonds);
    let bond_in_ring = rings::ring_bonds(&adjacency, conn.bonds.len());

    // A PDBQT's score takes nothing from the bond orders (its types, tree
    // and charges are the file's), and the file states no formal charges: a
    // carboxylate or nitro O⁻ it holds cannot be told from a lone C=O, so
    // the orders are drawn as found and not warned about.
    let mut order_warnings = Warnings::default();
    orders::assign_orders(
        mol,
        &mut conn,
        &adjacency,
        &bond_in_ring,
        &explicit_h,
        if mol.autodock.is_some() {
            &mut order_warnings
        } else {
            &mut warn
        },
    );
    let (aromatic, bond_aromatic) =
        aromatic::perceive(mol, &conn, &adjacency, &bond_in_ring, &explicit_h);

    let hydro = typing::hydrogens(mol, &conn, &adjacency, &explicit_h, &mut warn);
    let hybridisation = typing::hybridisation(
        mol,
        &conn.bonds,
        &adjacency,
        &aromatic,
        &bond_aromatic,
        &hydro,
    );
    // A PDBQT states what Vina reads: its types, tree and charges stand.
    let file = mol.autodock.as_ref();
    let xs = match file {
        Some(ad) => autodock::file_xs_types(mol, ad, &adjacency),
        None => typing::xs_types(mol, &adjacency, &hybridisation, &hydro, &mut warn),
    };
    let given = file.and_then(|ad| {
        autodock::file_rotatable(mol, ad, &conn.bonds, &adjacency, &bond_in_ring, &mut warn)
    });
    let held_count = given.as_ref().map_or(0.0, |g| g.held_count);
    let mut torsions = torsions::build(
        mol,
        &conn.bonds,
        &adjacency,
        &bond_in_ring,
        &bond_aromatic,
        &hydro,
        given.map(|g| g.rotatable),
    );
    torsions.vina_count += held_count;
    let charges = match file {
        Some(ad) => autodock::file_charges(mol, ad),
        None => gasteiger::charges(
            mol,
            &conn.bonds,
            &adjacency,
            &aromatic,
            &hybridisation,
            &hydro,
            &mut warn,
        ),
    };

    Chemistry {
        bonds: conn.bonds,
        adjacency,
        bond_in_ring,
        bond_aromatic,
        aromatic,
        formal_charges: hydro.charges.clone(),
        hydrogen_count: hydro
            .count
            .iter()
            .zip(&hydro.atom_h)
            .map(|(a, b)| a.saturating_add(*b))
            .collect(),
        implicit_hydrogens: explicit_h.iter().map(Option::is_none).collect(),
        hybridisation,
        xs,
        charges: charges.heavy,
        polar_hydrogen_charge: charges.polar_h,
        hydrogen_charges: charges.kept_h,
        torsions,
        warnings: warn.into_vec(),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::model::{AtomInfo, BondOrder, LoadOptions, sdf::parse_sdf};

    /// A hetero ligand from elements and coordinates, with no bonds.
    fn ligand(atoms: &[(&str, [f64; 3])]) -> Molecule {
        let infos = atoms
            .iter()
            .enumerate()
            .map(|(i, (e, _))| AtomInfo {
                serial: i as i64 + 1,
                name: format!("{e}{}", i + 1).into(),
                residue: "LIG".into(),
                seq: 1,
                insertion: Default::default(),
                chain: "A".into(),
                element: (*e).into(),
                radius: 1.7,
                polar: matches!(*e, "N" | "O"),
                hetero: true,
            })
            .collect();
        let pos: Vec<DVec3> = atoms.iter().map(|(_, p)| DVec3::from_array(*p)).collect();
        Molecule::new("test.pdb LIG", infos, &pos)
    }

    fn ring(elements: &[&str], radius: f64) -> Vec<(&'static str, [f64; 3])> {
        let n = elements.len();
        elements
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let e: &'static str = match *e {
                    "N" => "N",
                    _ => "C",
                };
                (e, [radius * a.cos(), radius * a.sin(), 0.0])
            })
            .collect()
    }

    fn doubles(c: &Chemistry) -> usize {
        c.bonds
            .iter()
            .filter(|b| b.order == BondOrder::Double)
            .count()
    }

    /// An aspartate with no hydrogens, its two side-chain oxygens at the
    /// given heights.
    fn aspartate(od1_z: f64, od2_z: f64) -> Molecule {
        let atoms = [
            ("N", "N", [-1.9, 0.6, 0.0]),
            ("CA", "C", [-0.5, 0.4, 0.0]),
            ("C", "C", [0.0, 1.2, 1.2]),
            ("O", "O", [-0.4, 2.3, 1.4]),
            ("CB", "C", [0.0, -1.0, 0.0]),
            ("CG", "C", [1.5, -1.2, 0.0]),
            ("OD1", "O", [2.1, -1.9, od1_z]),
            ("OD2", "O", [2.2, -0.6, od2_z]),
        ];
        let infos = atoms
            .iter()
            .enumerate()
            .map(|(i, (name, e, _))| AtomInfo {
                serial: i as i64 + 1,
                name: (*name).into(),
                residue: "ASP".into(),
                seq: 27,
                insertion: Default::default(),
                chain: "A".into(),
                element: (*e).into(),
                radius: 1.7,
                polar: matches!(*e, "N" | "O"),
                hetero: false,
            })
            .collect();
        let pos: Vec<DVec3> = atoms.iter().map(|(.., p)| DVec3::from_array(*p)).collect();
        Molecule::new("test.pdb", infos, &pos)
    }

    #[test]
    fn a_crystal_aspartate_protonates_its_higher_oxygen_as_open_babel_does() {
        for (z1, z2, hydroxyl) in [(-0.3, 0.3, 7), (0.3, -0.3, 6)] {
            let m = aspartate(z1, z2);
            let c = m.chemistry();
            for o in [6, 7] {
                let want = if o == hydroxyl {
                    XsType::O_DA
                } else {
                    XsType::O_A
                };
                assert_eq!(c.xs[o], Some(want), "OD{} with z {z1}, {z2}", o - 5);
                assert_eq!(c.hydrogen_count[o], u8::from(o == hydroxyl));
            }
        }
    }

    /// A charge the file gives an oxygen makes the aspartate a carboxylate,
    /// whichever oxygen lies higher: both accept, neither donates (as Open
    /// Babel types a PDB written with `1-` in columns 79-80).
    #[test]
    fn a_charged_aspartate_oxygen_makes_a_carboxylate() {
        for (z1, z2) in [(-0.3, 0.3), (0.3, -0.3)] {
            for charged in [6, 7] {
                let mut m = aspartate(z1, z2);
                m.formal_charges = vec![0; m.len()];
                m.formal_charges[charged] = -1;
                let c = m.chemistry();
                for o in [6, 7] {
                    assert_eq!(c.xs[o], Some(XsType::O_A), "OD{} charged {charged}", o - 5);
                    assert_eq!(c.hydrogen_count[o], 0);
                }
                assert!(c.warnings.is_empty(), "{:?}", c.warnings);
            }
        }
    }

    /// An indazole-5-carboxamide read without hydrogens, as docked in CDK8
    /// (heavy atoms of ligand 1 of the Open Force Field protein-ligand
    /// benchmark's cdk8 set): its ring nitrogens first take the π bonds,
    /// leaving a benzene carbon without one, so one N gives its own up and
    /// carries the hydrogen (1H-indazole, the N beside the benzene ring).
    #[test]
    fn a_fused_azole_read_without_hydrogens_gives_a_ring_n_its_hydrogen() {
        let m = ligand(&[
            ("C", [-7.226, 9.851, -7.984]),
            ("C", [-7.562, 9.684, -9.443]),
            ("N", [-8.246, 8.646, -9.860]),
            ("N", [-8.416, 8.805, -11.197]),
            ("C", [-7.827, 9.947, -11.695]),
            ("C", [-7.241, 10.545, -10.548]),
            ("C", [-6.529, 11.747, -10.741]),
            ("C", [-6.356, 12.308, -12.026]),
            ("C", [-7.002, 11.715, -13.132]),
            ("C", [-7.733, 10.526, -12.971]),
            ("C", [-5.536, 13.557, -12.182]),
            ("O", [-5.963, 14.490, -12.859]),
            ("N", [-4.377, 13.627, -11.487]),
            ("C", [-3.796, 14.896, -11.044]),
            ("C", [-3.531, 12.479, -11.119]),
        ]);
        let c = m.chemistry();
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
        assert_eq!((c.xs[2], c.hydrogen_count[2]), (Some(XsType::N_A), 0));
        assert_eq!((c.xs[3], c.hydrogen_count[3]), (Some(XsType::N_D), 1));
        // Four double bonds in the fused rings, and the amide's C=O.
        assert_eq!(doubles(c), 5);
    }

    #[test]
    fn benzene_from_geometry() {
        let m = ligand(&ring(&["C"; 6], 1.39));
        let c = m.chemistry();
        assert_eq!(c.bonds.len(), 6);
        assert_eq!(doubles(c), 3);
        assert!(c.aromatic.iter().all(|&a| a));
        assert!(c.bond_aromatic.iter().all(|&a| a));
        assert!(c.hydrogen_count.iter().all(|&h| h == 1));
        assert!(c.xs.iter().all(|&t| t == Some(XsType::C_H)));
        assert!(c.torsions.is_empty() && c.vina_torsion_count() == 0.0);
        // Symmetric: every carbon (with its hydrogen merged) is neutral.
        assert!(c.charges.iter().all(|q| q.abs() < 1e-4), "{:?}", c.charges);
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    }

    #[test]
    fn pyridine_nitrogen_is_an_acceptor() {
        let m = ligand(&ring(&["N", "C", "C", "C", "C", "C"], 1.39));
        let c = m.chemistry();
        assert_eq!(doubles(c), 3);
        assert_eq!(c.xs[0], Some(XsType::N_A));
        assert_eq!(c.hydrogen_count[0], 0);
        assert_eq!(c.xs[1], Some(XsType::C_P));
        assert_eq!(c.xs[3], Some(XsType::C_H));
        assert!(c.aromatic[0]);
        // Gasteiger: the nitrogen takes charge from its carbons.
        assert!(c.charges[0] < -0.1 && c.charges[1] > 0.0);
    }

    #[test]
    fn acetic_acid_and_its_hydroxyl() {
        let m = ligand(&[
            ("C", [0.0, 0.0, 0.0]),
            ("C", [1.52, 0.0, 0.0]),
            ("O", [2.125, 1.048, 0.0]),
            ("O", [2.2, -1.178, 0.0]),
        ]);
        let c = m.chemistry();
        let order = |a: u32, b: u32| {
            c.bonds
                .iter()
                .find(|x| x.a == a && x.b == b)
                .map(|x| x.order)
        };
        assert_eq!(order(1, 2), Some(BondOrder::Double));
        assert_eq!(order(1, 3), Some(BondOrder::Single));
        assert_eq!(
            c.xs,
            vec![
                Some(XsType::C_H),
                Some(XsType::C_P),
                Some(XsType::O_A),
                Some(XsType::O_DA)
            ]
        );
        assert_eq!(c.hydrogen_count, vec![3, 0, 0, 1]);
        // The C–OH bond turns a hydrogen only: it counts ½.
        assert_eq!(c.torsions.len(), 1);
        assert_eq!(c.vina_torsion_count(), 0.5);
        let total: f32 = c.united_charges().iter().sum();
        assert!(total.abs() < 1e-4, "{total}");
    }

    #[test]
    fn amide_bond_does_not_rotate_and_butane_does() {
        let nma = ligand(&[
            ("C", [0.0, 0.0, 0.0]),
            ("C", [1.51, 0.0, 0.0]),
            ("O", [2.125, 1.065, 0.0]),
            ("N", [2.175, -1.152, 0.0]),
            ("C", [3.625, -1.177, 0.0]),
        ]);
        let c = nma.chemistry();
        assert_eq!(c.xs[3], Some(XsType::N_D));
        assert_eq!(c.xs[2], Some(XsType::O_A));
        assert_eq!(c.hydrogen_count[3], 1);
        assert!(c.torsions.is_empty(), "{:?}", c.torsions.bonds);

        let butane = ligand(
            &(0..4)
                .map(|i| ("C", [i as f64 * 1.26, (i % 2) as f64 * 0.89, 0.0]))
                .collect::<Vec<_>>(),
        );
        let c = butane.chemistry();
        assert_eq!(c.torsions.len(), 1);
        assert_eq!(c.vina_torsion_count(), 1.0);
        let rb = c.torsions.bonds[0];
        assert_eq!(
            (
                rb.parent_atom.min(rb.child_atom),
                rb.parent_atom.max(rb.child_atom)
            ),
            (1, 2)
        );
        let (small, _, _) = c.torsions.smaller_side(0);
        assert_eq!(small.len(), 2);
        // Vina scores the 1-4 pair of butane? No: within three bonds.
        assert!(c.torsions.vina_pairs(&c.adjacency, &c.xs).is_empty());
        assert_eq!(
            torsions::pairs_beyond_three_bonds(&c.adjacency),
            Vec::<(u32, u32)>::new()
        );
    }

    #[test]
    fn hexane_pairs_across_rotors() {
        let hexane = ligand(
            &(0..6)
                .map(|i| ("C", [i as f64 * 1.26, (i % 2) as f64 * 0.89, 0.0]))
                .collect::<Vec<_>>(),
        );
        let c = hexane.chemistry();
        // C1–C2 and C4–C5... rotatable bonds: 1-2, 2-3, 3-4 (0-based).
        assert_eq!(c.torsions.len(), 3);
        let pairs = c.torsions.vina_pairs(&c.adjacency, &c.xs);
        assert_eq!(pairs, vec![(0, 4), (0, 5), (1, 5)]);
        assert_eq!(
            torsions::pairs_beyond_three_bonds(&c.adjacency),
            vec![(0, 4), (0, 5), (1, 5)]
        );
    }

    #[test]
    fn a_piece_no_bond_joins_moves_with_the_root() {
        // Hexane and, 6 Å off, a zinc no bond joins to it: its own root.
        let mut atoms: Vec<(&str, [f64; 3])> = (0..6)
            .map(|i| ("C", [i as f64 * 1.26, (i % 2) as f64 * 0.89, 0.0]))
            .collect();
        atoms.push(("Zn", [3.0, 6.0, 0.0]));
        let mol = ligand(&atoms);
        let c = mol.chemistry();
        assert_eq!(c.torsions.len(), 3);
        let movable = c.torsions.movable_pairs(&c.adjacency);
        for pair in [(0, 4), (0, 5), (1, 5)] {
            assert!(movable.contains(&pair), "{movable:?}");
        }
        // No turn changes the zinc's distance to the root's atoms, as both
        // move only with the pose; Vina's pairs count them.
        let all = vec![Some(()); 7];
        let vina = c.torsions.vina_pairs(&c.adjacency, &all);
        let root = &c.torsions.nodes[0].atoms;
        assert!(!root.contains(&6));
        for &r in root {
            assert!(vina.contains(&(r, 6)), "{vina:?}");
            assert!(!movable.contains(&(r, 6)), "{movable:?}");
        }
        // The ends swing round the turned bonds, and past the zinc.
        assert!(movable.contains(&(0, 6)) && movable.contains(&(5, 6)));
    }

    const V2000_HEAD: &str = "lig\n  test\n\n";

    fn sdf(atoms: &[(&str, [f64; 3])], bonds: &[(i64, i64, i64)], extra: &str) -> String {
        let mut t = String::from(V2000_HEAD);
        t += &format!(
            "{:>3}{:>3}  0  0  0  0  0  0  0  0999 V2000\n",
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
        t += extra;
        t += "M  END\n$$$$\n";
        t
    }

    fn load(text: &str) -> (Molecule, Vec<String>) {
        let l = parse_sdf(text, "bad.sdf", &LoadOptions::default()).expect("loads");
        (
            crate::model::receptor_only(&l.structure).expect("molecule"),
            l.warnings,
        )
    }

    #[test]
    fn bad_bond_blocks_load_with_warnings() {
        let atoms = [("C", [0.0, 0.0, 0.0]), ("O", [1.43, 0.0, 0.0])];
        for (bond, what) in [
            ((0, 2, 1), "atom 0"),
            ((1, 3, 1), "atom 3"),
            ((2, 2, 1), "itself"),
        ] {
            let (m, w) = load(&sdf(&atoms, &[bond], ""));
            assert!(
                w.iter()
                    .any(|w| w.contains("bad.sdf:7") && w.contains(what)),
                "{w:?}"
            );
            // The bond is left out, so the two atoms are perceived.
            let c = m.chemistry();
            assert_eq!(c.bonds.len(), 1);
        }
    }

    #[test]
    fn odd_valence_and_unknown_elements_are_named() {
        // A carbon with five single bonds.
        let mut atoms = vec![("C", [0.0, 0.0, 0.0])];
        for d in [
            [1.5, 0.0, 0.0],
            [-1.5, 0.0, 0.0],
            [0.0, 1.5, 0.0],
            [0.0, -1.5, 0.0],
            [0.0, 0.0, 1.5],
        ] {
            atoms.push(("C", d));
        }
        let bonds: Vec<(i64, i64, i64)> = (2..=6).map(|k| (1, k, 1)).collect();
        let (m, _) = load(&sdf(&atoms, &bonds, ""));
        let c = m.chemistry();
        assert!(
            c.warnings.iter().any(|w| w.contains("bad.sdf")
                && w.contains("atom 1 (C1")
                && w.contains("odd valence")),
            "{:?}",
            c.warnings
        );
        // An element no table knows.
        let (m, _) = load(&sdf(
            &[("C", [0.0, 0.0, 0.0]), ("Xx", [1.5, 0.0, 0.0])],
            &[(1, 2, 1)],
            "",
        ));
        let c = m.chemistry();
        assert_eq!(c.xs[1], None);
        assert!(
            c.warnings
                .iter()
                .any(|w| w.contains("atom 2 (Xx2") && w.contains("unknown element")),
            "{:?}",
            c.warnings
        );
    }

    #[test]
    fn hydrogens_kept_as_atoms_count_as_hydrogens() {
        // Methanol with its hydrogens, loaded keeping them as atoms.
        let atoms = [
            ("C", [0.0, 0.0, 0.0]),
            ("O", [1.43, 0.0, 0.0]),
            ("H", [1.75, 0.9, 0.0]),
            ("H", [-0.36, 1.03, 0.0]),
            ("H", [-0.36, -0.51, 0.89]),
            ("H", [-0.36, -0.51, -0.89]),
        ];
        let bonds = [(1, 2, 1), (2, 3, 1), (1, 4, 1), (1, 5, 1), (1, 6, 1)];
        let keep = LoadOptions {
            hydrogens: crate::model::Hydrogens::Keep,
            ..LoadOptions::default()
        };
        let l = parse_sdf(&sdf(&atoms, &bonds, ""), "m.sdf", &keep).expect("loads");
        let m = crate::model::receptor_only(&l.structure).expect("molecule");
        let c = m.chemistry();
        assert_eq!(&c.hydrogen_count[..2], &[3, 1]);
        assert_eq!(&c.xs[..2], &[Some(XsType::C_P), Some(XsType::O_DA)]);
        assert!(c.xs[2..].iter().all(Option::is_none));
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
        let total: f32 = c.charges.iter().sum();
        assert!(total.abs() < 1e-4 && c.charges[2] > 0.1, "{:?}", c.charges);
    }

    #[test]
    fn hydrogens_kept_as_atoms_turn_no_methyl() {
        // Ethanol with its hydrogens: only the C–O turns (the methyl does
        // not, its hydrogens are not neighbours that count), ½ in N_tors,
        // whether the hydrogens are kept as atoms or apart.
        let atoms = [
            ("C", [-1.2, 0.0, 0.0]),
            ("C", [0.3, 0.0, 0.0]),
            ("O", [0.8, 1.3, 0.0]),
            ("H", [1.75, 1.3, 0.0]),
            ("H", [-1.6, 1.0, 0.0]),
            ("H", [-1.6, -0.5, 0.87]),
            ("H", [-1.6, -0.5, -0.87]),
            ("H", [0.7, -0.5, 0.87]),
            ("H", [0.7, -0.5, -0.87]),
        ];
        let bonds = [
            (1, 2, 1),
            (2, 3, 1),
            (3, 4, 1),
            (1, 5, 1),
            (1, 6, 1),
            (1, 7, 1),
            (2, 8, 1),
            (2, 9, 1),
        ];
        for hydrogens in [crate::model::Hydrogens::Keep, crate::model::Hydrogens::Drop] {
            let opts = LoadOptions {
                hydrogens,
                ..LoadOptions::default()
            };
            let l = parse_sdf(&sdf(&atoms, &bonds, ""), "e.sdf", &opts).expect("loads");
            let m = crate::model::receptor_only(&l.structure).expect("molecule");
            let c = m.chemistry();
            assert_eq!(c.torsions.bonds.len(), 1, "{hydrogens:?}");
            let b = c.bonds[c.torsions.bonds[0].bond as usize];
            assert_eq!((b.a, b.b), (1, 2), "{hydrogens:?}: the C–O");
            assert_eq!(c.vina_torsion_count(), 0.5, "{hydrogens:?}");
        }
    }

    #[test]
    fn a_missing_bond_block_is_perceived() {
        let atoms = ring(&["C"; 6], 1.39);
        let (m, _) = load(&sdf(&atoms, &[], ""));
        let c = m.chemistry();
        assert_eq!(c.bonds.len(), 6);
        assert_eq!(doubles(c), 3);
        assert!(
            c.warnings.iter().any(|w| w.contains("no bonds")),
            "{:?}",
            c.warnings
        );
    }

    #[test]
    fn charges_and_aromatic_bonds_from_sdf() {
        // Pyridinium written with aromatic bonds and M  CHG.
        let atoms = ring(&["N", "C", "C", "C", "C", "C"], 1.39);
        let bonds: Vec<(i64, i64, i64)> = (1..=6).map(|k| (k, k % 6 + 1, 4)).collect();
        let (m, _) = load(&sdf(&atoms, &bonds, "M  CHG  1   1   1\n"));
        assert_eq!(m.formal_charges[0], 1);
        let c = m.chemistry();
        assert_eq!(doubles(c), 3);
        assert!(c.aromatic.iter().all(|&a| a));
        // Pyridinium: the N+ carries a hydrogen, a donor.
        assert_eq!(c.hydrogen_count[0], 1);
        assert_eq!(c.xs[0], Some(XsType::N_D));
    }

    #[test]
    fn peptide_templates_and_chain_breaks() {
        // Two glycines 1.33 Å apart, a third 4 Å further: linked, then broken.
        let gly = |seq: i64, x: f64, serial: i64| -> Vec<(AtomInfo, DVec3)> {
            [
                ("N", [0.0, 0.0, 0.0]),
                ("CA", [1.46, 0.0, 0.0]),
                ("C", [2.0, 1.4, 0.0]),
                ("O", [1.4, 2.4, 0.0]),
            ]
            .iter()
            .enumerate()
            .map(|(k, (name, p))| {
                (
                    AtomInfo {
                        serial: serial + k as i64,
                        name: (*name).into(),
                        residue: "GLY".into(),
                        seq,
                        insertion: Default::default(),
                        chain: "A".into(),
                        element: name[..1].into(),
                        radius: 1.7,
                        polar: false,
                        hetero: false,
                    },
                    DVec3::new(p[0] + x, p[1], p[2]),
                )
            })
            .collect()
        };
        let mut all = gly(1, 0.0, 1);
        // Residue 2's N sits 1.33 Å from residue 1's C.
        let c1 = all[2].1;
        all.extend(
            gly(2, c1.x + 1.0 - 0.0, 5)
                .into_iter()
                .map(|(a, p)| (a, p + DVec3::new(0.0, c1.y - 0.88, 0.0))),
        );
        all.extend(gly(3, 30.0, 9));
        let (atoms, pos): (Vec<_>, Vec<_>) = all.into_iter().unzip();
        let m = Molecule::new("gly", atoms, &pos);
        let c = m.chemistry();
        let link = c.bonds.iter().any(|b| (b.a, b.b) == (2, 4));
        assert!(link, "{:?}", c.bonds);
        assert!(
            !c.bonds.iter().any(|b| b.a < 8 && b.b >= 8),
            "no bond across the break"
        );
        // Linked N has one hydrogen (N_D); the chain starts (two H) are N_DA.
        assert_eq!(c.xs[4], Some(XsType::N_D));
        assert_eq!(c.xs[0], Some(XsType::N_DA));
        assert_eq!(c.xs[8], Some(XsType::N_DA));
        assert_eq!(c.xs[3], Some(XsType::O_A));
    }
}
