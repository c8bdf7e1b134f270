//! The live score in the session: computed on the first frame after it is
//! switched on and on every frame in which the drug moves relative to the
//! receptor, never on a frame in which nothing (or only the camera) moved;
//! its RMSD measures the move from the crystal pose.

mod common;

use bump::model::{self, LigandSpec, LoadOptions};
use bump::session::{Command, FrameInput, Mode, Motion6, Session, Settings};
use glam::DVec3;

fn dhfr_trimethoprim() -> Option<Session> {
    let dir = common::shared_pdb()?;
    let loaded =
        model::load(&dir.join("6xg5_tmp_prepared.pdb"), &LoadOptions::default()).expect("6xg5");
    let spec = LigandSpec::parse("TOP").expect("spec");
    let (r, d) = model::split_complex(&loaded.structure, &spec).expect("split");
    Some(Session::new(vec![r, d], Settings::default()).expect("session"))
}

fn moved(translate: DVec3) -> FrameInput {
    FrameInput {
        commands: vec![Command::MoveBy {
            translate,
            axis: DVec3::Z,
            degrees: 0.0,
        }],
        ..FrameInput::default()
    }
}

#[test]
fn scored_only_when_the_drug_moves() {
    let Some(mut s) = dhfr_trimethoprim() else {
        return;
    };
    assert!(
        s.step(&FrameInput::default(), 0.01).score.is_none(),
        "off by default"
    );
    s.enable_score();
    let first = s
        .step(&FrameInput::default(), 0.01)
        .score
        .expect("first frame scores");
    assert_eq!((first.drug, first.receptor), (1, 0));
    // Trimethoprim in its crystal pose binds: a clearly negative score,
    // with hydrogen bonds and its rotatable bonds counted.
    assert!(first.score.total < -5.0, "{}", first.score.total);
    assert!(!first.score.hbonds.is_empty());
    assert!(first.rotatable >= 4, "{}", first.rotatable);
    assert_eq!(first.rmsd, 0.0);
    assert!(!first.receptor_atoms.is_empty());
    assert!(first.receptor_atoms.windows(2).all(|w| w[0].0 < w[1].0));
    // Nothing moved: nothing computed.
    assert!(s.step(&FrameInput::default(), 0.01).score.is_none());
    // The camera moved: the drug did not move relative to the receptor.
    let view = FrameInput {
        view_nudge: Motion6 {
            translate: DVec3::new(1.0, 0.0, 0.0),
            rotate: DVec3::new(0.0, 0.3, 0.0),
        },
        ..FrameInput::default()
    };
    let out = s.step(&view, 0.01);
    assert!(out.changed && out.score.is_none());
    // The drug moved 1 Å: scored, 1 Å from the crystal pose, and worse.
    let s1 = s
        .step(&moved(DVec3::new(1.0, 0.0, 0.0)), 0.01)
        .score
        .expect("moved");
    assert!((s1.rmsd - 1.0).abs() < 1e-9, "{}", s1.rmsd);
    assert!(s1.score.total > first.score.total);
    assert_eq!(s.live_score().map(|l| l.rmsd), Some(s1.rmsd));
    // Back: the same score, bit for bit.
    let s2 = s
        .step(&moved(DVec3::new(-1.0, 0.0, 0.0)), 0.01)
        .score
        .expect("back");
    assert!(s2.rmsd < 1e-9);
    assert!((s2.score.total - first.score.total).abs() < 1e-9);
    // Pinning the current pose makes it the reference.
    s.step(&moved(DVec3::new(0.0, 2.0, 0.0)), 0.01);
    assert!(s.pin_reference());
    let pinned = s
        .step(&FrameInput::default(), 0.01)
        .score
        .expect("pinned rescored");
    assert!(pinned.pinned && pinned.rmsd < 1e-9);
    let _ = Mode::Object;
}

/// Benzamidine turned over about its long axis in trypsin's pocket lands
/// each atom on one of its own kind: the RMSD, which allows for the swap,
/// stays near 0; a quarter turn does not.
#[test]
fn the_rmsd_counts_benzamidine_turned_over_as_the_crystal_pose() {
    let Some(dir) = common::shared_pdb() else {
        return;
    };
    let loaded = model::load(&dir.join("3ptb.pdb"), &LoadOptions::default()).expect("3ptb");
    let spec = LigandSpec::parse("BEN").expect("spec");
    let (r, d) = model::split_complex(&loaded.structure, &spec).expect("split");
    let mut s = Session::new(vec![r, d], Settings::default()).expect("session");
    s.enable_score();
    s.step(&FrameInput::default(), 0.01);
    let ben = &s.bodies()[1];
    let at = |name: &str| {
        let i = ben
            .molecule
            .atoms
            .iter()
            .position(|a| a.name.trim() == name)
            .unwrap_or_else(|| panic!("no atom {name}"));
        ben.pose.transform_point(ben.molecule.local[i].as_dvec3())
    };
    // The long axis: from the ring's para carbon (C4) through the ring
    // carbon that carries the amidine (C1) to the amidine carbon (C).
    let axis = at("C") - at("C4");
    let turn = |degrees: f64| FrameInput {
        commands: vec![Command::MoveBy {
            translate: DVec3::ZERO,
            axis,
            degrees,
        }],
        ..FrameInput::default()
    };
    let over = s.step(&turn(180.0), 0.01).score.expect("turned over");
    assert!(over.rmsd < 0.3, "{}", over.rmsd);
    s.step(&turn(-180.0), 0.01);
    let quarter = s.step(&turn(90.0), 0.01).score.expect("a quarter turn");
    assert!(quarter.rmsd > 1.0, "{}", quarter.rmsd);
}
