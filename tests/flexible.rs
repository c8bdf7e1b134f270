//! Flexible torsions and settle in the session, against brute force on
//! every shared ligand: random torsion turns of any size (up to ±180°)
//! never end, or pass through, an overlap with the receptor or within the
//! drug (pairs more than three bonds apart), checked at the end of every
//! accepted turn and at 64 points along it; undo and reset restore the
//! file's conformation bit for bit; settle in the session never ends
//! colliding; a recorded session with soft contacts, torsion turns and
//! settle replays bit for bit. `torsion_step_timing` (ignored; run with
//! `--release -- --ignored --nocapture`) times a torsion step on TMP/DHFR.

// A test that fails on an unexpected error may just unwrap.
#![allow(clippy::unwrap_used)]

mod score_support;

use std::path::Path;

use bump::chem::torsions::pairs_beyond_three_bonds;
use bump::collide::torsion::Turn;
use bump::collide::{ContactRule, Response};
use bump::model::{LigandSpec, LoadOptions, Molecule, split_complex};
use bump::motion::Pose;
use bump::rng::Rng;
use bump::session::log::{frame_line, to_text};
use bump::session::{Command, FrameInput, LogFrame, Session, SessionLog, Settings, replay};
use glam::{DVec3, Vec3};
use score_support::{COMPLEXES, load_complex, shared_pdb};

/// The shared ligands of the Vina reference (the drug-like ones; NAP is a
/// cofactor but flexible too).
const LIGANDS: &[&str] = &[
    "6xg5_TOP", "3ptb_BEN", "1s3v_TQD", "4dfr_MTX", "1u72_MTX", "3nzd_D2Q", "1hvr_XK2", "1rx1_NAP",
];

/// The shared files' other ligands and cofactors: id, file and residue
/// (the receptor is the rest of the file). Heme's iron is bonded to none
/// of its atoms; 3nzd's NADPH has two atoms 2.3 Å apart in the file.
const MORE: &[(&str, &str, &str)] = &[
    ("1bdg_GLC", "1bdg_stripped.pdb", "GLC"),
    ("4kya_1UG", "4kya.pdb.gz", "1UG:A"),
    ("1dt6_HEM", "1dt6.pdb", "HEM"),
    ("1u72_NDP", "1u72.pdb", "NDP:A"),
    ("3nzd_NDP", "3nzd.cif", "NDP:A"),
];

/// Receptor and drug of `id`, from [`LIGANDS`] or [`MORE`].
fn load(dir: &Path, id: &str) -> (Molecule, Molecule) {
    let Some(&(_, file, residue)) = MORE.iter().find(|m| m.0 == id) else {
        assert!(COMPLEXES.iter().any(|c| c.0 == id), "{id}");
        return load_complex(dir, id);
    };
    let s = bump::model::load(&dir.join(file), &LoadOptions::default())
        .unwrap()
        .structure;
    split_complex(&s, &LigandSpec::parse(residue).unwrap()).unwrap()
}

/// A session of receptor and drug at the crystal pose, docking, with `response`.
fn docking(dir: &Path, id: &str, response: Response) -> Session {
    let (receptor, drug) = load(dir, id);
    let mut s = Session::new(vec![receptor, drug], Settings::default()).unwrap();
    s.step(&FrameInput::docking(), 0.0);
    s.step(
        &FrameInput::with_commands(&[Command::SetResponse(response)]),
        0.0,
    );
    s
}

/// Brute force: world positions of molecule `b`.
fn world(s: &Session, b: usize, pose: &Pose, local: &[Vec3]) -> Vec<DVec3> {
    let _ = b;
    let _ = s;
    local
        .iter()
        .map(|p| pose.transform_point(p.as_dvec3()))
        .collect()
}

/// The brute-force checker of one drug against its receptor.
struct Judge {
    rule: ContactRule,
    receptor: Vec<(DVec3, f32, bool)>,
    drug: Molecule,
    inner: Vec<(u32, u32, f64)>,
}

/// An overlap: (kind, atoms, distance, contact).
type Overlap = (&'static str, u32, u32, f64, f64);

impl Judge {
    fn new(s: &Session) -> Self {
        let rule = s.settings().rule;
        let r = &s.bodies()[0];
        let receptor = r
            .molecule
            .local
            .iter()
            .zip(&r.molecule.atoms)
            .map(|(p, a)| (r.pose.transform_point(p.as_dvec3()), a.radius, a.polar))
            .collect();
        let drug = s.bodies()[1].molecule.clone();
        let chem = drug.chemistry();
        let inner = pairs_beyond_three_bonds(&chem.adjacency)
            .into_iter()
            .map(|(i, j)| {
                let (a, b) = (&drug.atoms[i as usize], &drug.atoms[j as usize]);
                (
                    i,
                    j,
                    f64::from(rule.contact_distance(a.radius, a.polar, b.radius, b.polar)),
                )
            })
            .collect();
        Self {
            rule,
            receptor,
            drug,
            inner,
        }
    }

    /// Every overlapping pair at drug world positions `x`, under the rule
    /// loosened by `soft` Å (receptor pairs and the drug's own alike).
    fn overlaps(&self, x: &[DVec3], soft: f64) -> Vec<Overlap> {
        let mut out = Vec::new();
        let centre = x.iter().copied().sum::<DVec3>() / x.len() as f64;
        let reach = x.iter().map(|p| (*p - centre).length()).fold(0.0, f64::max) + 8.0;
        for (j, &(q, rq, pq)) in self.receptor.iter().enumerate() {
            if (q - centre).length() > reach {
                continue;
            }
            for (i, p) in x.iter().enumerate() {
                let a = &self.drug.atoms[i];
                let c = f64::from(self.rule.contact_distance(a.radius, a.polar, rq, pq)) - soft;
                let d = (*p - q).length();
                if c >= 0.0 && d <= c {
                    out.push(("receptor", i as u32, j as u32, d, c));
                }
            }
        }
        for &(i, j, c) in &self.inner {
            let c = c - soft;
            let d = (x[i as usize] - x[j as usize]).length();
            if c >= 0.0 && d <= c {
                out.push(("drug", i, j, d, c));
            }
        }
        out
    }
}

/// Overlaps at `after` that are new, or deeper than at `before`.
fn worse(after: &[Overlap], before: &[Overlap]) -> Vec<Overlap> {
    after
        .iter()
        .filter(|o| {
            !before
                .iter()
                .any(|b| (b.0, b.1, b.2) == (o.0, o.1, o.2) && o.3 >= b.3 - 1e-4)
        })
        .copied()
        .collect()
}

fn wrap(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let y = x.rem_euclid(TAU);
    if y > PI { y - TAU } else { y }
}

/// Random turns of random bonds of every shared ligand in its pocket,
/// each checked by brute force at its end and along its path.
fn random_turns(response: Response, steps: usize, seed: u64) {
    let Some(dir) = shared_pdb() else {
        return;
    };
    let mut report = Vec::new();
    let mut total_pressed = 0;
    for id in LIGANDS.iter().copied().chain(MORE.iter().map(|m| m.0)) {
        let mut s = docking(&dir, id, response);
        let judge = Judge::new(&s);
        let soft = if response == Response::Soft {
            s.settings().soft_limit
        } else {
            0.0
        };
        let n = s.rotatable_bonds(1).len();
        if n == 0 {
            report.push(format!("{id}: no rotatable bond"));
            continue;
        }
        let file_local = s.bodies()[1].molecule.local.clone();
        // Brute force: a turn changes the distance of two atoms when it
        // moves one and not the other and neither lies on its axis.
        let bonds = s.rotatable_bonds(1).to_vec();
        let movable = |i: u32, j: u32| {
            bonds.iter().any(|b| {
                let moves = |a: u32| b.moving.binary_search(&a).is_ok();
                moves(i) != moves(j) && !b.atoms.contains(&i) && !b.atoms.contains(&j)
            })
        };
        let file_h = s.bodies()[1].molecule.hydrogens.local.clone();
        let loaded = s.bodies()[1].pose;
        let mut rng = Rng(seed);
        let (mut turned, mut blocked) = (0, 0);
        let mut undo = 0;
        let mut pressed = 0;
        for step in 0..steps {
            let k = (rng.f64() * n as f64) as usize % n;
            let degrees = rng.range(-180.0, 180.0);
            let before_pose = s.bodies()[1].pose;
            let before_t = s.torsion_angles(1).to_vec();
            let before_x = world(&s, 1, &before_pose, &s.bodies()[1].molecule.local);
            let before_o = judge.overlaps(&before_x, soft);
            let out = s.step(
                &FrameInput::with_commands(&[
                    Command::SelectTorsion(Some(k)),
                    Command::TurnTorsion { degrees },
                ]),
                0.0,
            );
            let after_pose = s.bodies()[1].pose;
            let after_t = s.torsion_angles(1).to_vec();
            if after_t == before_t {
                blocked += 1;
                assert_eq!(
                    after_pose, before_pose,
                    "{id} step {step}: moved without turning"
                );
                continue;
            }
            turned += 1;
            undo += 1;
            if out.t < 1.0 {
                blocked += 1;
            }
            // Only bond k turned, by at most what was asked.
            for (j, (a, b)) in before_t.iter().zip(&after_t).enumerate() {
                if j != k {
                    assert_eq!(a, b, "{id} step {step}: bond {j} turned too");
                }
            }
            let delta = wrap(after_t[k] - before_t[k]);
            assert!(
                delta.abs() <= degrees.to_radians().abs() + 1e-9 && delta * degrees >= 0.0,
                "{id} step {step}: turned {delta} rad for {degrees}°"
            );
            let after_x = world(&s, 1, &after_pose, &s.bodies()[1].molecule.local);
            let bad = worse(&judge.overlaps(&after_x, soft), &before_o);
            assert!(
                bad.is_empty(),
                "{id} step {step} ({degrees:.1}° of bond {k}): {bad:?}"
            );
            // Pressed into the band within the drug (only `soft` may).
            let inside = |x: &[DVec3]| -> Vec<Overlap> {
                let all = judge.overlaps(x, 0.0);
                all.into_iter().filter(|o| o.0 == "drug").collect()
            };
            let (now_inside, was_inside) = (inside(&after_x), inside(&before_x));
            if !worse(&now_inside, &was_inside).is_empty() {
                assert_eq!(response, Response::Soft, "{id} step {step}: {now_inside:?}");
                pressed += 1;
                total_pressed += 1;
            }
            // Every such pair whose distance some turn changes (not two
            // atoms a rigid piece holds, as the file has them), and no
            // other, is listed as a contact of the drug with itself.
            let mut got: Vec<(u32, u32)> = s
                .contacts()
                .iter()
                .filter(|c| c.moving.0 == 1 && c.other.0 == 1)
                .map(|c| {
                    let (i, j) = (c.moving.1 as u32, c.other.1 as u32);
                    (i.min(j), i.max(j))
                })
                .collect();
            let mut want: Vec<(u32, u32)> = now_inside
                .iter()
                .filter(|o| movable(o.1, o.2))
                .map(|o| (o.1.min(o.2), o.1.max(o.2)))
                .collect();
            want.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, want, "{id} step {step}: the drug's own pressed pairs");
            // Along the path: the moving side turns about the bond.
            let bond = &s.rotatable_bonds(1)[k];
            let before_local = s.shape_at(1, &before_t).unwrap().0;
            let origin = before_local[bond.atoms[0] as usize].as_dvec3();
            let axis = (before_local[bond.atoms[1] as usize].as_dvec3() - origin).normalize();
            let sign = if bond.child_moves { 1.0 } else { -1.0 };
            for f in 1..64 {
                let frac = f as f64 / 64.0;
                let mut t = before_t.clone();
                t[k] += delta * frac;
                let local = s.shape_at(1, &t).unwrap().0;
                let pose = if bond.child_moves {
                    before_pose
                } else {
                    before_pose.compose(
                        &Turn {
                            origin,
                            axis,
                            angle: -delta * frac,
                        }
                        .at(1.0),
                    )
                };
                let x = world(&s, 1, &pose, &local);
                let bad = worse(&judge.overlaps(&x, soft), &before_o);
                assert!(
                    bad.is_empty(),
                    "{id} step {step}: passes through at {frac} of the turn: {bad:?}"
                );
                // The fixed side stays where it was in the world.
                let moving: std::collections::HashSet<u32> = bond.moving.iter().copied().collect();
                for (i, (p, q)) in x.iter().zip(&before_x).enumerate() {
                    if !moving.contains(&(i as u32)) {
                        assert!((*p - *q).length() < 1e-4, "{id}: fixed atom {i} moved");
                    }
                }
                let _ = sign;
            }
        }
        report.push(format!(
            "{id}: {n} bonds, {turned} turns made ({blocked} stopped short or refused, {pressed} pressed the drug's own atoms into the band)"
        ));
        assert!(turned > 0, "{id}: no turn was ever allowed");
        // Undo every turn: back at the file's conformation and pose, bit for bit.
        for _ in 0..undo {
            s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
        }
        let d = &s.bodies()[1];
        assert_eq!(d.pose, loaded, "{id}: undo did not restore the pose");
        assert_eq!(
            d.molecule.local, file_local,
            "{id}: undo did not restore the shape"
        );
        assert_eq!(d.molecule.hydrogens.local, file_h);
        assert!(s.torsion_angles(1).iter().all(|&t| t == 0.0));
        // Redo them all, then Home: the file again.
        for _ in 0..undo {
            s.step(&FrameInput::with_commands(&[Command::Redo]), 0.0);
        }
        s.step(&FrameInput::with_commands(&[Command::ResetMolecule]), 0.0);
        let d = &s.bodies()[1];
        assert_eq!(d.pose, loaded, "{id}: Home did not restore the pose");
        assert_eq!(
            d.molecule.local, file_local,
            "{id}: Home did not restore the shape"
        );
        assert!(s.unsaved().is_empty() || s.unsaved() == [1]);
    }
    eprintln!("{}", report.join("\n"));
    if response == Response::Soft {
        assert!(
            total_pressed > 0,
            "no turn pressed the drug's own atoms into the soft band"
        );
    }
}

#[test]
fn random_torsion_turns_never_overlap_or_pass_through_with_touch() {
    random_turns(
        Response::Touch,
        if cfg!(debug_assertions) { 12 } else { 60 },
        44,
    );
}

#[test]
fn random_torsion_turns_never_pass_the_soft_limit() {
    random_turns(
        Response::Soft,
        if cfg!(debug_assertions) { 8 } else { 40 },
        45,
    );
}

#[test]
fn settle_in_the_session_never_ends_colliding_and_undoes() {
    let Some(dir) = shared_pdb() else {
        return;
    };
    let mut settled = 0;
    for &id in &["6xg5_TOP", "3ptb_BEN", "1s3v_TQD"] {
        let mut s = docking(&dir, id, Response::Touch);
        let judge = Judge::new(&s);
        // Somewhere off the crystal pose: a push, a few turns.
        let mut rng = Rng(7);
        s.step(
            &FrameInput::with_commands(&[Command::MoveBy {
                translate: rng.unit() * 1.0,
                axis: rng.unit(),
                degrees: 15.0,
            }]),
            0.0,
        );
        for k in 0..s.rotatable_bonds(1).len().min(3) {
            s.step(
                &FrameInput::with_commands(&[
                    Command::SelectTorsion(Some(k)),
                    Command::TurnTorsion { degrees: 40.0 },
                ]),
                0.0,
            );
        }
        let before_pose = s.bodies()[1].pose;
        let before_local = s.bodies()[1].molecule.local.clone();
        let out = s.step(&FrameInput::with_commands(&[Command::Settle]), 0.0);
        let Some(path) = out.settled.clone() else {
            // Settle found no step: nothing changed.
            assert_eq!(s.bodies()[1].pose, before_pose, "{id}: {:?}", out.messages);
            assert_eq!(s.bodies()[1].molecule.local, before_local);
            eprintln!("{id}: {:?}", out.messages);
            continue;
        };
        settled += 1;
        let d = &s.bodies()[1];
        assert_eq!(path.to, d.pose);
        assert_eq!(path.to_torsions, s.torsion_angles(1));
        let x = world(&s, 1, &d.pose, &d.molecule.local);
        let o = judge.overlaps(&x, 0.0);
        assert!(o.is_empty(), "{id}: settle ends colliding: {o:?}");
        eprintln!(
            "{id}: settle inter {:.2} -> {:.2} kcal/mol, {:.2} Å, {} steps",
            path.inter.0, path.inter.1, path.rmsd, path.steps
        );
        // One undo takes it all back.
        s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
        assert_eq!(s.bodies()[1].pose, before_pose);
        assert_eq!(s.bodies()[1].molecule.local, before_local);
    }
    assert!(settled >= 2, "settle moved only {settled} of 3 drugs");
}

#[test]
fn a_session_with_soft_contacts_torsions_and_settle_replays_bit_for_bit() {
    let Some(dir) = shared_pdb() else {
        return;
    };
    let id = "6xg5_TOP";
    let frames = {
        let mut f = vec![
            FrameInput::docking(),
            FrameInput::with_commands(&[Command::SetResponse(Response::Soft)]),
        ];
        // Push the drug into the pocket wall, soft.
        let mut rng = Rng(3);
        let push = rng.unit();
        for _ in 0..20 {
            f.push(FrameInput::nudged(push * 0.3, DVec3::ZERO));
        }
        f.push(FrameInput::with_commands(&[Command::NextTorsion]));
        for k in 0..30 {
            f.push(FrameInput {
                torsion_velocity: 120.0,
                nudge: bump::session::Motion6 {
                    translate: push * 0.05,
                    rotate: DVec3::new(0.0, 0.01 * k as f64, 0.0),
                },
                ..FrameInput::default()
            });
        }
        f.push(FrameInput::with_commands(&[
            Command::NextTorsion,
            Command::TurnTorsion { degrees: -75.0 },
            Command::SelectTorsionNear(3),
        ]));
        f.push(FrameInput {
            torsion_nudge: 33.0,
            ..FrameInput::default()
        });
        f.push(FrameInput::with_commands(&[Command::Settle]));
        f.push(FrameInput::with_commands(&[Command::Undo, Command::Redo]));
        f
    };
    let log = SessionLog {
        meta: vec![("complex".into(), id.into())],
        frames: frames
            .into_iter()
            .map(|input| LogFrame {
                dt: 1.0 / 60.0,
                input,
            })
            .collect(),
        finals: Vec::new(),
    };
    // Through the text format and back.
    let text = to_text(&log);
    assert!(text.contains(" tv=") && text.contains("c=settle"));
    let read = SessionLog::parse(&text, Path::new("flexible.log")).unwrap();
    assert_eq!(read, log);
    let _ = frame_line;
    let run = |log: &SessionLog| {
        let (receptor, drug) = load_complex(&dir, id);
        let mut s = Session::new(vec![receptor, drug], Settings::default()).unwrap();
        let mut settled = 0;
        let mut turned = 0;
        let mut soft_pressed = false;
        let mut frames = Vec::new();
        replay(&mut s, log, |_, out| {
            frames.push((out.t, out.contacts.len(), out.reshaped.clone()));
            settled += usize::from(out.settled.is_some());
            turned += usize::from(!out.reshaped.is_empty());
            soft_pressed |= out.resistance > 0.0;
        });
        (
            s.bodies()[1].pose,
            s.bodies()[1].molecule.local.clone(),
            s.torsion_angles(1).to_vec(),
            settled,
            turned,
            soft_pressed,
            frames,
        )
    };
    let a = run(&log);
    let b = run(&read);
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    assert_eq!(a.6, b.6, "every frame's outcome is the same");
    assert_eq!(a.3, 1, "settle ran once");
    assert!(a.4 > 5, "the torsions turned in {} frames", a.4);
    assert!(a.2.iter().any(|&t| t != 0.0));
    assert!(a.5, "the soft response pressed into the receptor");
}

/// Median and p99 of a torsion step (a turn of up to 5° of a random bond
/// through `touch`) for TMP in DHFR (6xg5), µs.
#[test]
#[ignore = "a timing: run in release with --ignored --nocapture"]
fn torsion_step_timing() {
    let Some(dir) = shared_pdb() else {
        return;
    };
    for response in [Response::Touch, Response::Soft] {
        let mut s = docking(&dir, "6xg5_TOP", response);
        s.prepare_response();
        let n = s.rotatable_bonds(1).len();
        let mut rng = Rng(11);
        let mut times = Vec::new();
        for i in 0..4000 {
            let input = FrameInput::with_commands(&[
                Command::SelectTorsion(Some(i % n)),
                Command::TurnTorsion {
                    degrees: rng.range(-5.0, 5.0),
                },
            ]);
            let t0 = std::time::Instant::now();
            s.step(&input, 1.0 / 60.0);
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            if i % 200 == 199 {
                s.step(&FrameInput::with_commands(&[Command::ResetMolecule]), 0.0);
            }
        }
        times.sort_by(f64::total_cmp);
        let q = |f: f64| times[((times.len() - 1) as f64 * f) as usize];
        eprintln!(
            "torsion step, {} on 6xg5/TOP ({n} bonds): median {:.1} µs, p99 {:.1} µs, max {:.1} µs",
            response.name(),
            q(0.5),
            q(0.99),
            q(1.0)
        );
    }
}

#[test]
fn saving_writes_the_current_conformation() {
    let Some(dir) = shared_pdb() else {
        return;
    };
    let (receptor, drug) = load_complex(&dir, "1s3v_TQD");
    let mut s = Session::new(vec![receptor, drug], Settings::default()).unwrap();
    s.step(
        &FrameInput::with_commands(&[
            Command::SelectTorsion(Some(0)),
            Command::TurnTorsion { degrees: 90.0 },
            Command::NextTorsion,
            Command::TurnTorsion { degrees: -120.0 },
        ]),
        0.0,
    );
    assert!(s.torsion_angles(1).iter().any(|&t| t != 0.0));
    assert_eq!(s.unsaved(), [1]);
    // What Ctrl+S writes: the drug in the receptor's frame.
    let pose = s.pose_in_frame_of(1, 0).unwrap();
    let mol = &s.bodies()[1].molecule;
    let path = std::env::temp_dir().join(format!("bump-flexible-{}.sdf", std::process::id()));
    bump::model::write::write_sdf(mol, &pose, &path).unwrap();
    let back = bump::model::load(&path, &bump::model::LoadOptions::default()).unwrap();
    let back = bump::model::receptor_only(&back.structure).unwrap();
    let _ = std::fs::remove_file(&path);
    assert_eq!(back.len(), mol.len());
    let want: Vec<DVec3> = mol
        .local
        .iter()
        .map(|p| pose.transform_point(p.as_dvec3()))
        .collect();
    let file = s
        .shape_at(1, &vec![0.0; s.torsion_angles(1).len()])
        .unwrap()
        .0;
    let mut differs = 0;
    for (i, p) in back.file_positions().iter().enumerate() {
        assert!(
            (*p - want[i]).length() < 1e-3,
            "atom {i} saved at {p}, is at {}",
            want[i]
        );
        differs += usize::from((file[i] - mol.local[i]).length() > 0.1);
    }
    assert!(differs > 0, "the saved conformation is the file's");
    s.mark_saved(1);
    assert!(s.unsaved().is_empty());
}

#[test]
fn torsions_set_directly_are_checked_and_home_undoes_them() {
    use bump::session::TorsionError;
    let Some(dir) = shared_pdb() else {
        return;
    };
    let (receptor, drug) = load_complex(&dir, "6xg5_TOP");
    let mut s = Session::new(vec![receptor, drug], Settings::default()).unwrap();
    let n = s.rotatable_bonds(1).len();
    assert!(s.rotatable_bonds(0).is_empty(), "the receptor is rigid");
    assert_eq!(
        s.set_torsions(1, &[0.1]),
        Err(TorsionError::Count { got: 1, bonds: n })
    );
    assert!(matches!(
        s.set_torsions(1, &vec![f64::NAN; n]),
        Err(TorsionError::NotFinite(_))
    ));
    assert_eq!(s.set_torsions(0, &[]), Err(TorsionError::NotFlexible(0)));
    let file = s.bodies()[1].molecule.local.clone();
    let angles: Vec<f64> = (0..n).map(|k| 0.3 * (k as f64 + 1.0)).collect();
    s.set_torsions(1, &angles).unwrap();
    assert_eq!(s.torsion_angles(1), angles);
    assert_ne!(s.bodies()[1].molecule.local, file);
    assert_eq!(s.history().undo_len(), 0, "not an undoable move");
    s.step(&FrameInput::with_commands(&[Command::ResetMolecule]), 0.0);
    assert_eq!(s.bodies()[1].molecule.local, file);
    s.step(&FrameInput::with_commands(&[Command::Undo]), 0.0);
    assert_eq!(s.torsion_angles(1), angles);
}
