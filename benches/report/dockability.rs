//! Dockability: can the fixed steering controller of `bump steer`
//! ([`bump::session::steer`]) bring each shared drug from outside into its
//! pocket, under each collision response? 32 start directions per complex
//! (a Fibonacci sphere), every response, rigid and flexible; success rate (heavy-atom
//! RMSD ≤ 2 Å at some frame), median frames to get there, the deepest
//! overlap beyond the contact rule, the steps' time; then, for soft
//! flexible, the session's settle (RMSD after it, collision-free count).
//!
//! The runs are split over the machine's cores by direction (each run is
//! its own session, seeded and deterministic), and gathered in direction
//! order, so the table does not depend on the threads.
//!
//! Where no response gets there, the `pass` rows say why: under `pass`
//! (collision off) the controller's path is the straight one, and its
//! deepest overlap, least over the directions, is how far the drug must
//! press into the receptor on the best straight path from outside, and the
//! length of the path pressed deeper than the soft limit, how much of the
//! receptor lies between a start and the pocket. The soft-limit sweep then
//! runs soft flexible at looser limits and measures, for the runs that get
//! there, how much of their path ran deeper than the default limit: set
//! beside the straight path's length through the receptor, it tells a
//! drug that went round the receptor from one that went through it.
//! Where the flexible slide and soft runs that miss end: pressed against the
//! receptor with the push head-on into its smoothed surface, or not, and
//! how far their centre, orientation and bonds are from the file pose's.
//! Last, the way out: the controller run from the file pose out to each
//! start (`escape`), which tells a pocket that holds its drug in from one
//! the straight push from outside cannot find the way into.

use std::path::Path;
use std::time::Instant;

use bump::collide::soft::DEFAULT_LIMIT;
use bump::collide::{ContactRule, Response};
use bump::model::{self, Hydrogens, LigandSpec, LoadOptions, Molecule, RadiiSet};
use bump::session::Settings;
use bump::session::steer::{SteerOptions, SteerReport, steer};
use glam::DVec3;

use super::timing::{Progress, median, quantile};
use super::{Context, Part, Section};

/// (label, receptor file, drug file or ligand residue).
const COMPLEXES: [(&str, &str, Drug); 7] = [
    ("6xg5/TOP", "6xg5_tmp_prepared.pdb", Drug::Residue("TOP")),
    ("3ptb/BEN", "3ptb.pdb", Drug::Residue("BEN")),
    (
        "1s3v/TQD",
        "1s3v_protein.pdb",
        Drug::File("1s3v_ligand_tqd.sdf"),
    ),
    ("4dfr/MTX", "4dfr.pdb", Drug::Residue("MTX")),
    ("1u72/MTX", "1u72.pdb", Drug::Residue("MTX")),
    ("3nzd/D2Q", "3nzd.cif", Drug::Residue("D2Q")),
    ("1hvr/XK2", "1hvr.pdb", Drug::Residue("XK2")),
];

/// Where a complex's drug comes from.
#[derive(Clone, Copy)]
enum Drug {
    /// A residue of the receptor file, split off.
    Residue(&'static str),
    /// Its own file, in the receptor's frame.
    File(&'static str),
}

/// The responses, in the table's order.
const RESPONSES: [Response; 5] = [
    Response::Stop,
    Response::Touch,
    Response::Slide,
    Response::Soft,
    Response::Pass,
];

/// Start directions per complex (fewer under `--quick`).
const DIRECTIONS: usize = 32;
const QUICK_DIRECTIONS: usize = 8;

/// The section.
pub const SECTION: Section = Section {
    name: "dockability",
    steps,
    run,
};

fn steps(ctx: &Context) -> usize {
    match (&ctx.data, ctx.queries < QUICK_DIRECTIONS) {
        (None, _) => 0,
        (Some(_), true) => 1,
        (Some(_), false) => COMPLEXES.len(),
    }
}

/// Loads a complex as the command line does (Bondi radii, hydrogens
/// dropped): (receptor, drug).
fn load(dir: &Path, receptor: &str, drug: Drug) -> Result<(Molecule, Molecule), String> {
    let opts = LoadOptions {
        radii: RadiiSet::Bondi,
        hydrogens: Hydrogens::Drop,
        sdf_record: None,
        decompressed_limit: None,
    };
    let loaded = model::load(&dir.join(receptor), &opts).map_err(|e| e.to_string())?;
    match drug {
        Drug::Residue(name) => {
            let spec = LigandSpec::parse(name)?;
            model::split_complex_owned(loaded.structure, &spec).map_err(|e| e.to_string())
        }
        Drug::File(file) => {
            let r = model::receptor_only_owned(loaded.structure).map_err(|e| e.to_string())?;
            let d = model::load(&dir.join(file), &opts).map_err(|e| e.to_string())?;
            let d = model::receptor_only(&d.structure).map_err(|e| e.to_string())?;
            Ok((r, d))
        }
    }
}

/// One run's outcome (None: no clear start along the direction).
type Run = Option<SteerReport>;

/// Soft limits of the sweep, Å (the first is the default).
const SWEEP_LIMITS: [f64; 5] = [1.0, 1.5, 2.0, 2.5, 3.0];

/// The sweep's rate that counts as getting there (the target).
const TARGET_RATE: f64 = 75.0;

/// Every direction under `response` with soft limit `limit`, over the
/// machine's cores, in direction order.
fn runs(
    receptor: &Molecule,
    drug: &Molecule,
    dirs: &[DVec3],
    opts: SteerOptions,
    limit: f64,
) -> Vec<Run> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, dirs.len().max(1));
    let mut out: Vec<Run> = vec![None; dirs.len()];
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                s.spawn(move || {
                    (t..dirs.len())
                        .step_by(threads)
                        .map(|k| {
                            let settings = Settings {
                                rule: ContactRule::default(),
                                soft_limit: limit,
                                ..Settings::default()
                            };
                            // Each direction its own seed of the start's torsions.
                            let opts = SteerOptions {
                                seed: k as u64 + 1,
                                ..opts
                            };
                            let r = steer(receptor.clone(), drug.clone(), settings, dirs[k], &opts)
                                .ok();
                            (k, r)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for h in handles {
            if let Ok(rows) = h.join() {
                for (k, r) in rows {
                    out[k] = r;
                }
            }
        }
    });
    out
}

/// One row of the table: a complex under one response, rigid or flexible.
struct Row {
    complex: &'static str,
    response: Response,
    flexible: bool,
    starts: usize,
    reached: usize,
    median_frames: Option<f64>,
    deepest: f64,
    least_deepest: f64,
    /// Runs whose deepest overlap stays within the soft limit (under
    /// `pass`: the straight paths `soft` could follow).
    within_limit: usize,
    /// Median over the runs of the path's length deeper than the soft
    /// limit (under `pass`: how far the straight path runs through the
    /// receptor beyond what `soft` allows), Å.
    beyond_limit: f64,
    step_median: f64,
    step_p99: f64,
    /// Runs settled, median settled RMSD, collision-free after settle.
    settled: Option<(usize, f64, usize)>,
    /// The runs that do not get there: how many, how many of those end
    /// pressed against the receptor, the cosines of their push against the
    /// receptor's smoothed surface, and their final RMSDs.
    missed: Missed,
}

/// Where the runs that do not get there end.
#[derive(Default)]
struct Missed {
    runs: usize,
    cosines: Vec<f64>,
    rmsd: Vec<f64>,
    /// Their centres' distances from the file pose's centre, Å.
    offsets: Vec<f64>,
    /// Their turns from the file orientation, degrees.
    turns: Vec<f64>,
    /// Their bonds' RMS from the file angles, degrees.
    torsions: Vec<f64>,
}

/// A run that ends with its centre this close to the file pose's (Å) is
/// at the pocket; its RMSD is then its orientation's and shape's.
const AT_THE_POCKET: f64 = 3.0;

/// A push within 30° of the receptor's inward surface normal: head-on.
const HEAD_ON_COS: f64 = 0.866;

/// The responses of the way out, flexible.
const ESCAPE_RESPONSES: [Response; 2] = [Response::Slide, Response::Soft];

/// One row of the way out: the controller run the other way, from the file
/// pose out to the start, flexible, under one response.
struct EscapeRow {
    complex: &'static str,
    response: Response,
    starts: usize,
    /// Runs that got out (RMSD ≤ 2 Å to the start at some frame).
    out: usize,
    median_frames: Option<f64>,
    /// Runs that got in, the same response flexible, from the same starts.
    got_in: usize,
    /// Starts from which the run got out but the run in did not get there.
    out_not_in: usize,
}

/// The controller run the other way under each of [`ESCAPE_RESPONSES`].
fn escapes(
    complex: &'static str,
    receptor: &Molecule,
    drug: &Molecule,
    dirs: &[DVec3],
    ins: &[(Response, Vec<Run>)],
) -> Vec<EscapeRow> {
    ESCAPE_RESPONSES
        .iter()
        .map(|&response| {
            let opts = SteerOptions {
                response,
                flexible: true,
                settle: false,
                seed: 1,
                escape: true,
            };
            let r = runs(receptor, drug, dirs, opts, DEFAULT_LIMIT);
            let got = |run: &Run| run.as_ref().is_some_and(|r| r.reached);
            let way_in = ins
                .iter()
                .find(|(resp, _)| *resp == response)
                .map(|(_, r)| r);
            let frames: Vec<f64> = r
                .iter()
                .flatten()
                .filter_map(|r| r.reached_frame.map(|f| f as f64))
                .collect();
            EscapeRow {
                complex,
                response,
                starts: r.iter().flatten().count(),
                out: r.iter().filter(|run| got(run)).count(),
                median_frames: (!frames.is_empty()).then(|| median(&frames)),
                got_in: way_in.map_or(0, |w| w.iter().filter(|run| got(run)).count()),
                out_not_in: way_in.map_or(0, |w| {
                    r.iter().zip(w).filter(|(o, i)| got(o) && !got(i)).count()
                }),
            }
        })
        .collect()
}

/// The way out's table.
fn escape_markdown(rows: &[EscapeRow]) -> String {
    let mut md = String::from(
        "\n### Does the pocket let the drug out? The way back\n\n\
         The same controller run the other way (`bump steer --escape`): from the file pose and \
         file torsions out to each start (its pose and turned bonds), flexible, with the same \
         steps; *out* is an RMSD ≤ 2 Å to the start at some frame. A drug that gets out of its \
         pocket from its crystal pose has a way in under that response, the path reversed; \
         one that gets out but not in from the same start shows the pocket open and the \
         straight push from outside the obstacle, not the pocket's shape.\n\n\
         | complex | response | starts | out | rate | frames (median) | in, same starts | out but not in |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {:.0} % | {} | {} | {} |\n",
            r.complex,
            r.response.name(),
            r.starts,
            r.out,
            percent(r.out, r.starts),
            r.median_frames
                .map_or_else(|| "–".to_string(), |f| format!("{f:.0}")),
            r.got_in,
            r.out_not_in,
        ));
    }
    md
}

/// One row of the soft-limit sweep: soft flexible on a complex at one limit.
struct SweepRow {
    complex: &'static str,
    limit: f64,
    starts: usize,
    reached: usize,
    median_frames: Option<f64>,
    deepest: f64,
    /// Median over the runs that got there of their path's length pressed
    /// deeper than the default limit, Å.
    beyond_default: Option<f64>,
}

impl SweepRow {
    fn rate(&self) -> f64 {
        percent(self.reached, self.starts)
    }
}

/// Soft flexible at each limit of [`SWEEP_LIMITS`]: whether a looser limit
/// gets the drug there, and if so whether around the receptor or through it.
fn limit_sweep(
    complex: &'static str,
    receptor: &Molecule,
    drug: &Molecule,
    dirs: &[DVec3],
) -> Vec<SweepRow> {
    let opts = SteerOptions {
        response: Response::Soft,
        flexible: true,
        settle: false,
        seed: 1,
        escape: false,
    };
    SWEEP_LIMITS
        .iter()
        .map(|&limit| {
            let r = runs(receptor, drug, dirs, opts, limit);
            let done: Vec<&SteerReport> = r.iter().flatten().collect();
            let there: Vec<&&SteerReport> = done.iter().filter(|r| r.reached).collect();
            let frames: Vec<f64> = there
                .iter()
                .filter_map(|r| r.reached_frame.map(|f| f as f64))
                .collect();
            let beyond: Vec<f64> = there.iter().map(|r| r.path_beyond_default_limit).collect();
            SweepRow {
                complex,
                limit,
                starts: done.len(),
                reached: there.len(),
                median_frames: (!frames.is_empty()).then(|| median(&frames)),
                deepest: done
                    .iter()
                    .map(|r| r.deepest_overlap.max(r.deepest_inner_overlap))
                    .fold(0.0, f64::max),
                beyond_default: (!beyond.is_empty()).then(|| median(&beyond)),
            }
        })
        .collect()
}

/// The sweep's table, and per complex what the sweep found, for the
/// summary; `through` gives a complex's straight path through the receptor
/// (the flexible `pass` row's median length beyond the limit), Å.
fn sweep_markdown(
    sweep: &[SweepRow],
    through: impl Fn(&str) -> Option<f64>,
) -> (String, Vec<(&'static str, String)>) {
    let mut md = format!(
        "\n### Would a softer contact get there? The soft limit against the rate\n\n\
         The same controller and starts, `soft` flexible, with the soft limit raised from the \
         default {DEFAULT_LIMIT} Å (the first row of each complex is the table's soft flexible \
         row). *Beyond 1 Å* is the median, over the runs that got there, of how many Å of the \
         drug's path ran pressed deeper than the default limit; set beside the `pass` rows' \
         *beyond the limit* (the straight path's length through the receptor), it tells a run \
         that went round the receptor (near 0) from one that went through it (near the \
         straight path's).\n\n\
         | complex | soft limit Å | starts | reached | rate | frames (median) | deepest Å | beyond 1 Å, runs that got there (median) |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    for r in sweep {
        md.push_str(&format!(
            "| {} | {:.1} | {} | {} | {:.0} % | {} | {:.2} | {} |\n",
            r.complex,
            r.limit,
            r.starts,
            r.reached,
            r.rate(),
            r.median_frames
                .map_or_else(|| "–".to_string(), |f| format!("{f:.0}")),
            r.deepest,
            r.beyond_default
                .map_or_else(|| "–".to_string(), |b| format!("{b:.1}")),
        ));
    }
    let headline = sweep
        .iter()
        .map(|r| r.complex)
        .fold(Vec::<&str>::new(), |mut v, c| {
            if !v.contains(&c) {
                v.push(c);
            }
            v
        })
        .into_iter()
        .map(|c| {
            let rows: Vec<&SweepRow> = sweep.iter().filter(|r| r.complex == c).collect();
            let last = rows.last().map_or(0.0, |r| r.limit);
            let text = match rows.iter().find(|r| r.rate() >= TARGET_RATE) {
                Some(r) if r.limit <= DEFAULT_LIMIT => {
                    format!("{TARGET_RATE:.0} % at the default soft limit")
                }
                Some(r) => format!(
                    "{TARGET_RATE:.0} % first at a soft limit of {:.1} Å, where the runs that \
                     get there run {:.1} Å (median) pressed deeper than the default limit{}",
                    r.limit,
                    r.beyond_default.unwrap_or(0.0),
                    through(c).map_or(String::new(), |t| format!(
                        " (the straight path through the receptor: {t:.1} Å)"
                    ))
                ),
                None => format!("below {TARGET_RATE:.0} % up to a soft limit of {last:.1} Å"),
            };
            (c, text)
        })
        .collect();
    (md, headline)
}

fn summarise(complex: &'static str, opts: SteerOptions, runs: &[Run]) -> Row {
    let done: Vec<&SteerReport> = runs.iter().flatten().collect();
    let frames: Vec<f64> = done
        .iter()
        .filter_map(|r| r.reached_frame.map(|f| f as f64))
        .collect();
    let steps: Vec<f64> = done
        .iter()
        .flat_map(|r| r.step_us.iter().copied())
        .collect();
    let settled: Vec<_> = done.iter().filter_map(|r| r.settled.as_ref()).collect();
    let settled_rmsd: Vec<f64> = settled.iter().map(|s| s.rmsd).collect();
    Row {
        complex,
        response: opts.response,
        flexible: opts.flexible,
        settled: opts.settle.then(|| {
            (
                settled.len(),
                median(&settled_rmsd),
                settled.iter().filter(|s| !s.collides).count(),
            )
        }),
        starts: done.len(),
        reached: done.iter().filter(|r| r.reached).count(),
        median_frames: (!frames.is_empty()).then(|| median(&frames)),
        deepest: done
            .iter()
            .map(|r| r.deepest_overlap.max(r.deepest_inner_overlap))
            .fold(0.0, f64::max),
        least_deepest: done
            .iter()
            .map(|r| r.deepest_overlap)
            .fold(f64::INFINITY, f64::min),
        within_limit: done
            .iter()
            .filter(|r| r.deepest_overlap <= DEFAULT_LIMIT + 1e-9)
            .count(),
        beyond_limit: median(&done.iter().map(|r| r.path_beyond_limit).collect::<Vec<_>>()),
        step_median: median(&steps),
        step_p99: quantile(&steps, 0.99),
        missed: {
            let missed: Vec<&&SteerReport> = done.iter().filter(|r| !r.reached).collect();
            Missed {
                runs: missed.len(),
                cosines: missed
                    .iter()
                    .filter_map(|r| r.end_push_into_surface)
                    .collect(),
                rmsd: missed.iter().map(|r| r.final_rmsd).collect(),
                offsets: missed.iter().map(|r| r.final_offset).collect(),
                turns: missed.iter().map(|r| r.final_turn).collect(),
                torsions: missed.iter().map(|r| r.final_torsion_rms).collect(),
            }
        },
    }
}

/// Where the flexible slide and soft runs that do not get there end.
fn missed_markdown(rows: &[Row]) -> String {
    let mut md = String::from(
        "\n### Where the runs that do not get there end\n\n\
         The flexible `slide` and `soft` runs above that miss the pocket, at their last frame: \
         how many end pressed against the receptor; the cosine between the controller's push (towards the \
         file pose's centre) and the inward normal of the receptor's smoothed surface at the \
         touching atoms (the surface the glide follows: 1 is head-on into the receptor's \
         body, 0 along it); how many push within 30° of head-on; and how far from the file \
         pose they end. Near head-on the glide along the surface has little to slide along; \
         the glide round the receptor's body (its shape smoothed over 10 Å) carries such a \
         run on round, unless the body's shape, too, meets the push head-on there, or the \
         climb does not ride over the atoms in the way, or the receptor's mass round the drug \
         is as all-round as in a pocket's mouth, where nothing lifts the drug out. Then what \
         the RMSD at the end is made of: the centre's distance from the file pose's, the turn \
         from the file orientation and the bonds' RMS from their file angles (medians), and \
         how many end with the centre within 3 Å of the file pose's: at the pocket, but turned \
         round in it, where the controller's straight push, 3° a frame, cannot turn a drug \
         that the pocket holds on every side.\n\n\
         | complex | response | missed | end against the receptor | push into its surface, cos (median) | head-on (within 30°) | RMSD at the end Å (median) | centre off Å (median) | turned ° (median) | bonds off ° RMS (median) | centre within 3 Å |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows
        .iter()
        .filter(|r| r.flexible && matches!(r.response, Response::Slide | Response::Soft))
    {
        let m = &r.missed;
        let med = |v: &[f64], places: usize| {
            if v.is_empty() {
                "–".to_string()
            } else {
                format!("{:.*}", places, median(v))
            }
        };
        md.push_str(&format!(
            "| {} | {} | {} of {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.complex,
            r.response.name(),
            m.runs,
            r.starts,
            m.cosines.len(),
            med(&m.cosines, 2),
            m.cosines.iter().filter(|&&c| c >= HEAD_ON_COS).count(),
            med(&m.rmsd, 1),
            med(&m.offsets, 1),
            med(&m.turns, 0),
            med(&m.torsions, 0),
            m.offsets.iter().filter(|&&d| d <= AT_THE_POCKET).count(),
        ));
    }
    md
}

fn run(ctx: &Context, progress: &mut Progress) -> Part {
    let mut md = String::from("## Dockability: steering the drug into its pocket\n\n");
    let Some(dir) = ctx.data.as_ref() else {
        md.push_str("Skipped: `../shared/pdb` not found.\n");
        return Part::text(md);
    };
    // A smoke run (fewer queries than the quick directions) measures the
    // first complex only, from one direction.
    let smoke = ctx.queries < QUICK_DIRECTIONS;
    let n = match (ctx.quick, smoke) {
        (_, true) => 1,
        (true, false) => QUICK_DIRECTIONS,
        (false, false) => DIRECTIONS,
    };
    let dirs = bump::rng::sphere_directions(n);
    let t0 = Instant::now();
    let mut rows = Vec::new();
    let mut sweep = Vec::new();
    let mut escape = Vec::new();
    let mut skipped = Vec::new();
    for (label, receptor, drug) in
        COMPLEXES
            .into_iter()
            .take(if smoke { 1 } else { COMPLEXES.len() })
    {
        progress.step(&format!("dockability {label}"));
        let (receptor, drug) = match load(dir, receptor, drug) {
            Ok(m) => m,
            Err(e) => {
                skipped.push(format!("{label}: {e}"));
                continue;
            }
        };
        let mut flexible_runs = Vec::new();
        for flexible in [false, true] {
            for response in RESPONSES {
                // The soft flexible runs settle at the end.
                let opts = SteerOptions {
                    response,
                    flexible,
                    settle: flexible && response == Response::Soft,
                    seed: 1,
                    escape: false,
                };
                let r = runs(&receptor, &drug, &dirs, opts, DEFAULT_LIMIT);
                rows.push(summarise(label, opts, &r));
                if flexible {
                    flexible_runs.push((response, r));
                }
            }
        }
        escape.extend(escapes(label, &receptor, &drug, &dirs, &flexible_runs));
        sweep.extend(limit_sweep(label, &receptor, &drug, &dirs));
    }
    let seconds = t0.elapsed().as_secs_f64();
    md.push_str(&format!(
        "The controller of `bump steer` (issue 44): from the first pose along a direction at \
         least 8 Å from the file pose's centre where the drug, turned 30°, is clear of the \
         receptor by 3 Å (flexible: each rotatable bond first turned 60° either way, seeded by \
         the direction's number, or the other way, or not at all, where that would press the \
         drug's own atoms into each other), each frame proposes at most 0.3 Å and 3° towards \
         the file pose (flexible: and 5° per bond towards its file angle) through the response, \
         for at most 3000 frames; *reached* is a heavy-atom RMSD ≤ 2 Å to the file pose at some \
         frame (the least over the swaps of atoms the drug's bonds cannot tell apart, as \
         docking benchmarks count it). {n} Fibonacci directions per complex, Bondi radii, hydrogens dropped, the \
         default contact rule (overlap 0.6 Å, H-bond allowance 0.4 Å), soft limit 1 Å; run K \
         of a row is `bump steer RECEPTOR [DRUG] --direction K/{n} --response R [--flexible]`. \
         *Frames* is the median frame at which the runs that got there got there; *deepest* \
         the deepest overlap beyond the contact rule over every run, with the receptor or \
         within the drug (where a turn pressed its own atoms deeper than the file shape has \
         them); *least deepest* the least \
         of the runs' deepest overlaps (under `pass`, collision off, how far the best straight \
         path from outside presses into the receptor: more than the soft limit means no \
         response that keeps to it can follow a straight path in); *straight within the \
         limit*, under `pass`, how many starts have a straight path in whose deepest overlap \
         stays within the soft limit, and *beyond the limit* the median over the starts of \
         how many Å of the straight path run pressed deeper than that (through the receptor, \
         where no response that keeps to the limit can follow it). Step times are each \
         collision response's (a rigid move or one bond's turn), over every run. The soft \
         flexible runs then settle (the session's settle, exact Vina): the median heavy-atom \
         RMSD after settle and how many end free of overlaps (with the receptor and within \
         the drug). {} runs in {seconds:.0} s, with the way out and the sweep below.\n\n\
         | complex | drug | response | starts | reached | rate | frames (median) | deepest Å | least deepest Å | straight within the limit | beyond the limit Å (median) | step µs (median) | step µs (p99) | settled RMSD Å (median) | settled collision-free |\n\
         | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
        rows.iter().map(|r| r.starts).sum::<usize>()
    ));
    for r in &rows {
        let (settled_rmsd, free) = match r.settled {
            Some((k, rmsd, free)) if k > 0 => (format!("{rmsd:.2}"), format!("{free} of {k}")),
            _ => ("–".to_string(), "–".to_string()),
        };
        let (within, beyond) = if r.response == Response::Pass {
            (
                format!("{} of {}", r.within_limit, r.starts),
                format!("{:.1}", r.beyond_limit),
            )
        } else {
            ("–".to_string(), "–".to_string())
        };
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.0} % | {} | {:.2} | {:.2} | {within} | {beyond} | {:.1} | {:.1} | {settled_rmsd} | {free} |\n",
            r.complex,
            if r.flexible { "flexible" } else { "rigid" },
            r.response.name(),
            r.starts,
            r.reached,
            rate(r),
            r.median_frames
                .map_or_else(|| "–".to_string(), |f| format!("{f:.0}")),
            r.deepest,
            if r.least_deepest.is_finite() {
                r.least_deepest
            } else {
                0.0
            },
            r.step_median,
            r.step_p99
        ));
    }
    md.push_str("\n![dockability](bench/dockability.svg)\n");
    md.push_str(&missed_markdown(&rows));
    md.push_str(&escape_markdown(&escape));
    let (sweep_md, sweep_headline) = sweep_markdown(&sweep, |c| {
        rows.iter()
            .find(|r| r.complex == c && r.flexible && r.response == Response::Pass)
            .map(|r| r.beyond_limit)
    });
    md.push_str(&sweep_md);
    for s in &skipped {
        md.push_str(&format!("\nSkipped {s}\n"));
    }
    let headline = rows
        .iter()
        .filter(|r| r.response == Response::Soft && r.flexible)
        .map(|r| {
            let found = sweep_headline
                .iter()
                .find(|(c, _)| *c == r.complex)
                .map_or(String::new(), |(_, t)| format!("; {t}"));
            let head_on = r
                .missed
                .cosines
                .iter()
                .filter(|&&c| c >= HEAD_ON_COS)
                .count();
            format!(
                "Dockability, soft flexible: {} reached from {} of {} starts ({:.0} %; {head_on} of the {} that miss end pushing head-on into the receptor's body){found}",
                r.complex,
                r.reached,
                r.starts,
                rate(r),
                r.missed.runs
            )
        })
        .collect();
    Part {
        markdown: md,
        figures: vec![("dockability.svg".into(), figure(&rows))],
        headline,
    }
}

fn rate(r: &Row) -> f64 {
    percent(r.reached, r.starts)
}

/// `k` of `n` in per cent (0 of none).
fn percent(k: usize, n: usize) -> f64 {
    if n == 0 {
        0.0
    } else {
        100.0 * k as f64 / n as f64
    }
}

/// Grouped bars: success rate per complex, one bar per response.
fn figure(rows: &[Row]) -> String {
    let complexes: Vec<&str> = {
        let mut v: Vec<&str> = Vec::new();
        for r in rows {
            if !v.contains(&r.complex) {
                v.push(r.complex);
            }
        }
        v
    };
    let bars: Vec<(String, Vec<f64>)> = [false, true]
        .into_iter()
        .flat_map(|flexible| RESPONSES.iter().map(move |&resp| (flexible, resp)))
        .filter(|&(flexible, resp)| !flexible || matches!(resp, Response::Slide | Response::Soft))
        .map(|(flexible, resp)| {
            (
                format!(
                    "{}{}",
                    resp.name(),
                    if flexible { " (flexible)" } else { "" }
                ),
                complexes
                    .iter()
                    .map(|c| {
                        rows.iter()
                            .find(|r| {
                                r.complex == *c && r.response == resp && r.flexible == flexible
                            })
                            .map_or(0.0, rate)
                    })
                    .collect(),
            )
        })
        .collect();
    super::svg::bars(
        "Dockability: starts that reach the pocket (RMSD ≤ 2 Å)",
        "reached, %",
        &complexes,
        &bars,
        100.0,
    )
}
