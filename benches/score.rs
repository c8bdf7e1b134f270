//! Scoring benchmarks (criterion): trimethoprim (TOP) in E. coli DHFR
//! (`6xg5_tmp_prepared.pdb`):
//!
//! - `score/maps_energy_gradient`, `score/exact_energy_gradient`,
//!   `score/exact_energy`: Vina's energy at the crystal pose, with the
//!   gradient (force, torque, torsion torques) from 0.375 Å maps and
//!   exactly, and the energy alone exactly;
//! - `score/maps_build_24A`: maps for a 24 Å box at 0.375 Å on every thread;
//! - `score/settle`: settle on the maps from seeded perturbed crystal poses
//!   (up to 1.5 Å, 30°), cycled;
//! - `scaling/exact_energy_gradient/*`: the drug just outside the surface
//!   of receptors of 1.3k to 272k atoms.
//!
//! `cargo bench --bench score -- --report` instead prints the benchmark
//! report's scoring section (`bump_testkit::score_bench`, which also times AutoDock
//! Vina when Python has its package); `--report --quick` a short one;
//! `--count WHAT N` runs N calls of one evaluation for callgrind.
//! Data come from `../shared/pdb`; without it nothing runs.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use bump::collide::{Collider, ColliderKind, ContactRule};
use bump::model::{self, LoadOptions};
use bump::score::{
    Contacts, Exact, Gradient, MapField, Scoring, SettleOptions, Workspace, energies,
    energy_gradient, settle,
};
use criterion::Criterion;

use bump_testkit::score_bench as section;
use section::{SCALING, SPACING, Setup, at_surface, dhfr, perturbed, threads};

fn data_dir() -> Option<PathBuf> {
    let d = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/pdb"));
    if d.join("MANIFEST.md").is_file() {
        Some(d)
    } else {
        eprintln!("SKIP: {} not found: no benchmarks run", d.display());
        None
    }
}

fn dhfr_group(c: &mut Criterion, s: &Setup) {
    let exact = Exact::new(&s.receptor, Scoring::Vina);
    let maps = s.maps(&s.crystal, SPACING, threads());
    let field = MapField::new(&maps, exact);
    let (lig, conf) = (&s.lig, &s.crystal);
    let mut g = c.benchmark_group("score");
    let (mut ws, mut grad) = (Workspace::default(), Gradient::default());
    g.bench_function("maps_energy_gradient", |b| {
        b.iter(|| black_box(energy_gradient(&field, lig, conf, &mut ws, &mut grad)))
    });
    g.bench_function("exact_energy_gradient", |b| {
        b.iter(|| black_box(energy_gradient(&exact, lig, conf, &mut ws, &mut grad)))
    });
    g.bench_function("exact_energy", |b| {
        b.iter(|| black_box(energies(&exact, lig, conf, &mut ws)))
    });
    let rule = ContactRule::default();
    let collider = Collider::build(&s.receptor_mol, &rule, ColliderKind::Hashed);
    collider.wait_for_clearance();
    let mut contacts = Contacts::new(&collider, rule, &s.drug, lig);
    let starts = perturbed(conf, 43, 12);
    let opts = SettleOptions::default();
    let mut k = 0;
    g.bench_function("settle", |b| {
        b.iter(|| {
            k = (k + 1) % starts.len();
            black_box(settle(&field, lig, &mut contacts, &starts[k], &opts))
        })
    });
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("maps_build_24A", |b| {
        b.iter(|| black_box(s.maps(conf, SPACING, threads())))
    });
    g.finish();
}

fn scaling_group(c: &mut Criterion, data: &std::path::Path, drug: &bump::model::Molecule) {
    let mut g = c.benchmark_group("scaling/exact_energy_gradient");
    for &(label, file) in SCALING {
        let Ok(l) = model::load(&data.join(file), &LoadOptions::default()) else {
            eprintln!("SKIP: {file} not loaded");
            continue;
        };
        let Ok(rec) = model::receptor_only(&l.structure) else {
            continue;
        };
        let r = Setup::new(rec, drug.clone());
        let conf = at_surface(&r.receptor_mol, &r.lig);
        let exact = Exact::new(&r.receptor, Scoring::Vina);
        let (mut ws, mut grad) = (Workspace::default(), Gradient::default());
        g.bench_function(label, |b| {
            b.iter(|| black_box(energy_gradient(&exact, &r.lig, &conf, &mut ws, &mut grad)))
        });
    }
    g.finish();
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(data) = data_dir() else {
        return;
    };
    if let Some(k) = args.iter().position(|a| a == "--count") {
        let what = args.get(k + 1).map_or("maps", String::as_str);
        let n = args.get(k + 2).and_then(|v| v.parse().ok()).unwrap_or(0);
        section::count(&data, what, n);
        return;
    }
    if args.iter().any(|a| a == "--report") {
        let quick = args.iter().any(|a| a == "--quick");
        println!("{}", section::markdown(&data, quick));
        return;
    }
    let Some(s) = dhfr(&data) else {
        eprintln!("SKIP: 6xg5_tmp_prepared.pdb not loaded");
        return;
    };
    let mut c = Criterion::default().configure_from_args();
    dhfr_group(&mut c, &s);
    scaling_group(&mut c, &data, &s.drug);
    c.final_summary();
}
