//! The fixed steering controller of `bump steer` and the dockability
//! benchmark: can a drug be brought from outside into its pocket through a
//! collision response?
//!
//! The start: the first pose along `direction` (steps of 0.5 Å from 8 Å
//! off the file pose's centre) where the drug, turned 30° about a fixed
//! axis, collides with nothing and every drug atom lies at least 3 Å from
//! every receptor atom. With `flexible`, each rotatable bond is first
//! turned 60° from its file angle, either way as a seeded draw says (the
//! other way, or not at all, where that would press the drug's own atoms
//! into each other: [`SteerReport::start_torsions`]), and the start is
//! searched with that shape. Each frame then proposes at most
//! 0.3 Å and 3° towards the file pose (a [`Command::MoveBy`] through the
//! session, the same code as the window), and, with `flexible`, at most 5°
//! per bond towards its file angle (a [`Command::TurnTorsion`] of each
//! bond still turned), for at most 3000 frames. The run is reached when
//! the heavy-atom RMSD to the file pose (and file torsions) is at most
//! 2 Å at some frame: the RMSD docking benchmarks use, the least over the
//! swaps of atoms the drug's bond graph cannot tell apart (benzamidine's
//! ring turned over, a carboxylate's oxygens; [`symmetry`]). A frame that moves nothing ends the run early: the
//! session is a function of its state, so the next frame would propose
//! the same and be refused the same. With `settle`, the session's settle
//! ([`Command::Settle`]) runs from the final pose. A run that ends
//! pressed against the receptor reports how squarely its last push ran into
//! the receptor's smoothed surface ([`SteerReport::end_push_into_surface`]).
//!
//! With `escape` the controller runs the other way, as a measurement of
//! whether the pocket lets the drug out at all: from the file pose and
//! file torsions towards the start (its pose and, with `flexible`, its
//! turned bonds), with the same steps, and the run gets there when the
//! RMSD to the start is at most 2 Å. A run out that gets there, reversed,
//! is a way in that keeps to the response's limit: a pocket its drug gets
//! out of is open, and a start reached on the way out but not left on the
//! way in shows the straight push from outside in the way, not the
//! pocket.
//!
//! Everything a soft frame needs (the environment, the loosened index,
//! the clearance map) is built before the first frame
//! ([`Session::prepare_response`]), so the step times are the steps'.

use glam::DVec3;
use serde::Serialize;
use thiserror::Error;

use super::{Command, Contact, FrameInput, Session, SessionError, Settings, TorsionError};
use crate::chem::symmetry;
use crate::collide::{ContactRule, Response};
use crate::model::Molecule;
use crate::motion::Pose;
use crate::rng::Rng;

/// Farthest start searched along the direction, Å.
const FARTHEST_START: f64 = 200.0;
/// Nearest start, Å from the file pose's centre.
const NEAREST_START: f64 = 8.0;
/// Spacing of the starts tried, Å.
const START_STEP: f64 = 0.5;
/// Least distance between any drug and receptor atom at the start, Å.
const START_CLEARANCE: f64 = 3.0;
/// The start's turn, degrees, about [`START_AXIS`].
const START_TURN: f64 = 30.0;
/// The start's turn axis (fixed, normalised when used).
const START_AXIS: DVec3 = DVec3::new(1.0, 2.0, 3.0);
/// The start's turn of each rotatable bond with `flexible`, degrees
/// (either way, seeded).
pub const START_TORSION: f64 = 60.0;
/// Largest proposed translation per frame, Å.
pub const MAX_STEP: f64 = 0.3;
/// Largest proposed turn per frame, degrees.
pub const MAX_TURN: f64 = 3.0;
/// Largest proposed turn of one rotatable bond per frame, degrees.
pub const MAX_TORSION_TURN: f64 = 5.0;
/// Frames at most.
pub const MAX_FRAMES: usize = 3000;
/// Heavy-atom RMSD to the file pose that counts as reached, Å.
pub const REACHED_RMSD: f64 = 2.0;

/// A steering run that cannot start.
#[derive(Debug, Error)]
pub enum SteerError {
    /// The direction is zero or not finite.
    #[error("the direction must be a finite, non-zero vector, got {0:?}")]
    Direction([f64; 3]),
    /// No clear start within the search.
    #[error("no start pose along the direction within {FARTHEST_START} Å is clear of the receptor")]
    NoStart,
    /// The session could not start.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// The drug's torsions could not be set.
    #[error(transparent)]
    Torsion(#[from] TorsionError),
}

/// How the controller runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteerOptions {
    /// The collision response.
    pub response: Response,
    /// Turn the drug's rotatable bonds too.
    pub flexible: bool,
    /// Settle after the run.
    pub settle: bool,
    /// Seed of the start's torsion turns.
    pub seed: u64,
    /// Run the other way: from the file pose out to the start.
    pub escape: bool,
}

impl Default for SteerOptions {
    fn default() -> Self {
        Self {
            response: Response::Soft,
            flexible: false,
            settle: false,
            seed: 1,
            escape: false,
        }
    }
}

/// What the session's settle made of the final pose.
#[derive(Debug, Clone, Serialize)]
pub struct Settled {
    /// Whether settle changed the pose (it does only when it ends free of
    /// overlaps).
    pub applied: bool,
    /// Heavy-atom RMSD to the file pose after settle, Å.
    pub rmsd: f64,
    /// Vina's intermolecular energy after settle, kcal/mol (None when
    /// settle changed nothing).
    pub score: Option<f64>,
    /// Whether the drug collides with the receptor, or two of its own atoms
    /// more than three bonds apart that its torsions move relative to each
    /// other collide, under the contact rule after settle.
    pub collides: bool,
}

/// What one steering run did.
#[derive(Debug, Clone, Serialize)]
pub struct SteerReport {
    /// The unit direction of the start from the file pose.
    pub direction: [f64; 3],
    /// The response.
    pub response: Response,
    /// Whether the rotatable bonds turned.
    pub flexible: bool,
    /// Whether the run went the other way, from the file pose out to the
    /// start (every RMSD and `reached` are then to the start).
    pub escape: bool,
    /// Rotatable bonds turned (0 for a rigid run).
    pub torsions: usize,
    /// The start's turn of each rotatable bond from its file angle,
    /// degrees: ±60 as the seeded draw says or the other way, 0 where
    /// neither way leaves the drug clear of itself.
    pub start_torsions: Vec<f64>,
    /// Distance of the start from the file pose's centre, Å.
    pub start_distance: f64,
    /// Heavy-atom RMSD ≤ 2 Å at some frame (every RMSD here is the least
    /// over the drug's symmetric swaps of atoms, see [`rmsd`]).
    pub reached: bool,
    /// The first frame (1-based) at which it was reached.
    pub reached_frame: Option<usize>,
    /// Least heavy-atom RMSD to the file pose over the run, Å.
    pub best_rmsd: f64,
    /// Heavy-atom RMSD at the end, Å.
    pub final_rmsd: f64,
    /// How far the drug's centre ends from the target's (the file pose, or
    /// with `escape` the start), Å.
    pub final_offset: f64,
    /// How far the drug's orientation ends turned from the target's,
    /// degrees (0 to 180): with the centre near the target, a drug that
    /// reached the pocket turned round.
    pub final_turn: f64,
    /// Root mean square of the rotatable bonds' ends from the target
    /// torsions, degrees (0 for a rigid run).
    pub final_torsion_rms: f64,
    /// Frames run.
    pub frames: usize,
    /// Deepest overlap with the receptor beyond the default contact rule
    /// over the run, Å.
    pub deepest_overlap: f64,
    /// Deepest overlap between the drug's own atoms (more than three bonds
    /// apart, movable relative to each other) beyond the default contact
    /// rule at the start, Å: 0 unless the file shape has such a pair (the
    /// start's turns add none).
    pub start_inner_overlap: f64,
    /// Deepest overlap between the drug's own atoms beyond the default
    /// contact rule over the run's frames, counting a pair only where it
    /// is deeper than at the start (a pair the start pressed in may only
    /// come apart), Å.
    pub deepest_inner_overlap: f64,
    /// Length of the drug centre's path over the frames that end pressed
    /// deeper than the soft limit beyond the contact rule, Å: under `pass`
    /// (collision off), how much of the straight path runs through the
    /// receptor farther in than `soft` may go.
    pub path_beyond_limit: f64,
    /// The same against the default soft limit
    /// ([`crate::collide::soft::DEFAULT_LIMIT`]), whatever the session's:
    /// under `soft` with a looser limit, how much of the path ran through
    /// the receptor farther in than the default lets it.
    pub path_beyond_default_limit: f64,
    /// Where the run ends pressed against the receptor with the file
    /// pose's centre more than a step away: the cosine between the push
    /// towards it and the inward normal of the receptor's smoothed surface
    /// at the touching atoms ([`crate::collide::soft::glide_normal`]);
    /// near 1, the push runs head-on into the receptor's body and leaves
    /// the glide little to slide along. `None` when the drug ends free of
    /// the receptor or within a step of the file pose.
    pub end_push_into_surface: Option<f64>,
    /// Median time of one collision response step (a rigid move or a
    /// bond's turn), µs.
    pub step_us_median: f64,
    /// 99th percentile of the step times, µs.
    pub step_us_p99: f64,
    /// After `settle`: what it made of the final pose.
    pub settled: Option<Settled>,
    /// Per step, the collision response's time, µs (not serialised).
    #[serde(skip)]
    pub step_us: Vec<f64>,
}

/// World positions of `drug`'s heavy atoms at `pose`.
fn heavy_atoms(drug: &Molecule, pose: &Pose) -> Vec<DVec3> {
    drug.atoms
        .iter()
        .zip(&drug.local)
        .filter(|(atom, _)| !crate::model::element::is_hydrogen(&atom.element))
        .map(|(_, x)| pose.transform_point(x.as_dvec3()))
        .collect()
}

/// Heavy-atom RMSD between `drug` at `a` and at `b`, Å, the least over
/// the swaps of atoms its bond graph cannot tell apart (a ring turned
/// over, a carboxylate's oxygens: see [`symmetry`]).
pub fn rmsd(drug: &Molecule, a: &Pose, b: &Pose) -> f64 {
    symmetry::rmsd_over(
        &symmetry::heavy_swaps(drug),
        &heavy_atoms(drug, a),
        &heavy_atoms(drug, b),
    )
}

/// Whether `drug` at `pose` collides with `receptor` at `receptor_pose`
/// under `rule`, and every drug atom lies at least `clearance` Å from
/// every receptor atom (brute force: the judge, not the collider).
fn clear(
    receptor: &[(f32, bool, DVec3)],
    drug: &Molecule,
    pose: &Pose,
    rule: &ContactRule,
    clearance: f64,
) -> bool {
    drug.atoms.iter().zip(&drug.local).all(|(b, x)| {
        let x = pose.transform_point(x.as_dvec3());
        receptor.iter().all(|&(radius, polar, q)| {
            let d2 = (x - q).length_squared();
            d2 >= clearance * clearance
                && !rule.collides(radius, polar, b.radius, b.polar, d2 as f32)
        })
    })
}

/// The pairs of molecule 1's atoms more than three bonds apart whose
/// distance some turn of its rotatable bonds changes, by brute force from
/// the bonds' sides (a turn moves one atom and not the other, and neither
/// lies on its axis): the judge's pairs, found without the torsion tree's
/// own list of them.
fn judged_pairs(session: &Session) -> Vec<(usize, usize)> {
    let bonds = session.rotatable_bonds(1);
    let drug = &session.bodies()[1].molecule;
    crate::chem::torsions::pairs_beyond_three_bonds(&drug.chemistry().adjacency)
        .into_iter()
        .filter(|&(i, j)| {
            bonds.iter().any(|b| {
                let moves = |a: u32| b.moving.binary_search(&a).is_ok();
                moves(i) != moves(j) && !b.atoms.contains(&i) && !b.atoms.contains(&j)
            })
        })
        .map(|(i, j)| (i as usize, j as usize))
        .collect()
}

/// Those of `pairs` of `drug`'s atoms that collide under `rule`, with how
/// far each presses beyond its contact distance (brute force: the judge).
fn inner_overlaps(
    drug: &Molecule,
    pairs: &[(usize, usize)],
    rule: &ContactRule,
) -> Vec<((usize, usize), f32)> {
    pairs
        .iter()
        .filter_map(|&(i, j)| {
            let (a, b) = (drug.atoms.get(i)?, drug.atoms.get(j)?);
            let (p, q) = (drug.local.get(i)?, drug.local.get(j)?);
            rule.collides(a.radius, a.polar, b.radius, b.polar, p.distance_squared(*q))
                .then(|| {
                    let c = rule.contact_distance(a.radius, a.polar, b.radius, b.polar);
                    ((i.min(j), i.max(j)), (c - p.distance(*q)).max(0.0))
                })
        })
        .collect()
}

/// The receptor's atoms in the world: (radius, polar, position).
fn world_atoms(receptor: &Molecule, pose: &Pose) -> Vec<(f32, bool, DVec3)> {
    receptor
        .atoms
        .iter()
        .zip(&receptor.local)
        .map(|(a, x)| (a.radius, a.polar, pose.transform_point(x.as_dvec3())))
        .collect()
}

/// The start pose along `direction` (unit) from the drug's file pose
/// `file` (world), the receptor at `receptor_pose`.
pub fn start_pose(
    receptor: &Molecule,
    receptor_pose: &Pose,
    drug: &Molecule,
    file: &Pose,
    direction: DVec3,
    rule: &ContactRule,
) -> Option<(Pose, f64)> {
    let turned = crate::collide::sweep::turn(START_AXIS, START_TURN) * file.rotation;
    let rec = world_atoms(receptor, receptor_pose);
    let steps = ((FARTHEST_START - NEAREST_START) / START_STEP) as usize;
    (0..=steps).find_map(|k| {
        let s = NEAREST_START + START_STEP * k as f64;
        let pose = Pose::new(turned, file.translation + direction * s);
        clear(&rec, drug, &pose, rule, START_CLEARANCE).then_some((pose, s))
    })
}

/// The seeded draw of the start's turns of `n` rotatable bonds: which way
/// each turns, +1 or −1.
pub fn start_signs(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| if rng.next_u64() >> 63 == 0 { 1.0 } else { -1.0 })
        .collect()
}

/// The start's turns of the drug's rotatable bonds from their file
/// angles, degrees, set on the session: bond by bond, in order,
/// [`START_TORSION`]° the way the seeded draw ([`start_signs`]) says,
/// else the other way, else none, the first that leaves the drug colliding
/// with itself nowhere its file shape does not (a start collides with
/// nothing). So every bond is turned where either way is clear, and the
/// start never puts the drug's halves into each other.
fn start_shape(
    session: &mut Session,
    pairs: &[(usize, usize)],
    seed: u64,
    rule: &ContactRule,
) -> Result<Vec<f64>, TorsionError> {
    // Within the f32 noise of recomputing the untouched atoms' places.
    const SAME: f32 = 1e-4;
    let at_file = inner_overlaps(&session.bodies()[1].molecule, pairs, rule);
    let no_worse = |now: &[((usize, usize), f32)]| {
        now.iter()
            .all(|(p, d)| at_file.iter().any(|(q, e)| q == p && *d <= e + SAME))
    };
    let n = session.torsion_angles(1).len();
    let mut turns = vec![0.0; n];
    let radians = |turns: &[f64]| turns.iter().map(|t| t.to_radians()).collect::<Vec<_>>();
    for (k, sign) in start_signs(n, seed).into_iter().enumerate() {
        let mut clear = false;
        for candidate in [sign, -sign] {
            turns[k] = candidate * START_TORSION;
            session.set_torsions(1, &radians(&turns))?;
            if no_worse(&inner_overlaps(&session.bodies()[1].molecule, pairs, rule)) {
                clear = true;
                break;
            }
        }
        if !clear {
            turns[k] = 0.0;
        }
    }
    session.set_torsions(1, &radians(&turns))?;
    Ok(turns)
}

/// The frame's proposal towards the pose `target` and the torsions
/// `target_torsions` (radians from the file angles; empty for a rigid
/// run): the commands (none when there is nothing left to do).
fn proposal(session: &Session, target: &Pose, target_torsions: &[f64]) -> Vec<Command> {
    let pose = session.bodies()[1].pose;
    let mut translate = target.translation - pose.translation;
    if translate.length() > MAX_STEP {
        translate = translate.normalize() * MAX_STEP;
    }
    let q = (target.rotation * pose.rotation.conjugate()).normalize();
    let (axis, angle) = q.to_axis_angle();
    let mut degrees = angle.to_degrees();
    if degrees > 180.0 {
        degrees -= 360.0;
    }
    degrees = degrees.clamp(-MAX_TURN, MAX_TURN);
    let mut commands = Vec::new();
    if translate != DVec3::ZERO || degrees != 0.0 {
        commands.push(Command::MoveBy {
            translate,
            axis,
            degrees,
        });
    }
    for (k, (&t, &want)) in session
        .torsion_angles(1)
        .iter()
        .zip(target_torsions)
        .enumerate()
    {
        let turn = (want - t)
            .to_degrees()
            .clamp(-MAX_TORSION_TURN, MAX_TORSION_TURN);
        if turn != 0.0 {
            commands.push(Command::SelectTorsion(Some(k)));
            commands.push(Command::TurnTorsion { degrees: turn });
        }
    }
    commands
}

/// [`SteerReport::end_push_into_surface`] of the drug where it stands,
/// pushed towards `target`.
fn push_into_surface(session: &mut Session, target: &Pose) -> Option<f64> {
    let pose = session.bodies()[1].pose;
    let push = target.translation - pose.translation;
    if push.length() <= MAX_STEP {
        return None;
    }
    let tolerance = session.settings.touch.tolerance as f32;
    let env = session.environment()?;
    let rel = env.frame.inverse().compose(&pose);
    let contacts = crate::collide::pairs_within(&env.collider, &env.drug, &rel, tolerance);
    let inward = -crate::collide::soft::glide_normal(&env.collider, &env.drug, &rel, &contacts)?;
    // The normal is in the collider's frame.
    Some((env.frame.rotation.inverse() * push.normalize()).dot(inward))
}

/// Runs the controller: `receptor` stays, `drug` starts along `direction`
/// and is steered towards its file pose as `opts` says (with `escape`,
/// the other way).
///
/// # Errors
/// A zero direction, or no clear start.
pub fn steer(
    receptor: Molecule,
    drug: Molecule,
    mut settings: Settings,
    direction: DVec3,
    opts: &SteerOptions,
) -> Result<SteerReport, SteerError> {
    let d = direction
        .try_normalize()
        .filter(|d| d.is_finite())
        .ok_or(SteerError::Direction(direction.to_array()))?;
    settings.collision = true;
    settings.response = opts.response;
    let rule = settings.rule;
    let mut session = Session::new(vec![receptor, drug], settings)?;
    let file = session.bodies()[1].loaded;
    let file_atoms = heavy_atoms(&session.bodies()[1].molecule, &file);
    let swaps = symmetry::heavy_swaps(&session.bodies()[1].molecule);
    let torsions = if opts.flexible {
        session.rotatable_bonds(1).len()
    } else {
        0
    };
    let judged = judged_pairs(&session);
    let start_turns = if torsions > 0 {
        start_shape(&mut session, &judged, opts.seed, &rule)?
    } else {
        Vec::new()
    };
    let (rec, drg) = (&session.bodies()[0], &session.bodies()[1]);
    let receptor_atoms = world_atoms(&rec.molecule, &rec.pose);
    let (start, start_distance) =
        start_pose(&rec.molecule, &rec.pose, &drg.molecule, &file, d, &rule)
            .ok_or(SteerError::NoStart)?;
    let start_radians: Vec<f64> = start_turns.iter().map(|t| t.to_radians()).collect();
    // Where the run begins and where it is steered to: (pose, torsions
    // from the file angles, radians).
    let (from, target, target_torsions) = if opts.escape {
        let at_start = heavy_atoms(&session.bodies()[1].molecule, &start);
        if !start_radians.is_empty() {
            session.set_torsions(1, &vec![0.0; start_radians.len()])?;
        }
        (file, (start, at_start), start_radians)
    } else {
        let zeros = vec![0.0; start_radians.len()];
        (start, (file, file_atoms), zeros)
    };
    let (target, target_atoms) = target;
    // Sorted by pair for the lookups of each frame.
    let mut start_inner = inner_overlaps(&session.bodies()[1].molecule, &judged, &rule);
    start_inner.sort_by_key(|a| a.0);
    // Put the drug where the run begins (a jump, outside the controller's
    // frames), and build what the response needs before the first frame.
    session.bodies[1].pose = from;
    session.env = None;
    session.history = super::History::default();
    session.prepare_response();
    let now_rmsd = |s: &Session| {
        let b = &s.bodies()[1];
        symmetry::rmsd_over(&swaps, &heavy_atoms(&b.molecule, &b.pose), &target_atoms)
    };
    let mut report = SteerReport {
        direction: d.to_array(),
        response: opts.response,
        flexible: opts.flexible,
        escape: opts.escape,
        torsions,
        start_torsions: start_turns,
        start_distance,
        reached: false,
        reached_frame: None,
        best_rmsd: now_rmsd(&session),
        final_rmsd: 0.0,
        final_offset: 0.0,
        final_turn: 0.0,
        final_torsion_rms: 0.0,
        frames: 0,
        deepest_overlap: 0.0,
        start_inner_overlap: start_inner
            .iter()
            .map(|&(_, d)| f64::from(d))
            .fold(0.0, f64::max),
        deepest_inner_overlap: 0.0,
        path_beyond_limit: 0.0,
        path_beyond_default_limit: 0.0,
        end_push_into_surface: None,
        step_us_median: 0.0,
        step_us_p99: 0.0,
        settled: None,
        step_us: Vec::new(),
    };
    let limit = session.settings.soft_limit;
    let mut last_centre = session.bodies()[1].pose.translation;
    for frame in 1..=MAX_FRAMES {
        let commands = proposal(&session, &target, &target_torsions);
        if commands.is_empty() {
            break;
        }
        let out = session.step(&FrameInput::with_commands(&commands), 0.0);
        report.frames = frame;
        report.step_us.extend(out.collision_calls.iter().copied());
        let (inner, receptor): (Vec<&Contact>, Vec<&Contact>) =
            out.contacts.iter().partition(|c| c.other.0 == c.moving.0);
        let deepest = receptor.iter().map(|c| c.depth()).fold(0.0f32, f32::max);
        report.deepest_overlap = report.deepest_overlap.max(f64::from(deepest));
        for c in inner {
            let key = (c.moving.1.min(c.other.1), c.moving.1.max(c.other.1));
            let at_start = start_inner
                .binary_search_by(|(k, _)| k.cmp(&key))
                .map_or(0.0, |i| start_inner[i].1);
            if c.depth() > at_start + 1e-6 {
                report.deepest_inner_overlap =
                    report.deepest_inner_overlap.max(f64::from(c.depth()));
            }
        }
        let centre = session.bodies()[1].pose.translation;
        if f64::from(deepest) > limit + 1e-6 {
            report.path_beyond_limit += centre.distance(last_centre);
        }
        if f64::from(deepest) > crate::collide::soft::DEFAULT_LIMIT + 1e-6 {
            report.path_beyond_default_limit += centre.distance(last_centre);
        }
        last_centre = centre;
        let r = now_rmsd(&session);
        report.best_rmsd = report.best_rmsd.min(r);
        if r <= REACHED_RMSD && !report.reached {
            report.reached = true;
            report.reached_frame = Some(frame);
        }
        if !out.moved {
            break;
        }
    }
    report.final_rmsd = now_rmsd(&session);
    let end = session.bodies()[1].pose;
    report.final_offset = end.translation.distance(target.translation);
    report.final_turn = end
        .rotation
        .normalize()
        .angle_between(target.rotation.normalize())
        .to_degrees();
    let off: Vec<f64> = session
        .torsion_angles(1)
        .iter()
        .zip(&target_torsions)
        .map(|(t, want)| {
            let d = (t - want).rem_euclid(std::f64::consts::TAU);
            d.min(std::f64::consts::TAU - d).to_degrees()
        })
        .collect();
    if !off.is_empty() {
        report.final_torsion_rms =
            (off.iter().map(|d| d * d).sum::<f64>() / off.len() as f64).sqrt();
    }
    report.end_push_into_surface = push_into_surface(&mut session, &target);
    if opts.settle {
        let out = session.step(&FrameInput::with_commands(&[Command::Settle]), 0.0);
        let b = &session.bodies()[1];
        report.settled = Some(Settled {
            applied: out.settled.is_some(),
            rmsd: now_rmsd(&session),
            score: out.settled.as_ref().map(|p| p.inter.1),
            collides: !clear(&receptor_atoms, &b.molecule, &b.pose, &rule, 0.0)
                || !inner_overlaps(&b.molecule, &judged, &rule).is_empty(),
        });
    }
    let mut sorted = report.step_us.clone();
    sorted.sort_by(f64::total_cmp);
    let at = |q: f64| {
        let k = ((sorted.len() as f64 - 1.0) * q).round() as usize;
        sorted.get(k).copied().unwrap_or(0.0)
    };
    (report.step_us_median, report.step_us_p99) = (at(0.5), at(0.99));
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};

    fn opts(response: Response) -> SteerOptions {
        SteerOptions {
            response,
            ..SteerOptions::default()
        }
    }

    #[test]
    fn rmsd_counts_a_ring_turned_over_as_the_same_pose() {
        use crate::model::molecule::test_carbon;
        use std::f64::consts::PI;
        // A benzamidine: a hexagon of carbons, a carbon on it along +x and
        // two nitrogens on that one, all in the xy plane.
        let mut pos: Vec<DVec3> = (0..6)
            .map(|k| {
                let a = PI / 3.0 * f64::from(k);
                DVec3::new(a.cos(), a.sin(), 0.0) * 1.39
            })
            .collect();
        let c7 = DVec3::new(1.39 + 1.49, 0.0, 0.0);
        pos.push(c7);
        for a in [PI / 3.0, -PI / 3.0] {
            pos.push(c7 + DVec3::new(a.cos(), a.sin(), 0.0) * 1.33);
        }
        let mut atoms: Vec<_> = (1..=9).map(test_carbon).collect();
        for a in &mut atoms[7..] {
            a.element = "N".into();
        }
        let drug = Molecule::new("BEN", atoms, &pos);
        let at = Pose::from_translation(drug.centre);
        // Turned over about its long axis (through the centre of the ring
        // and the amidine), every atom lands on one of its own kind.
        let axis = DVec3::X;
        let centre_on_axis = DVec3::new(drug.centre.x, 0.0, 0.0);
        let turned = Pose::new(
            glam::DQuat::from_axis_angle(axis, PI),
            centre_on_axis
                + glam::DQuat::from_axis_angle(axis, PI) * (drug.centre - centre_on_axis),
        );
        let plain =
            crate::score::settle::rmsd(&heavy_atoms(&drug, &at), &heavy_atoms(&drug, &turned));
        assert!(plain > 1.0, "{plain}");
        assert!(
            rmsd(&drug, &at, &turned) < 1e-9,
            "{}",
            rmsd(&drug, &at, &turned)
        );
        // Turned a quarter, it is not the same pose.
        let quarter = Pose::new(glam::DQuat::from_axis_angle(axis, PI / 2.0), drug.centre);
        assert!(rmsd(&drug, &at, &quarter) > 0.5);
    }

    #[test]
    fn start_signs_are_either_way_and_seeded() {
        let a = start_signs(40, 7);
        assert_eq!(a, start_signs(40, 7));
        assert_ne!(a, start_signs(40, 8));
        assert!(a.iter().all(|t| t.abs() == 1.0));
        assert!(a.iter().any(|t| *t > 0.0) && a.iter().any(|t| *t < 0.0));
    }

    /// A wall of carbons in the plane z = 0, 48 Å wide
    /// ([`crate::model::molecule::test_wall`]), and three carbons behind it
    /// at z = −8 as the drug.
    fn wall_and_drug() -> (Molecule, Molecule) {
        use crate::model::molecule::{test_carbon, test_wall};
        let drug_at = [-1.3, 0.0, 1.3].map(|x| DVec3::new(x, 0.4, -8.0));
        let drug = Molecule::new("drug", (1..=3).map(test_carbon).collect(), &drug_at);
        (test_wall(), drug)
    }

    #[test]
    fn a_run_held_by_a_wall_ends_pushing_head_on_into_it() {
        let (wall, drug) = wall_and_drug();
        let r = steer(
            wall.clone(),
            drug.clone(),
            Settings::default(),
            DVec3::Z,
            &opts(Response::Touch),
        )
        .expect("steer");
        assert!(!r.reached, "{r:?}");
        let cos = r.end_push_into_surface.expect("pressed against the wall");
        assert!(cos > 0.99, "{r:?}");
        // From an oblique start, the push meets the wall at a slant.
        let slant = DVec3::new(1.0, 0.0, 1.0);
        let r = steer(
            wall.clone(),
            drug.clone(),
            Settings::default(),
            slant,
            &opts(Response::Touch),
        )
        .expect("steer");
        let cos = r.end_push_into_surface.expect("pressed against the wall");
        assert!(cos > 0.3 && cos < 0.95, "{r:?}");
        // Through the wall (collision off) it gets there: nothing to say.
        let r = steer(
            wall,
            drug,
            Settings::default(),
            DVec3::Z,
            &opts(Response::Pass),
        )
        .expect("steer");
        assert!(r.reached && r.end_push_into_surface.is_none(), "{r:?}");
        assert!(r.final_offset < 1e-9 && r.final_turn < 1e-4, "{r:?}");
    }

    #[test]
    fn an_escape_runs_from_the_file_pose_out_to_the_start() {
        let (wall, drug) = wall_and_drug();
        let out = |response| {
            steer(
                wall.clone(),
                drug.clone(),
                Settings::default(),
                DVec3::Z,
                &SteerOptions {
                    escape: true,
                    ..opts(response)
                },
            )
            .expect("steer")
        };
        // The wall stands between the file pose and the start: from this
        // side, too, the push runs head-on into it and stops there.
        let held = out(Response::Touch);
        assert!(held.escape && !held.reached, "{held:?}");
        assert!(held.end_push_into_surface.expect("pressed") > 0.99);
        assert!(
            held.final_offset > 3.0 && held.deepest_overlap == 0.0,
            "{held:?}"
        );
        // Collision off, it gets out to the start: its centre and its turn.
        let free = out(Response::Pass);
        assert!(free.reached && free.final_rmsd < 1e-6, "{free:?}");
        assert!(
            free.final_offset < 1e-9 && free.final_turn < 1e-4,
            "{free:?}"
        );
    }

    #[test]
    fn pass_always_reaches_and_stop_never_overlaps() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let pass = steer(
            rings.clone(),
            e.clone(),
            Settings::default(),
            DVec3::X,
            &opts(Response::Pass),
        )
        .expect("steer");
        assert!(pass.reached && pass.final_rmsd < 1e-6, "{pass:?}");
        for response in [Response::Stop, Response::Touch, Response::Slide] {
            let r = steer(
                rings.clone(),
                e.clone(),
                Settings::default(),
                DVec3::new(0.3, -1.0, 0.2),
                &opts(response),
            )
            .expect("steer");
            assert_eq!(r.deepest_overlap, 0.0, "{r:?}");
            assert!(r.frames >= 1 && r.best_rmsd <= r.final_rmsd + 1e-12);
        }
        let soft = steer(
            rings,
            e,
            Settings::default(),
            DVec3::Y,
            &opts(Response::Soft),
        )
        .expect("steer");
        assert!(soft.deepest_overlap <= 1.0 + 1e-4, "{soft:?}");
    }
}
