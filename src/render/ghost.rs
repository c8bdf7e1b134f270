//! The ghost: the drug drawn a second time, translucent and in one neutral
//! tint, at its reference pose (the file's crystal pose, or the pose the
//! user pinned), so the target stays in sight while docking.
//!
//! It costs one matrix and two instanced draws of the drug's atoms (the
//! ghost's front surface into depth, then blended where it is frontmost).
//! The ghost has the reference's conformation too: while the drug's
//! torsions are those of the reference, it draws the drug's own atoms; once
//! they differ, it draws its own copy of them placed at the reference
//! torsions ([`ghost_torsions`]), uploaded once per reference. It is
//! depth-tested against everything else, so it is seen inside the pocket
//! and in front of or behind the moving drug as it really lies.

use crate::motion::Pose;
use crate::session::{Role, Session};

/// How the ghost is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ghost {
    /// Opacity, 0..1.
    pub opacity: f32,
    /// Its colour (linear RGB), before lighting.
    pub tint: [f32; 3],
}

impl Default for Ghost {
    fn default() -> Self {
        Self {
            opacity: 0.3,
            tint: [0.8, 0.8, 0.8],
        }
    }
}

/// The drug's molecule index and the world pose of its ghost: the live
/// score's reference (which follows a pinned pose), or, before the live
/// score has prepared the pair, the drug's file pose relative to the
/// receptor's. `None` without a drug and another molecule.
pub fn ghost_pose(session: &Session) -> Option<(usize, Pose)> {
    let bodies = session.bodies();
    let (drug, receptor, relative) = match session.reference_pose() {
        Some(r) => r,
        None => {
            let d = session.drug()?;
            let others = || (0..bodies.len()).filter(move |&k| k != d);
            let r = others()
                .find(|&k| session.role(k) == Some(Role::Receptor))
                .or_else(|| others().next())?;
            let file = bodies[r].loaded.inverse().compose(&bodies[d].loaded);
            (d, r, file)
        }
    };
    let world = bodies.get(receptor)?.pose.compose(&relative);
    bodies.get(drug)?;
    Some((drug, world))
}

/// The torsions of drug `d`'s reference conformation (the pinned one, or
/// the file's) when they are not the drug's current ones: the ghost then
/// needs its own atoms, placed at them ([`Session::shape_at`]). `None`
/// when the drug's own atoms show the reference shape.
pub fn ghost_torsions(session: &Session, d: usize) -> Option<Vec<f64>> {
    let reference = session.reference_torsions(d);
    (reference.as_slice() != session.torsion_angles(d)).then_some(reference)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};
    use crate::session::{Command, FrameInput, Settings};
    use glam::DVec3;

    #[test]
    fn the_ghost_stays_at_the_file_pose_while_the_drug_moves() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        let (d, before) = ghost_pose(&s).expect("a ghost");
        assert_eq!(d, 1);
        assert!((before.translation - s.bodies()[1].loaded.translation).length() < 1e-12);
        s.step(
            &FrameInput::with_commands(&[Command::MoveBy {
                translate: DVec3::new(0.0, 0.0, 40.0),
                axis: DVec3::Z,
                degrees: 30.0,
            }]),
            0.0,
        );
        let (_, after) = ghost_pose(&s).expect("a ghost");
        assert!((after.translation - before.translation).length() < 1e-9);
        assert!(after.rotation.angle_between(before.rotation) < 1e-9);
    }

    #[test]
    fn a_pinned_pose_becomes_the_ghost_and_the_rmsd_reference() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        s.enable_score();
        s.step(&FrameInput::default(), 0.0);
        let move_by = |s: &mut Session, t: DVec3| {
            s.step(
                &FrameInput::with_commands(&[Command::MoveBy {
                    translate: t,
                    axis: DVec3::Z,
                    degrees: 0.0,
                }]),
                0.0,
            )
        };
        move_by(&mut s, DVec3::new(0.0, 0.0, 30.0));
        let out = s.step(&FrameInput::with_commands(&[Command::PinReference]), 0.0);
        assert!(
            out.messages.iter().any(|m| m.contains("pinned")),
            "{:?}",
            out.messages
        );
        let live = out.score.expect("scored again after pinning");
        assert!(live.pinned && live.rmsd < 1e-9, "rmsd {}", live.rmsd);
        let (_, ghost) = ghost_pose(&s).expect("a ghost");
        let drug = s.bodies()[1].pose;
        assert!((ghost.translation - drug.translation).length() < 1e-9);
        // Moving on: the RMSD is measured from the pinned pose.
        let live = move_by(&mut s, DVec3::new(0.0, 0.0, 2.0))
            .score
            .expect("scored");
        assert!((live.rmsd - 2.0).abs() < 1e-9, "rmsd {}", live.rmsd);
    }
}
