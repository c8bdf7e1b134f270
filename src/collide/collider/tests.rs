//! The colliders' own tests: cells, and the grids with and without their
//! padded rows against brute force.

use super::*;

#[test]
fn cell_of_is_floor() {
    for v in [-3.5f32, -3.0, -0.2, 0.0, 0.2, 2.999, 3.0, 1e9, -1e9] {
        assert_eq!(cell_of(v, 0.0, 1.0), v.floor() as i32, "{v}");
    }
    assert_eq!(cell_of(f32::NAN, 0.0, 1.0), 0);
    assert_eq!(cell_of(1e30, 0.0, 1.0), i32::MAX);
}

#[test]
fn cover_is_cell_of_on_each_axis_and_clips() {
    let cells = Cells::new(
        Vec3::new(-1.0, 2.0, 0.5),
        Vec3::new(1.0 / 1.5, 1.0 / 4.5, 1.0 / 4.5),
        [-10, -10, -10],
        [10, 10, 10],
    );
    let (inv, o) = ([1.0 / 1.5, 1.0 / 4.5, 1.0 / 4.5], [-1.0, 2.0, 0.5]);
    for (lo, hi) in [
        (Vec3::new(-3.1, 0.0, 2.9), Vec3::new(3.0, 4.5, 3.0)),
        (Vec3::splat(-0.0), Vec3::splat(1e-7)),
        (Vec3::new(-1.0, 2.0, 0.5), Vec3::new(-1.0, 2.0, 0.5)),
    ] {
        let (first, last) = cells.cover(lo, hi).expect("inside");
        for k in 0..3 {
            assert_eq!(first[k], cell_of(lo[k], o[k], inv[k]).max(-10));
            assert_eq!(last[k], cell_of(hi[k], o[k], inv[k]).min(10));
        }
    }
    let (first, last) = cells
        .cover(Vec3::splat(-1e30), Vec3::splat(f32::INFINITY))
        .expect("everything");
    assert_eq!((first, last), ([-10; 3], [10; 3]));
    assert!(cells.cover(Vec3::splat(1e3), Vec3::splat(2e3)).is_none());
    assert!(cells.cover(Vec3::splat(1.0), Vec3::splat(0.0)).is_none());
}

/// `n` carbon atoms at random in the box `±half`.
fn random_carbons(rng: &mut bump_testkit::Rng, n: i64, half: glam::DVec3) -> Molecule {
    use crate::model::molecule::test_carbon;
    let atoms = (1..=n).map(test_carbon).collect();
    let pos: Vec<glam::DVec3> = (0..n).map(|_| rng.in_box(half)).collect();
    Molecule::new("random carbons", atoms, &pos)
}

/// The grids answer through their padded rows and, for balls past
/// their margin or before they are built, through the plain grid: both
/// must give brute force's atoms, each once, with the same `d²`.
#[test]
fn grids_with_and_without_their_rows_are_brute_force() {
    use bump_testkit::Rng;
    use glam::DVec3;
    let mut rng = Rng(23);
    let mol = random_carbons(&mut rng, 600, DVec3::new(14.0, 10.0, 12.0));
    let rule = ContactRule::default();
    let brute = Collider::build(&mol, &rule, ColliderKind::Brute);
    let sorted = |mut v: Vec<(u32, u32)>| {
        let n = v.len();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), n, "an atom reported twice");
        v
    };
    for kind in [ColliderKind::Grid, ColliderKind::Hashed] {
        let grid = Collider::build(&mol, &rule, kind);
        grid.wait_for_clearance();
        let rows = grid.padded_rows().expect("padded rows");
        let (mut in_rows, mut past) = (0, 0);
        for _ in 0..3000 {
            let p = rng.in_box(DVec3::splat(22.0)).as_vec3();
            let r = rng.range(0.0, 12.0) as f32;
            let mut want = Vec::new();
            brute.near(p, r, |_, m, d2| want.push((m, d2.to_bits())));
            let mut plain = Vec::new();
            grid.near_plain(p, r, |_, m, d2| plain.push((m, d2.to_bits())));
            let mut both = Vec::new();
            grid.near(p, r, |_, m, d2| both.push((m, d2.to_bits())));
            let want = sorted(want);
            assert_eq!(sorted(plain), want, "{kind:?} plain near {p} {r}");
            assert_eq!(sorted(both), want, "{kind:?} near {p} {r}");
            if r <= rows.margin() {
                in_rows += 1;
            } else {
                past += 1;
            }
        }
        assert!(in_rows > 500 && past > 500, "{kind:?} {in_rows} {past}");
    }
}

/// A few atoms spread widely: the hashed table is 64 buckets, so rows
/// share buckets and wrap at the table's end. The plain table's search
/// (and, once they are built, the padded rows') must still give brute
/// force's atoms and `visit` every atom of the box once.
#[test]
fn hashed_rows_that_share_and_wrap_buckets_report_each_atom_once() {
    use bump_testkit::Rng;
    use glam::DVec3;
    let mut rng = Rng(11);
    let mol = random_carbons(&mut rng, 12, DVec3::new(40.0, 6.0, 6.0));
    let rule = ContactRule::default();
    let brute = Collider::build(&mol, &rule, ColliderKind::Brute);
    let hashed = Collider::build(&mol, &rule, ColliderKind::Hashed);
    // Queries below ask the plain table and the rows explicitly, so
    // neither depends on when the rows' thread finishes.
    hashed.wait_for_clearance();
    let Index::Hashed { mask, .. } = &hashed.index else {
        panic!("hashed index");
    };
    assert_eq!(*mask, 63);
    let mut wrapped = false;
    for _ in 0..2000 {
        let p = rng.in_box(DVec3::new(45.0, 8.0, 8.0)).as_vec3();
        let r = rng.range(0.5, 30.0) as f32;
        let sorted = |mut v: Vec<(u32, u32)>| {
            v.sort_unstable();
            v
        };
        let (mut want, mut plain, mut near) = (Vec::new(), Vec::new(), Vec::new());
        brute.near(p, r, |_, m, d2| want.push((m, d2.to_bits())));
        hashed.near_plain(p, r, |_, m, d2| plain.push((m, d2.to_bits())));
        hashed.near(p, r, |_, m, d2| near.push((m, d2.to_bits())));
        let want = sorted(want);
        assert_eq!(sorted(plain), want, "plain near {p} {r}");
        assert_eq!(sorted(near), want, "near {p} {r}");
        let (lo, hi) = (p - Vec3::splat(r), p + Vec3::splat(r));
        let mut seen = Vec::new();
        hashed.visit(lo, hi, |_, m| seen.push(m));
        let before = seen.len();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), before, "an atom visited twice");
        let mut inside = Vec::new();
        brute.visit(lo, hi, |a, m| {
            if a.truncate().cmpge(lo).all() && a.truncate().cmple(hi).all() {
                inside.push(m);
            }
        });
        assert!(inside.iter().all(|m| seen.binary_search(m).is_ok()));
        if let Index::Hashed { cells, .. } = &hashed.index
            && let Some(([x0, y0, z0], [x1, y1, z1])) = cells.cover(lo, hi)
        {
            let width = (x1 - x0 + 1) as u32;
            for z in z0..=z1 {
                for y in y0..=y1 {
                    wrapped |= width <= 64 && hash_cell(x0, y, z, 63) + width > 64;
                }
            }
        }
    }
    assert!(wrapped, "no query wrapped at the table's end");
}
