//! Collision benchmarks, every method in one run so the ratios are fair:
//!
//! - `dhfr_tmp/*`: trimethoprim (21 heavy atoms) against E. coli DHFR
//!   (1268 heavy atoms) from `6xg5_tmp_prepared.pdb`: the static check at the
//!   crystal pose, and move-to-touch of a 1 Å step (16 directions out of the
//!   pocket, cycled) at 1e-3 Å tolerance, for each collider, the thesis method
//!   and parry3d (`intersection_test`, `cast_shapes`).
//! - `scaling/*`: a 30-atom drug (the receptor's outermost atom and the next
//!   29, pushed out until free) against receptors from 1.3k to 272k atoms:
//!   a 1.5 Å move-to-touch back towards the surface.
//!
//! Data come from `../shared/pdb`; when it is missing the benchmarks say so and
//! run nothing. Run with `cargo bench --bench collide`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, TouchOptions, check, move_to_touch,
};
use bump::model::{self, LigandSpec, LoadOptions, Molecule};
use bump::motion::Pose;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::{DVec3, Vec3};
use parry3d::math::{Pose as PPose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Compound, SharedShape};

fn data_dir() -> Option<PathBuf> {
    let d = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if d.join("MANIFEST.md").is_file() {
        Some(d)
    } else {
        eprintln!("SKIP: {} not found: no benchmarks run", d.display());
        None
    }
}

/// parry's sphere model of the rule: balls of radius r − overlap/2.
fn compound(m: &Molecule, rule: &ContactRule) -> Compound {
    let half = rule.overlap / 2.0;
    Compound::new(
        m.local
            .iter()
            .zip(&m.atoms)
            .map(|(p, a)| {
                (
                    PPose::from_translation(Vector::new(p.x, p.y, p.z)),
                    SharedShape::ball((a.radius - half).max(0.01)),
                )
            })
            .collect(),
    )
}

fn ppose(p: &Pose) -> PPose {
    PPose::from_parts(p.translation.as_vec3(), p.rotation.as_quat())
}

fn fibonacci(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
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
    let crystal = Pose::from_translation(drug.centre - receptor.centre);
    let queries: Vec<(Pose, Pose)> = fibonacci(16)
        .into_iter()
        .map(|d| (crystal, crystal.moved(d, DVec3::ZERO, 0.0)))
        .collect();
    let mut g = c.benchmark_group("dhfr_tmp");
    g.sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for kind in ColliderKind::ALL {
        let col = Collider::build(&receptor, &rule, kind);
        let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
        g.bench_function(BenchmarkId::new("check", kind.name()), |b| {
            b.iter(|| black_box(check(&col, &atoms, black_box(&crystal))))
        });
        for method in [Method::Swept, Method::Thesis] {
            if method == Method::Thesis && kind != ColliderKind::Hashed {
                continue;
            }
            let opts = TouchOptions {
                tolerance: 1e-3,
                method,
            };
            let name = format!("{}-{}", method.name(), kind.name());
            let mut k = 0;
            g.bench_function(BenchmarkId::new("touch_1A", name), |b| {
                b.iter(|| {
                    let (s, e) = &queries[k % queries.len()];
                    k += 1;
                    black_box(move_to_touch(&col, &atoms, s, e, &opts))
                })
            });
        }
    }
    let rec = compound(&receptor, &rule);
    let dr = compound(&drug, &rule);
    g.bench_function(BenchmarkId::new("check", "parry3d"), |b| {
        b.iter(|| {
            black_box(query::intersection_test(
                &PPose::IDENTITY,
                &rec,
                &ppose(black_box(&crystal)),
                &dr,
            ))
        })
    });
    let mut k = 0;
    g.bench_function(BenchmarkId::new("touch_1A", "parry3d"), |b| {
        b.iter(|| {
            let (s, e) = &queries[k % queries.len()];
            k += 1;
            let v: Vec3 = (e.translation - s.translation).as_vec3();
            black_box(query::cast_shapes(
                &PPose::IDENTITY,
                Vector::ZERO,
                &rec,
                &ppose(s),
                v,
                &dr,
                ShapeCastOptions::with_max_time_of_impact(1.0),
            ))
        })
    });
    g.finish();
}

/// A 30-atom "drug" copied from the receptor's surface and pushed out along
/// the radial direction until it is free: (drug, start pose, direction).
fn surface_drug(receptor: &Molecule, rule: &ContactRule) -> (Molecule, Pose, DVec3) {
    let far = receptor
        .local
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.length().total_cmp(&b.1.length()))
        .map(|(i, _)| i)
        .unwrap_or(0);
    let end = (far + 30).min(receptor.len());
    let atoms = receptor.atoms[far..end].to_vec();
    let pos: Vec<DVec3> = (far..end).map(|i| receptor.file_position(i)).collect();
    let drug = Molecule::new("surface drug", atoms, &pos);
    let dir = (drug.centre - receptor.centre).normalize_or(DVec3::X);
    let col = Collider::build(receptor, rule, ColliderKind::Hashed);
    let atoms = DrugAtoms::new(&drug, rule, col.max_radius());
    let mut shift = 0.5;
    let start = loop {
        let p = Pose::from_translation(drug.centre - receptor.centre + dir * shift);
        if check(&col, &atoms, &p).is_empty() || shift > 50.0 {
            break p;
        }
        shift += 0.5;
    };
    (drug, start, dir)
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
        let (drug, start, out) = surface_drug(&receptor, &rule);
        let end = start.moved(-out * 1.5, DVec3::ZERO, 0.0);
        let label = format!("{n}");
        for kind in ColliderKind::ALL {
            let col = Collider::build(&receptor, &rule, kind);
            let atoms = DrugAtoms::new(&drug, &rule, col.max_radius());
            g.bench_function(
                BenchmarkId::new(format!("check-{}", kind.name()), &label),
                |b| b.iter(|| black_box(check(&col, &atoms, black_box(&end)))),
            );
            let opts = TouchOptions::default();
            g.bench_function(
                BenchmarkId::new(format!("touch-{}", kind.name()), &label),
                |b| {
                    b.iter(|| {
                        black_box(move_to_touch(&col, &atoms, &start, black_box(&end), &opts))
                    })
                },
            );
        }
        let rec = compound(&receptor, &rule);
        let dr = compound(&drug, &rule);
        g.bench_function(BenchmarkId::new("touch-parry3d", &label), |b| {
            b.iter(|| {
                black_box(query::cast_shapes(
                    &PPose::IDENTITY,
                    Vector::ZERO,
                    &rec,
                    &ppose(&start),
                    (end.translation - start.translation).as_vec3(),
                    &dr,
                    ShapeCastOptions::with_max_time_of_impact(1.0),
                ))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, dhfr, scaling);
criterion_main!(benches);
