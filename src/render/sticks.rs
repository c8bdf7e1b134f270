//! The pocket in ball-and-stick and hydrogen bonds as dashed sticks: which
//! atoms become balls and which sticks are drawn (pure; the cylinders are
//! drawn by [`super::cylinders`]).
//!
//! The pocket is the drug and every residue of the other molecules with a
//! heavy atom within a chosen distance of a drug atom. [`Pocket`] keeps a
//! molecule's residues and a hashed grid of its atoms (cells as wide as the
//! distance, built once per molecule and distance, in the molecule's own
//! frame), so finding the pocket costs a few cell lookups per drug atom
//! whatever the molecule's size; the window asks again on frames in which
//! something moved and uploads the bond list only when the set changed.
//! Balls are [`BALL_SCALE`] of the atom's radius; sticks follow the
//! molecules' real bonds ([`crate::model::Molecule::chemistry`]) between
//! two atoms of the set. A hydrogen bond is a row of short sticks
//! ([`super::dashes::dash_ranges`]) from the drug's atom to the receptor's.

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;

use super::cylinders::Stick;
use super::dashes::dash_ranges;
use super::spheres::SphereRenderer;
use crate::model::Molecule;
use crate::session::{LiveScore, Session, labels};

/// Share of an atom's radius its ball has in ball-and-stick.
pub const BALL_SCALE: f32 = 0.25;
/// Radius of a bond's stick, Å.
pub const BOND_RADIUS: f32 = 0.16;
/// Radius of a hydrogen bond's dashes, Å.
pub const HBOND_RADIUS: f32 = 0.07;
/// Dash and gap of a hydrogen bond, Å.
pub const HBOND_DASH: (f64, f64) = (0.3, 0.2);
/// Hydrogen bonds: deep sky blue (sRGB 0, 191, 255, as ChimeraX draws
/// them), in linear RGB.
pub const HBOND_COLOR: [f32; 3] = [0.0, 0.521, 1.0];
/// The default distance from the drug of the residues shown, Å.
pub const DEFAULT_DISTANCE: f64 = 5.0;
/// The distances the HUD offers, Å.
pub const DISTANCE_RANGE: std::ops::RangeInclusive<f64> = 2.0..=12.0;

/// A residue of a molecule: its atoms and how it is labelled.
#[derive(Debug, Clone, PartialEq)]
pub struct Residue {
    /// Its atoms (indices into the molecule's atoms), ascending.
    pub atoms: Vec<u32>,
    /// `ASP A 27`.
    pub label: String,
    /// Where its label goes: the alpha carbon, else the atom nearest the
    /// residue's centre.
    pub anchor: u32,
}

/// The residues of `m`, in the order of their first atoms: atoms with the
/// same residue name, chain, number and insertion code, wherever they are
/// in the file.
pub fn residues(m: &Molecule) -> Vec<Residue> {
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut out: Vec<Residue> = Vec::new();
    let mut current: Option<usize> = None;
    for (i, a) in m.atoms.iter().enumerate() {
        let same = i > 0 && {
            let p = &m.atoms[i - 1];
            p.residue == a.residue
                && p.chain == a.chain
                && p.seq == a.seq
                && p.insertion == a.insertion
        };
        let k = match current.filter(|_| same) {
            Some(k) => k,
            None => {
                let label = labels::residue(a);
                *index.entry(label.clone()).or_insert_with(|| {
                    out.push(Residue {
                        atoms: Vec::new(),
                        label,
                        anchor: i as u32,
                    });
                    out.len() - 1
                })
            }
        };
        out[k].atoms.push(i as u32);
        current = Some(k);
    }
    for r in &mut out {
        r.anchor = anchor(m, &r.atoms);
    }
    out
}

fn anchor(m: &Molecule, atoms: &[u32]) -> u32 {
    if let Some(&ca) = atoms
        .iter()
        .find(|&&i| m.atoms[i as usize].name.as_str().trim() == "CA")
    {
        return ca;
    }
    let centre = atoms
        .iter()
        .map(|&i| m.local[i as usize].as_dvec3())
        .sum::<DVec3>()
        / atoms.len().max(1) as f64;
    atoms
        .iter()
        .copied()
        .min_by(|&a, &b| {
            let da = (m.local[a as usize].as_dvec3() - centre).length_squared();
            let db = (m.local[b as usize].as_dvec3() - centre).length_squared();
            da.total_cmp(&db).then(a.cmp(&b))
        })
        .unwrap_or(0)
}

/// A molecule's residues and a grid of its atoms for finding those near
/// the drug.
#[derive(Debug, Clone)]
pub struct Pocket {
    distance: f64,
    /// The residues.
    pub residues: Vec<Residue>,
    residue_of: Vec<u32>,
    grid: HashMap<[i64; 3], Vec<u32>>,
}

fn cell_of(p: DVec3, size: f64) -> [i64; 3] {
    let c = (p / size).floor();
    [c.x as i64, c.y as i64, c.z as i64]
}

impl Pocket {
    /// The residues of `m` and a grid for finding those within `distance`
    /// Å (clamped to [`DISTANCE_RANGE`]) of a point.
    pub fn new(m: &Molecule, distance: f64) -> Self {
        let residues = residues(m);
        let mut residue_of = vec![0u32; m.len()];
        for (k, r) in residues.iter().enumerate() {
            for &a in &r.atoms {
                residue_of[a as usize] = k as u32;
            }
        }
        let mut p = Self {
            distance: 0.0,
            residues,
            residue_of,
            grid: HashMap::new(),
        };
        p.set_distance(m, distance);
        p
    }

    /// The distance residues are chosen within, Å.
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// Chooses residues within `distance` Å (clamped to
    /// [`DISTANCE_RANGE`]) from now on; the grid is rebuilt when it changes.
    pub fn set_distance(&mut self, m: &Molecule, distance: f64) {
        let d = if distance.is_finite() {
            distance.clamp(*DISTANCE_RANGE.start(), *DISTANCE_RANGE.end())
        } else {
            DEFAULT_DISTANCE
        };
        if d == self.distance && !self.grid.is_empty() {
            return;
        }
        self.distance = d;
        self.grid.clear();
        for (i, p) in m.local.iter().enumerate() {
            self.grid
                .entry(cell_of(p.as_dvec3(), d))
                .or_default()
                .push(i as u32);
        }
    }

    /// The residues (indices into [`Pocket::residues`], ascending) with an
    /// atom of `m` within the distance of one of `points`, given in `m`'s
    /// own frame (relative to its centre).
    pub fn select(&self, m: &Molecule, points: &[DVec3]) -> Vec<u32> {
        let d = self.distance;
        let d2 = d * d;
        let mut hit = vec![false; self.residues.len()];
        for &q in points {
            let c = cell_of(q, d);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(atoms) = self.grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &a in atoms {
                            let r = self.residue_of[a as usize] as usize;
                            if !hit[r]
                                && (m.local[a as usize].as_dvec3() - q).length_squared() <= d2
                            {
                                hit[r] = true;
                            }
                        }
                    }
                }
            }
        }
        (0..self.residues.len() as u32)
            .filter(|&r| hit[r as usize])
            .collect()
    }
}

/// The pocket of a session: per molecule other than the drug, its
/// [`Pocket`], and the residues chosen now.
#[derive(Debug, Clone, Default)]
pub struct PocketSet {
    /// (molecule, its pocket, its chosen residues).
    pub parts: Vec<(usize, Pocket, Vec<u32>)>,
    /// The drug.
    pub drug: Option<usize>,
}

/// What ball-and-stick draws: the atoms shown as balls and the bonds
/// between them, as `(molecule, atom)` and `((molecule, a), (molecule, b))`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BallAndStick {
    /// Atoms drawn as balls, sorted.
    pub balls: Vec<(usize, usize)>,
    /// Bonds drawn as sticks: molecule, and its two atoms.
    pub bonds: Vec<(usize, u32, u32)>,
}

impl PocketSet {
    /// The pockets of `session`'s molecules around its drug, within
    /// `distance` Å; nothing chosen yet.
    pub fn new(session: &Session, distance: f64) -> Self {
        let drug = session.drug().filter(|_| session.bodies().len() > 1);
        let parts = session
            .bodies()
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != drug)
            .map(|(k, b)| (k, Pocket::new(&b.molecule, distance), Vec::new()))
            .collect();
        Self { parts, drug }
    }

    /// True when this set was made for `session`'s molecules and drug.
    pub fn fits(&self, session: &Session) -> bool {
        let drug = session.drug().filter(|_| session.bodies().len() > 1);
        drug == self.drug
            && self.parts.len() + usize::from(drug.is_some()) == session.bodies().len()
    }

    /// The distance residues are chosen within, Å.
    pub fn distance(&self) -> f64 {
        self.parts
            .first()
            .map_or(DEFAULT_DISTANCE, |(_, p, _)| p.distance())
    }

    /// Chooses again the residues near the drug where it stands now, with
    /// `distance` Å; `true` when the choice changed.
    pub fn update(&mut self, session: &Session, distance: f64) -> bool {
        let bodies = session.bodies();
        let Some(drug) = self.drug.and_then(|d| bodies.get(d)) else {
            return false;
        };
        let world: Vec<DVec3> = drug
            .molecule
            .local
            .iter()
            .map(|p| drug.pose.transform_point(p.as_dvec3()))
            .collect();
        let mut changed = false;
        for (k, pocket, chosen) in &mut self.parts {
            let Some(b) = bodies.get(*k) else { continue };
            pocket.set_distance(&b.molecule, distance);
            let to_local = b.pose.inverse();
            let points: Vec<DVec3> = world.iter().map(|&p| to_local.transform_point(p)).collect();
            let now = pocket.select(&b.molecule, &points);
            if now != *chosen {
                *chosen = now;
                changed = true;
            }
        }
        changed
    }

    /// The balls and bonds of the drug and the chosen residues.
    pub fn ball_and_stick(&self, session: &Session) -> BallAndStick {
        let mut out = BallAndStick::default();
        let bodies = session.bodies();
        if let Some(d) = self.drug.filter(|&d| d < bodies.len()) {
            let m = &bodies[d].molecule;
            out.balls.extend((0..m.len()).map(|i| (d, i)));
            out.bonds
                .extend(m.chemistry().bonds.iter().map(|b| (d, b.a, b.b)));
        }
        for (k, pocket, chosen) in &self.parts {
            let Some(b) = bodies.get(*k) else { continue };
            if chosen.is_empty() {
                continue;
            }
            let mut inside = vec![false; b.molecule.len()];
            for &r in chosen {
                for &a in &pocket.residues[r as usize].atoms {
                    inside[a as usize] = true;
                    out.balls.push((*k, a as usize));
                }
            }
            // Each bond once, from its lower atom, through the chosen
            // atoms' neighbours only (not every bond of the molecule).
            let adjacency = &b.molecule.chemistry().adjacency;
            for &(_, a) in out.balls.iter().filter(|(m, _)| m == k) {
                for &(n, _) in adjacency.of(a) {
                    if n as usize > a && inside[n as usize] {
                        out.bonds.push((*k, a as u32, n));
                    }
                }
            }
        }
        out.balls.sort_unstable();
        out.bonds.sort_unstable();
        out
    }

    /// The labels of the chosen residues and where they go:
    /// (label, molecule, anchor atom).
    pub fn labels(&self) -> Vec<(&str, usize, usize)> {
        let mut out = Vec::new();
        for (k, pocket, chosen) in &self.parts {
            for &r in chosen {
                let res = &pocket.residues[r as usize];
                out.push((res.label.as_str(), *k, res.anchor as usize));
            }
        }
        out
    }
}

/// Where each molecule's atoms start in the sphere renderer's atom list
/// (the molecules' atoms one after another, in order).
pub fn atom_offsets(session: &Session) -> Vec<u32> {
    let mut at = 0u32;
    session
        .bodies()
        .iter()
        .map(|b| {
            let o = at;
            at = at.saturating_add(b.molecule.len() as u32);
            o
        })
        .collect()
}

/// The sticks of `bonds` ([`BallAndStick::bonds`]) for the renderer.
pub fn bond_sticks(offsets: &[u32], bonds: &[(usize, u32, u32)]) -> Vec<Stick> {
    bonds
        .iter()
        .filter_map(|&(k, a, b)| {
            let o = *offsets.get(k)?;
            Some(Stick::bond(o + a, o + b, BOND_RADIUS))
        })
        .collect()
}

/// The dashes of `score`'s hydrogen bonds at the molecules' poses now,
/// each from the drug's atom towards the receptor's.
pub fn hbond_sticks(session: &Session, offsets: &[u32], score: &LiveScore) -> Vec<Stick> {
    let bodies = session.bodies();
    let (Some(d), Some(r)) = (bodies.get(score.drug), bodies.get(score.receptor)) else {
        return Vec::new();
    };
    let (Some(&od), Some(&or)) = (offsets.get(score.drug), offsets.get(score.receptor)) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for h in &score.score.hbonds {
        let (Some(a), Some(b)) = (
            d.molecule.local.get(h.drug_atom as usize),
            r.molecule.local.get(h.receptor_atom as usize),
        ) else {
            continue;
        };
        let pa = d.pose.transform_point(a.as_dvec3());
        let pb = r.pose.transform_point(b.as_dvec3());
        let len = (pb - pa).length();
        for (t0, t1) in dash_ranges(len, HBOND_DASH.0, HBOND_DASH.1) {
            out.push(Stick::piece(
                od + h.drug_atom,
                or + h.receptor_atom,
                (t0 as f32, t1 as f32),
                HBOND_RADIUS,
                Some(HBOND_COLOR),
            ));
        }
    }
    out
}

/// Scales of atoms' radii: [`BALL_SCALE`] for each of `balls`, 1 for the
/// atoms that were balls and are not now. `was` and `balls` are sorted.
pub fn radius_changes(
    was: &[(usize, usize)],
    balls: &[(usize, usize)],
) -> Vec<(usize, usize, f32)> {
    let now: std::collections::BTreeSet<_> = balls.iter().copied().collect();
    let before: std::collections::BTreeSet<_> = was.iter().copied().collect();
    let mut out: BTreeMap<(usize, usize), f32> = BTreeMap::new();
    for &a in now.difference(&before) {
        out.insert(a, BALL_SCALE);
    }
    for &a in before.difference(&now) {
        out.insert(a, 1.0);
    }
    out.into_iter().map(|((k, i), s)| (k, i, s)).collect()
}

/// The ball-and-stick and hydrogen-bond views of a renderer: what they
/// show now, so that a frame uploads only what changed.
#[derive(Debug, Clone, Default)]
pub struct StickView {
    pocket: Option<PocketSet>,
    balls: Vec<(usize, usize)>,
}

impl StickView {
    /// Shows the pocket within `distance` Å in ball-and-stick (`None`:
    /// spheres everywhere) for `session` as it stands: the residues are
    /// chosen again, and radii and bonds are uploaded only when the set
    /// changed. Returns whether anything was uploaded.
    pub fn show_pocket(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        spheres: &mut SphereRenderer,
        session: &Session,
        distance: Option<f64>,
    ) -> bool {
        let Some(d) = distance else {
            if self.pocket.take().is_none() && self.balls.is_empty() {
                return false;
            }
            let was = std::mem::take(&mut self.balls);
            spheres.set_radius_scales(queue, &radius_changes(&was, &[]));
            if spheres
                .cylinders_made()
                .is_some_and(|c| !c.bonds().is_empty())
            {
                spheres.cylinders(device).set_bonds(device, queue, &[]);
            }
            return true;
        };
        if !self.pocket.as_ref().is_some_and(|p| p.fits(session)) {
            self.pocket = Some(PocketSet::new(session, d));
        }
        let Some(pocket) = &mut self.pocket else {
            return false;
        };
        let first = self.balls.is_empty();
        if !pocket.update(session, d) && !first {
            return false;
        }
        let bs = pocket.ball_and_stick(session);
        spheres.set_radius_scales(queue, &radius_changes(&self.balls, &bs.balls));
        self.balls = bs.balls;
        let sticks = bond_sticks(&atom_offsets(session), &bs.bonds);
        spheres.cylinders(device).set_bonds(device, queue, &sticks);
        true
    }

    /// Shows the hydrogen bonds of `score` as dashed sticks (`None`: none).
    /// Returns whether anything was uploaded.
    pub fn show_hbonds(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        spheres: &mut SphereRenderer,
        session: &Session,
        score: Option<&LiveScore>,
    ) -> bool {
        let dashes = score
            .map(|s| hbond_sticks(session, &atom_offsets(session), s))
            .unwrap_or_default();
        if dashes.is_empty()
            && spheres
                .cylinders_made()
                .is_none_or(|c| c.dashes().is_empty())
        {
            return false;
        }
        spheres.cylinders(device).set_dashes(device, queue, &dashes)
    }

    /// The chosen residues' labels and where they go: (label, molecule,
    /// anchor atom); empty while ball-and-stick is off.
    pub fn labels(&self) -> Vec<(&str, usize, usize)> {
        self.pocket
            .as_ref()
            .map(PocketSet::labels)
            .unwrap_or_default()
    }

    /// The distance residues are chosen within now, if ball-and-stick is on.
    pub fn distance(&self) -> Option<f64> {
        self.pocket.as_ref().map(PocketSet::distance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};
    use crate::session::Settings;

    /// Brute force: every residue with an atom within `d` of a point.
    fn brute(m: &Molecule, res: &[Residue], points: &[DVec3], d: f64) -> Vec<u32> {
        let mut out = Vec::new();
        for (k, r) in res.iter().enumerate() {
            let near = r.atoms.iter().any(|&a| {
                points
                    .iter()
                    .any(|q| (m.local[a as usize].as_dvec3() - *q).length() <= d)
            });
            if near {
                out.push(k as u32);
            }
        }
        out
    }

    fn random_protein(seed: u64) -> Molecule {
        use crate::model::{AtomInfo, Label};
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let mut atoms = Vec::new();
        let mut pos = Vec::new();
        for i in 0..600 {
            let a = AtomInfo {
                serial: i + 1,
                name: if i % 6 == 1 { "CA" } else { "C" }.into(),
                residue: "ALA".into(),
                seq: i / 6 + 1,
                insertion: Label::EMPTY,
                chain: "A".into(),
                element: "C".into(),
                radius: 1.7,
                polar: false,
                hetero: false,
            };
            atoms.push(a);
            pos.push(DVec3::new(next(), next(), next()) * 30.0 - DVec3::splat(15.0));
        }
        Molecule::new("random", atoms, &pos)
    }

    #[test]
    fn the_pocket_is_what_brute_force_finds() {
        for seed in 1..6u64 {
            let m = random_protein(seed);
            for d in [2.0, 3.5, 5.0, 8.0, 12.0] {
                let pocket = Pocket::new(&m, d);
                let mut rng = seed * 7919;
                let points: Vec<DVec3> = (0..20)
                    .map(|i| {
                        rng = rng.wrapping_mul(2_862_933_555_777_941_757).wrapping_add(3);
                        let f = |s: u64| ((rng >> s) & 0xffff) as f64 / 65535.0 * 24.0 - 12.0;
                        DVec3::new(f(1), f(17), f(33)) + DVec3::splat(i as f64 * 0.01)
                    })
                    .collect();
                let got = pocket.select(&m, &points);
                assert_eq!(
                    got,
                    brute(&m, &pocket.residues, &points, d),
                    "seed {seed} d {d}"
                );
                assert!(!got.is_empty());
                if d <= 5.0 {
                    assert!(got.len() < pocket.residues.len(), "seed {seed} d {d}");
                }
            }
        }
    }

    #[test]
    fn residues_group_atoms_and_anchor_at_the_alpha_carbon() {
        let m = random_protein(3);
        let r = residues(&m);
        assert_eq!(r.len(), 100);
        assert_eq!(r[0].label, "ALA A 1");
        assert_eq!(r[0].atoms, (0..6).collect::<Vec<u32>>());
        assert_eq!(r[0].anchor, 1, "the CA");
        assert_eq!(r[99].anchor, 595);
    }

    #[test]
    fn the_set_changes_only_when_the_drug_moves_enough() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        let mut p = PocketSet::new(&s, 5.0);
        assert!(p.fits(&s));
        p.update(&s, 5.0);
        // The same pose again: the same set.
        assert!(!p.update(&s, 5.0));
        let bs = p.ball_and_stick(&s);
        // Every bond joins two balls.
        for &(k, a, b) in &bs.bonds {
            assert!(bs.balls.binary_search(&(k, a as usize)).is_ok());
            assert!(bs.balls.binary_search(&(k, b as usize)).is_ok());
        }
        // With the widest distance the rings are in the pocket: its bonds
        // are exactly the molecules' bonds between two balls.
        let drug = p.drug.expect("a drug");
        let other = 1 - drug;
        let to = s.bodies()[other].pose.translation - s.bodies()[drug].pose.translation;
        s.step(
            &crate::session::FrameInput::with_commands(&[crate::session::Command::MoveBy {
                translate: to,
                axis: DVec3::Z,
                degrees: 0.0,
            }]),
            0.0,
        );
        assert!(p.update(&s, 12.0));
        let bs = p.ball_and_stick(&s);
        let mut want = Vec::new();
        for (k, b) in s.bodies().iter().enumerate() {
            for bond in &b.molecule.chemistry().bonds {
                let ball = |a: u32| bs.balls.binary_search(&(k, a as usize)).is_ok();
                if ball(bond.a) && ball(bond.b) {
                    want.push((k, bond.a, bond.b));
                }
            }
        }
        want.sort_unstable();
        assert!(bs.balls.iter().any(|&(k, _)| k == other), "rings chosen");
        assert_eq!(bs.bonds, want);
        let offsets = atom_offsets(&s);
        assert_eq!(offsets[0], 0);
        assert_eq!(
            offsets.get(1).copied(),
            Some(s.bodies()[0].molecule.len() as u32)
        );
        let sticks = bond_sticks(&offsets, &bs.bonds);
        assert_eq!(sticks.len(), bs.bonds.len());
    }

    #[test]
    fn radius_changes_shrink_new_balls_and_restore_old_ones() {
        let was = vec![(0, 1), (0, 2), (1, 0)];
        let now = vec![(0, 2), (1, 0), (1, 1)];
        assert_eq!(
            radius_changes(&was, &now),
            vec![(0, 1, 1.0), (1, 1, BALL_SCALE)]
        );
        assert!(radius_changes(&now, &now).is_empty());
    }
}
