//! The scoring's benchmarks: the setups that `benches/score.rs`'s
//! criterion groups and the report's scoring section share, and
//! [`markdown`], which measures and returns that section's Markdown.
//!
//! - Trimethoprim (TOP) in E. coli DHFR (`6xg5_tmp_prepared.pdb`): Vina's
//!   energy with the gradient (force, torque, torsion torques) from maps
//!   and exactly (the whole drug at once, and one atom at a time as the
//!   baseline; also with the candidate lists built afresh every call),
//!   Vina's energy alone exactly; the same table reads alone,
//!   from pair lists made beforehand (the exact evaluation's pairs, the
//!   drug's intramolecular pairs): the floors; maps for a 24 Å box at
//!   0.375 Å built on every thread; settle from seeded perturbed crystal
//!   poses (up to 1.5 Å and 30°) on maps. Timings alternate the methods
//!   in rounds and report the minimum and median of the rounds.
//! - Cost against receptor size (1.3k to 272k atoms): the same drug just
//!   outside each receptor's surface, exact energy with gradient (lists
//!   kept, and built afresh every call) and the 24 Å maps' build.
//! - The maps' error against exact per spacing: |Δ inter| over the crystal
//!   pose and seeded perturbations, median and max.

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use bump::collide::{Collider, ColliderKind, ContactRule};
use bump::model::{self, LigandSpec, LoadOptions, Molecule};
use bump::motion::Pose;
use bump::rng::Rng;
use bump::score::XsType;
use bump::score::function::curl_with_slope;
use bump::score::maps::{MapBox, Maps};
use bump::score::table::{Table, smooth_at};
use bump::score::{
    Conformation, Contacts, Exact, Gradient, Ligand, MapField, PerAtom, Receptor, RigidDrug,
    Scoring, SettleOptions, Workspace, energies, energy_gradient, prepare, settle,
};
use glam::{DQuat, DVec3};

/// The box edge (Å) and spacing of the maps timed.
pub const BOX_SIDE: f64 = 24.0;
/// Vina's default spacing (Å).
pub const SPACING: f64 = 0.375;

/// A receptor and a drug prepared for scoring, the drug at its file pose.
pub struct Setup {
    /// The receptor molecule.
    pub receptor_mol: Molecule,
    /// The drug molecule.
    pub drug: Molecule,
    /// Typed receptor.
    pub receptor: Receptor,
    /// Typed drug.
    pub lig: Ligand,
    /// The drug's file pose relative to the receptor.
    pub crystal: Conformation,
}

impl Setup {
    /// `file` split with `--ligand residue` (receptor: everything else).
    pub fn complex(file: &Path, residue: &str) -> Option<Self> {
        let s = model::load(file, &LoadOptions::default()).ok()?.structure;
        let spec = LigandSpec::parse(residue).ok()?;
        let (receptor_mol, drug) = model::split_complex(&s, &spec).ok()?;
        Some(Self::new(receptor_mol, drug))
    }

    /// Prepares both molecules.
    pub fn new(receptor_mol: Molecule, drug: Molecule) -> Self {
        let receptor = prepare::receptor(&receptor_mol);
        let lig = prepare::ligand(&drug).expect("the drug's tree");
        let crystal = lig.rigid(Pose::from_translation(drug.centre - receptor_mol.centre));
        Self {
            receptor_mol,
            drug,
            receptor,
            lig,
            crystal,
        }
    }

    /// Maps for the drug's types over a [`BOX_SIDE`] cube at `spacing`
    /// centred on the drug at `conf`, on `threads` threads.
    pub fn maps(&self, conf: &Conformation, spacing: f64, threads: usize) -> Maps {
        let x = self.lig.place(conf);
        let centre = x.iter().copied().sum::<DVec3>() / x.len().max(1) as f64;
        let bx = MapBox::cube(centre, BOX_SIDE, spacing);
        Maps::build(&self.receptor, Scoring::Vina, &self.lig.xs, &bx, threads).expect("maps")
    }
}

/// The trimethoprim–DHFR setup.
pub fn dhfr(data: &Path) -> Option<Setup> {
    Setup::complex(&data.join("6xg5_tmp_prepared.pdb"), "TOP")
}

/// Seeded perturbations of `conf`: a shift of up to 1.5 Å and a turn of up
/// to 30° about the drug's centre.
pub fn perturbed(conf: &Conformation, seed: u64, n: usize) -> Vec<Conformation> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let shift = rng.unit() * 1.5 * rng.f64().cbrt();
            let turn = DQuat::from_axis_angle(rng.unit(), rng.f64() * 30f64.to_radians());
            let mut c = conf.clone();
            c.pose = Pose::new(turn * conf.pose.rotation, conf.pose.translation + shift);
            c
        })
        .collect()
}

/// Threads the machine offers.
pub fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Min and median of `rounds` rounds of `fs` timed in turn, each round
/// `inner` calls (µs per call).
fn alternated(rounds: usize, inner: usize, fs: &mut [&mut dyn FnMut()]) -> Vec<(f64, f64)> {
    let mut times = vec![Vec::with_capacity(rounds); fs.len()];
    for f in fs.iter_mut() {
        f();
    }
    for _ in 0..rounds {
        for (k, f) in fs.iter_mut().enumerate() {
            let t0 = Instant::now();
            for _ in 0..inner {
                f();
            }
            times[k].push(t0.elapsed().as_secs_f64() * 1e6 / inner as f64);
        }
    }
    times
        .into_iter()
        .map(|mut t| {
            t.sort_by(f64::total_cmp);
            (t[0], t[t.len() / 2])
        })
        .collect()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The drug at its file shape with its centre 5 Å beyond the receptor atom
/// farthest along +x (its surface, where a docked drug's neighbourhood is
/// most like a pocket's rim).
pub fn at_surface(receptor_mol: &Molecule, lig: &Ligand) -> Conformation {
    let far = receptor_mol.local.iter().map(|v| v.as_dvec3()).fold(
        DVec3::splat(f64::NEG_INFINITY),
        |a, b| {
            if b.x > a.x { b } else { a }
        },
    );
    lig.rigid(Pose::from_translation(far + DVec3::X * 5.0))
}

/// A typed position.
type Typed = (DVec3, XsType);

/// The pairs an exact evaluation of `lig` at `conf` reads from the table,
/// found beforehand: per scored atom, its position, type and the receptor
/// atoms within 8 Å (position and type). Timing [`pairs_floor`] on them
/// gives the cost of the table reads and the gradient's arithmetic alone,
/// with no neighbour search: the floor of any evaluator that reads Vina's
/// table pair by pair.
pub struct PairList {
    /// Per scored atom: position, type and the receptor atoms near it.
    atoms: Vec<(DVec3, XsType, Vec<Typed>)>,
    /// The drug's intramolecular pairs: indices into `atoms`.
    intra: Vec<[usize; 2]>,
}

impl PairList {
    /// The pairs of `lig` at `conf` with the evaluator's receptor, and
    /// the drug's intramolecular pairs.
    pub fn new(exact: &Exact<'_>, lig: &Ligand, conf: &Conformation) -> Self {
        let x = lig.place(conf);
        let receptor = exact.receptor();
        let atoms = lig
            .scored
            .iter()
            .zip(&lig.xs)
            .map(|(&i, &t)| {
                let xi = x[i as usize];
                let mut near = Vec::new();
                exact.neighbours(xi, |a, _| {
                    near.push((receptor.positions[a], receptor.xs[a]))
                });
                (xi, t, near)
            })
            .collect();
        let intra = lig
            .pairs
            .iter()
            .map(|&[a, b]| [a as usize, b as usize])
            .collect();
        Self { atoms, intra }
    }

    /// The number of intramolecular pairs.
    pub fn intra_len(&self) -> usize {
        self.intra.len()
    }

    /// The number of pairs.
    pub fn len(&self) -> usize {
        self.atoms.iter().map(|a| a.2.len()).sum()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Each pair's energy and gradient from Vina's table, summed per drug atom
/// into `out` (as the exact evaluator does, without its search).
pub fn pairs_floor(list: &PairList, table: &Table, out: &mut Vec<(f64, DVec3)>) {
    out.clear();
    for (x, t, near) in &list.atoms {
        let rows = table.smooth_rows(*t);
        let (mut e, mut g) = (0.0, DVec3::ZERO);
        for &(p, u) in near {
            let d = *x - p;
            let (v, dv) = smooth_at(rows[u.index()], d.length_squared());
            e += v;
            g += d * (2.0 * dv);
        }
        out.push((e, g));
    }
}

/// The intramolecular pairs' energies (curled) and their forces on each
/// scored atom into `out`, from Vina's table: what the flexible evaluation
/// adds to the rigid one's work, alone.
pub fn intra_floor(list: &PairList, table: &Table, out: &mut Vec<DVec3>) -> f64 {
    out.clear();
    out.resize(list.atoms.len(), DVec3::ZERO);
    let mut e = 0.0;
    for &[a, b] in &list.intra {
        let ((xa, ta, _), (xb, tb, _)) = (&list.atoms[a], &list.atoms[b]);
        let d = *xa - *xb;
        let (v, dv) = smooth_at(table.smooth_row(*ta, *tb), d.length_squared());
        let (v, s) = curl_with_slope(v);
        e += v;
        let f = d * (2.0 * dv * s);
        out[a] += f;
        out[b] -= f;
    }
    e
}

/// The report's row of the exact evaluator's energy and gradient.
const EXACT_ROW: &str = "energy + gradient, exact";

/// The scaling receptors: (label, file), 1.3k to 272k atoms.
pub const SCALING: &[(&str, &str)] = &[
    ("1rx1", "1rx1.pdb"),
    ("4kya", "4kya.pdb.gz"),
    ("2btv", "2btv.pdb.gz"),
    ("1aon", "1aon.pdb.gz"),
    ("1f2n assembly", "1f2n_assembly1.cif.gz"),
];

/// Measures and returns the section (`quick`: fewer rounds and receptors).
pub fn markdown(data: &Path, quick: bool) -> String {
    let mut md = String::from("## Scoring: Vina's energy, maps and settle\n\n");
    let Some(s) = dhfr(data) else {
        md += "6xg5_tmp_prepared.pdb not found: nothing measured.\n";
        return md;
    };
    let rounds = if quick { 5 } else { 31 };
    let exact = Exact::new(&s.receptor, Scoring::Vina);
    let th = threads();
    let maps = s.maps(&s.crystal, SPACING, th);
    let field = MapField::new(&maps, exact);
    let (mut ws, mut g) = (Workspace::default(), Gradient::default());
    let (mut ws2, mut g2, mut ws3) = (
        Workspace::default(),
        Gradient::default(),
        Workspace::default(),
    );
    let (mut ws4, mut g4) = (Workspace::default(), Gradient::default());
    let (mut ws5, mut g5) = (Workspace::default(), Gradient::default());
    let (mut ws6, mut g6) = (Workspace::default(), Gradient::default());
    let exact_per_atom = PerAtom(&exact);
    let lig = &s.lig;
    let c = &s.crystal;
    let pairs = PairList::new(&exact, lig, c);
    let table = Table::of(Scoring::Vina);
    let (mut floor, mut intra_forces) = (Vec::new(), Vec::new());
    let rigid = RigidDrug::new(&field, lig, &c.torsions);
    let per_atom = PerAtom(&field);
    let t = alternated(
        rounds,
        2000,
        &mut [
            &mut || {
                black_box(rigid.energy_gradient(&field, &c.pose));
            },
            &mut || {
                black_box(rigid.energy_gradient(&per_atom, &c.pose));
            },
            &mut || {
                black_box(rigid.energy_full_gradient(&field, &c.pose, &mut ws6, &mut g6));
            },
            &mut || {
                black_box(energy_gradient(&field, lig, c, &mut ws, &mut g));
            },
            &mut || {
                black_box(intra_floor(black_box(&pairs), table, &mut intra_forces));
            },
            &mut || {
                black_box(energy_gradient(&exact, lig, c, &mut ws2, &mut g2));
            },
            &mut || {
                pairs_floor(black_box(&pairs), table, &mut floor);
                black_box(&floor);
            },
            &mut || {
                black_box(energy_gradient(&exact_per_atom, lig, c, &mut ws4, &mut g4));
            },
            &mut || {
                black_box(energies(&exact, lig, c, &mut ws3));
            },
            &mut || {
                s.receptor.forget_candidates();
                black_box(energy_gradient(&exact, lig, c, &mut ws5, &mut g5));
            },
        ],
    );
    let build = alternated(
        if quick { 3 } else { 11 },
        1,
        &mut [&mut || {
            black_box(s.maps(&s.crystal, SPACING, th));
        }],
    );
    // Settle from perturbed crystal poses on the maps.
    let rule = ContactRule::default();
    let collider = Collider::build(&s.receptor_mol, &rule, ColliderKind::Hashed);
    collider.wait_for_clearance();
    let mut contacts = Contacts::new(&collider, rule, &s.drug, lig);
    let starts = perturbed(c, 43, if quick { 4 } else { 12 });
    let opts = SettleOptions::default();
    let (mut per, mut steps, mut evals) = (Vec::new(), Vec::new(), Vec::new());
    for st in &starts {
        let mut best = f64::INFINITY;
        let mut out = None;
        for _ in 0..if quick { 2 } else { 5 } {
            let t0 = Instant::now();
            let r = settle(&field, lig, &mut contacts, st, &opts);
            best = best.min(t0.elapsed().as_secs_f64() * 1e6);
            out = Some(r);
        }
        let r = out.expect("a settle");
        per.push(best);
        steps.push(r.steps as f64);
        evals.push(r.evaluations as f64);
    }
    let settle_min = per.iter().copied().fold(f64::INFINITY, f64::min);
    let settle_med = median(&mut per.clone());
    // From the crystal pose itself: the workload of Vina's optimize row.
    let crystal = alternated(
        if quick { 5 } else { 21 },
        1,
        &mut [&mut || {
            black_box(settle(&field, lig, &mut contacts, c, &opts));
        }],
    );
    let crystal_steps = settle(&field, lig, &mut contacts, c, &opts).steps;
    md += &format!(
        "Trimethoprim (TOP, {} heavy atoms, {} rotatable bonds) in E. coli DHFR ({} typed receptor atoms), \
         at the crystal pose; {} rounds alternating the methods, each 2000 calls; {th} threads for the maps.\n\n",
        lig.len(),
        lig.torsions(),
        s.receptor.len(),
        rounds
    );
    md += "| what | min | median | target |\n|---|---|---|---|\n";
    let pairs_row = format!(
        "its {} pairs within 8 Å alone, listed beforehand: table reads and gradient, no search (the floor of reading Vina's table pair by pair)",
        pairs.len()
    );
    let intra_row = format!(
        "its {} intramolecular pairs alone: table reads, curl and forces (what the flexible row adds to the rigid one's work, besides placing the atoms and the torsion tree)",
        pairs.intra_len()
    );
    let rows = [
        (
            "rigid drug (torsions held): inter energy, force and torque, maps",
            "≤ 0.3 µs",
        ),
        (
            "the same, one atom at a time (the generic path: baseline for the row above)",
            "",
        ),
        (
            "conformation held, drug moved rigidly (the query between torsion turns): energy + whole gradient (force, torque, torsion torques; intra kept from when the torsions last turned), maps",
            "≤ 0.3 µs",
        ),
        (
            "energy + gradient (force, torque, torsion torques, intra), maps, at torsions that change every call (atoms placed through the torsion tree, intra pairs summed)",
            "≤ 0.3 µs",
        ),
        (intra_row.as_str(), ""),
        (EXACT_ROW, "≤ 10 µs"),
        (pairs_row.as_str(), ""),
        (
            "energy + gradient, exact, one atom at a time (each its own cell visit: baseline for the exact row)",
            "",
        ),
        ("energy alone, exact", ""),
        (
            "energy + gradient, exact, every candidate list built afresh (each call: what a drug pays on entering cells it has not visited)",
            "",
        ),
    ];
    let exact_median = rows
        .iter()
        .zip(&t)
        .find(|(row, _)| row.0 == EXACT_ROW)
        .map_or(f64::NAN, |(_, (_, med))| *med);
    for ((what, target), (min, med)) in rows.iter().zip(&t) {
        md += &format!("| {what} | {min:.3} µs | {med:.3} µs | {target} |\n");
    }
    md += &format!(
        "| maps, {BOX_SIDE} Å box at {SPACING} Å ({} types, {} points each) | {:.0} ms | {:.0} ms | ≤ 200 ms |\n",
        maps.types().len(),
        maps.lattice().len(),
        build[0].0 / 1e3,
        build[0].1 / 1e3
    );
    md += &format!(
        "| settle from {} perturbed poses (best of repeats per pose; median {} steps, {} evaluations) | {:.0} µs | {:.0} µs | ≤ 1 ms |\n",
        starts.len(),
        median(&mut steps),
        median(&mut evals),
        settle_min,
        settle_med
    );
    md += &format!(
        "| settle from the crystal pose ({crystal_steps} steps; Vina's optimize below starts there too) | {:.0} µs | {:.0} µs | |\n\n",
        crystal[0].0, crystal[0].1
    );

    md += &vina_rows(data, if quick { 1 } else { 3 });

    // Cost against receptor size.
    md += "### Cost against receptor size\n\nTOP at its file shape, its centre 5 Å beyond each receptor's outermost atom along +x: \
           exact energy + gradient (median of rounds of 2000 calls), the same with its candidate lists built afresh every call, and the 24 Å maps around it.\n\n";
    md += "| receptor | atoms | typed | exact energy + gradient | lists built afresh | maps build |\n|---|---|---|---|---|---|\n";
    md += &format!(
        "| 6xg5 (pocket) | {} | {} | {:.2} µs | {:.2} µs | {:.0} ms |\n",
        s.receptor_mol.len(),
        s.receptor.len(),
        exact_median,
        t[t.len() - 1].1,
        build[0].1 / 1e3
    );
    let scaling = if quick { &SCALING[..1] } else { SCALING };
    for &(label, file) in scaling {
        let Ok(l) = model::load(&data.join(file), &LoadOptions::default()) else {
            md += &format!("| {label} | {file} not loaded | | | | |\n");
            continue;
        };
        let Ok(rec) = model::receptor_only(&l.structure) else {
            continue;
        };
        let r = Setup::new(rec, s.drug.clone());
        let conf = at_surface(&r.receptor_mol, &r.lig);
        let ex = Exact::new(&r.receptor, Scoring::Vina);
        let (mut w, mut gg) = (Workspace::default(), Gradient::default());
        let (mut w2, mut gg2) = (Workspace::default(), Gradient::default());
        let rl = &r.lig;
        let te = alternated(
            rounds,
            2000,
            &mut [
                &mut || {
                    black_box(energy_gradient(&ex, rl, &conf, &mut w, &mut gg));
                },
                &mut || {
                    r.receptor.forget_candidates();
                    black_box(energy_gradient(&ex, rl, &conf, &mut w2, &mut gg2));
                },
            ],
        );
        let tb = alternated(
            if quick { 2 } else { 5 },
            1,
            &mut [&mut || {
                black_box(r.maps(&conf, SPACING, th));
            }],
        );
        md += &format!(
            "| {label} | {} | {} | {:.2} µs | {:.2} µs | {:.0} ms |\n",
            r.receptor_mol.len(),
            r.receptor.len(),
            te[0].1,
            te[1].1,
            tb[0].1 / 1e3
        );
    }

    // The maps' error against exact.
    let poses: Vec<Conformation> = std::iter::once(c.clone())
        .chain(perturbed(c, 7, if quick { 10 } else { 50 }))
        .collect();
    md += &format!(
        "\n### The maps' error against exact\n\n|Δ inter| (kcal/mol) between maps and exact over the crystal pose and {} seeded perturbations \
         (up to 1.5 Å, 30°), {BOX_SIDE} Å box; relative to |inter| at the crystal pose ({:.2} kcal/mol).\n\n",
        poses.len() - 1,
        energies(&exact, lig, c, &mut ws).inter.abs()
    );
    md += "| spacing | median | max | median relative |\n|---|---|---|---|\n";
    let exact_inter: Vec<f64> = poses
        .iter()
        .map(|p| energies(&exact, lig, p, &mut ws).inter)
        .collect();
    for spacing in [0.2, 0.375, 0.5] {
        let m = s.maps(c, spacing, th);
        let f = MapField::new(&m, exact);
        let mut err: Vec<f64> = poses
            .iter()
            .zip(&exact_inter)
            .map(|(p, e)| (energies(&f, lig, p, &mut ws).inter - e).abs())
            .collect();
        let mut rel: Vec<f64> = err
            .iter()
            .zip(&exact_inter)
            .map(|(d, e)| d / e.abs().max(1.0))
            .collect();
        let max = err.iter().copied().fold(0.0, f64::max);
        md += &format!(
            "| {spacing} Å | {:.3} | {:.3} | {:.1} % |\n",
            median(&mut err),
            max,
            100.0 * median(&mut rel)
        );
    }
    md
}

/// AutoDock Vina 1.2's own times on this machine, in the same run, from
/// `benches/score/vina_times.py` (when Python has the `vina` package).
fn vina_rows(data: &Path, reps: usize) -> String {
    // The repository's root, two levels above this crate.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = std::process::Command::new("python3")
        .arg(dir.join("benches/score/vina_times.py"))
        .arg(data.join("6xg5_tmp_prepared.pdb"))
        .arg(dir.join("tests/reference/vina/values.json"))
        .arg("6xg5_TOP")
        .arg(reps.to_string())
        .output();
    let parsed = out
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| serde_json::from_slice::<serde_json::Value>(&o.stdout).ok());
    let Some(v) = parsed else {
        return "AutoDock Vina's times not measured: `python3 benches/score/vina_times.py` needs `pip install vina`.\n\n"
            .to_string();
    };
    let pair = |k: &str| {
        (
            v[k][0].as_f64().unwrap_or(f64::NAN),
            v[k][1].as_f64().unwrap_or(f64::NAN),
        )
    };
    let (m20, m24, opt) = (pair("maps_20_ms"), pair("maps_24_ms"), pair("optimize_ms"));
    format!(
        "AutoDock Vina 1.2.7 (Python package, {} threads) in the same run, same complex (min / median):\n\n\
         | Vina | min | median |\n|---|---|---|\n\
         | maps, 20 Å box at 0.375 Å | {:.0} ms | {:.0} ms |\n\
         | maps, 24 Å box at 0.375 Å | {:.0} ms | {:.0} ms |\n\
         | optimize from the crystal pose | {:.2} ms | {:.2} ms |\n\n",
        v["threads"], m20.0, m20.1, m24.0, m24.1, opt.0, opt.1
    )
}

/// Runs `n` calls of `what` (`rigid_maps`, `held_maps`, `maps`, `exact_gradient` or
/// `exact`) on the DHFR setup at the crystal pose, with maps over a small
/// box; `n` settles (`settle`, see `count_settle`); the pair counts behind
/// the exact evaluator's cost (`pairs`); or `n` builds of the 24 Å maps on
/// one thread (`build`): for counting instructions under callgrind, or CPU
/// time (`/usr/bin/time -f %U`), where the machine is too busy for wall
/// times (`n` = 0 gives the setup's count to subtract).
pub fn count(data: &Path, what: &str, n: usize) {
    let Some(s) = dhfr(data) else {
        return;
    };
    let exact = Exact::new(&s.receptor, Scoring::Vina);
    let bx = MapBox::around(&s.lig.place(&s.crystal), 2.0, SPACING);
    let maps = Maps::build(&s.receptor, Scoring::Vina, &s.lig.xs, &bx, 1).expect("maps");
    let field = MapField::new(&maps, exact);
    let rigid = RigidDrug::new(&field, &s.lig, &s.crystal.torsions);
    let (mut ws, mut g) = (Workspace::default(), Gradient::default());
    let (lig, c) = (&s.lig, &s.crystal);
    if what == "settle" {
        count_settle(&s, exact, n);
        return;
    }
    if what == "pairs" {
        // What the exact evaluator's cost is made of: the receptor atoms
        // its cell visits read, the pairs within 8 Å, the intramolecular
        // pairs.
        let x = lig.place(c);
        let (mut read, mut near) = (0, 0);
        for &i in &lig.scored {
            let xi = x[i as usize];
            s.receptor.cells().visit(xi, 8.0, |_| read += 1);
            exact.neighbours(xi, |_, _| near += 1);
        }
        println!(
            "{} scored atoms, {} receptor atoms read, {} pairs within 8 Å, {} intramolecular pairs",
            lig.scored.len(),
            read,
            near,
            lig.pairs.len()
        );
        return;
    }
    for _ in 0..n {
        match what {
            "rigid_maps" => {
                black_box(rigid.energy_gradient(&field, &c.pose));
            }
            "held_maps" => {
                black_box(rigid.energy_full_gradient(&field, &c.pose, &mut ws, &mut g));
            }
            "maps" => {
                black_box(energy_gradient(&field, lig, c, &mut ws, &mut g));
            }
            "build" => {
                black_box(s.maps(c, SPACING, 1));
            }
            "exact_gradient" => {
                black_box(energy_gradient(&exact, lig, c, &mut ws, &mut g));
            }
            _ => {
                black_box(energies(&exact, lig, c, &mut ws));
            }
        }
    }
}

/// `n` settles on the 24 Å maps (which they do not leave) from the
/// benchmark's perturbed poses in turn.
fn count_settle(s: &Setup, exact: Exact<'_>, n: usize) {
    let rule = ContactRule::default();
    let collider = Collider::build(&s.receptor_mol, &rule, ColliderKind::Hashed);
    collider.wait_for_clearance();
    let mut contacts = Contacts::new(&collider, rule, &s.drug, &s.lig);
    let starts = perturbed(&s.crystal, 43, 12);
    let opts = SettleOptions::default();
    let maps = s.maps(&s.crystal, SPACING, 1);
    let field = MapField::new(&maps, exact);
    for call in 0..n {
        black_box(settle(
            &field,
            &s.lig,
            &mut contacts,
            &starts[call % starts.len()],
            &opts,
        ));
    }
}
