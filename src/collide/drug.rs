//! A drug prepared for queries against one receptor collider: its atoms'
//! local positions, radii and the per-atom parts of the contact distance,
//! and its atoms four at a time (groups of atoms close together, see
//! [`super::grouping`], in SIMD lanes) with each group's bounding ball,
//! which move-to-touch and the static check test before the atoms in it.

use glam::{DMat3, DQuat, DVec3, Mat3, Vec3};
use wide::f32x4;

use super::grouping::compact_order;
use super::rule::ContactRule;
use crate::model::Molecule;
use crate::motion::Pose;

/// x, y and z of four points, each in SIMD lanes.
pub type Lanes3 = [f32x4; 3];

/// A rotation applied to four points at a time, in f32 lanes.
#[derive(Debug, Clone, Copy)]
pub struct Turn4 {
    /// The matrix's columns, each element in every lane.
    cols: [Lanes3; 3],
}

impl Turn4 {
    /// The rotation `rotation` (its matrix rounded to f32).
    pub fn new(rotation: DQuat) -> Self {
        let m: Mat3 = DMat3::from_quat(rotation).as_mat3();
        let col = |c: Vec3| [c.x, c.y, c.z].map(f32x4::splat);
        Self {
            cols: [col(m.x_axis), col(m.y_axis), col(m.z_axis)],
        }
    }

    /// Four points turned: within a few f32 roundings of the exact
    /// rotation's values rounded to f32.
    #[inline]
    pub fn apply(&self, [x, y, z]: Lanes3) -> Lanes3 {
        let [cx, cy, cz] = &self.cols;
        std::array::from_fn(|k| cx[k] * x + cy[k] * y + cz[k] * z)
    }
}

/// Bounding balls of four groups of four atoms (see
/// [`DrugAtoms::local_fours`]), in SIMD lanes: a group's atoms lie within
/// `radius` of `centre` (lanes past the last group: radius −∞).
#[derive(Debug, Clone, Copy)]
pub struct Balls4 {
    /// Centres, relative to the drug's centre.
    pub centre: Lanes3,
    /// Radii.
    pub radius: f32x4,
    /// Radii plus the largest [`DrugAtoms::own`] in the group (−∞ past
    /// the last group): the clearance the ball's centre needs for none of
    /// its atoms to have a receptor atom within its own reach.
    pub reach: f32x4,
}

/// A drug atom as a search for its receptor atoms needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Searched {
    /// Its index.
    pub atom: u32,
    /// [`DrugAtoms::reach`]: the radius to search.
    pub reach: f32,
    /// [`DrugAtoms::contact_parts`]: its contact distance with a receptor
    /// atom is that atom's radius plus `parts[polar]`.
    pub parts: [f32; 2],
}

/// `f` of up to four items in SIMD lanes, `pad` in the lanes past them.
fn lanes<T>(items: &[T], f: impl Fn(&T) -> f32, pad: f32) -> f32x4 {
    f32x4::from(std::array::from_fn::<f32, 4, _>(|l| {
        items.get(l).map_or(pad, &f)
    }))
}

/// Drug atoms with their contact-rule constants precomputed.
#[derive(Debug, Clone)]
pub struct DrugAtoms {
    /// Positions relative to the drug's centre.
    pub local: Vec<Vec3>,
    /// Van der Waals radii.
    pub radius: Vec<f32>,
    /// N/O flags.
    pub polar: Vec<bool>,
    /// `r_i − overlap`: add a non-polar partner's radius for the contact distance.
    c_plain: Vec<f32>,
    /// `r_i − overlap − hbond` for polar atoms (equal to `c_plain` otherwise).
    c_polar: Vec<f32>,
    /// Largest contact distance atom `i` can have with a receptor atom, less
    /// that atom's radius (the larger of `c_plain` and `c_polar`).
    own: Vec<f32>,
    /// `own` four atoms at a time (SIMD lanes; the atoms of each group, see
    /// `members`), the last group padded with −∞, which no clearance test
    /// proves.
    own_fours: Vec<[f32; 4]>,
    /// The atoms in group order: group `g` holds atoms `members[4g ..
    /// 4g + 4]` (the last group may hold fewer), spatially compact
    /// ([`compact_order`]).
    members: Vec<u32>,
    /// What a search needs of each atom, in group order (as `members`):
    /// one load for what would be four, from four arrays.
    searched: Vec<Searched>,
    /// `local` four atoms at a time (each group's): x, y and z in SIMD
    /// lanes, the last group padded with the origin.
    local_fours: Vec<Lanes3>,
    /// Bounding balls of the groups of `local_fours`, four groups at a time.
    group_balls: Vec<Balls4>,
    /// Largest contact distance atom `i` can have with any receptor atom.
    pub reach: Vec<f32>,
    /// Largest `reach`.
    pub max_reach: f32,
    /// Distance from the centre to the farthest atom centre.
    pub extent: f64,
}

impl DrugAtoms {
    /// Prepares `drug` for a receptor whose largest atom radius is
    /// `receptor_max_radius`, judged by `rule`.
    pub fn new(drug: &Molecule, rule: &ContactRule, receptor_max_radius: f32) -> Self {
        Self::with_groups(drug, rule, receptor_max_radius, compact_order(&drug.local))
    }

    /// [`Self::new`] with the atoms grouped in runs of four of `members` (a
    /// permutation of the atom indices, as [`compact_order`] gives) instead
    /// of a grouping computed here: for a drug whose shape changes a little
    /// between queries (its torsions turn), the grouping of its first shape
    /// stays compact and need not be computed again. Groups affect only a
    /// query's cost, never its answer.
    ///
    /// # Panics
    /// When `members` is not a permutation of the atom indices.
    pub fn with_groups(
        drug: &Molecule,
        rule: &ContactRule,
        receptor_max_radius: f32,
        members: Vec<u32>,
    ) -> Self {
        assert!(
            {
                let mut seen = vec![false; drug.len()];
                members.len() == drug.len()
                    && members.iter().all(|&i| {
                        seen.get_mut(i as usize)
                            .is_some_and(|s| !std::mem::replace(s, true))
                    })
            },
            "DrugAtoms::with_groups: members must be a permutation of the atoms"
        );
        let radius: Vec<f32> = drug.atoms.iter().map(|a| a.radius).collect();
        let polar: Vec<bool> = drug.atoms.iter().map(|a| a.polar).collect();
        let c_plain: Vec<f32> = radius.iter().map(|r| r - rule.overlap).collect();
        let c_polar: Vec<f32> = radius
            .iter()
            .zip(&polar)
            .map(|(r, &p)| {
                if p {
                    r - rule.overlap - rule.hbond_allowance
                } else {
                    r - rule.overlap
                }
            })
            .collect();
        let own: Vec<f32> = c_plain
            .iter()
            .zip(&c_polar)
            .map(|(a, b)| a.max(*b))
            .collect();
        // The groups: runs of four of `members`, atoms close together.
        let grouped = |v: &[f32]| -> Vec<f32> { members.iter().map(|&i| v[i as usize]).collect() };
        let (own_grouped, local_grouped): (Vec<f32>, Vec<Vec3>) = (
            grouped(&own),
            members.iter().map(|&i| drug.local[i as usize]).collect(),
        );
        let own_fours = own_grouped
            .chunks(4)
            .map(|c| std::array::from_fn(|l| c.get(l).copied().unwrap_or(f32::NEG_INFINITY)))
            .collect();
        let local_fours = local_grouped
            .chunks(4)
            .map(|c| [0, 1, 2].map(|axis| lanes(c, |p| p[axis], 0.0)))
            .collect();
        let balls: Vec<(Vec3, f32, f32)> = local_grouped
            .chunks(4)
            .zip(own_grouped.chunks(4))
            .map(|(c, own)| {
                let lo = c.iter().fold(Vec3::INFINITY, |a, p| a.min(*p));
                let hi = c.iter().fold(Vec3::NEG_INFINITY, |a, p| a.max(*p));
                let centre = 0.5 * (lo + hi);
                let r = c
                    .iter()
                    .map(|p| (p.as_dvec3() - centre.as_dvec3()).length())
                    .fold(0.0, f64::max);
                // Rounded up past f32's rounding of the radius and of the
                // centre's rotation.
                let r = (r * (1.0 + 1e-6) + 1e-5) as f32;
                let own = own.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                (centre, r, r + own)
            })
            .collect();
        let group_balls = balls
            .chunks(4)
            .map(|c| Balls4 {
                centre: [0, 1, 2].map(|axis| lanes(c, |b| b.0[axis], 0.0)),
                radius: lanes(c, |b| b.1, f32::NEG_INFINITY),
                reach: lanes(c, |b| b.2, f32::NEG_INFINITY),
            })
            .collect();
        let reach: Vec<f32> = own.iter().map(|o| o + receptor_max_radius).collect();
        let max_reach = reach.iter().copied().fold(0.0, f32::max);
        let extent = drug
            .local
            .iter()
            .map(|p| f64::from(p.length()))
            .fold(0.0, f64::max);
        let searched = members
            .iter()
            .map(|&i| {
                let i = i as usize;
                Searched {
                    atom: i as u32,
                    reach: reach[i],
                    parts: [c_plain[i], c_polar[i]],
                }
            })
            .collect();
        Self {
            local: drug.local.clone(),
            radius,
            polar,
            c_plain,
            c_polar,
            own,
            own_fours,
            searched,
            members,
            local_fours,
            group_balls,
            reach,
            max_reach,
            extent,
        }
    }

    /// Number of atoms.
    pub fn len(&self) -> usize {
        self.local.len()
    }

    /// True when there are no atoms.
    pub fn is_empty(&self) -> bool {
        self.local.is_empty()
    }

    /// The largest contact distance of drug atom `i` with a receptor atom,
    /// less that atom's radius: `contact(i, r, polar) ≤ r + own(i)`.
    #[inline]
    pub fn own(&self, i: usize) -> f32 {
        self.own[i]
    }

    /// [`DrugAtoms::own`] of the atoms of group `g` (−∞ past the last atom).
    #[inline]
    pub fn own_four(&self, g: usize) -> [f32; 4] {
        self.own_fours[g]
    }

    /// The atom in lane `k % 4` of group `k / 4` (`k` below
    /// [`DrugAtoms::len`]): the groups' atoms in order.
    #[inline]
    pub fn member(&self, k: usize) -> usize {
        self.members[k] as usize
    }

    /// What a search for the atom in lane `k % 4` of group `k / 4` needs
    /// (`k` below [`DrugAtoms::len`]).
    #[inline]
    pub fn searched(&self, k: usize) -> Searched {
        self.searched[k]
    }

    /// Contact distance of drug atom `i` with a receptor atom of radius `r`
    /// and polarity `polar` (see [`ContactRule`]).
    #[inline]
    pub fn contact(&self, i: usize, r: f32, polar: bool) -> f32 {
        r + self.contact_parts(i)[usize::from(polar)]
    }

    /// The parts of atom `i`'s contact distances that do not depend on the
    /// receptor atom's radius: with a non-polar partner (`[0]`) and a
    /// polar one (`[1]`), so that [`DrugAtoms::contact`] is
    /// `r + contact_parts(i)[polar as usize]`. The searches look them up
    /// once per drug atom, before visiting the receptor atoms in its reach.
    #[inline]
    pub fn contact_parts(&self, i: usize) -> [f32; 2] {
        [self.c_plain[i], self.c_polar[i]]
    }

    /// Atom positions in the receptor frame for the relative pose `rel`,
    /// computed in f64 and rounded to f32 once.
    pub fn placed(&self, rel: &Pose) -> impl Iterator<Item = Vec3> + '_ {
        let m = DMat3::from_quat(rel.rotation);
        let t = rel.translation;
        (0..self.len()).map(move |i| self.place(&m, t, i))
    }

    /// Position of atom `i` in the receptor frame for the relative pose with
    /// rotation matrix `m` (`DMat3::from_quat` of its rotation) and
    /// translation `t`: the value [`DrugAtoms::placed`] gives for it.
    #[inline]
    pub fn place(&self, m: &DMat3, t: DVec3, i: usize) -> Vec3 {
        (*m * self.local[i].as_dvec3() + t).as_vec3()
    }

    /// Atom offsets from the centre, four atoms (a group: lane `l` of group
    /// `g` is atom [`DrugAtoms::member`]`(4g + l)`) at a time in SIMD lanes
    /// (x, y, z; the last group padded with zeros).
    pub fn local_fours(&self) -> &[Lanes3] {
        &self.local_fours
    }

    /// Bounding balls of the groups of [`DrugAtoms::local_fours`], four
    /// groups at a time.
    pub fn group_balls(&self) -> &[Balls4] {
        &self.group_balls
    }

    /// [`DrugAtoms::group_balls`] with their centres turned by `turn`.
    pub fn turned_balls_into(&self, turn: &Turn4, out: &mut Vec<Balls4>) {
        out.clear();
        out.extend(self.group_balls.iter().map(|b| Balls4 {
            centre: turn.apply(b.centre),
            ..*b
        }));
    }

    /// Atom offsets from the centre, rotated by `rotation` (f64).
    pub fn rotated(&self, rel: &Pose) -> Vec<DVec3> {
        let mut out = Vec::with_capacity(self.len());
        self.rotated_into(rel, &mut out);
        out
    }

    /// [`DrugAtoms::rotated`] into a reused buffer.
    pub fn rotated_into(&self, rel: &Pose, out: &mut Vec<DVec3>) {
        out.clear();
        if rel.rotation == DQuat::IDENTITY {
            // The identity matrix would give the same values (up to the
            // sign of a zero), nine products per atom later.
            out.extend(self.local.iter().map(|p| p.as_dvec3()));
            return;
        }
        let m = DMat3::from_quat(rel.rotation);
        out.extend(self.local.iter().map(|p| m * p.as_dvec3()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::AtomInfo;
    use crate::model::molecule::test_carbon;

    /// `local_fours` holds `local` in lanes (padded with the origin),
    /// `Turn4` rotates them to within a few f32 roundings of `rotated`'s
    /// f64 values, and every atom lies inside its group's ball, turned or
    /// not.
    #[test]
    fn offsets_in_lanes_are_the_offsets() {
        let mut rng = crate::rng::Rng(11);
        for n in [1usize, 4, 6, 9] {
            let atoms: Vec<AtomInfo> = (0..n).map(|k| test_carbon(k as i64 + 1)).collect();
            let pos: Vec<DVec3> = (0..n).map(|_| rng.in_box(DVec3::splat(8.0))).collect();
            let drug = DrugAtoms::new(
                &Molecule::new("d", atoms, &pos),
                &ContactRule::default(),
                1.8,
            );
            let lane = |g: &Lanes3, i: usize| {
                let [x, y, z] = g.map(|v| v.to_array()[i % 4]);
                Vec3::new(x, y, z)
            };
            let groups = drug.local_fours();
            assert_eq!(groups.len(), n.div_ceil(4));
            // Lane k holds atom member(k), each atom once.
            let mut seen = vec![false; n];
            for k in 0..groups.len() * 4 {
                let want = if k < n {
                    let i = drug.member(k);
                    assert!(!std::mem::replace(&mut seen[i], true), "atom {i} twice");
                    drug.local[i]
                } else {
                    Vec3::ZERO
                };
                assert_eq!(lane(&groups[k / 4], k), want, "lane {k} of {n}");
            }
            let mut balls = Vec::new();
            for _ in 0..20 {
                let axis = rng.in_box(DVec3::ONE).normalize_or(DVec3::Z);
                let pose = Pose::new(
                    DQuat::from_axis_angle(axis, rng.range(-3.0, 3.0)),
                    DVec3::ZERO,
                );
                let turn = Turn4::new(pose.rotation);
                drug.turned_balls_into(&turn, &mut balls);
                assert_eq!(balls.len(), n.div_ceil(16));
                let rotated = drug.rotated(&pose);
                for k in 0..n {
                    let (i, y) = (drug.member(k), rotated[drug.member(k)]);
                    let got = lane(&turn.apply(groups[k / 4]), k).as_dvec3();
                    assert!((got - y).length() < 1e-5, "atom {i}: {got} vs {y}");
                    // Inside its group's ball, turned with it.
                    let (g, b) = (k / 4, &balls[k / 16]);
                    let c = lane(&b.centre, g).as_dvec3();
                    let r = f64::from(b.radius.to_array()[g % 4]);
                    assert!((y - c).length() <= r, "atom {i}: outside its ball");
                }
            }
            // Lanes past the last group are empty balls.
            let last = drug
                .group_balls()
                .last()
                .expect("a group")
                .radius
                .to_array();
            for (g, r) in last.iter().enumerate() {
                assert_eq!(
                    *r == f32::NEG_INFINITY,
                    (balls.len() - 1) * 4 + g >= groups.len()
                );
            }
        }
    }

    /// The largest `own` of each group of four atoms.
    fn own_of_groups(drug: &DrugAtoms) -> Vec<f32> {
        (0..drug.len())
            .step_by(4)
            .map(|first| {
                (first..(first + 4).min(drug.len()))
                    .map(|k| drug.own(drug.member(k)))
                    .fold(f32::NEG_INFINITY, f32::max)
            })
            .collect()
    }

    /// `contact` is the rule's contact distance: radii summed less the
    /// overlap, and less the H-bond allowance only for two N/O atoms.
    #[test]
    fn contact_is_the_rule() {
        let rule = ContactRule::default();
        let atoms: Vec<AtomInfo> = (0..4)
            .map(|k| {
                let mut a = test_carbon(k as i64 + 1);
                a.polar = k % 2 == 1;
                a.radius = 1.5 + 0.1 * k as f32;
                a
            })
            .collect();
        let pos: Vec<DVec3> = (0..4).map(|k| DVec3::X * (3.0 * k as f64)).collect();
        let drug = DrugAtoms::new(&Molecule::new("d", atoms.clone(), &pos), &rule, 1.8);
        for (i, a) in atoms.iter().enumerate() {
            for (r, polar) in [(1.7f32, false), (1.55, true)] {
                let allowance = if a.polar && polar {
                    rule.hbond_allowance
                } else {
                    0.0
                };
                let want = r + a.radius - rule.overlap - allowance;
                assert!(
                    (drug.contact(i, r, polar) - want).abs() < 1e-6,
                    "atom {i} {polar}"
                );
                let parts = drug.contact_parts(i);
                assert_eq!(drug.contact(i, r, polar), r + parts[usize::from(polar)]);
            }
        }
        // A search's view of each atom, in group order, is the atom's own.
        for k in 0..atoms.len() {
            let (s, i) = (drug.searched(k), drug.member(k));
            assert_eq!(s.atom as usize, i);
            assert_eq!((s.reach, s.parts), (drug.reach[i], drug.contact_parts(i)));
        }
    }

    /// The lanes of `own_four` are `own` in group order, padded with −∞ (which
    /// the clearance map never proves) past the last atom; polar atoms
    /// keep the larger of their two contact distances; a group's ball
    /// reaches its radius plus the largest of its atoms'.
    #[test]
    fn own_fours_are_own_in_lanes() {
        let rule = ContactRule::default();
        for n in [1usize, 4, 5, 7] {
            let atoms: Vec<AtomInfo> = (0..n)
                .map(|k| {
                    let mut a = test_carbon(k as i64 + 1);
                    a.polar = k % 2 == 1;
                    a.radius = 1.5 + 0.1 * k as f32;
                    a
                })
                .collect();
            let pos: Vec<DVec3> = (0..n).map(|k| DVec3::X * (2.0 * k as f64)).collect();
            let drug = DrugAtoms::new(&Molecule::new("d", atoms, &pos), &rule, 1.8);
            // Each group's ball reach is its radius plus its largest own.
            for (g, own) in own_of_groups(&drug).iter().enumerate() {
                let b = &drug.group_balls()[g / 4];
                let (radius, reach) = (b.radius.to_array()[g % 4], b.reach.to_array()[g % 4]);
                assert_eq!(reach, radius + own, "group {g} of {n}");
            }
            for k in 0..n.div_ceil(4) * 4 {
                let lane = drug.own_four(k / 4)[k % 4];
                if k < n {
                    let i = drug.member(k);
                    assert_eq!(lane, drug.own(i), "atom {i} of {n}");
                    assert_eq!(lane, drug.radius[i] - rule.overlap);
                } else {
                    assert_eq!(lane, f32::NEG_INFINITY, "padding {k} of {n}");
                }
            }
        }
    }
}
