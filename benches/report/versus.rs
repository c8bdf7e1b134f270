//! bump against parry3d on the scaling bench's surface approaches, the two
//! timed alternately.
//!
//! The criterion bench times each method in its own stretch of a run, one
//! after another; on a shared machine the load changes between those
//! stretches by more than the methods differ, and a ratio of two such times
//! carries both changes.
//! Here every round times each method once over all the patches, in an
//! order that turns with the round, so the methods share the machine's
//! state within a few milliseconds; a round's ratio is parry3d's time over
//! bump's, and the table gives the median and the spread of those ratios.
//!
//! The queries are the criterion bench's `scaling` group: up to 16 surface patches
//! of 30 atoms per receptor ([`bump_testkit::surface::surface_drugs`]), free under
//! parry3d's rule, each stepping 1.5 Å back towards the surface. bump runs
//! under the default rule (with the N/O allowance, as the program does) and,
//! on the full grid, under parry3d's own rule; the accuracy columns compare
//! both answers with the closed-form time of impact under parry3d's rule.

use std::time::Instant;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, TouchOptions, TouchResult, move_to_touch,
    move_to_touch_into,
};
use bump::motion::Pose;
use bump_testkit::oracle::{closed_form_touch, min_gap};
use bump_testkit::parry::{self, Spheres};
use bump_testkit::surface::{Patch, surface_drugs};

use super::scaling::{load, receptors};
use super::timing::{Progress, median, quantile};
use super::{Context, Part, Section};

/// Surface patches per receptor (the criterion bench's `SURFACE_PATCHES`).
const PATCHES: usize = 16;

/// Length of each approach step, Å (the criterion bench's).
const STEP: f64 = 1.5;

/// The methods timed, in the order of the table's columns.
const METHODS: [&str; 5] = [
    "bump, full grid",
    "bump, hashed grid",
    "bump, full grid, parry3d's rule",
    "parry3d cast + contacts",
    "parry3d cast",
];

/// The section.
pub const SECTION: Section = Section {
    name: "parry3d",
    steps,
    run,
};

/// Number of progress steps [`run`] takes.
fn steps(ctx: &Context) -> usize {
    if ctx.data.is_none() {
        0
    } else {
        receptors(ctx).len()
    }
}

/// One receptor's results.
struct Row {
    file: String,
    atoms: usize,
    patches: usize,
    /// Median over rounds of each method's time per query, µs.
    time: [f64; 5],
    /// Per-round ratios of parry3d's cast + contacts to bump's full grid,
    /// hashed grid and full grid under parry3d's rule, and of parry3d's cast
    /// alone to the full grid: (median, 10th and 90th percentiles).
    ratio: [(f64, f64, f64); 4],
    /// Largest distance short of the exact contact, bump's full grid under
    /// parry3d's rule, Å; and parry3d's largest distance past it.
    bump_short: f64,
    parry_past: f64,
    /// Queries whose stop overlaps under parry3d's rule: bump, parry3d.
    overlapping: (usize, usize),
}

/// Times the methods on `receptor`'s surface approaches.
fn measure(ctx: &Context, file: &str, receptor: &bump::model::Molecule) -> Option<Row> {
    let rule = ContactRule::default();
    let strict = ContactRule::new(rule.overlap, 0.0).unwrap_or(rule);
    let patches: Vec<Patch> = surface_drugs(receptor, &strict, 30, PATCHES);
    if patches.is_empty() {
        return None;
    }
    let steps: Vec<(Pose, Pose)> = patches.iter().map(|p| (p.start, p.step_in(STEP))).collect();
    let built = |rule: &ContactRule, kind| {
        let col = Collider::build(receptor, rule, kind);
        col.wait_for_clearance();
        let atoms: Vec<DrugAtoms> = patches
            .iter()
            .map(|p| DrugAtoms::new(&p.drug, rule, col.max_radius()))
            .collect();
        (col, atoms)
    };
    let grid = built(&rule, ColliderKind::Grid);
    let hashed = built(&rule, ColliderKind::Hashed);
    let strict_grid = built(&strict, ColliderKind::Grid);
    let rec = Spheres::new(receptor, &rule);
    let drugs: Vec<Spheres> = patches
        .iter()
        .map(|p| Spheres::new(&p.drug, &rule))
        .collect();
    let opts = TouchOptions::default();

    // Accuracy under parry3d's rule, against the closed form.
    let (mut bump_short, mut parry_past) = (0.0f64, 0.0f64);
    let mut overlapping = (0, 0);
    for (k, (s, e)) in steps.iter().enumerate() {
        let d = e.translation - s.translation;
        let exact = closed_form_touch(&strict_grid.0, &strict_grid.1[k], s, d).unwrap_or(1.0);
        let ours = move_to_touch(&strict_grid.0, &strict_grid.1[k], s, e, &opts);
        let theirs = parry::cast(&rec, &drugs[k], s, e);
        bump_short = bump_short.max((exact - ours.t) * STEP);
        parry_past = parry_past.max((theirs - exact) * STEP);
        let at = |t: f64| Pose::new(s.rotation, s.translation + d * t);
        let overlaps = |t: f64| min_gap(&strict, receptor, &patches[k].drug, &at(t)) < -1e-6;
        overlapping.0 += usize::from(overlaps(ours.t));
        overlapping.1 += usize::from(overlaps(theirs));
    }

    // A bump query takes well under a microsecond: each timing covers
    // `cycles` passes over the patches (about a thousand queries).
    let (rounds, cycles) = if ctx.quick { (3, 2) } else { (41, 64) };
    let mut times: [Vec<f64>; 5] = Default::default();
    // Each side keeps its answer's storage from query to query, as a
    // loop of queries can: bump's result, parry3d's contact list.
    let mut result = TouchResult::default();
    let mut contacts = Vec::new();
    let per_query = 1e6 / (cycles * steps.len()) as f64;
    // Round 0 warms the caches and is not kept.
    for r in 0..=rounds {
        for m in (0..METHODS.len()).map(|i| (i + r) % METHODS.len()) {
            let t0 = Instant::now();
            for _ in 0..cycles {
                for (k, (s, e)) in steps.iter().enumerate() {
                    let e = std::hint::black_box(e);
                    match m {
                        0..=2 => {
                            let (col, atoms) = [&grid, &hashed, &strict_grid][m];
                            move_to_touch_into(col, &atoms[k], s, e, &opts, &mut result);
                            std::hint::black_box(&result);
                        }
                        3 => {
                            std::hint::black_box(parry::touch(
                                &rec,
                                &drugs[k],
                                s,
                                e,
                                opts.tolerance as f32,
                                &mut contacts,
                            ));
                            std::hint::black_box(&contacts);
                        }
                        _ => {
                            std::hint::black_box(parry::cast(&rec, &drugs[k], s, e));
                        }
                    }
                }
            }
            if r > 0 {
                times[m].push(t0.elapsed().as_secs_f64() * per_query);
            }
        }
    }
    let ratios = |num: usize, den: usize| {
        let v: Vec<f64> = times[num]
            .iter()
            .zip(&times[den])
            .map(|(a, b)| a / b)
            .collect();
        (median(&v), quantile(&v, 0.1), quantile(&v, 0.9))
    };
    Some(Row {
        file: file.to_string(),
        atoms: receptor.len(),
        patches: steps.len(),
        time: std::array::from_fn(|m| median(&times[m])),
        ratio: [ratios(3, 0), ratios(3, 1), ratios(3, 2), ratios(4, 0)],
        bump_short,
        parry_past,
        overlapping,
    })
}

/// Runs the comparison on every receptor of the scaling section.
fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let mut md =
        String::from("## bump against parry3d on surface approaches, timed alternately\n\n");
    let Some(dir) = ctx.data.as_ref() else {
        md.push_str("Skipped: `../shared/pdb` not found.\n");
        return Part::text(md);
    };
    let mut rows = Vec::new();
    for file in receptors(ctx) {
        progress.step(&format!("against parry3d: {file}"));
        match load(dir, file) {
            Ok(r) => match measure(ctx, file, &r) {
                Some(row) => rows.push(row),
                None => md.push_str(&format!("- {file} skipped: no atoms\n")),
            },
            Err(e) => md.push_str(&format!("- {file} skipped: {e}\n")),
        }
    }
    md.push_str(&format!(
        "The criterion bench's `scaling` queries: up to {PATCHES} patches of each receptor's \
         surface (30 atoms each; fewer where two directions share an outermost atom), every one stepping {STEP} Å back towards the surface, \
         tolerance 10⁻³ Å. Each round times every method once over all the patches (about \
         a thousand queries), the methods' order turning with the round, so they share \
         the machine's state; *ratio* is the median over rounds of parry3d's time over \
         bump's in the same round (in brackets the 10th and 90th percentiles of the rounds' ratios: \
         a round that the machine interrupts in one method's timing gives an outlier). Each side \
         keeps its answer's storage from query to query (bump's result through \
         `move_to_touch_into`, parry3d's contact list), so neither allocates for it. *Short* is the \
         largest distance bump's full grid under parry3d's rule stops before the exact \
         contact (closed form, f64); *past* parry3d's largest distance beyond it; \
         *overlapping* counts stops where a pair overlaps by more than 10⁻⁶ Å (bump / \
         parry3d).\n\n\
         | receptor | atoms | bump grid | bump hashed | bump grid, parry rule | parry3d cast + contacts | parry3d cast | ratio, grid | ratio, hashed | ratio, grid, parry rule | cast alone / grid | short Å | past Å | overlapping |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    ));
    let ratio = |(m, lo, hi): (f64, f64, f64)| format!("**{m:.1}×** ({lo:.1}–{hi:.1})");
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {:.3} µs | {:.3} µs | {:.3} µs | {:.2} µs | {:.2} µs | {} | {} | {} | {} | {:.1e} | {:.1e} | {} / {} of {} |\n",
            r.file,
            r.atoms,
            r.time[0],
            r.time[1],
            r.time[2],
            r.time[3],
            r.time[4],
            ratio(r.ratio[0]),
            ratio(r.ratio[1]),
            ratio(r.ratio[2]),
            ratio(r.ratio[3]),
            r.bump_short,
            r.parry_past,
            r.overlapping.0,
            r.overlapping.1,
            r.patches,
        ));
    }
    let mut headline = Vec::new();
    if !rows.is_empty() {
        let range = |k: usize| {
            let v: Vec<f64> = rows.iter().map(|r| r.ratio[k].0).collect();
            (quantile(&v, 0.0), quantile(&v, 1.0))
        };
        let ((g0, g1), (h0, h1)) = (range(0), range(1));
        headline.push(format!(
            "Surface approaches on receptors of {}–{} atoms, timed alternately: parry3d doing \
             move-to-touch (cast + contacts) takes {:.1}–{:.1}× bump's time ({g0:.1}–{g1:.1}× \
             the full grid's, {h0:.1}–{h1:.1}× the hashed grid's; medians over rounds)",
            rows.iter().map(|r| r.atoms).min().unwrap_or(0),
            rows.iter().map(|r| r.atoms).max().unwrap_or(0),
            g0.min(h0),
            g1.max(h1),
        ));
    }
    Part {
        markdown: md,
        figures: Vec::new(),
        headline,
    }
}
