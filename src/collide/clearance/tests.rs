//! The clearance map against exact clearances: every vertex rounded down,
//! points proved one and four at a time, NaN atoms, lattices past 2²⁴
//! vertices.

use super::*;
use bump_testkit::Rng;
use glam::DVec3;

fn exact(atoms: &[Vec4], x: Vec3) -> f64 {
    atoms
        .iter()
        .map(|a| (x.as_dvec3() - a.truncate().as_dvec3()).length() - f64::from(a.w))
        .fold(f64::INFINITY, f64::min)
}

/// `n` atoms of radius 1.2–2 Å, centres in the cube `±half`.
fn random_atoms(rng: &mut Rng, n: usize, half: f64) -> Vec<Vec4> {
    (0..n)
        .map(|_| {
            let q = rng.in_box(DVec3::splat(half)).as_vec3();
            q.extend(rng.range(1.2, 2.0) as f32)
        })
        .collect()
}

/// Every vertex holds its clearance (capped) rounded down to a step,
/// whichever slab and thread filled it: none is left at the cap by a
/// slab that missed an atom, none is above the exact value.
#[test]
fn every_vertex_holds_its_clearance_rounded_down() {
    let mut rng = Rng(3);
    let atoms = random_atoms(&mut rng, 60, 10.0);
    let map = Clearance::build(&atoms).expect("atoms");
    let [nx, ny, nz] = map.dims;
    assert!(nz > slab_planes(nx, ny), "{nz} planes: one slab only");
    let [ox, oy, oz] = map.origin.to_array().map(f64::from);
    let h = f64::from(map.spacing);
    let mut below_cap = 0;
    for iz in 0..nz {
        for iy in 0..ny {
            for ix in 0..nx {
                let v = DVec3::new(ox + ix as f64 * h, oy + iy as f64 * h, oz + iz as f64 * h);
                let f = exact(&atoms, v.as_vec3()).min(f64::from(CAP));
                let stored = f64::from(map.values[(iz * ny + iy) * nx + ix]) / 32.0;
                // 0 stands for any clearance up to 1/32 Å, negative too.
                assert!(
                    stored <= f.max(0.0),
                    "vertex {ix} {iy} {iz}: {stored} above {f}"
                );
                assert!(
                    stored >= f - 1.0 / 32.0 - 2e-3 || f <= 0.0,
                    "vertex {ix} {iy} {iz}: {stored} far below {f}"
                );
                below_cap += usize::from(f < f64::from(CAP) - 0.1);
            }
        }
    }
    assert!(below_cap > 1000, "{below_cap}");
}

/// Atoms with NaN coordinates or radius (either sign of NaN, which
/// sorts first or last) among real ones change neither the lattice nor
/// any stored value.
#[test]
fn nan_atoms_change_nothing() {
    let mut rng = Rng(9);
    let atoms = random_atoms(&mut rng, 80, 12.0);
    let clean = Clearance::build(&atoms).expect("atoms");
    let mut mixed = atoms.clone();
    for (k, bad) in [
        Vec4::new(0.0, 0.0, -f32::NAN, 1.5),
        Vec4::new(1.0, f32::NAN, f32::NAN, 1.5),
        Vec4::new(2.0, 2.0, 2.0, f32::NAN),
        Vec4::new(-3.0, 1.0, f32::NAN, 1.7),
    ]
    .into_iter()
    .enumerate()
    {
        mixed.insert(k * 20, bad);
    }
    let map = Clearance::build(&mixed).expect("atoms");
    assert_eq!(map.dims, clean.dims);
    assert!(map.values == clean.values, "a NaN atom changed the map");
}

/// A lattice that would reach beyond f32's rounding room gets no map
/// (its queries run without one); one just inside it does.
#[test]
fn lattices_beyond_the_rounding_room_are_not_built() {
    let atom = |x: f32| Vec4::new(x, 0.0, 0.0, 1.7);
    let reach = CAP + 1.7 + FINEST;
    let inside = MAX_LATTICE_COORDINATE - reach - 2.0;
    assert!(Clearance::build(&[atom(-inside), atom(inside)]).is_some());
    let outside = MAX_LATTICE_COORDINATE - reach + 1.0;
    assert!(Clearance::build(&[atom(0.0), atom(outside)]).is_none());
    assert!(Clearance::build(&[atom(-1e5), atom(1e5)]).is_none());
}

/// Random atoms, random points and thresholds: whenever the map says
/// clear, the exact clearance is larger; and it does say clear for most
/// points well away from the atoms.
#[test]
fn clear_is_a_lower_bound_of_the_exact_clearance() {
    let mut rng = Rng(5);
    let atoms = random_atoms(&mut rng, 300, 15.0);
    let map = Clearance::build(&atoms).expect("atoms");
    assert_eq!(map.spacing(), FINEST);
    let (mut said, mut could) = (0, 0);
    for _ in 0..20_000 {
        let x = rng.in_box(DVec3::splat(25.0)).as_vec3();
        let d = rng.range(0.0, 3.2) as f32;
        let f = exact(&atoms, x);
        let clear = map.clear(x, d);
        if clear {
            said += 1;
            assert!(f > f64::from(d), "{x} d {d}: exact {f}");
        }
        // The nearest vertex proves it past twice its distance
        // (at most half a cell diagonal) plus the rounding of the values.
        if f > f64::from(d) + f64::from(FINEST) * 3f64.sqrt() + 0.05 && d < 2.0 {
            could += 1;
            assert!(clear, "{x} d {d}: exact {f} not proved");
        }
    }
    assert!(said > 1000 && could > 1000, "said {said}, could {could}");
}

/// Four points at a time answer exactly as [`Clearance::clear`] does
/// one at a time, for points inside, on the edge of and beyond the
/// lattice, NaN and infinite, and thresholds out of range; padding
/// lanes are never set.
#[test]
fn four_lanes_answer_as_one_at_a_time() {
    let mut rng = Rng(11);
    let atoms = random_atoms(&mut rng, 200, 12.0);
    let map = Clearance::build(&atoms).expect("atoms");
    let [nx, ny, nz] = map.dims;
    let far = map.origin + Vec3::new(nx as f32, ny as f32, nz as f32) * map.spacing;
    let (mut proved, mut left, mut beyond) = (0, 0, 0);
    for k in 0..20_000 {
        let mut x = [Vec3::ZERO; 4];
        let mut d = [0.0f32; 4];
        for l in 0..4 {
            x[l] = rng.in_box(DVec3::splat(22.0)).as_vec3();
            d[l] = rng.range(-0.2, 3.2) as f32;
        }
        if k % 97 == 0 {
            x[1] = Vec3::new(f32::NAN, 0.0, 0.0);
            x[2] = Vec3::new(f32::INFINITY, 1.0, 1.0);
            d[3] = f32::NAN;
        }
        if k % 89 == 0 {
            // On the lattice's edges: its first vertex, its last, and
            // just inside and just past its far side.
            let o = map.origin;
            let end = far - Vec3::splat(map.spacing);
            x[0] = o;
            x[1] = end - Vec3::splat(1e-3);
            x[2] = end + Vec3::splat(1e-3);
            x[3] = Vec3::new(end.x - 1e-3, o.y + 1.0, end.z + 1e-3);
        }
        let lanes = |f: fn(&Vec3) -> f32| f32x4::from(x.each_ref().map(f));
        let count = 1 + k % 4;
        let padded: [f32; 4] = std::array::from_fn(|l| if l < count { d[l] } else { 0.0 });
        let bits = map.clear_nearest4(
            [lanes(|v| v.x), lanes(|v| v.y), lanes(|v| v.z)],
            f32x4::from(padded),
        );
        assert_eq!(bits >> count, 0, "padding lanes set: {bits:b}");
        for l in 0..count {
            let four = bits & (1 << l) != 0;
            assert_eq!(four, map.clear(x[l], d[l]), "{} d {}", x[l], d[l]);
            proved += usize::from(four);
            left += usize::from(!four);
            let outside = (x[l].cmplt(map.origin) | x[l].cmpgt(far)).any();
            beyond += usize::from(four && outside);
        }
    }
    assert!(
        proved > 1000 && left > 1000 && beyond > 100,
        "{proved} {left} {beyond}"
    );
}

/// A lattice of more than 2²⁴ vertices (f32 holds integers exactly only
/// that far): four points at a time still answer as one at a time, and
/// never claim more than the exact clearance. (An index computed in f32
/// past 2²⁴ would read a neighbouring vertex.)
#[test]
fn lattices_past_two_to_the_24_vertices_answer_exactly() {
    let mut rng = Rng(13);
    let atoms = random_atoms(&mut rng, 1500, 30.0);
    let map = Clearance::build(&atoms).expect("atoms");
    assert_eq!(map.spacing(), FINEST);
    assert!(map.bytes() > 1 << 24, "{} vertices", map.bytes());
    let (mut proved, mut high) = (0, 0);
    for _ in 0..20_000 {
        // Near an atom, where the bound is tight.
        let x: [Vec3; 4] = std::array::from_fn(|_| {
            let a = atoms[(rng.next_u64() % atoms.len() as u64) as usize].truncate();
            a + rng.in_box(DVec3::splat(4.5)).as_vec3()
        });
        let d: [f32; 4] = std::array::from_fn(|_| rng.range(0.1, 3.0) as f32);
        let lanes = |f: fn(&Vec3) -> f32| f32x4::from(x.each_ref().map(f));
        let got = map.clear_nearest4(
            [lanes(|v| v.x), lanes(|v| v.y), lanes(|v| v.z)],
            f32x4::from(d),
        );
        for l in 0..4 {
            let four = got & (1 << l) != 0;
            assert_eq!(four, map.clear(x[l], d[l]), "{} d {}", x[l], d[l]);
            if four {
                let f = exact(&atoms, x[l]);
                assert!(f > f64::from(d[l]), "{} d {}: exact {f}", x[l], d[l]);
                proved += 1;
                high += usize::from(map.nearest(x[l]).0 >= 1 << 24);
            }
        }
    }
    assert!(
        proved > 5000 && high > 2000,
        "{proved} proved, {high} past 2^24"
    );
}

/// Points on and beyond the lattice's edge, NaN and infinite points, and
/// thresholds out of range never panic and never claim too much.
#[test]
fn edges_and_absurd_input() {
    let atoms = [Vec4::new(0.0, 0.0, 0.0, 1.5), Vec4::new(3.0, 0.0, 0.0, 1.7)];
    let map = Clearance::build(&atoms).expect("atoms");
    // More than half a spacing beyond the lattice (where the clearance
    // exceeds the cap) every usable threshold is proved, at any
    // distance; a NaN point proves nothing.
    for x in [
        Vec3::new(100.0, 0.0, 0.0),
        Vec3::new(-1e30, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1e30),
        Vec3::splat(f32::INFINITY),
        Vec3::splat(f32::NEG_INFINITY),
    ] {
        assert!(map.clear(x, 1.0), "{x}");
        assert!(map.clear(x, CAP - 2.0 * ROUNDING), "{x}");
    }
    assert!(!map.clear(Vec3::splat(f32::NAN), 1.0));
    assert!(!map.clear(Vec3::new(0.0, f32::NAN, 100.0), 1.0));
    // Just within half a spacing of the edge, the edge vertex's own
    // value (the cap) proves a threshold below it less the distance,
    // and not one above.
    let edge = map.origin.x + (map.dims[0] - 1) as f32 * map.spacing;
    let x = Vec3::new(edge + 0.4 * map.spacing, 0.0, 0.0);
    assert!(map.clear(x, CAP - 0.5 * map.spacing - 0.05));
    assert!(!map.clear(x, CAP - 0.3 * map.spacing));
    assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), 0.0));
    assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), CAP));
    assert!(!map.clear(Vec3::new(100.0, 0.0, 0.0), f32::NAN));
    // Inside an atom, and just outside its surface.
    assert!(!map.clear(Vec3::ZERO, 0.1));
    assert!(!map.clear(Vec3::new(-1.6, 0.0, 0.0), 0.2));
    // Along the x axis past the second atom, the clearance is x − 4.7.
    for k in 0..200 {
        let x = 4.7 + k as f32 * 0.05;
        for d in [0.3f32, 1.0, 2.5] {
            if map.clear(Vec3::new(x, 0.0, 0.0), d) {
                assert!(f64::from(x) - 4.7 > f64::from(d), "x {x} d {d}");
            }
        }
    }
    assert!(Clearance::build(&[]).is_none());
    assert!(Clearance::build(&[Vec4::new(f32::NAN, 0.0, 0.0, 1.0)]).is_none());
}

/// A receptor too large for the finest lattice gets a coarser one
/// within the vertex budget.
#[test]
fn large_boxes_get_a_coarser_lattice() {
    let atoms = [
        Vec4::new(-400.0, 0.0, 0.0, 1.5),
        Vec4::new(400.0, 300.0, 200.0, 1.5),
    ];
    let map = Clearance::build(&atoms).expect("atoms");
    assert!(map.spacing() > FINEST);
    assert!(map.bytes() <= MAX_VERTICES);
    assert!(map.clear(Vec3::new(0.0, 100.0, 100.0), 1.0));
    assert!(!map.clear(Vec3::new(-400.0, 0.0, 1.0), 0.2));
    // Absurdly far apart: no map (see MAX_LATTICE_COORDINATE), and no
    // panic or endless coarsening on the way.
    let atoms = [
        Vec4::new(-1e30, 0.0, 0.0, 1.5),
        Vec4::new(1e30, 1e6, -1e6, 1.5),
    ];
    assert!(Clearance::build(&atoms).is_none());
}
