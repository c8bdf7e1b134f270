//! Agreement with AutoDock Vina 1.2.7 on every complex and pose recorded in
//! `tests/reference/vina/values.json`, with Vina's own atom types, tree,
//! pairs and torsion count: totals, inter and intra energies and every term
//! agree to 1e-6 kcal/mol (Vina's and bump's table are the same samples).

mod score_support;

use bump::motion::Pose;
use bump::score::{Evaluator, Exact, Scoring, score};
use score_support::*;

#[test]
fn every_pose_scores_as_vina_with_vinas_types() {
    let v = values();
    let mut worst = 0.0f64;
    let mut count = 0;
    for name in complex_names(&v) {
        let cx = &v["complexes"][&name];
        let (receptor, _) = receptor(cx);
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
                check("inter", s.inter, want["score"]["lig_inter"].as_f64().unwrap());
                check("intra", s.intra, want["score"]["lig_intra"].as_f64().unwrap());
                check("total", s.total, want["score"]["total"].as_f64().unwrap());
                check("divisor", s.divisor, want["divisor"].as_f64().unwrap());
                for t in &s.terms {
                    let raw = &want["terms_raw"][t.name];
                    check(t.name, t.inter_raw, raw["inter"].as_f64().unwrap());
                    check(t.name, t.intra_raw, raw["intra"].as_f64().unwrap());
                }
                let atoms: f64 = s.atoms.iter().map(|a| a.inter).sum();
                assert!((atoms - s.inter).abs() < 1e-9, "{id}: atoms' shares sum to inter");
            }
        }
    }
    eprintln!("{count} numbers, largest difference from Vina {worst:.2e} kcal/mol");
}
