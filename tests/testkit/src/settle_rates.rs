//! Settle from perturbed crystal poses on every shared complex of the Vina
//! reference (`tests/reference/vina/values.json`): what `tests/settle.rs`
//! checks and the report's scoring section prints, from the same runs.
//!
//! Each complex is loaded as the reference prepared it ([`load_complex`]:
//! the file's polymer as the receptor), the drug starts at seeded
//! perturbations of its crystal pose ([`perturbations`]: up to 1.5 Å and
//! 30°) and settles on maps (0.375 Å, 6 Å around the crystal pose) with
//! the hashed grid keeping it collision-free under the default rule. Each
//! run's end is checked for collisions independently of what settle says,
//! and the RMSD to the crystal pose is measured over the heavy atoms.

use std::path::{Path, PathBuf};

use bump::collide::{Collider, ColliderKind, ContactRule};
use bump::motion::Pose;
use bump::rng::Rng;
use bump::score::maps::{MapBox, Maps};
use bump::score::settle::rmsd;
use bump::score::{Contacts, Exact, MapField, Scoring, SettleOptions, prepare, settle};
use glam::{DQuat, DVec3};

use crate::vina_reference::{COMPLEXES, load_complex};

/// Seeded perturbations of a pose: a shift of up to 1.5 Å and a turn of up
/// to 30° about the drug's centre.
pub fn perturbations(seed: u64, n: usize) -> Vec<(DVec3, DQuat)> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let shift = rng.unit() * 1.5 * rng.f64().cbrt();
            let turn = DQuat::from_axis_angle(rng.unit(), rng.f64() * 30f64.to_radians());
            (shift, turn)
        })
        .collect()
}

/// The seed of the runs reported.
pub const SEED: u64 = 43;

/// What settling one complex's perturbed starts gave.
#[derive(Debug, Clone)]
pub struct Rates {
    /// The complex.
    pub id: &'static str,
    /// Starts settled.
    pub runs: usize,
    /// Starts that already collided.
    pub colliding_start: usize,
    /// Runs that ended within 1 Å heavy-atom RMSD of the crystal pose.
    pub back: usize,
    /// Runs that ended colliding.
    pub colliding_end: usize,
    /// Median RMSD to the crystal pose after settle (Å).
    pub median_rmsd: f64,
    /// Median steps taken.
    pub median_steps: usize,
    /// Vina's own optimize on the reference's small perturbations: the
    /// RMSD to the crystal pose after it (Å).
    pub vina_after: Vec<f64>,
    /// What went wrong: a run whose energy rose from a clear start, one
    /// that ended colliding, or one whose reported collisions disagree with
    /// the independent check.
    pub problems: Vec<String>,
}

/// Settles `runs` seeded perturbations of complex `id`'s crystal pose.
pub fn settle_complex(dir: &Path, id: &'static str, runs: usize) -> Rates {
    let rule = ContactRule::default();
    let (rec_mol, drug) = load_complex(dir, id);
    let receptor = prepare::receptor(&rec_mol);
    let lig = prepare::ligand(&drug).expect("ligand");
    let collider = Collider::build(&rec_mol, &rule, ColliderKind::Hashed);
    let crystal = Pose::from_translation(drug.centre - rec_mol.centre);
    let x_crystal = lig.place(&lig.rigid(crystal));
    let bx = MapBox::around(&x_crystal, 6.0, 0.375);
    let maps = Maps::build(&receptor, Scoring::Vina, &lig.xs, &bx, 2).expect("maps");
    let field = MapField::new(&maps, Exact::new(&receptor, Scoring::Vina));
    let mut contacts = Contacts::new(&collider, rule, &drug, &lig);
    let mut r = Rates {
        id,
        runs,
        colliding_start: 0,
        back: 0,
        colliding_end: 0,
        median_rmsd: f64::NAN,
        median_steps: 0,
        vina_after: vina_optimize_after(id),
        problems: Vec::new(),
    };
    let (mut after, mut steps) = (Vec::new(), Vec::new());
    for (k, (shift, turn)) in perturbations(SEED, runs).into_iter().enumerate() {
        let start = Pose::new(turn * crystal.rotation, crystal.translation + shift);
        let s = settle(
            &field,
            &lig,
            &mut contacts,
            &lig.rigid(start),
            &SettleOptions::default(),
        );
        let x = lig.place(&s.conf);
        let d = rmsd(&x, &x_crystal);
        after.push(d);
        steps.push(s.steps);
        r.back += usize::from(d < 1.0);
        let clear_start = s.start_collisions.is_empty();
        r.colliding_start += usize::from(!clear_start);
        if clear_start && s.minimised.1 > s.minimised.0 + 1e-9 {
            r.problems.push(format!("{id} run {k}: energy rose"));
        }
        // Checked independently of what settle reports.
        let end = contacts.collisions(&x);
        if !end.is_empty() {
            r.colliding_end += 1;
            let how = if clear_start { "clear" } else { "colliding" };
            r.problems.push(format!(
                "{id} run {k}: ends colliding (start {how}): {end:?}"
            ));
        }
        if end.is_empty() != s.end_collisions.is_empty() {
            r.problems.push(format!(
                "{id} run {k}: settle reports {} end collisions, the check finds {}",
                s.end_collisions.len(),
                end.len()
            ));
        }
    }
    after.sort_by(f64::total_cmp);
    steps.sort_unstable();
    r.median_rmsd = after.get(runs / 2).copied().unwrap_or(f64::NAN);
    r.median_steps = steps.get(runs / 2).copied().unwrap_or(0);
    r
}

/// The committed reference values.
fn values_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../reference/vina/values.json")
}

/// Vina's own optimize on complex `id`'s small perturbations (the
/// reference's `small_*` poses): the RMSD to the crystal pose after it.
pub fn vina_optimize_after(id: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(values_path()).expect("values.json is committed");
    let v: serde_json::Value = serde_json::from_str(&text).expect("values.json parses");
    v["complexes"][id]["optimize"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter(|o| o["pose"].as_str().is_some_and(|p| p.starts_with("small")))
                .filter_map(|o| o["rmsd_to_crystal_after"].as_f64())
                .collect()
        })
        .unwrap_or_default()
}

/// The table of [`settle_complex`] over every complex, `runs` starts each.
pub fn table(rates: &[Rates]) -> String {
    let mut s = String::from(
        "| complex | runs | start colliding | returned within 1 Å | ends colliding | median RMSD after (Å) | median steps | Vina's optimize (RMSD after, small_1/small_2) |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in rates {
        let vina: Vec<String> = r.vina_after.iter().map(|d| format!("{d:.2}")).collect();
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.2} | {} | {} |\n",
            r.id,
            r.runs,
            r.colliding_start,
            r.back,
            r.colliding_end,
            r.median_rmsd,
            r.median_steps,
            vina.join(", ")
        ));
    }
    s
}

/// The report's subsection: every complex, `runs` starts each.
pub fn markdown(dir: &Path, runs: usize) -> String {
    let rates: Vec<Rates> = COMPLEXES
        .iter()
        .map(|&(id, ..)| settle_complex(dir, id, runs))
        .collect();
    format!(
        "### Settle from perturbed crystal poses\n\n\
         Every shared complex of the Vina reference (receptor: the file's polymer), {runs} seeded \
         starts each, shifted up to 1.5 Å and turned up to 30° from the crystal pose; settle on \
         maps (0.375 Å) with the hashed grid, default contact rule; *returned*: heavy-atom RMSD \
         to the crystal pose under 1 Å after settle; *ends colliding*: checked independently of \
         settle's own answer. Vina's column: its `optimize` on the reference's two small \
         perturbations (`tests/reference/vina/values.json`).\n\n{}\n",
        table(&rates)
    )
}
