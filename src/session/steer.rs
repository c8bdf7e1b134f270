//! The fixed steering controller of `bump steer` and the dockability
//! benchmark: can a drug be brought from outside into its pocket through a
//! collision response?
//!
//! The start: the first pose along `direction` (steps of 0.5 Å from 8 Å
//! off the file pose's centre) where the drug, turned 30° about a fixed
//! axis, collides with nothing and every drug atom lies at least 3 Å from
//! every receptor atom. Each frame then proposes at most 0.3 Å and 3°
//! towards the file pose (a [`Command::MoveBy`] through the session, the
//! same code as the window), for at most 3000 frames. The run is reached
//! when the heavy-atom RMSD to the file pose is at most 2 Å at some frame.
//! A frame that moves nothing ends the run early: the session is a
//! function of its state, so the next frame would propose the same and be
//! refused the same.

use glam::DVec3;
use serde::Serialize;
use thiserror::Error;

use super::{Command, Contact, FrameInput, Session, SessionError, Settings};
use crate::collide::{ContactRule, Response};
use crate::model::Molecule;
use crate::motion::Pose;

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
/// Largest proposed translation per frame, Å.
pub const MAX_STEP: f64 = 0.3;
/// Largest proposed turn per frame, degrees.
pub const MAX_TURN: f64 = 3.0;
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
}

/// What one steering run did.
#[derive(Debug, Clone, Serialize)]
pub struct SteerReport {
    /// The unit direction of the start from the file pose.
    pub direction: [f64; 3],
    /// The response.
    pub response: Response,
    /// Distance of the start from the file pose's centre, Å.
    pub start_distance: f64,
    /// Heavy-atom RMSD ≤ 2 Å at some frame.
    pub reached: bool,
    /// The first frame (1-based) at which it was reached.
    pub reached_frame: Option<usize>,
    /// Least heavy-atom RMSD to the file pose over the run, Å.
    pub best_rmsd: f64,
    /// Heavy-atom RMSD at the end, Å.
    pub final_rmsd: f64,
    /// Frames run.
    pub frames: usize,
    /// Deepest overlap beyond the default contact rule over the run, Å.
    pub deepest_overlap: f64,
    /// Median time of one collision response step, µs.
    pub step_us_median: f64,
    /// 99th percentile of the step times, µs.
    pub step_us_p99: f64,
    /// Per frame, the collision response's time, µs (not serialised).
    #[serde(skip)]
    pub step_us: Vec<f64>,
}

/// Heavy-atom RMSD between `drug` at `a` and at `b`, Å.
pub fn rmsd(drug: &Molecule, a: &Pose, b: &Pose) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for (atom, x) in drug.atoms.iter().zip(&drug.local) {
        if atom.element.eq_ignore_ascii_case("H") {
            continue;
        }
        let x = x.as_dvec3();
        sum += (a.transform_point(x) - b.transform_point(x)).length_squared();
        n += 1;
    }
    if n == 0 { 0.0 } else { (sum / n as f64).sqrt() }
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
    let rec: Vec<DVec3> = receptor
        .local
        .iter()
        .map(|x| receptor_pose.transform_point(x.as_dvec3()))
        .collect();
    let steps = ((FARTHEST_START - NEAREST_START) / START_STEP) as usize;
    (0..=steps).find_map(|k| {
        let s = NEAREST_START + START_STEP * k as f64;
        let pose = Pose::new(turned, file.translation + direction * s);
        let clear = drug.atoms.iter().zip(&drug.local).all(|(b, x)| {
            let x = pose.transform_point(x.as_dvec3());
            receptor.atoms.iter().zip(&rec).all(|(a, q)| {
                let d2 = (x - *q).length_squared();
                d2 >= START_CLEARANCE * START_CLEARANCE
                    && !rule.collides(a.radius, a.polar, b.radius, b.polar, d2 as f32)
            })
        });
        clear.then_some((pose, s))
    })
}

/// Runs the controller: `receptor` stays, `drug` starts along `direction`
/// and is steered towards its file pose under `response`.
///
/// # Errors
/// A zero direction, or no clear start.
pub fn steer(
    receptor: Molecule,
    drug: Molecule,
    mut settings: Settings,
    direction: DVec3,
    response: Response,
) -> Result<SteerReport, SteerError> {
    let d = direction
        .try_normalize()
        .filter(|d| d.is_finite())
        .ok_or(SteerError::Direction(direction.to_array()))?;
    settings.collision = true;
    settings.response = response;
    let rule = settings.rule;
    let mut session = Session::new(vec![receptor, drug], settings)?;
    let (rec, drg) = (&session.bodies()[0], &session.bodies()[1]);
    let file = drg.loaded;
    let (start, start_distance) =
        start_pose(&rec.molecule, &rec.pose, &drg.molecule, &file, d, &rule)
            .ok_or(SteerError::NoStart)?;
    // Put the drug at the start (a jump, outside the controller's frames).
    session.bodies[1].pose = start;
    session.env = None;
    session.history = super::History::default();
    session.prepare_response();
    let drug = session.bodies()[1].molecule.clone();
    let mut report = SteerReport {
        direction: d.to_array(),
        response,
        start_distance,
        reached: false,
        reached_frame: None,
        best_rmsd: rmsd(&drug, &start, &file),
        final_rmsd: 0.0,
        frames: 0,
        deepest_overlap: 0.0,
        step_us_median: 0.0,
        step_us_p99: 0.0,
        step_us: Vec::new(),
    };
    for frame in 1..=MAX_FRAMES {
        let pose = session.bodies()[1].pose;
        let mut translate = file.translation - pose.translation;
        if translate.length() > MAX_STEP {
            translate = translate.normalize() * MAX_STEP;
        }
        let q = (file.rotation * pose.rotation.conjugate()).normalize();
        let (axis, angle) = q.to_axis_angle();
        let mut degrees = angle.to_degrees();
        if degrees > 180.0 {
            degrees -= 360.0;
        }
        degrees = degrees.clamp(-MAX_TURN, MAX_TURN);
        if translate == DVec3::ZERO && degrees == 0.0 {
            break;
        }
        let out = session.step(
            &FrameInput::with_commands(&[Command::MoveBy {
                translate,
                axis,
                degrees,
            }]),
            0.0,
        );
        report.frames = frame;
        report.step_us.extend(out.collision_calls.iter().copied());
        let deepest = out
            .contacts
            .iter()
            .map(Contact::depth)
            .fold(0.0f32, f32::max);
        report.deepest_overlap = report.deepest_overlap.max(f64::from(deepest));
        let now = session.bodies()[1].pose;
        let r = rmsd(&drug, &now, &file);
        report.best_rmsd = report.best_rmsd.min(r);
        if r <= REACHED_RMSD && !report.reached {
            report.reached = true;
            report.reached_frame = Some(frame);
        }
        if !out.moved {
            break;
        }
    }
    report.final_rmsd = rmsd(&drug, &session.bodies()[1].pose, &file);
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

    #[test]
    fn pass_always_reaches_and_stop_never_overlaps() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let pass = steer(
            rings.clone(),
            e.clone(),
            Settings::default(),
            DVec3::X,
            Response::Pass,
        )
        .expect("steer");
        assert!(pass.reached && pass.final_rmsd < 1e-6, "{pass:?}");
        for response in [Response::Stop, Response::Touch, Response::Slide] {
            let r = steer(
                rings.clone(),
                e.clone(),
                Settings::default(),
                DVec3::new(0.3, -1.0, 0.2),
                response,
            )
            .expect("steer");
            assert_eq!(r.deepest_overlap, 0.0, "{r:?}");
            assert!(r.frames >= 1 && r.best_rmsd <= r.final_rmsd + 1e-12);
        }
        let soft = steer(rings, e, Settings::default(), DVec3::Y, Response::Soft).expect("steer");
        assert!(soft.deepest_overlap <= 1.0 + 1e-4, "{soft:?}");
    }
}
