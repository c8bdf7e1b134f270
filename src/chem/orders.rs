//! Bond orders for bonds the file does not give them to: a Kekulé structure
//! from the atoms' hydrogen counts when the file has hydrogens, otherwise
//! from geometry; and a Kekulé structure for bonds a file marks aromatic.
//!
//! Each atom gets a number of π bonds it needs, and whether it must have
//! them (a planar carbon must) or may (a terminal oxygen on a planar
//! carbon, a five-ring nitrogen that may carry a hydrogen instead):
//! - with hydrogens: the atom's usual valence less its bonds and hydrogens;
//! - from geometry (after the approach of Baber & Hodgkin, J. Chem. Inf.
//!   Comput. Sci. 32 (1992) 401, and Open Babel's `PerceiveBondOrders`):
//!   an atom whose bond angles average over 155° is linear (sp, two π
//!   bonds), over 115° (117° with two neighbours) trigonal (sp2, one), and
//!   an atom of a flat five-membered ring (all atoms within 0.15 Å of a
//!   plane, where angles cannot tell) trigonal; a terminal atom may take a
//!   double bond when its bond is short enough (C–O under 1.40 Å, C–N under
//!   1.36, C–C under 1.38, C–S under 1.75). A trigonal nitrogen with three
//!   neighbours (amide, aniline, pyrrole) needs none, unless it sits in a
//!   flat six-ring (pyridinium); sulfur and phosphorus take their double
//!   bonds to terminal oxygens (sulfone, phosphate), a nitro N to one of
//!   its oxygens, an azide's middle N a triple bond to its terminal N. A
//!   two-neighbour N in a six-ring that is trigonal throughout must have
//!   one (pyridine), unless a neighbouring carbon carries a carbonyl oxygen
//!   (a lactam or imide N, as in uracil and guanine): then it may, and
//!   carries a hydrogen when the carbonyl takes the double bond. A ring
//!   with a saturated atom (a dihydropyridine) is not trigonal throughout.
//!   Among candidates, the bond shortest relative to the sum of covalent
//!   radii goes first, a carbonyl oxygen favoured and an exocyclic imine N,
//!   and more so a three-neighbour N (which the bond would charge),
//!   disfavoured, as Open Babel's order of assignment has it.
//!
//! An atom counts as trigonal only when one of its bonds is shorter than
//! 0.96 of the sum of the covalent radii (some double-bond character).
//! Triple bonds join pairs of linear atoms; double bonds are a matching:
//! first among the atoms that must have one and the early partners that
//! may (clear carbonyl oxygens, ring nitrogens), then from those still
//! without to any candidate, each by augmenting paths (Kuhn's method) that
//! try the shortest bond (relative to a single bond) first, so the
//! structure follows the geometry; then an atom that must have one and is
//! still without takes its partner from an atom that only may (a fused
//! azole's ring N, which then carries the hydrogen); last, two azole
//! nitrogens still without pair with each other (the N=N of a triazole or
//! tetrazole).
//! An atom that must have a π bond and gets none is reported by name.

use glam::Vec3;

use super::Warnings;
use super::connect::Connection;
use super::elements::charged_valences;
use super::graph::Adjacency;
use super::rings::{ring_deviation, smallest_rings};
use crate::model::{BondOrder, Molecule};

/// Average bond angle (degrees) above which an atom is linear.
const LINEAR: f32 = 155.0;
/// Average bond angle (degrees) above which an atom is trigonal.
const TRIGONAL: f32 = 115.0;
/// Largest ratio of a bond's length to the sum of its atoms' covalent
/// radii for a bond with some double-bond character (single bonds are near
/// 1.0, aromatic 0.91, double 0.88).
const SHORT_BOND: f32 = 0.96;
/// Largest out-of-plane distance (Å) of a flat ring's atoms.
const FLAT_RING: f32 = 0.15;

/// What an atom needs in π bonds.
#[derive(Debug, Clone, Copy, Default)]
struct Need {
    /// π bonds wanted.
    count: u8,
    /// True when the atom must get them.
    required: bool,
    /// True when an atom that may have one is still a partner in the
    /// matching's first round, among the atoms that must: a clear carbonyl
    /// oxygen, and a ring N (a lactam N carries a hydrogen if the carbonyl
    /// beside it takes the double bond).
    early: bool,
    /// True for a two-neighbour N of a flat five-ring: left without a π
    /// bond, it pairs with a neighbour such as itself (the N=N of a
    /// triazole or tetrazole).
    azole: bool,
}

/// Fills in the orders of `conn`'s unspecified and aromatic bonds.
/// `explicit_h[i]` is the number of hydrogens atom `i` has in the file,
/// when its residue has hydrogens.
pub(crate) fn assign_orders(
    mol: &Molecule,
    conn: &mut Connection,
    adj: &Adjacency,
    in_ring: &[bool],
    explicit_h: &[Option<u8>],
    warn: &mut Warnings,
) {
    let n = mol.len();
    // Atoms whose bonds need orders: an unspecified or aromatic bond.
    let mut open = vec![false; n];
    let mut any = false;
    for b in &conn.bonds {
        if is_free(b.order) {
            open[b.a as usize] = true;
            open[b.b as usize] = true;
            any = true;
        }
    }
    if !any {
        return;
    }
    let shapes = RingShapes::new(mol, conn, adj, in_ring, &open, explicit_h);
    let mut need = needs(mol, conn, adj, &open, explicit_h, &shapes);
    // Bonds that may take a higher order: unspecified or aromatic.
    let mut order: Vec<BondOrder> = conn.bonds.iter().map(|b| b.order).collect();
    hypervalent_doubles(mol, adj, &open, &mut need, &mut order);
    triple_bonds(conn, adj, &mut need, &mut order);
    match_doubles(mol, adj, &need, &mut order, warn);
    for (k, b) in conn.bonds.iter_mut().enumerate() {
        b.order = match order[k] {
            BondOrder::Unspecified | BondOrder::Aromatic => BondOrder::Single,
            o => o,
        };
    }
}

/// True for an order that may still be raised: unspecified or aromatic.
fn is_free(o: BondOrder) -> bool {
    matches!(o, BondOrder::Unspecified | BondOrder::Aromatic)
}

/// True when atom `j` is an oxygen with one neighbour.
fn is_terminal_o(mol: &Molecule, adj: &Adjacency, j: usize) -> bool {
    adj.degree(j) == 1 && mol.atoms[j].element.as_str() == "O"
}

/// How many terminal oxygens atom `i` carries.
fn terminal_oxygens(mol: &Molecule, adj: &Adjacency, i: usize) -> usize {
    adj.of(i)
        .iter()
        .filter(|&&(j, _)| is_terminal_o(mol, adj, j as usize))
        .count()
}

/// What the open atoms' rings say about their shape.
struct RingShapes {
    /// 5 for an atom of a flat five-ring, else 0.
    in_flat_ring: Vec<u8>,
    /// The atom is in a six-ring.
    in_six: Vec<bool>,
    /// The atom is in a six-ring that is trigonal throughout.
    ring_trigonal: Vec<bool>,
}

impl RingShapes {
    /// The smallest rings among the open atoms without hydrogens in the
    /// file, and the shapes they give their atoms.
    fn new(
        mol: &Molecule,
        conn: &Connection,
        adj: &Adjacency,
        in_ring: &[bool],
        open: &[bool],
        explicit_h: &[Option<u8>],
    ) -> Self {
        let n = mol.len();
        let pos = &mol.local;
        // Flat rings among the open atoms.
        let rings = smallest_rings(adj, &conn.bonds, in_ring, &|i| {
            open[i] && explicit_h[i].is_none()
        });
        let mut in_flat_ring = vec![0u8; n];
        for ring in &rings {
            if ring.len() == 5 && ring_deviation(ring, pos) <= FLAT_RING {
                for &i in ring {
                    let s = &mut in_flat_ring[i as usize];
                    if *s == 0 || (ring.len() as u8) < *s {
                        *s = ring.len() as u8;
                    }
                }
            }
        }

        let mut in_six = vec![false; n];
        for ring in rings.iter().filter(|r| r.len() == 6) {
            for &i in ring {
                in_six[i as usize] = true;
            }
        }
        // Six-rings most of whose atoms look trigonal are trigonal throughout:
        // low-resolution structures bend single angles out of range.
        let mut ring_trigonal = vec![false; n];
        for ring in rings.iter().filter(|r| r.len() == 6) {
            let looks = ring
                .iter()
                .filter(|&&i| {
                    let row = adj.of(i as usize);
                    row.len() <= 3 && mean_angle(i as usize, row, pos) > TRIGONAL
                })
                .count();
            // An atom with four neighbours, or with every bond at
            // single-bond length, is sp3 however the ring bends (the CH of
            // a 1,4-dihydropyridine).
            let saturated = ring.iter().any(|&i| {
                let row = adj.of(i as usize);
                row.len() > 3 || shortest_bond(i as usize, row, pos, mol) >= SHORT_BOND
            });
            if looks >= 4 && !saturated && ring_deviation(ring, pos) <= 2.0 * FLAT_RING {
                for &i in ring {
                    ring_trigonal[i as usize] = true;
                }
            }
        }
        Self {
            in_flat_ring,
            in_six,
            ring_trigonal,
        }
    }
}

/// The π bonds each open atom needs: from its valence where the file has
/// its hydrogens, from the aromatic bonds the file marks, else from its
/// geometry.
fn needs(
    mol: &Molecule,
    conn: &Connection,
    adj: &Adjacency,
    open: &[bool],
    explicit_h: &[Option<u8>],
    shapes: &RingShapes,
) -> Vec<Need> {
    let n = mol.len();
    let bonds = &conn.bonds;
    let pos = &mol.local;
    let mut need = vec![Need::default(); n];
    for i in 0..n {
        if !open[i] {
            continue;
        }
        let row = adj.of(i);
        let stated: u32 = row
            .iter()
            .map(|&(_, k)| match bonds[k as usize].order {
                BondOrder::Double => 1,
                BondOrder::Triple => 2,
                _ => 0,
            })
            .sum();
        let has_aromatic = row
            .iter()
            .any(|&(_, k)| bonds[k as usize].order == BondOrder::Aromatic);
        let deg = row.len() as u32;
        let e = mol.atoms[i].element.as_str();
        need[i] = match explicit_h[i] {
            Some(h) => from_valence(e, conn.charges[i], deg, u32::from(h), stated, row, mol),
            None if has_aromatic => aromatic_need(e, deg, stated),
            None => {
                let flat = if shapes.ring_trigonal[i] {
                    6
                } else {
                    shapes.in_flat_ring[i]
                };
                let geometry =
                    from_geometry(i, e, row, pos, adj, mol, flat, shapes.in_six[i], stated);
                with_charge(geometry, e, conn.charges[i], deg, stated)
            }
        };
    }
    // An azide's middle N (two π bonds, between two N): each N beside it
    // may take one, bent as the first is (N=[N+]=[N-]).
    for i in 0..n {
        let row = adj.of(i);
        let middle = need[i].count == 2
            && need[i].required
            && mol.atoms[i].element.as_str() == "N"
            && row.len() == 2
            && row
                .iter()
                .all(|&(j, _)| mol.atoms[j as usize].element.as_str() == "N");
        if middle {
            for &(j, _) in row {
                let j = j as usize;
                if open[j] && explicit_h[j].is_none() && need[j].count == 0 {
                    need[j].count = 1;
                }
            }
        }
    }
    need
}

/// `need` bounded by the valence of the charge the file gives the atom:
/// an anionic O or S (a carboxylate's `1-`) takes no π bond, an azide's
/// terminal `N1-` one, a cationic N its fourth bond.
fn with_charge(need: Need, e: &str, charge: i8, deg: u32, stated: u32) -> Need {
    if charge == 0 || !matches!(e, "N" | "O" | "S" | "P") {
        return need;
    }
    let most = charged_valences(e, charge)
        .last()
        .copied()
        .map_or(0, u32::from);
    let room = most.saturating_sub(deg + stated);
    if room == 0 {
        return Need::default();
    }
    Need {
        count: need.count.min(u8::try_from(room).unwrap_or(u8::MAX)),
        ..need
    }
}

/// Hypervalent S and P, and nitro N: double bonds to their shortest
/// terminal O/S/N first (an acid's terminal oxygens in file order).
fn hypervalent_doubles(
    mol: &Molecule,
    adj: &Adjacency,
    open: &[bool],
    need: &mut [Need],
    order: &mut [BondOrder],
) {
    let pos = &mol.local;
    let elem = |i: usize| mol.atoms[i].element.as_str();
    for i in 0..mol.len() {
        // A nitro N too: its N=O before the matching, which could pair it
        // with the ring carbon it sits on.
        let nitro = elem(i) == "N" && terminal_oxygens(mol, adj, i) >= 2;
        if !open[i] || !(matches!(elem(i), "S" | "P") || nitro) || need[i].count == 0 {
            continue;
        }
        let mut terminal: Vec<(f32, u32, u32)> = adj
            .of(i)
            .iter()
            .filter(|&&(j, k)| {
                is_free(order[k as usize])
                    && matches!(elem(j as usize), "O" | "S" | "N")
                    && adj.degree(j as usize) == 1
                    && need[j as usize].count > 0
            })
            .map(|&(j, k)| (pos[i].distance(pos[j as usize]), j, k))
            .collect();
        // An acid's terminal oxygens take the double bonds in file order,
        // as the carboxylic acids' do in the matching.
        if terminal_oxygens(mol, adj, i) > 1 {
            for t in &mut terminal {
                if is_terminal_o(mol, adj, t.1 as usize) {
                    t.0 = f32::MIN;
                }
            }
        }
        terminal.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        for (_, j, k) in terminal {
            if need[i].count == 0 {
                break;
            }
            order[k as usize] = BondOrder::Double;
            need[i].count -= 1;
            need[j as usize].count = 0;
        }
    }
}

/// Triple bonds between pairs of atoms that need two; then an atom still
/// wanting two (a cumulene centre, a lone nitrile carbon) takes what the
/// matching gives it, one at a time.
fn triple_bonds(conn: &Connection, adj: &Adjacency, need: &mut [Need], order: &mut [BondOrder]) {
    for (k, b) in conn.bonds.iter().enumerate() {
        let (a, c) = (b.a as usize, b.b as usize);
        if is_free(order[k]) && need[a].count >= 2 && need[c].count >= 2 {
            order[k] = BondOrder::Triple;
            need[a].count -= 2;
            need[c].count -= 2;
        }
    }
    // A centre still wanting two with no partner for a triple bond (an
    // azide written N=[N+]=[N-], an allene) takes two double bonds.
    for i in 0..need.len() {
        if need[i].count < 2 {
            continue;
        }
        let ends: Vec<(usize, usize)> = adj
            .of(i)
            .iter()
            .map(|&(j, k)| (k as usize, j as usize))
            .filter(|&(k, j)| is_free(order[k]) && need[j].count >= 1)
            .collect();
        if ends.len() == 2 {
            for (k, j) in ends {
                order[k] = BondOrder::Double;
                need[j].count -= 1;
            }
            need[i].count = 0;
        }
    }
    for nd in need.iter_mut() {
        nd.count = nd.count.min(1);
    }
}

/// The free bonds from atom `i` to atoms that want a π bond, shortest
/// relative to a single bond first, as (partner, bond).
fn candidates(
    mol: &Molecule,
    adj: &Adjacency,
    i: usize,
    order: &[BondOrder],
    need: &[Need],
) -> Vec<(u32, u32)> {
    let pos = &mol.local;
    let elem = |i: usize| mol.atoms[i].element.as_str();
    let mut c: Vec<(f32, u32, u32)> = adj
        .of(i)
        .iter()
        .filter(|&&(j, k)| is_free(order[k as usize]) && need[j as usize].count > 0)
        .map(|&(j, k)| {
            // Shortest relative to a single bond first.
            let single = super::elements::covalent_radius(elem(i)).unwrap_or(0.76)
                + super::elements::covalent_radius(elem(j as usize)).unwrap_or(0.76);
            let mut lj = pos[i].distance(pos[j as usize]) / single as f32;
            if elem(j as usize) == "N" {
                match adj.degree(j as usize) {
                    // A ring bond beats an exocyclic imine where the
                    // geometry cannot tell them apart (cytosine's C4: N3,
                    // not N4).
                    1 => lj += 0.02,
                    // A neutral partner beats a nitrogen that the double
                    // bond would charge (a pyridinium N), as Open Babel
                    // prefers.
                    3 => lj += 0.05,
                    _ => {}
                }
            }
            if is_terminal_o(mol, adj, j as usize) {
                // A carbonyl beats an imine where the geometry cannot
                // tell them apart (an amide, a carboxylic acid).
                lj -= 0.04;
                // Between an acid's terminal oxygens (carboxylic,
                // phosphoric, sulfonic) the first in the file is the
                // double bond and the others carry the hydrogens: the
                // lengths are equal within a crystal structure's error,
                // and it is the choice a bond-order template (RDKit's,
                // which prepares the reference ligands) makes.
                if terminal_oxygens(mol, adj, i) > 1 {
                    lj = f32::MIN;
                }
            }
            (lj, j, k)
        })
        .collect();
    c.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    c.into_iter().map(|(_, j, k)| (j, k)).collect()
}

/// Double bonds: a matching over the bonds between atoms that want one,
/// first among the atoms that must have one (and clear carbonyl oxygens and
/// ring nitrogens), then from those still without to any partner, then
/// taking partners from atoms that only may have one, then between azole
/// nitrogens still without. An atom that must have one and
/// gets none is warned of.
fn match_doubles(
    mol: &Molecule,
    adj: &Adjacency,
    need: &[Need],
    order: &mut [BondOrder],
    warn: &mut Warnings,
) {
    let n = mol.len();
    let mut mate: Vec<Option<(u32, u32)>> = vec![None; n]; // (partner, bond)
    let adjacency: Vec<Vec<(u32, u32)>> = (0..n)
        .map(|i| {
            if need[i].count > 0 {
                candidates(mol, adj, i, order, need)
            } else {
                Vec::new()
            }
        })
        .collect();
    let constrained = |i: usize| (adjacency[i].len(), i);
    // Phase 1: atoms that must have a double bond, among themselves and
    // with the early partners.
    let mut required: Vec<usize> = (0..n)
        .filter(|&i| need[i].count > 0 && need[i].required)
        .collect();
    required.sort_by_key(|&i| constrained(i));
    let required_only: Vec<Vec<(u32, u32)>> = (0..n)
        .map(|i| {
            adjacency[i]
                .iter()
                .copied()
                .filter(|&(j, _)| {
                    need[i].required && (need[j as usize].required || need[j as usize].early)
                })
                .collect()
        })
        .collect();
    for &i in &required {
        if mate[i].is_none() {
            let mut visited = vec![false; n];
            augment(i, &required_only, &mut mate, &mut visited, need, false);
        }
    }
    // Phase 2: the rest of them, with any partner (a terminal O, a
    // five-ring N), re-routing earlier pairs where that helps.
    for &i in &required {
        if mate[i].is_none() {
            let mut visited = vec![false; n];
            augment(i, &adjacency, &mut mate, &mut visited, need, false);
        }
    }
    // Phase 2b: any still without take a partner from an atom that only
    // may have one, along an alternating path (the fused ring of an
    // indazole or a benzimidazole read without hydrogens: its ring
    // nitrogens took π bonds the carbons need, and the one left without
    // carries the hydrogen).
    for &i in &required {
        if mate[i].is_none() {
            let mut visited = vec![false; n];
            augment(i, &adjacency, &mut mate, &mut visited, need, true);
        }
    }
    // Phase 3: azole nitrogens still without one, with each other.
    for i in 0..n {
        if mate[i].is_some() || !need[i].azole || need[i].count == 0 {
            continue;
        }
        if let Some(&(j, k)) = adjacency[i]
            .iter()
            .find(|&&(j, _)| mate[j as usize].is_none() && need[j as usize].azole)
        {
            mate[i] = Some((j, k));
            mate[j as usize] = Some((i as u32, k));
        }
    }
    for i in 0..n {
        if let Some((_, k)) = mate[i] {
            order[k as usize] = BondOrder::Double;
        } else if need[i].required && need[i].count > 0 {
            warn.atom(
                mol,
                i,
                "no Kekulé structure gives this atom the double bond its geometry or valence \
                 asks for; its bonds are read as single"
                    .to_string(),
            );
        }
    }
}

/// Kuhn's augmenting path from free atom `v`: true when `v` got a partner.
/// With `steal`, a partner whose mate cannot be matched again is taken
/// from that mate all the same when the mate only may have a π bond.
fn augment(
    v: usize,
    adjacency: &[Vec<(u32, u32)>],
    mate: &mut [Option<(u32, u32)>],
    visited: &mut [bool],
    need: &[Need],
    steal: bool,
) -> bool {
    visited[v] = true;
    // A free partner first, so optional atoms are not displaced needlessly.
    for &(w, k) in &adjacency[v] {
        let w = w as usize;
        if mate[w].is_none() && !visited[w] && need[w].count > 0 {
            mate[v] = Some((w as u32, k));
            mate[w] = Some((v as u32, k));
            return true;
        }
    }
    for &(w, k) in &adjacency[v] {
        let w = w as usize;
        if visited[w] {
            continue;
        }
        visited[w] = true;
        if let Some((x, _)) = mate[w] {
            let x = x as usize;
            if visited[x] {
                continue;
            }
            // Take w from a mate that can rematch, or (stealing) that only
            // may have a π bond.
            if augment(x, adjacency, mate, visited, need, steal) || (steal && !need[x].required) {
                if mate[x].is_some_and(|(y, _)| y as usize == w) {
                    mate[x] = None;
                }
                mate[v] = Some((w as u32, k));
                mate[w] = Some((v as u32, k));
                return true;
            }
        }
    }
    false
}

/// π bonds an atom needs given its hydrogens.
#[allow(clippy::too_many_arguments)]
fn from_valence(
    e: &str,
    charge: i8,
    deg: u32,
    h: u32,
    stated: u32,
    row: &[(u32, u32)],
    mol: &Molecule,
) -> Need {
    let used = deg + h + stated;
    if matches!(e, "S" | "P") {
        let terminal_o = row
            .iter()
            .filter(|&&(j, _)| matches!(mol.atoms[j as usize].element.as_str(), "O" | "S"))
            .count() as u32;
        let want = match (e, deg + h) {
            ("S", 3) => 1,
            ("S", 4) => 2,
            ("P", 4) => 1,
            ("S", 1) | ("P", 1) | ("P", 2) => 1,
            _ => 0,
        };
        return Need {
            count: want
                .min(terminal_o.max(u32::from(deg + h <= 2)))
                .saturating_sub(stated) as u8,
            required: false,
            early: false,
            azole: false,
        };
    }
    let valences = charged_valences(e, charge);
    let Some(&v) = valences.first() else {
        return Need::default();
    };
    Need {
        count: u8::try_from(u32::from(v).saturating_sub(used))
            .unwrap_or(0)
            .min(2),
        required: true,
        early: false,
        azole: false,
    }
}

/// π bonds an atom of a file-aromatic bond needs (no hydrogens known).
fn aromatic_need(e: &str, deg: u32, stated: u32) -> Need {
    match e {
        "C" if stated == 0 && deg <= 3 => Need {
            count: 1,
            required: true,
            early: false,
            azole: false,
        },
        "N" | "P" if stated == 0 && deg == 2 => Need {
            count: 1,
            required: false,
            early: false,
            azole: false,
        },
        "B" if stated == 0 => Need {
            count: 1,
            required: false,
            early: false,
            azole: false,
        },
        _ => Need::default(),
    }
}

/// π bonds an atom needs by its geometry.
#[allow(clippy::too_many_arguments)]
fn from_geometry(
    i: usize,
    e: &str,
    row: &[(u32, u32)],
    pos: &[Vec3],
    adj: &Adjacency,
    mol: &Molecule,
    flat_ring: u8,
    in_six_ring: bool,
    stated: u32,
) -> Need {
    // `flat_ring == 6` comes only from a trigonal six-ring.
    let ring_trigonal_flag = flat_ring == 6;
    let deg = row.len();
    let angle = mean_angle(i, row, pos);
    // A trigonal atom has some bond shorter than a single bond (an
    // aromatic, double or conjugated one): with every bond at single-bond
    // length the atom is sp3 whatever its angles.
    let conjugated = shortest_bond(i, row, pos, mol) < SHORT_BOND;
    // A two-neighbour sp3 atom opens its angle more than a three-neighbour
    // one (a CH2 between rings reaches 116°).
    let trigonal = if deg == 2 { TRIGONAL + 2.0 } else { TRIGONAL };
    // In a five-ring every angle is near 108° either way: flatness decides.
    let shape = if deg >= 2 && angle > LINEAR {
        2
    } else if (conjugated && ((deg >= 2 && angle > trigonal) || (flat_ring == 5 && deg <= 3)))
        || (flat_ring == 6 && deg <= 3 && ring_trigonal_flag)
    {
        1
    } else {
        0
    };
    let need = |count: u32, required: bool| Need {
        count: u8::try_from(count.saturating_sub(stated)).unwrap_or(0),
        required,
        early: false,
        azole: false,
    };
    match (e, deg) {
        ("C", 4) => need(0, false),
        ("C", 3) => need(u32::from(shape >= 1), true),
        ("C", 2) => need(shape, true),
        // An azide's middle N (linear between two N): the triple bond to
        // its terminal N (N⁻–N⁺≡N).
        ("N", 2)
            if shape == 2
                && row
                    .iter()
                    .all(|&(j, _)| mol.atoms[j as usize].element.as_str() == "N") =>
        {
            need(2, true)
        }
        // A pyridine-like N in a trigonal six-ring must; elsewhere (an
        // amide or pyrrole N with an implicit hydrogen, a dihydropyridine
        // N) it may, and so may a six-ring N beside a carbonyl carbon (a
        // lactam or imide N, as in uracil and guanine), whose carbonyl
        // takes the double bond. A ring N is an early partner.
        ("N", 2) if shape >= 1 => {
            let lactam = beside_carbonyl(i, row, pos, adj, mol);
            Need {
                early: shape == 1 && (in_six_ring || flat_ring == 5),
                azole: shape == 1 && flat_ring == 5,
                ..need(shape.min(1), ring_trigonal_flag && shape == 1 && !lactam)
            }
        }
        // A pyridinium N (three neighbours in a trigonal six-ring) may.
        ("N", 3) if ring_trigonal_flag => need(1, false),
        ("N", 3) => {
            // A nitro or N-oxide nitrogen keeps one N=O.
            let terminal_o = row
                .iter()
                .filter(|&&(j, _)| {
                    mol.atoms[j as usize].element == "O" && adj.degree(j as usize) == 1
                })
                .count();
            // It must: the oxygens only may.
            need(u32::from(terminal_o >= 2), terminal_o >= 2)
        }
        ("S", 3) => need(1, false),
        ("S", 4) => need(2, false),
        ("P", 4) => need(1, false),
        (_, 1) => {
            let j = row[0].0 as usize;
            let other = mol.atoms[j].element.as_str();
            let d = pos[i].distance(pos[j]);
            let double = match (e, other) {
                ("O", "C") if d < CLEAR_CARBONYL => {
                    return Need {
                        early: true,
                        ..need(1, false)
                    };
                }
                ("O", "C") => d < CARBONYL,
                ("O", "N") => d < 1.30,
                ("O", "S" | "P") => true,
                ("N", "C") if d < 1.21 => return need(2, false),
                // An azide's or a diazo group's terminal N.
                ("N", "N") if d < 1.20 => return need(2, false),
                ("N", "C") => d < 1.36,
                ("C", "C") if d < 1.25 => return need(2, false),
                ("C", "C") => d < 1.38,
                ("C", "N") => d < 1.30,
                ("C", "O") => d < 1.30,
                ("S", "C") => d < 1.75,
                ("S", "P") => true,
                _ => false,
            };
            need(u32::from(double), false)
        }
        _ => need(0, false),
    }
}

/// Atom `i`'s shortest bond relative to the sum of the covalent radii
/// (infinite with no bonds).
fn shortest_bond(i: usize, row: &[(u32, u32)], pos: &[Vec3], mol: &Molecule) -> f32 {
    let e = mol.atoms[i].element.as_str();
    row.iter()
        .map(|&(j, _)| {
            let single = super::elements::covalent_radius(e).unwrap_or(0.76)
                + super::elements::covalent_radius(mol.atoms[j as usize].element.as_str())
                    .unwrap_or(0.76);
            pos[i].distance(pos[j as usize]) / single as f32
        })
        .fold(f32::INFINITY, f32::min)
}

/// True when a neighbour of atom `i` is a carbon with a terminal oxygen
/// close enough to be a carbonyl (the length [`from_geometry`] lets a
/// terminal O take a double bond at).
fn beside_carbonyl(
    i: usize,
    row: &[(u32, u32)],
    pos: &[Vec3],
    adj: &Adjacency,
    mol: &Molecule,
) -> bool {
    row.iter().any(|&(c, _)| {
        let c = c as usize;
        mol.atoms[c].element == "C"
            && adj.of(c).iter().any(|&(o, _)| {
                let o = o as usize;
                o != i && is_terminal_o(mol, adj, o) && pos[c].distance(pos[o]) < CARBONYL
            })
    })
}

/// Longest C–O bond (Å) a terminal oxygen may take a double bond at.
const CARBONYL: f32 = 1.40;

/// Longest C–O bond (Å) of a terminal oxygen that the matching's first
/// round pairs (a carbonyl or a carboxyl is 1.21–1.27 Å, a phenol's or an
/// enol's C–O 1.36).
const CLEAR_CARBONYL: f32 = 1.30;

/// Mean angle (degrees) between atom `i`'s bonds (0 with fewer than two).
fn mean_angle(i: usize, row: &[(u32, u32)], pos: &[Vec3]) -> f32 {
    let mut sum = 0.0;
    let mut count = 0;
    for (x, &(a, _)) in row.iter().enumerate() {
        for &(b, _) in &row[x + 1..] {
            let u = pos[a as usize] - pos[i];
            let v = pos[b as usize] - pos[i];
            sum += u.angle_between(v).to_degrees();
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { sum / count as f32 }
}
