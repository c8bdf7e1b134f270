//! Agreement with AutoDock Vina 1.2.7 on every complex and pose recorded in
//! `tests/reference/vina/values.json`, with Vina's own atom types, tree,
//! pairs and torsion count: totals, inter and intra energies and every term
//! agree to 1e-6 kcal/mol (Vina's and bump's table are the same samples).

#![allow(clippy::unwrap_used)]

mod score_support;

use bump::motion::Pose;
use bump::score::{Evaluator, Exact, Scoring, score};
use glam::DVec3;
use score_support::*;

#[test]
fn every_pose_scores_as_vina_with_vinas_types() {
    let v = values();
    let mut worst = 0.0f64;
    let mut count = 0;
    for name in complex_names(&v) {
        let cx = &v["complexes"][&name];
        let (receptor, _) = receptor_from_values(cx);
        for pose in cx["poses"].as_array().unwrap() {
            let lig = ligand_at(cx, &pose_xyz(pose));
            let conf = lig.rigid(Pose::IDENTITY);
            for sf in [Scoring::Vina, Scoring::Vinardo] {
                let exact = Exact::new(&receptor, sf);
                let s = score(&exact, Evaluator::Exact, &exact, &lig, &conf);
                let want = &pose[sf.name()];
                let id = format!("{name} {} {}", pose["id"], sf.name());
                let mut check = |what: &str, got: f64, want: f64| {
                    let d = (got - want).abs();
                    worst = worst.max(d);
                    count += 1;
                    assert!(d < 1e-5, "{id} {what}: bump {got}, Vina {want}");
                };
                check(
                    "inter",
                    s.inter,
                    want["score"]["lig_inter"].as_f64().unwrap(),
                );
                check(
                    "intra",
                    s.intra,
                    want["score"]["lig_intra"].as_f64().unwrap(),
                );
                check("total", s.total, want["score"]["total"].as_f64().unwrap());
                check("divisor", s.divisor, want["divisor"].as_f64().unwrap());
                for t in &s.terms {
                    let raw = &want["terms_raw"][t.name];
                    check(t.name, t.inter_raw, raw["inter"].as_f64().unwrap());
                    check(t.name, t.intra_raw, raw["intra"].as_f64().unwrap());
                }
                let atoms: f64 = s.atoms.iter().map(|a| a.inter).sum();
                assert!(
                    (atoms - s.inter).abs() < 1e-9,
                    "{id}: atoms' shares sum to inter"
                );
            }
        }
    }
    eprintln!("{count} numbers, largest difference from Vina {worst:.2e} kcal/mol");
}

/// With bump's own loading and typing (`src/chem`): every pose's
/// intermolecular energy is within 0.1 kcal/mol + 3 % of Vina's on every
/// complex; and the same loading with the reference's types on the atoms
/// bump types differently (if any) agrees with Vina to 1e-3 (relative, on
/// clashes) on every pose, so the
/// typing is the whole difference. Prints, per complex, the atoms typed
/// differently and what each costs at the crystal pose.
#[test]
fn every_pose_scores_as_vina_with_bumps_typing() {
    use std::collections::HashMap;
    let Some(dir) = shared_pdb() else {
        return;
    };
    let v = values();
    let table = bump::score::table::Table::of(Scoring::Vina);
    let mut lines = vec![
        "| complex | poses | largest \\|Δinter\\| (kcal/mol) | its bound | crystal inter: Vina, bump | N_tors Vina / bump | atoms typed differently (receptor within 8 Å, drug) that change the crystal score |".to_string(),
        "|---|---|---|---|---|---|---|".to_string(),
    ];
    let mut failures = Vec::new();
    for &(id, ..) in COMPLEXES {
        let cx = &v["complexes"][id];
        let (rec_mol, drug) = load_complex(&dir, id);
        let receptor = bump::score::prepare::receptor(&rec_mol);
        let lig = bump::score::prepare::ligand(&drug).expect("a ligand");
        assert_eq!(lig.xs.len(), drug.len(), "{id}: every drug atom typed");
        let exact = Exact::new(&receptor, Scoring::Vina);
        let crystal = &cx["poses"][0];
        let rel0 = relative_pose(crystal, &rec_mol, &drug);
        let xyz = lig.place(&lig.rigid(rel0));

        // The reference's types, where bump's differ, and each one's effect
        // at the crystal pose (pair energies with the other molecule).
        let by_key: HashMap<_, usize> = (0..receptor.len())
            .map(|j| (key(receptor.positions[j] + rec_mol.centre), j))
            .collect();
        let mut rec_types = receptor.xs.clone();
        let mut lig_types = lig.xs.clone();
        let mut diffs = Vec::new();
        for a in cx["receptor"]["atoms_near"].as_array().unwrap() {
            let p = DVec3::new(
                a[4].as_f64().unwrap(),
                a[5].as_f64().unwrap(),
                a[6].as_f64().unwrap(),
            );
            let theirs = xs(&a[8]);
            let Some(&j) = by_key.get(&key(p)) else {
                continue;
            };
            let ours = receptor.xs[j];
            if ours == theirs {
                continue;
            }
            rec_types[j] = theirs;
            let q = receptor.positions[j];
            let effect: f64 = lig
                .scored
                .iter()
                .zip(&lig.xs)
                .map(|(&i, &t)| {
                    let r2 = (xyz[i as usize] - q).length_squared();
                    table.fast(t, ours, r2) - table.fast(t, theirs, r2)
                })
                .sum();
            let label = format!(
                "{} {}{} {}",
                a[1].as_str().unwrap(),
                a[0].as_str().unwrap(),
                a[2].as_str().unwrap(),
                a[3].as_str().unwrap()
            );
            diffs.push((
                effect,
                format!("{label}: {}→{} {:+.3}", theirs.name(), ours.name(), effect),
            ));
        }
        let drug_key: HashMap<_, usize> = (0..drug.len())
            .map(|i| (key(drug.file_position(i)), i))
            .collect();
        let slot: HashMap<u32, usize> = lig
            .scored
            .iter()
            .enumerate()
            .map(|(k, &i)| (i, k))
            .collect();
        for row in cx["ligand"]["heavy_atoms"].as_array().unwrap() {
            let p = DVec3::new(
                row[1].as_f64().unwrap(),
                row[2].as_f64().unwrap(),
                row[3].as_f64().unwrap(),
            );
            let theirs = xs(&row[5]);
            let Some(&i) = drug_key.get(&key(p)) else {
                continue;
            };
            let Some(&k) = slot.get(&(i as u32)) else {
                continue;
            };
            let ours = lig.xs[k];
            if ours == theirs {
                continue;
            }
            lig_types[k] = theirs;
            let mut effect = 0.0;
            exact.neighbours(xyz[i], |j, r2| {
                effect +=
                    table.fast(ours, receptor.xs[j], r2) - table.fast(theirs, receptor.xs[j], r2);
            });
            diffs.push((
                effect,
                format!(
                    "drug {} (serial {}): {}→{} {:+.3}",
                    drug.atoms[i].name,
                    drug.atoms[i].serial,
                    theirs.name(),
                    ours.name(),
                    effect
                ),
            ));
        }
        diffs.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
        let relevant: Vec<String> = diffs
            .iter()
            .filter(|d| d.0.abs() >= 0.005)
            .map(|d| d.1.clone())
            .collect();

        // The same loading with the reference's types on those atoms.
        let rec_as_ref = bump::score::Receptor::new(
            &receptor.positions,
            &rec_types.iter().copied().map(Some).collect::<Vec<_>>(),
            &receptor.charges,
        );
        let mut lig_as_ref = lig.clone();
        lig_as_ref.xs = lig_types;
        let exact_as_ref = Exact::new(&rec_as_ref, Scoring::Vina);

        let (mut worst, mut bound_at_worst) = (0.0f64, 0.0);
        for pose in cx["poses"].as_array().unwrap() {
            let conf = lig.rigid(relative_pose(pose, &rec_mol, &drug));
            let want = pose["vina"]["score"]["lig_inter"].as_f64().unwrap();
            let s = score(&exact, Evaluator::Exact, &exact, &lig, &conf);
            let bound = 0.1 + 0.03 * want.abs();
            let d = (s.inter - want).abs();
            if d >= worst {
                (worst, bound_at_worst) = (d, bound);
            }
            if d > bound {
                failures.push(format!(
                    "{id} {}: bump {:.4}, Vina {want:.4} (bound {bound:.3})",
                    pose["id"], s.inter
                ));
            }
            let r = score(
                &exact_as_ref,
                Evaluator::Exact,
                &exact_as_ref,
                &lig_as_ref,
                &conf,
            );
            // Vina read the poses with 4-6 decimals (5e-5 Å), bump places
            // them from f32 coordinates: on a clash's steep repulsion that
            // is up to 1e-3 of the energy.
            if (r.inter - want).abs() > 1e-3 * (1.0 + want.abs()) {
                failures.push(format!(
                    "{id} {}: with the reference's types on {} atoms, bump {:.4}, Vina {want:.4}",
                    pose["id"],
                    diffs.len(),
                    r.inter
                ));
            }
        }
        let vina = crystal["vina"]["score"]["lig_inter"].as_f64().unwrap();
        let mine = score(&exact, Evaluator::Exact, &exact, &lig, &lig.rigid(rel0)).inter;
        lines.push(format!(
            "| {id} | {} | {worst:.3} | {bound_at_worst:.3} | {vina:.3}, {mine:.3} | {} / {} | {} of {}: {} |",
            cx["poses"].as_array().unwrap().len(),
            cx["ligand"]["vina_num_tors"],
            lig.torsion_count,
            relevant.len(),
            diffs.len(),
            if relevant.is_empty() { "none".to_string() } else { relevant.join("; ") }
        ));
    }
    eprintln!("{}", lines.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The live score's one walk over the pairs gives the same score and the
/// same receptor atoms' shares, to the bit, as `score` and the separate
/// `receptor_contributions`; the shares sum to the pairs' energy (the drug
/// atoms' sums before the curl).
#[test]
fn a_score_with_contributions_is_the_score_and_the_contributions() {
    use bump::score::contrib::receptor_contributions;
    use bump::score::{Field, score_with_contributions};
    let v = values();
    let mut checked = 0;
    for name in complex_names(&v) {
        let cx = &v["complexes"][&name];
        let (receptor, _) = receptor_from_values(cx);
        for pose in cx["poses"].as_array().unwrap() {
            let lig = ligand_at(cx, &pose_xyz(pose));
            let conf = lig.rigid(Pose::IDENTITY);
            let exact = Exact::new(&receptor, Scoring::Vina);
            let (s, shares) =
                score_with_contributions(&exact, Evaluator::Exact, &exact, &lig, &conf);
            assert!(s == score(&exact, Evaluator::Exact, &exact, &lig, &conf));
            let x = lig.place(&conf);
            let want = receptor_contributions(&exact, &lig, &x);
            assert_eq!(shares.len(), want.len(), "{name}");
            for (a, b) in shares.iter().zip(&want) {
                assert_eq!((a.0, a.1.to_bits()), (b.0, b.1.to_bits()), "{name}");
            }
            assert!(!shares.is_empty() && shares.windows(2).all(|w| w[0].0 < w[1].0));
            let pairs: f64 = lig
                .scored
                .iter()
                .zip(&lig.xs)
                .map(|(&i, &t)| exact.atom_energy(t, x[i as usize]))
                .sum();
            let sum: f64 = shares.iter().map(|s| s.1).sum();
            assert!((sum - pairs).abs() < 1e-9, "{name}: {sum} vs {pairs}");
            checked += 1;
        }
    }
    assert!(checked > 0);
}

/// The benchmark report's floors (`bump_testkit::score_bench`) compute
/// what the evaluators compute, to the bit, for trimethoprim in DHFR: the
/// exact evaluator's pairs, and the flexible evaluation's intramolecular
/// pairs. So the floors time the same table reads, not fewer.
#[test]
fn the_reports_floors_compute_what_the_evaluators_do() {
    use bump::score::table::Table;
    use bump::score::{Field, Gradient, Workspace, energy_gradient};
    use bump_testkit::score_bench::{PairList, dhfr, intra_floor, pairs_floor};

    let Some(dir) = shared_pdb() else {
        return;
    };
    let s = dhfr(&dir).unwrap();
    let exact = Exact::new(&s.receptor, Scoring::Vina);
    let table = Table::of(Scoring::Vina);
    let list = PairList::new(&exact, &s.lig, &s.crystal);
    assert!(list.len() > 1000 && list.intra_len() > 50);

    let mut floor = Vec::new();
    pairs_floor(&list, table, &mut floor);
    let x = s.lig.place(&s.crystal);
    let at: Vec<DVec3> = s.lig.scored.iter().map(|&i| x[i as usize]).collect();
    let mut want = vec![(0.0, DVec3::ZERO); at.len()];
    exact.atoms_energy_gradient(&s.lig.xs, &at, &mut want);
    assert_eq!(floor, want);

    let mut forces = Vec::new();
    let intra = intra_floor(&list, table, &mut forces);
    let (mut ws, mut g) = (Workspace::default(), Gradient::default());
    let e = energy_gradient(&exact, &s.lig, &s.crystal, &mut ws, &mut g);
    assert_eq!(intra, e.intra);
}

/// Trimethoprim held at a conformation and moved rigidly gives, at any
/// pose, the energies and the whole gradient (force, torque, each bond's
/// torque) that the flexible evaluation gives at that pose and those
/// torsions: to rounding on the exact evaluator, to the maps' f32 lanes on
/// the maps.
#[test]
fn a_held_conformation_gives_the_flexible_evaluations_gradient() {
    use bump::score::{Field, Gradient, MapField, RigidDrug, Workspace, energy_gradient};
    use bump_testkit::score_bench::{SPACING, dhfr, perturbed};

    let Some(dir) = shared_pdb() else {
        return;
    };
    let s = dhfr(&dir).unwrap();
    let exact = Exact::new(&s.receptor, Scoring::Vina);
    let maps = s.maps(&s.crystal, SPACING, 2);
    let field = MapField::new(&maps, exact);
    let (mut ws, mut want) = (Workspace::default(), Gradient::default());
    let (mut ws2, mut got) = (Workspace::default(), Gradient::default());
    let fields: [(&str, &dyn Field, f64); 2] = [("exact", &exact, 1e-9), ("maps", &field, 2e-4)];
    let mut torqued = 0;
    for (k, mut conf) in perturbed(&s.crystal, 5, 12).into_iter().enumerate() {
        let n = conf.torsions.len();
        conf.torsions = (0..n)
            .map(|j| ((k * 7 + j * 3) % 11) as f64 * 0.25 - 1.25)
            .collect();
        for &(name, f, tol) in &fields {
            let held = RigidDrug::new(f, &s.lig, &conf.torsions);
            let e = energy_gradient(f, &s.lig, &conf, &mut ws, &mut want);
            let h = held.energy_full_gradient(f, &conf.pose, &mut ws2, &mut got);
            let close = |a: f64, b: f64| (a - b).abs() <= tol * (1.0 + b.abs());
            let what = format!("{name}, pose {k}");
            assert!(
                close(h.inter, e.inter),
                "{what}: inter {} vs {}",
                h.inter,
                e.inter
            );
            assert!(
                close(h.intra, e.intra),
                "{what}: intra {} vs {}",
                h.intra,
                e.intra
            );
            for a in 0..3 {
                assert!(
                    close(got.translation[a], want.translation[a]),
                    "{what}: {got:?} vs {want:?}"
                );
                assert!(
                    close(got.rotation[a], want.rotation[a]),
                    "{what}: {got:?} vs {want:?}"
                );
            }
            assert_eq!(got.torsions.len(), n);
            for j in 0..n {
                assert!(
                    close(got.torsions[j], want.torsions[j]),
                    "{what}: {got:?} vs {want:?}"
                );
                torqued += usize::from(want.torsions[j].abs() > 0.01);
            }
        }
    }
    // The bonds' torques were there to compare.
    assert!(torqued > 20, "{torqued}");
}
