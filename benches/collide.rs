//! Collision benchmarks, every method in one run so the ratios are fair:
//!
//! - `dhfr_tmp/*`: trimethoprim (21 heavy atoms) against E. coli DHFR
//!   (1268 heavy atoms) from `6xg5_tmp_prepared.pdb`: the static check at the
//!   crystal pose, and move-to-touch of a 1 Å step (16 directions out of the
//!   pocket, cycled) at 1e-3 Å tolerance, for each collider, the thesis method
//!   and parry3d (`intersection_test`; `cast_shapes` alone, and with the
//!   contact pairs at its stop, which is all move-to-touch answers); and the same steps
//!   with a 10° turn about the drug's centre (a screw motion) for the grid
//!   colliders and parry3d's `cast_shapes_nonlinear`.
//! - `scaling/*`: 30-atom drugs against receptors from 1.3k to 272k atoms:
//!   16 patches of the receptor's surface (an outermost atom in each of 16
//!   directions and its 29 nearest neighbours, pushed out until free; the
//!   first, about the outermost atom of all, is the report's), cycled: the
//!   static check at the end pose and a 1.5 Å move-to-touch back towards the
//!   surface, for each collider, the thesis method and parry3d (the cast
//!   alone, and with contacts).
//!
//! parry3d models the rule as balls of radius `r − overlap/2`, which is the
//! rule without the N/O hydrogen-bond allowance; the `*-parry-rule` rows run
//! bump under that same rule, and the setup prints how often the two agree.
//!
//! Data come from `../shared/pdb`; when it is missing the benchmarks say so and
//! run nothing. Run with `cargo bench --bench collide`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, TouchOptions, TouchResult, check,
    move_to_touch, move_to_touch_into,
};
use bump::model::{self, LigandSpec, LoadOptions, Molecule};
use bump::motion::{Pose, Screw};
use bump_testkit::sphere_directions;
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use parry3d::math::Pose as PPose;
use parry3d::query::{self, NonlinearRigidMotion};

// The parry3d baseline and the scaling drugs the report times too.
use bump_testkit::parry::{self, Spheres, pose as ppose};
use bump_testkit::surface::surface_drugs;

/// Surface patches per receptor in the scaling group, timed in turn.
const SURFACE_PATCHES: usize = 16;

/// The test structures (a skip with a message when they are missing; a
/// failure under `CI=true`).
fn data_dir() -> Option<PathBuf> {
    bump_testkit::shared_pdb()
}

/// `col` once its clearance map (built on its own thread) is there, so
/// every sample times the queries as they run from then on.
fn ready(col: Collider) -> Collider {
    col.wait_for_clearance();
    col
}

/// Up to `n` move-to-touch queries: from collision-free starts (under
/// `rule`) 3, 2, 1.5 or 1 Å out of the crystal pose, a 1 Å step back towards it.
fn approach_queries(
    receptor: &Molecule,
    drug: &Molecule,
    rule: &ContactRule,
    crystal: Pose,
    n: usize,
) -> Vec<(Pose, Pose)> {
    let col = Collider::build(receptor, rule, ColliderKind::Grid);
    let atoms = DrugAtoms::new(drug, rule, col.max_radius());
    let mut out = Vec::new();
    for dist in [3.0, 2.0, 1.5, 1.0] {
        for d in sphere_directions(400) {
            let start = crystal.moved(d * dist, DVec3::ZERO, 0.0);
            if out.len() < n && check(&col, &atoms, &start).is_empty() {
                out.push((start, start.moved(-d, DVec3::ZERO, 0.0)));
            }
        }
    }
    out
}

/// Prints how parry3d's cast agrees with the swept method on the same
/// queries under the same (parry-equivalent) rule, and whether parry's
/// contact list at the swept method's stop is the swept method's own.
fn report_parry_agreement(
    label: &str,
    receptor: &Molecule,
    rule: &ContactRule,
    rec: &Spheres,
    queries: &[(&Molecule, &Spheres, Pose, Pose)],
) {
    let col = Collider::build(receptor, rule, ColliderKind::Grid);
    let opts = TouchOptions::default();
    let (mut agree, mut worst, mut zero, mut same) = (0, 0.0f64, 0, 0);
    for (drug, dr, s, e) in queries {
        let atoms = DrugAtoms::new(drug, rule, col.max_radius());
        let ours = move_to_touch(&col, &atoms, s, e, &opts);
        let theirs = parry::cast(rec, dr, s, e);
        if theirs == 0.0 {
            zero += 1;
        }
        let err = (ours.t - theirs).abs() * (e.translation - s.translation).length();
        worst = worst.max(err);
        if err < 1e-2 {
            agree += 1;
        }
        let pairs: Vec<(u32, u32)> = ours.contacts.iter().map(|p| (p.receptor, p.drug)).collect();
        if parry::contacts(rec, dr, &ours.pose, opts.tolerance as f32) == pairs {
            same += 1;
        }
    }
    eprintln!(
        "{label}: parry3d agrees with swept (|Δt|·step < 0.01 Å) on {agree}/{n} queries, worst {worst:.2e} Å, {zero} at t = 0; same contacts at swept's stop on {same}/{n}",
        n = queries.len()
    );
}

fn dhfr(c: &mut Criterion) {
    let Some(dir) = data_dir() else { return };
    let Ok(loaded) = model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default())
    else {
        eprintln!("SKIP: cannot load 6xg5_tmp_prepared.pdb");
        return;
    };
    let Ok(spec) = LigandSpec::parse("TOP") else {
        return;
    };
    let Ok((receptor, drug)) = model::split_complex(&loaded.structure, &spec) else {
        return;
    };
    let rule = ContactRule::default();
    // parry's balls of radius r − 0.3 are this rule exactly (no H-bond allowance).
    let parry_rule = ContactRule::new(rule.overlap, 0.0).unwrap_or(rule);
    let crystal = Pose::from_translation(drug.centre - receptor.centre);
    let queries = approach_queries(&receptor, &drug, &parry_rule, crystal, 16);
    if queries.is_empty() {
        eprintln!("SKIP: no collision-free start near the TMP crystal pose");
        return;
    }
    eprintln!("dhfr_tmp: {} approach queries", queries.len());
    let mut g = c.benchmark_group("dhfr_tmp");
    g.sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let variants: Vec<(String, Collider)> = ColliderKind::ALL
        .iter()
        .map(|&kind| {
            (
                kind.name().to_string(),
                ready(Collider::build(&receptor, &rule, kind)),
            )
        })
        .collect();
    for (name, col) in &variants {
        let kind = col.kind();
        let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
        g.bench_function(BenchmarkId::new("check", name), |b| {
            b.iter(|| black_box(check(col, &atoms, black_box(&crystal))))
        });
        for method in [Method::Swept, Method::Thesis] {
            if method == Method::Thesis && kind != ColliderKind::Hashed {
                continue;
            }
            let opts = TouchOptions {
                tolerance: 1e-3,
                method,
            };
            let label = format!("{}-{name}", method.name());
            touch_cycle(
                &mut g,
                BenchmarkId::new("touch_1A", label),
                (col, &atoms),
                &queries,
                &opts,
            );
        }
    }
    let (rec, dr) = (Spheres::new(&receptor, &rule), Spheres::new(&drug, &rule));
    let with_drug: Vec<_> = queries.iter().map(|(s, e)| (&drug, &dr, *s, *e)).collect();
    report_parry_agreement("dhfr_tmp", &receptor, &parry_rule, &rec, &with_drug);
    for kind in [ColliderKind::Grid, ColliderKind::Hashed] {
        let col = ready(Collider::build(&receptor, &parry_rule, kind));
        let atoms = DrugAtoms::new(&drug, &parry_rule, col.max_radius());
        touch_cycle(
            &mut g,
            BenchmarkId::new("touch_1A", format!("swept-{}-parry-rule", kind.name())),
            (&col, &atoms),
            &queries,
            &TouchOptions::default(),
        );
    }
    g.bench_function(BenchmarkId::new("check", "parry3d"), |b| {
        b.iter(|| {
            black_box(query::intersection_test(
                &PPose::IDENTITY,
                &rec.compound,
                &ppose(black_box(&crystal)),
                &dr.compound,
            ))
        })
    });
    let mut k = 0;
    g.bench_function(BenchmarkId::new("touch_1A", "parry3d"), |b| {
        b.iter(|| {
            let (s, e) = &queries[k % queries.len()];
            k += 1;
            black_box(parry::cast(&rec, &dr, s, black_box(e)))
        })
    });
    let mut k = 0;
    let mut contacts = Vec::new();
    g.bench_function(BenchmarkId::new("touch_1A", "parry3d-contacts"), |b| {
        b.iter(|| {
            let (s, e) = &queries[k % queries.len()];
            k += 1;
            black_box(parry::touch(
                &rec,
                &dr,
                s,
                black_box(e),
                1e-3,
                &mut contacts,
            ));
            black_box(&contacts);
        })
    });
    // The same steps with a 10° turn about the drug's centre: a screw
    // motion, which parry3d casts with `cast_shapes_nonlinear`.
    let screws: Vec<(Pose, Pose)> = queries
        .iter()
        .map(|(s, e)| {
            let d = e.translation - s.translation;
            let axis = d.cross(DVec3::Z).try_normalize().unwrap_or(DVec3::X);
            (*s, s.moved(d, axis, 10f64.to_radians()))
        })
        .collect();
    for (name, col) in variants
        .iter()
        .filter(|(_, c)| c.kind() != ColliderKind::Brute)
    {
        let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
        touch_cycle(
            &mut g,
            BenchmarkId::new("touch_1A_10deg", format!("swept-{name}")),
            (col, &atoms),
            &screws,
            &TouchOptions::default(),
        );
    }
    let motions: Vec<NonlinearRigidMotion> = screws
        .iter()
        .filter_map(|(s, e)| {
            let screw = Screw::between(*s, *e);
            let a = screw.axis_point()?;
            Some(NonlinearRigidMotion::new(
                ppose(s),
                s.inverse().transform_point(a).as_vec3(),
                screw.slide().as_vec3(),
                (screw.axis() * screw.angle()).as_vec3(),
            ))
        })
        .collect();
    let still = NonlinearRigidMotion::constant_position(PPose::IDENTITY);
    let mut k = 0;
    g.sample_size(10);
    g.bench_function(BenchmarkId::new("touch_1A_10deg", "parry3d"), |b| {
        b.iter(|| {
            let m = &motions[k % motions.len()];
            k += 1;
            black_box(query::cast_shapes_nonlinear(
                &still,
                &rec.compound,
                m,
                &dr.compound,
                0.0,
                1.0,
                true,
            ))
        })
    });
    g.finish();
}

/// Benchmarks move-to-touch over `queries`, one per iteration, cycled.
fn touch_cycle(
    g: &mut BenchmarkGroup<'_, WallTime>,
    id: BenchmarkId,
    (col, atoms): (&Collider, &DrugAtoms),
    queries: &[(Pose, Pose)],
    opts: &TouchOptions,
) {
    let mut k = 0;
    // One result, its storage reused, as a loop of queries can keep it
    // (`move_to_touch_into`).
    let mut result = TouchResult::default();
    g.bench_function(id, |b| {
        b.iter(|| {
            let (s, e) = &queries[k % queries.len()];
            k += 1;
            move_to_touch_into(col, atoms, s, e, opts, &mut result);
            black_box(&result);
        })
    });
}

fn scaling(c: &mut Criterion) {
    let Some(dir) = data_dir() else { return };
    let rule = ContactRule::default();
    let mut g = c.benchmark_group("scaling");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for file in [
        "1rx1.pdb",
        "4kya.pdb.gz",
        "2btv.pdb.gz",
        "1aon.pdb.gz",
        "1f2n_assembly1.cif.gz",
    ] {
        let Ok(loaded) = model::load(&dir.join(file), &LoadOptions::default()) else {
            eprintln!("SKIP: cannot load {file}");
            continue;
        };
        let Ok(receptor) = model::receptor_only(&loaded.structure) else {
            continue;
        };
        let n = receptor.len();
        // Free under the stricter (parry-equivalent) rule, so both models start free.
        let strict = ContactRule::new(rule.overlap, 0.0).unwrap_or(rule);
        let patches = surface_drugs(&receptor, &strict, 30, SURFACE_PATCHES);
        if patches.is_empty() {
            continue;
        }
        let steps: Vec<(Pose, Pose)> = patches.iter().map(|p| (p.start, p.step_in(1.5))).collect();
        let label = format!("{n}");
        // Each sample cycles through the patches: its time is their mean.
        let cycle = |b: &mut criterion::Bencher, f: &mut dyn FnMut(usize)| {
            let mut k = 0;
            b.iter(|| {
                f(k % patches.len());
                k += 1;
            })
        };
        // The patches' drugs for a collider under a rule, and one patch's
        // move-to-touch (for every touch row).
        let drug_atoms = |col: &Collider, rule: &ContactRule| -> Vec<DrugAtoms> {
            patches
                .iter()
                .map(|p| DrugAtoms::new(&p.drug, rule, col.max_radius()))
                .collect()
        };
        // The result's storage is reused, as a loop of queries can keep it
        // (`move_to_touch_into`).
        let touch = |col: &Collider,
                     atoms: &[DrugAtoms],
                     opts: &TouchOptions,
                     k: usize,
                     result: &mut TouchResult| {
            let (s, e) = &steps[k];
            move_to_touch_into(col, &atoms[k], s, black_box(e), opts, result);
            black_box(result);
        };
        for kind in ColliderKind::ALL {
            let col = ready(Collider::build(&receptor, &rule, kind));
            let atoms = drug_atoms(&col, &rule);
            g.bench_function(
                BenchmarkId::new(format!("check-{}", kind.name()), &label),
                |b| {
                    cycle(b, &mut |k| {
                        drop(black_box(check(&col, &atoms[k], black_box(&steps[k].1))))
                    })
                },
            );
            for (name, method) in [("touch", Method::Swept), ("touch-thesis", Method::Thesis)] {
                if method == Method::Thesis && kind != ColliderKind::Hashed {
                    continue;
                }
                let opts = TouchOptions {
                    method,
                    ..TouchOptions::default()
                };
                let mut result = TouchResult::default();
                g.bench_function(
                    BenchmarkId::new(format!("{name}-{}", kind.name()), &label),
                    |b| cycle(b, &mut |k| touch(&col, &atoms, &opts, k, &mut result)),
                );
            }
        }
        let rec = Spheres::new(&receptor, &rule);
        let drugs: Vec<Spheres> = patches
            .iter()
            .map(|p| Spheres::new(&p.drug, &rule))
            .collect();
        let parry_rule = ContactRule::new(rule.overlap, 0.0).unwrap_or(rule);
        let queries: Vec<_> = patches
            .iter()
            .zip(&drugs)
            .zip(&steps)
            .map(|((p, dr), (s, e))| (&p.drug, dr, *s, *e))
            .collect();
        report_parry_agreement(
            &format!("scaling {label}"),
            &receptor,
            &parry_rule,
            &rec,
            &queries,
        );
        let col = ready(Collider::build(&receptor, &parry_rule, ColliderKind::Grid));
        let atoms = drug_atoms(&col, &parry_rule);
        let opts = TouchOptions::default();
        let mut result = TouchResult::default();
        g.bench_function(BenchmarkId::new("touch-grid-parry-rule", &label), |b| {
            cycle(b, &mut |k| touch(&col, &atoms, &opts, k, &mut result))
        });
        g.bench_function(BenchmarkId::new("check-parry3d", &label), |b| {
            cycle(b, &mut |k| {
                let _ = black_box(query::intersection_test(
                    &PPose::IDENTITY,
                    &rec.compound,
                    &ppose(black_box(&steps[k].1)),
                    &drugs[k].compound,
                ));
            })
        });
        g.bench_function(BenchmarkId::new("touch-parry3d", &label), |b| {
            cycle(b, &mut |k| {
                let (s, e) = &steps[k];
                black_box(parry::cast(&rec, &drugs[k], s, black_box(e)));
            })
        });
        let mut contacts = Vec::new();
        g.bench_function(BenchmarkId::new("touch-parry3d-contacts", &label), |b| {
            cycle(b, &mut |k| {
                let (s, e) = &steps[k];
                black_box(parry::touch(
                    &rec,
                    &drugs[k],
                    s,
                    black_box(e),
                    1e-3,
                    &mut contacts,
                ));
                black_box(&contacts);
            })
        });
    }
    g.finish();
}

criterion_group!(benches, dhfr, scaling);
criterion_main!(benches);
