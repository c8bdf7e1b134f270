//! What each optional layer of the collision queries saves
//! ([`bump::collide::Layers`]): every query kind timed with all layers on
//! and with each one off, on the same queries, alternately.
//!
//! A timing on this shared machine drifts by more than some layers save,
//! so no configuration is timed in its own stretch of the run: every round
//! times each configuration once over all of a workload's queries, in an
//! order that turns with the round, and a round's ratio (a configuration's
//! time over all layers' time) compares timings a few milliseconds apart.
//! The table gives the median of those ratios over the rounds and their
//! 10th–90th percentiles. Every configuration's answers are compared with
//! all layers' (same `t`, same contacts, bit for bit).

use std::time::Instant;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Layers, TouchOptions, TouchResult, check,
    move_to_touch_into,
};
use bump::model::Molecule;
use bump::motion::Pose;
use bump_testkit::Rng;
use bump_testkit::surface::surface_drugs;
use glam::DQuat;

use super::accuracy::cases;
use super::scaling::{load, receptors};
use super::timing::{Progress, median, quantile};
use super::{Context, Part, Section};

/// The section.
pub const SECTION: Section = Section {
    name: "layers",
    steps,
    run,
};

/// Which query a workload asks.
#[derive(Clone, Copy, PartialEq)]
enum Query {
    /// Move-to-touch from the start to the end pose.
    Touch,
    /// The static check at the start and at the end pose.
    Check,
}

/// Queries of one kind on one receptor.
struct Workload {
    name: String,
    query: Query,
    receptor: Molecule,
    drugs: Vec<Molecule>,
    /// (drug, start, end), relative poses.
    queries: Vec<(usize, Pose, Pose)>,
}

/// The configurations timed: all layers, then each one off.
fn configurations() -> Vec<(&'static str, Layers)> {
    let mut v = vec![("all layers", Layers::ALL)];
    for name in Layers::NAMES {
        if let Some(l) = Layers::without(name) {
            v.push((name, l));
        }
    }
    v
}

/// The approaches of the accuracy section (DHFR's pocket, the E through
/// the rings) under the default rule, DHFR's also turning 10° about a
/// seeded axis, and the surface approaches of the scaling receptors.
fn workloads(ctx: &Context, progress: &mut Progress) -> (Vec<Workload>, Vec<String>) {
    let rule = ContactRule::default();
    let n = if ctx.quick { ctx.queries } else { 200 };
    let (approaches, mut notes) = cases(ctx, &rule, n);
    let mut out = Vec::new();
    for case in approaches {
        let dhfr = case.name.contains("DHFR");
        let short = if dhfr {
            "TMP into DHFR's pocket"
        } else {
            "the E through the rings"
        };
        let moves: Vec<(usize, Pose, Pose)> =
            case.queries.iter().map(|(s, e)| (0, *s, *e)).collect();
        let workload = |name: String, query, queries| Workload {
            name,
            query,
            receptor: case.receptor.clone(),
            drugs: vec![case.drug.clone()],
            queries,
        };
        out.push(workload(
            format!("touch: {short}"),
            Query::Touch,
            moves.clone(),
        ));
        if dhfr {
            let mut rng = Rng(0x10);
            let turned = moves
                .iter()
                .map(|&(k, s, e)| {
                    let turn = DQuat::from_axis_angle(rng.unit(), 10f64.to_radians());
                    (k, s, Pose::new(turn * s.rotation, e.translation))
                })
                .collect();
            out.push(workload(
                format!("touch: {short}, turning 10°"),
                Query::Touch,
                turned,
            ));
            out.push(workload(
                format!("check: {short}, start and end poses"),
                Query::Check,
                moves,
            ));
        }
    }
    if let Some(dir) = &ctx.data {
        let files = if ctx.quick {
            &receptors(ctx)[..1]
        } else {
            receptors(ctx)
        };
        for file in files {
            progress.step(&format!("layers: surface patches of {file}"));
            let receptor = match load(dir, file) {
                Ok(r) => r,
                Err(e) => {
                    notes.push(format!("{file} skipped: {e}"));
                    continue;
                }
            };
            let patches = surface_drugs(&receptor, &rule, 30, 16);
            let queries: Vec<(usize, Pose, Pose)> = patches
                .iter()
                .enumerate()
                .map(|(k, p)| (k, p.start, p.step_in(1.5)))
                .collect();
            let drugs: Vec<Molecule> = patches.into_iter().map(|p| p.drug).collect();
            for query in [Query::Touch, Query::Check] {
                let what = if query == Query::Touch {
                    "touch"
                } else {
                    "check"
                };
                out.push(Workload {
                    name: format!("{what}: surface patches of {file}"),
                    query,
                    receptor: receptor.clone(),
                    drugs: drugs.clone(),
                    queries: queries.clone(),
                });
            }
        }
    }
    (out, notes)
}

/// One workload's results: all layers' time per query (µs), each other
/// configuration's ratio to it (median, 10th, 90th percentile over
/// rounds), and whether every configuration answered as all layers did.
struct Row {
    name: String,
    query: Query,
    atoms: usize,
    queries: usize,
    base_us: f64,
    ratios: Vec<(f64, f64, f64)>,
    same_answers: bool,
}

/// A configuration ready to run: its collider and drugs.
struct Ready<'a> {
    collider: &'a Collider,
    drugs: Vec<DrugAtoms>,
}

/// One pass over `w`'s queries with `r`; the answers, for comparing.
fn pass(w: &Workload, r: &Ready<'_>, result: &mut TouchResult, answers: Option<&mut Vec<u64>>) {
    let opts = TouchOptions::default();
    let mut keep = answers;
    for (k, s, e) in &w.queries {
        let drug = &r.drugs[*k];
        match w.query {
            Query::Touch => {
                move_to_touch_into(r.collider, drug, s, std::hint::black_box(e), &opts, result);
                if let Some(a) = keep.as_deref_mut() {
                    a.push(result.t.to_bits());
                    a.extend(result.contacts.iter().map(|p| {
                        (u64::from(p.receptor) << 32 | u64::from(p.drug))
                            ^ u64::from(p.distance.to_bits())
                    }));
                }
                std::hint::black_box(&result);
            }
            Query::Check => {
                for pose in [s, e] {
                    let pairs = check(r.collider, drug, std::hint::black_box(pose));
                    if let Some(a) = keep.as_deref_mut() {
                        a.extend(
                            pairs
                                .iter()
                                .map(|p| u64::from(p.receptor) << 32 | u64::from(p.drug)),
                        );
                    }
                    std::hint::black_box(pairs);
                }
            }
        }
    }
}

/// Times `w` under every configuration, alternately.
fn measure(ctx: &Context, w: &Workload) -> Row {
    let rule = ContactRule::default();
    let configs = configurations();
    // One collider for each set of the collider's own layers (the others
    // are the drug's).
    let key = |l: &Layers| (l.clearance_map, l.padded_rows);
    let mut colliders: Vec<((bool, bool), Collider)> = Vec::new();
    for (_, layers) in &configs {
        if !colliders.iter().any(|(k, _)| *k == key(layers)) {
            let c = Collider::build_with(&w.receptor, &rule, ColliderKind::Hashed, layers);
            c.wait_for_clearance();
            colliders.push((key(layers), c));
        }
    }
    let ready: Vec<Ready<'_>> = configs
        .iter()
        .filter_map(|(_, layers)| {
            let collider = &colliders.iter().find(|(k, _)| *k == key(layers))?.1;
            let drugs = w
                .drugs
                .iter()
                .map(|d| DrugAtoms::with_layers(d, &rule, collider.max_radius(), layers))
                .collect();
            Some(Ready { collider, drugs })
        })
        .collect();
    let mut result = TouchResult::default();
    let answers: Vec<Vec<u64>> = ready
        .iter()
        .map(|r| {
            let mut a = Vec::new();
            pass(w, r, &mut result, Some(&mut a));
            a
        })
        .collect();
    let same_answers = answers.iter().all(|a| *a == answers[0]);
    let per_pass = w.queries.len() * if w.query == Query::Check { 2 } else { 1 };
    // About a thousand queries per timing, so the clock's resolution and a
    // timer interrupt are small beside it.
    let cycles = (1000 / per_pass.max(1)).max(1);
    let rounds = if ctx.quick { 3 } else { 31 };
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); ready.len()];
    // Round 0 warms the caches and is not kept.
    for round in 0..=rounds {
        for m in (0..ready.len()).map(|i| (i + round) % ready.len()) {
            let t0 = Instant::now();
            for _ in 0..cycles {
                pass(w, &ready[m], &mut result, None);
            }
            if round > 0 {
                times[m].push(t0.elapsed().as_secs_f64() * 1e6 / (cycles * per_pass) as f64);
            }
        }
    }
    let ratios = (1..ready.len())
        .map(|m| {
            let v: Vec<f64> = times[m].iter().zip(&times[0]).map(|(a, b)| a / b).collect();
            (median(&v), quantile(&v, 0.1), quantile(&v, 0.9))
        })
        .collect();
    Row {
        name: w.name.clone(),
        query: w.query,
        atoms: w.receptor.len(),
        queries: per_pass,
        base_us: median(&times[0]),
        ratios,
        same_answers,
    }
}

/// Number of progress steps [`run`] takes.
fn steps(ctx: &Context) -> usize {
    let receptors = match (&ctx.data, ctx.quick) {
        (None, _) => 0,
        (Some(_), true) => 1,
        (Some(_), false) => receptors(ctx).len(),
    };
    // Each receptor's loading and its two workloads; DHFR's three and the
    // E's one.
    3 * receptors + 3 * usize::from(ctx.data.is_some()) + 1
}

/// Measures every workload and writes the table.
fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let (work, notes) = workloads(ctx, progress);
    let mut rows = Vec::new();
    for w in &work {
        progress.step(&format!("layers: {}", w.name));
        rows.push(measure(ctx, w));
    }
    let names: Vec<&str> = configurations()[1..].iter().map(|c| c.0).collect();
    let mut md = String::from("## Optimisation layers\n\n");
    md.push_str(
        "What each optional layer of the queries saves (`bump::collide::Layers`; answers \
         are the same without any of them): each workload's queries with all layers on, \
         and with each one off, on the hashed grid (the default collider), default rule, \
         tolerance 10⁻³ Å. Every round times each configuration once over all the \
         workload's queries (about a thousand), in an order that turns with the round; \
         a cell is the median over rounds of that round's time without the layer over \
         its time with all layers (above 1: the layer saves time), with the 10th–90th \
         percentiles of the rounds' ratios in brackets. *Same answers*: every \
         configuration returned all layers' `t` and contacts, bit for bit.\n\n",
    );
    for n in &notes {
        md.push_str(&format!("- {n}\n"));
    }
    md.push_str("| workload | receptor atoms | queries | all layers |");
    for n in &names {
        md.push_str(&format!(" without {n} |"));
    }
    md.push_str(" same answers |\n| --- | ---: | ---: | ---: |");
    for _ in &names {
        md.push_str(" ---: |");
    }
    md.push_str(" --- |\n");
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {} | {:.3} µs |",
            r.name, r.atoms, r.queries, r.base_us
        ));
        for (m, lo, hi) in &r.ratios {
            md.push_str(&format!(" **{m:.2}×** ({lo:.2}–{hi:.2}) |"));
        }
        md.push_str(if r.same_answers {
            " yes |\n"
        } else {
            " **no** |\n"
        });
    }
    let mut headline = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let range = |q: Query| {
            let v: Vec<f64> = rows
                .iter()
                .filter(|r| r.query == q)
                .map(|r| r.ratios[k].0)
                .collect();
            (quantile(&v, 0.0), quantile(&v, 1.0))
        };
        let ((t0, t1), (c0, c1)) = (range(Query::Touch), range(Query::Check));
        headline.push(format!(
            "Without the {name}, move-to-touch takes {t0:.2}–{t1:.2}× as long and the static check {c0:.2}–{c1:.2}× (medians over alternated rounds, per workload)"
        ));
    }
    if rows.iter().any(|r| !r.same_answers) {
        headline.push("**A layer changed an answer** (see the layers table)".into());
    }
    md.push_str(&format!(
        "\nA layer stays where it saves at least 10 % on its workloads (a cell of 1.10× or \
         more); otherwise the simpler code without it wins. Drug sizes: {} atoms (TMP), {} \
         (the E), 30 (surface patches).\n",
        work.first().map_or(0, |w| w.drugs[0].len()),
        work.iter()
            .find(|w| w.name.contains("the E"))
            .map_or(0, |w| w.drugs[0].len()),
    ));
    Part {
        markdown: md,
        figures: Vec::new(),
        headline,
    }
}
