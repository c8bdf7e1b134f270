//! Scaling: the static check and move-to-touch against receptor size (1.3k to
//! 272k atoms) and drug size (10 to 200 atoms) for each collider, and collider
//! build time against atom count.
//!
//! The drug is a patch of the receptor's own surface: its outermost atom and
//! that atom's nearest neighbours (a copy), pushed outwards until it is free
//! ([`bump_testkit::surface`], which the criterion bench shares).
//! The check is at the end pose, a 1.5 Å step back towards the surface (it
//! collides there); move-to-touch is that step (it touches on the way).

use std::path::Path;
use std::time::Instant;

use bump::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, TouchOptions, TouchResult, check,
    move_to_touch, move_to_touch_into,
};
use bump::model::{self, LoadOptions, Molecule};
use bump::motion::Pose;
use bump_testkit::surface::surface_drug;

use super::svg::{Panel, Series};
use super::timing::{Progress, median, median_us};
use super::{Context, Part, Section};

/// Receptors from small to large.
static RECEPTORS: [&str; 5] = [
    "1rx1.pdb",
    "4kya.pdb.gz",
    "2btv.pdb.gz",
    "1aon.pdb.gz",
    "1f2n_assembly1.cif.gz",
];

/// Drug sizes for the drug-size sweep.
const DRUG_SIZES: [usize; 5] = [10, 20, 50, 100, 200];

/// The receptor file the drug-size sweep uses.
const DRUG_SWEEP_RECEPTOR: &str = "4kya.pdb.gz";

pub(super) fn receptors(ctx: &Context) -> &'static [&'static str] {
    if ctx.quick {
        &RECEPTORS[..2]
    } else {
        &RECEPTORS
    }
}

/// The section.
pub const SECTION: Section = Section {
    name: "scaling",
    steps,
    run,
};

/// Number of progress steps [`run`] takes.
fn steps(ctx: &Context) -> usize {
    if ctx.data.is_none() {
        return 0;
    }
    receptors(ctx).len() + DRUG_SIZES.len()
}

/// An `n`-atom surface patch of `receptor` ([`surface_drug`]), its free
/// start and the end of a 1.5 Å step back in (relative poses).
fn patch(receptor: &Molecule, rule: &ContactRule, n: usize) -> Option<(Molecule, Pose, Pose)> {
    let p = surface_drug(receptor, rule, n)?;
    let end = p.step_in(1.5);
    Some((p.drug, p.start, end))
}

/// Times of one drug against one receptor, per collider (µs).
struct Timing {
    check: [f64; 3],
    touch: [f64; 3],
    thesis: f64,
    build: [f64; 3],
    touched: bool,
}

impl Timing {
    /// The table cells shared by the receptor- and drug-size tables: checks
    /// and touches per collider, the thesis method, and whether it touched.
    fn cells(&self) -> String {
        format!(
            "{} | {} | {} | {} | {} | {} | {} | {}",
            us(self.check[0]),
            us(self.check[1]),
            us(self.check[2]),
            us(self.touch[0]),
            us(self.touch[1]),
            us(self.touch[2]),
            us(self.thesis),
            if self.touched { "yes" } else { "no" }
        )
    }
}

fn time_all(
    ctx: &Context,
    rule: &ContactRule,
    receptor: &Molecule,
    drug: &Molecule,
    start: &Pose,
    end: &Pose,
) -> Timing {
    let mut t = Timing {
        check: [0.0; 3],
        touch: [0.0; 3],
        thesis: 0.0,
        build: [0.0; 3],
        touched: false,
    };
    let opts = TouchOptions::default();
    for (k, kind) in ColliderKind::ALL.into_iter().enumerate() {
        let builds: Vec<f64> = (0..ctx.reps.min(7))
            .map(|_| {
                // The whole build: the grid and its clearance map (which the
                // collider builds on its own thread, answering meanwhile).
                let t0 = Instant::now();
                let col = Collider::build(receptor, rule, kind);
                col.wait_for_clearance();
                std::hint::black_box(col);
                t0.elapsed().as_secs_f64() * 1e6
            })
            .collect();
        t.build[k] = median(&builds);
        let col = Collider::build(receptor, rule, kind);
        col.wait_for_clearance();
        let atoms = DrugAtoms::new(drug, rule, col.max_radius());
        // Brute force on 272k atoms takes milliseconds: fewer repetitions.
        let reps = if kind == ColliderKind::Brute {
            ctx.reps.min(5)
        } else {
            ctx.reps
        };
        let inner = if kind == ColliderKind::Brute { 1 } else { 20 };
        t.check[k] = median_us(reps, inner, || check(&col, &atoms, end));
        // The result's storage is reused, as a loop of queries can keep it
        // (and as the comparison with parry3d times it).
        let mut result = TouchResult::default();
        t.touch[k] = median_us(reps, inner, || {
            move_to_touch_into(&col, &atoms, start, end, &opts, &mut result);
            result.t
        });
        if kind == ColliderKind::Hashed {
            t.touched = move_to_touch(&col, &atoms, start, end, &opts).t < 1.0;
            let thesis = TouchOptions {
                method: Method::Thesis,
                ..opts
            };
            t.thesis = median_us(reps, inner, || {
                move_to_touch_into(&col, &atoms, start, end, &thesis, &mut result);
                result.t
            });
        }
    }
    t
}

/// One series per collider of the figure `pick` chooses.
fn per_collider(data: &[(f64, &Timing)], pick: impl Fn(&Timing) -> [f64; 3]) -> Vec<Series> {
    ColliderKind::ALL
        .iter()
        .enumerate()
        .map(|(k, kind)| Series {
            name: kind.name().to_string(),
            points: data.iter().map(|(x, t)| (*x, pick(t)[k])).collect(),
        })
        .collect()
}

fn us(v: f64) -> String {
    if v >= 1000.0 {
        format!("{:.2} ms", v / 1000.0)
    } else {
        format!("{v:.2} µs")
    }
}

pub(super) fn load(dir: &Path, file: &str) -> Result<Molecule, String> {
    let l = model::load(&dir.join(file), &LoadOptions::default()).map_err(|e| e.to_string())?;
    model::receptor_only(&l.structure).map_err(|e| e.to_string())
}

/// Runs the receptor-size and drug-size sweeps.
fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let mut md = String::from("## Scaling\n\n");
    let Some(dir) = ctx.data.as_ref() else {
        md.push_str("Skipped: `../shared/pdb` not found.\n");
        return Part::text(md);
    };
    let rule = ContactRule::default();
    let mut headline = Vec::new();
    // Receptor size.
    let mut rows: Vec<(String, usize, Timing)> = Vec::new();
    for file in receptors(ctx) {
        progress.step(&format!("receptor size: {file}"));
        match load(dir, file) {
            Ok(r) => match patch(&r, &rule, 30) {
                Some((drug, start, end)) => {
                    let t = time_all(ctx, &rule, &r, &drug, &start, &end);
                    rows.push((file.to_string(), r.len(), t));
                }
                None => md.push_str(&format!("- {file} skipped: no atoms\n")),
            },
            Err(e) => md.push_str(&format!("- {file} skipped: {e}\n")),
        }
    }
    md.push_str(
        "### Receptor size: a 30-atom drug against 1.3k to 272k atoms\n\n\
         Default rule (ChimeraX clash values), tolerance 10⁻³ Å. Medians of repeated runs.\n\n\
         | receptor | atoms | check brute | check grid | check hashed | touch brute | touch grid | touch hashed | touch thesis (hashed) | touched |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |\n",
    );
    for (f, n, t) in &rows {
        md.push_str(&format!("| {f} | {n} | {} |\n", t.cells()));
    }
    if let (Some(a), Some(b)) = (rows.first(), rows.last())
        && rows.len() > 1
    {
        let r = |x: f64, y: f64| format!("{:.2}×", y / x);
        md.push_str(&format!(
            "| **largest / smallest** | {:.0}× | {} | {} | {} | {} | {} | {} | {} | |\n",
            b.1 as f64 / a.1 as f64,
            r(a.2.check[0], b.2.check[0]),
            r(a.2.check[1], b.2.check[1]),
            r(a.2.check[2], b.2.check[2]),
            r(a.2.touch[0], b.2.touch[0]),
            r(a.2.touch[1], b.2.touch[1]),
            r(a.2.touch[2], b.2.touch[2]),
            r(a.2.thesis, b.2.thesis),
        ));
        headline.push(format!(
            "Receptor size {}→{} atoms: move-to-touch grows {:.2}× (grid), {:.2}× (hashed), {:.0}× (brute); at {} atoms the hashed grid is {:.0}× faster than brute force (touch), the full grid {:.0}×",
            a.1,
            b.1,
            b.2.touch[1] / a.2.touch[1],
            b.2.touch[2] / a.2.touch[2],
            b.2.touch[0] / a.2.touch[0],
            b.1,
            b.2.touch[0] / b.2.touch[2],
            b.2.touch[0] / b.2.touch[1],
        ));
    }
    md.push_str(
        "\n### Collider build time against atom count\n\n\
         The grids' times include their clearance maps, which a collider builds on its own \
         thread: it answers queries from the start, faster once the map is there.\n\n\
         | receptor | atoms | brute (copy) | full grid | hashed grid |\n| --- | ---: | ---: | ---: | ---: |\n",
    );
    for (f, n, t) in &rows {
        md.push_str(&format!(
            "| {f} | {n} | {} | {} | {} |\n",
            us(t.build[0]),
            us(t.build[1]),
            us(t.build[2])
        ));
    }
    // Drug size.
    let mut drows: Vec<(usize, Timing)> = Vec::new();
    let receptor = load(dir, DRUG_SWEEP_RECEPTOR);
    for n in DRUG_SIZES {
        progress.step(&format!("drug size: {n} atoms"));
        if let Ok(r) = &receptor
            && let Some((drug, start, end)) = patch(r, &rule, n)
        {
            drows.push((drug.len(), time_all(ctx, &rule, r, &drug, &start, &end)));
        }
    }
    match &receptor {
        Ok(r) => {
            md.push_str(&format!(
                "\n### Drug size: 10 to 200 atoms against {DRUG_SWEEP_RECEPTOR} ({} atoms)\n\n\
                 | drug atoms | check brute | check grid | check hashed | touch brute | touch grid | touch hashed | touch thesis | touched |\n\
                 | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |\n",
                r.len()
            ));
            for (n, t) in &drows {
                md.push_str(&format!("| {n} | {} |\n", t.cells()));
            }
            if let (Some(a), Some(b)) = (drows.first(), drows.last()) {
                headline.push(format!(
                    "Drug size {}→{} atoms ({:.0}×): move-to-touch grows {:.1}× (grid), {:.1}× (hashed)",
                    a.0,
                    b.0,
                    b.0 as f64 / a.0 as f64,
                    b.1.touch[1] / a.1.touch[1],
                    b.1.touch[2] / a.1.touch[2]
                ));
            }
        }
        Err(e) => md.push_str(&format!(
            "\nDrug-size sweep skipped: {DRUG_SWEEP_RECEPTOR}: {e}\n"
        )),
    }
    md.push_str("\n![scaling](bench/scaling.svg)\n");
    let by_receptor: Vec<(f64, &Timing)> = rows.iter().map(|(_, n, t)| (*n as f64, t)).collect();
    let by_drug: Vec<(f64, &Timing)> = drows.iter().map(|(n, t)| (*n as f64, t)).collect();
    let mut touch_r = per_collider(&by_receptor, |t| t.touch);
    touch_r.push(Series {
        name: "thesis (hashed)".into(),
        points: by_receptor.iter().map(|(x, t)| (*x, t.thesis)).collect(),
    });
    let panel = |title: &str, x: &str, series| Panel {
        title: title.into(),
        x_label: x.into(),
        y_label: "median time, µs".into(),
        series,
        x_floor: 0.0,
    };
    let panels = vec![
        panel(
            "static check vs receptor size",
            "receptor atoms",
            per_collider(&by_receptor, |t| t.check),
        ),
        panel("move-to-touch vs receptor size", "receptor atoms", touch_r),
        panel(
            "move-to-touch vs drug size",
            "drug atoms",
            per_collider(&by_drug, |t| t.touch),
        ),
        panel(
            "collider build vs atoms",
            "receptor atoms",
            per_collider(&by_receptor, |t| t.build),
        ),
    ];
    Part {
        markdown: md,
        figures: vec![("scaling.svg".into(), super::svg::figure(&panels, 2))],
        headline,
    }
}
