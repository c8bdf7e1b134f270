//! Padded rows against brute force (each atom in a ball reported once, in
//! either table), their layout (every full-grid row starts at a block) and
//! their limits.

use super::*;
use bump_testkit::Rng;
use glam::DVec3;

/// Each atom's index as its tag.
fn tags(n: usize) -> Vec<u32> {
    (0..n as u32).collect()
}

/// The atoms within `radius` of `p` by brute force, with `d²` as the
/// collider computes it, sorted.
fn brute(atoms: &[Vec4], p: Vec3, radius: f32) -> Vec<(usize, u32)> {
    let r2 = radius * radius;
    let mut v: Vec<(usize, u32)> = atoms
        .iter()
        .enumerate()
        .filter_map(|(i, a)| {
            let d2 = (a.truncate() - p).length_squared();
            (d2 <= r2).then_some((i, d2.to_bits()))
        })
        .collect();
    v.sort_unstable();
    v
}

/// What `rows` (built with each atom's index as its tag) reports.
fn found(rows: &PaddedRows, atoms: &[Vec4], p: Vec3, radius: f32) -> Vec<(usize, u32)> {
    let mut v = Vec::new();
    rows.near(p, radius, |a, tag, d2| {
        assert_eq!(a, atoms[tag as usize], "atom {tag} as stored");
        v.push((tag as usize, d2.to_bits()));
    });
    let n = v.len();
    v.sort_unstable();
    v.dedup();
    assert_eq!(v.len(), n, "an atom reported twice near {p}");
    v
}

/// Clustered atoms (a protein-like blob with a few strays), so rows
/// hold many atoms and some runs are empty.
fn atoms(rng: &mut Rng, n: usize) -> Vec<Vec4> {
    (0..n)
        .map(|i| {
            let c = if i % 10 == 0 {
                rng.in_box(DVec3::splat(30.0))
            } else {
                rng.in_box(DVec3::new(12.0, 8.0, 10.0))
            };
            c.as_vec3().extend(rng.range(1.2, 2.0) as f32)
        })
        .collect()
}

#[test]
fn near_reports_exactly_the_atoms_in_the_ball_each_once() {
    let mut rng = Rng(5);
    for round in 0..12 {
        let atoms = atoms(&mut rng, 200 + 75 * round);
        let margin = rng.range(2.5, 4.5) as f32;
        let hashed = round % 2 == 1;
        let rows =
            PaddedRows::build(&atoms, &tags(atoms.len()), margin, 1.5, hashed).expect("rows");
        for _ in 0..3000 {
            // Inside, around and well outside the atoms' box.
            let p = rng.in_box(DVec3::splat(45.0)).as_vec3();
            let radius = rng.range(0.0, f64::from(margin)) as f32;
            assert_eq!(
                found(&rows, &atoms, p, radius),
                brute(&atoms, p, radius),
                "{p} {radius}"
            );
        }
        // Points on an atom, and a hair off the ball's edge.
        for a in atoms.iter().take(50) {
            let p = a.truncate();
            assert_eq!(found(&rows, &atoms, p, margin), brute(&atoms, p, margin));
            let q = p + Vec3::new(margin, 0.0, 0.0) * (1.0 + f32::EPSILON);
            assert_eq!(found(&rows, &atoms, q, margin), brute(&atoms, q, margin));
        }
    }
}

/// A full grid's rows each start at a block (what lets its scans test
/// whole blocks): each row's atoms, then fewer than a block of unused
/// slots, infinitely far; and every atom of the row is a real one.
#[test]
fn full_grid_rows_start_at_blocks() {
    let mut rng = Rng(7);
    let atoms = atoms(&mut rng, 500);
    let rows = PaddedRows::build(&atoms, &tags(atoms.len()), 3.5, 1.5, false).expect("rows");
    let [nx, ny, nz] = rows.dims.map(|n| n as usize);
    let mut padded = 0;
    for row in 0..ny * nz {
        let (first, end) = (
            rows.start[row * nx] as usize,
            rows.start[(row + 1) * nx] as usize,
        );
        assert_eq!(first % LANES, 0, "row {row} starts at {first}");
        let entry = |e: usize| rows.blocks[e / LANES].map(|v| v.to_array()[e % LANES]);
        let unused = |e: usize| entry(e)[..3].iter().all(|v| *v == f32::INFINITY);
        // The row's real entries first, each an atom as stored.
        let used = (first..end).take_while(|&e| !unused(e)).count();
        for e in first..first + used {
            let tag = rows.tag[e] as usize;
            assert_eq!(
                Vec4::from_array(entry(e)),
                atoms[tag],
                "row {row} entry {e}"
            );
        }
        // Then its padding, to the next block: nothing else.
        assert!(
            (first + used..end).all(unused),
            "row {row}: an atom after padding"
        );
        assert_eq!(end % LANES, 0, "row {row} ends at {end}");
        assert!(
            end - first - used < LANES,
            "row {row}: {} unused",
            end - first - used
        );
        padded += end - first - used;
    }
    assert!(padded > 0, "no row needed padding");
}

#[test]
fn a_coarser_spacing_keeps_the_copies_within_the_limit() {
    let mut rng = Rng(9);
    let atoms = atoms(&mut rng, 400);
    for hashed in [false, true] {
        let fine = PaddedRows::build(&atoms, &tags(atoms.len()), 3.75, 1.5, hashed).expect("rows");
        let limit = fine.entries() / 3;
        let coarse = PaddedRows::build_within(&atoms, &tags(atoms.len()), 3.75, 1.5, hashed, limit)
            .expect("coarser rows");
        assert!(coarse.entries() <= limit, "{} > {limit}", coarse.entries());
        let few =
            PaddedRows::build_within(&atoms, &tags(atoms.len()), 3.75, 1.5, hashed, atoms.len());
        assert!(few.is_none());
        for _ in 0..2000 {
            let p = rng.in_box(DVec3::splat(40.0)).as_vec3();
            let radius = rng.range(0.0, 3.75) as f32;
            assert_eq!(found(&coarse, &atoms, p, radius), brute(&atoms, p, radius));
        }
    }
}

/// A few atoms spread along x: their rows' (row, x cell)s nearly fill
/// the table, so runs share buckets with other rows and some wrap at
/// the table's end; a query still reports exactly the atoms in its
/// ball, each once.
#[test]
fn hashed_rows_that_share_and_wrap_buckets_report_each_atom_once() {
    let mut rng = Rng(17);
    let atoms: Vec<Vec4> = (0..20)
        .map(|_| {
            let c = rng.in_box(DVec3::new(120.0, 9.0, 9.0));
            c.as_vec3().extend(1.7)
        })
        .collect();
    let rows = PaddedRows::build(&atoms, &tags(atoms.len()), 3.0, 1.5, true).expect("rows");
    let Buckets::Hashed { mask, .. } = &rows.buckets else {
        panic!("hashed buckets");
    };
    let size = *mask as usize + 1;
    let (mut wrapped, mut shared) = (0, 0);
    for _ in 0..40_000 {
        let p = rng.in_box(DVec3::new(125.0, 12.0, 12.0)).as_vec3();
        let radius = rng.range(0.0, 3.0) as f32;
        let want = brute(&atoms, p, radius);
        assert_eq!(found(&rows, &atoms, p, radius), want, "{p} {radius}");
        // Count the queries whose buckets wrap, and those whose run
        // holds entries of other rows.
        let cell = |v: f32, o: usize| {
            let inv = rows.inv.to_array()[o];
            let origin = rows.origin.to_array()[o];
            cell_of(v, origin, inv)
        };
        let (x0, x1) = (
            cell(p.x - radius, 0).max(0),
            cell(p.x + radius, 0).min(rows.dims[0] - 1),
        );
        let (iy, iz) = (
            cell(p.y, 1).clamp(0, rows.dims[1] - 1),
            cell(p.z, 2).clamp(0, rows.dims[2] - 1),
        );
        if x0 <= x1 {
            let h0 = hash_cell(x0, iy, iz, *mask) as usize;
            let h1 = h0 + (x1 - x0 + 1) as usize;
            wrapped += usize::from(h1 > size);
            let Buckets::Hashed { row_of: tags, .. } = &rows.buckets else {
                unreachable!()
            };
            let row = (iz * rows.dims[1] + iy) as u32;
            let (a, b) = (rows.start[h0] as usize, rows.start[h1.min(size)] as usize);
            shared += usize::from(tags[a..b].iter().any(|&t| t != row));
        }
    }
    assert!(
        wrapped > 40 && shared > 500,
        "{wrapped} wrapped, {shared} shared"
    );
}

#[test]
fn odd_input_gives_no_rows_or_no_atoms() {
    let one = [Vec4::new(1.0, 2.0, 3.0, 1.7)];
    for hashed in [false, true] {
        let build = |atoms: &[Vec4], margin| {
            PaddedRows::build(atoms, &tags(atoms.len()), margin, 1.5, hashed)
        };
        assert!(build(&[], 3.0).is_none());
        assert!(build(&one, 0.0).is_none());
        assert!(build(&one, f32::NAN).is_none());
        let far = [one[0], Vec4::new(f32::INFINITY, 0.0, 0.0, 1.7)];
        assert!(build(&far, 3.0).is_none());
        // Atoms too far apart for the limits at any spacing (cells, or
        // a hashed row's length).
        let spread = [
            Vec4::new(-3e7, -3e5, -3e5, 1.7),
            Vec4::new(3e7, 3e5, 3e5, 1.7),
        ];
        assert!(build(&spread, 3.0).is_none());
        // A tag for every atom, or no rows.
        assert!(PaddedRows::build(&one, &[], 3.0, 1.5, hashed).is_none());
        let rows = build(&one, 3.0).expect("one atom");
        assert_eq!(found(&rows, &one, Vec3::new(1.0, 2.0, 3.0), 0.0).len(), 1);
        assert!(found(&rows, &one, Vec3::NAN, 3.0).is_empty());
        assert!(found(&rows, &one, Vec3::splat(1e30), 3.0).is_empty());
        assert!(found(&rows, &one, Vec3::new(1.0, 2.0, 6.01), 3.0).is_empty());
        assert_eq!(found(&rows, &one, Vec3::new(1.0, 2.0, 5.99), 3.0).len(), 1);
    }
}
