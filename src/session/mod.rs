//! The docking session: the application's state machine, without devices,
//! pixels or sound.
//!
//! A session holds the molecules (one *body* each, with its world pose), the
//! camera, the mode (view or object), the selected molecule, the collision
//! settings and the undo history. [`Session::step`] takes one frame's
//! [`FrameInput`] and a time step and returns a [`FrameOutcome`]: whether
//! anything moved, the contacts, whether a new contact began (the beep), and
//! how long collision detection took. The window, the headless replay and the
//! tests all drive this same code.
//!
//! Collisions: only the selected molecule moves, so every other molecule is
//! its *environment*, indexed by one collider. A move of the selected
//! molecule is then one query of the two-body core
//! ([`crate::collide::respond`]), with any number of molecules loaded. When
//! the environment is one molecule (a receptor and a drug), its collider is
//! built in the molecule's own frame, once: it does not depend on where the
//! molecule is, so selecting another molecule and back, or moving this one,
//! rebuilds nothing: for a large receptor a merged copy of every atom, its
//! grid and its clearance map would cost a frame and then seconds of both
//! cores. A molecule's atoms set up to move are kept likewise. Two or more other
//! molecules are merged, at their current poses, into one collider,
//! rebuilt when the selection changes or one of them moves.

pub mod camera;
mod collisions;
mod commands;
pub mod framing;
pub mod history;
pub mod input;
pub mod keys;
pub mod labels;
pub mod log;
pub mod replay;
pub mod score;
pub mod steer;
pub mod timing;
pub mod torsion;

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use thiserror::Error;

pub use camera::Camera;
pub use history::History;
pub use input::{Command, FrameInput, Motion6};
pub use keys::{KeyEvent, KeySteps, Step, StepAxis, StepKey, StepSize};
pub use labels::Role;

use collisions::Environment;
pub use log::{LogError, LogFrame, LogWriter, SessionLog};
pub use replay::{Replayed, replay};
pub use score::LiveScore;
pub use timing::{Summary, Timing};
pub use torsion::{Reshaped, SettlePath, TorsionBond, TorsionError};

use crate::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, Response, TouchOptions,
};
use crate::model::Molecule;
use crate::motion::{Pose, Rock};

/// What the devices move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mode {
    /// Everything moves together (the camera moves).
    #[default]
    View,
    /// The selected molecule moves.
    Object,
}

/// Which axes a motion is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Space {
    /// Screen axes: x right, y up, z towards the viewer (the default).
    #[default]
    Screen,
    /// The moved molecule's own axes.
    Object,
}

/// Collision settings of a session.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Collision detection on (thesis key `c`); off at start as in the thesis.
    pub collision: bool,
    /// What happens when a move would collide.
    pub response: Response,
    /// Move-to-touch tolerance and method.
    pub touch: TouchOptions,
    /// The contact rule.
    pub rule: ContactRule,
    /// The spatial index.
    pub collider: ColliderKind,
    /// Screen or object space for motions.
    pub space: Space,
    /// How far beyond the contact rule `soft` lets a pair press, Å.
    pub soft_limit: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            collision: false,
            response: Response::Touch,
            touch: TouchOptions {
                tolerance: 1e-3,
                method: Method::Swept,
            },
            rule: ContactRule::default(),
            collider: ColliderKind::Hashed,
            space: Space::Screen,
            soft_limit: crate::collide::soft::DEFAULT_LIMIT,
        }
    }
}

/// A molecule in the session.
#[derive(Debug, Clone)]
pub struct Body {
    /// The molecule (coordinates relative to its centre).
    pub molecule: Molecule,
    /// Where it is now (world).
    pub pose: Pose,
    /// Where it was loaded.
    pub loaded: Pose,
}

/// A pair of atoms in contact, identified across molecules.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The moving molecule and its atom.
    pub moving: (usize, usize),
    /// The other molecule and its atom: another atom of the moving
    /// molecule itself for two of a drug's own atoms (more than three bonds
    /// apart) that a torsion turn under `soft` pressed into each other.
    pub other: (usize, usize),
    /// Centre distance, Å.
    pub distance: f32,
    /// Contact distance of the pair (collides at or below), Å.
    pub contact: f32,
}

impl Contact {
    /// `distance − contact`: ≤ 0 collides.
    pub fn gap(&self) -> f32 {
        self.distance - self.contact
    }

    /// How far the pair presses beyond the contact rule (the `soft`
    /// response's band), Å; 0 when it does not collide.
    pub fn depth(&self) -> f32 {
        (self.contact - self.distance).max(0.0)
    }
}

/// The highest highlight level: a pair pressed to the `soft` limit (or
/// beyond it, in a pose loaded that way).
pub const PRESS_LEVELS: u8 = 8;

/// The highlight level of a contact pressed `depth` Å past the contact
/// rule: 1 when it only touches or `limit` is not positive (not `soft`),
/// else 2 to [`PRESS_LEVELS`] in equal steps of the band up to `limit`.
pub fn press_level(depth: f32, limit: Option<f64>) -> u8 {
    let Some(limit) = limit.filter(|l| *l > 0.0) else {
        return 1;
    };
    if depth.is_nan() || depth <= 0.0 {
        return 1;
    }
    let steps = f64::from(PRESS_LEVELS - 1);
    let k = (f64::from(depth) / limit * steps).ceil().clamp(1.0, steps);
    1 + k as u8
}

/// What one frame did.
#[derive(Debug, Clone, Default)]
pub struct FrameOutcome {
    /// Something visible changed (a pose, the camera, a highlight, a setting).
    pub changed: bool,
    /// The selected molecule moved.
    pub moved: bool,
    /// Fraction of the requested molecule motion allowed (1 when free).
    pub t: f64,
    /// Contacts of the selected molecule at its new pose (collision on only).
    pub contacts: Vec<Contact>,
    /// A contact began that was not there the frame before (beep, flash).
    pub new_contact: bool,
    /// Atoms whose highlight changed: (molecule, atom, its level now; see
    /// [`Session::highlight_level`]).
    pub highlight_changes: Vec<(usize, usize, u8)>,
    /// The `soft` response's resistance at the new pose, in [0, 1) (0 for
    /// the other responses): what a controller's rumble follows.
    pub resistance: f64,
    /// Time spent in collision detection this frame, µs (None: no query).
    pub collision_us: Option<f64>,
    /// Each collision query of this frame, µs (the thesis's per-call timing).
    pub collision_calls: Vec<f64>,
    /// Messages for the status line.
    pub messages: Vec<String>,
    /// The user asked to quit.
    pub quit: bool,
    /// The live score, when it was computed this frame (the drug moved
    /// relative to the receptor; see [`score`]).
    pub score: Option<Arc<LiveScore>>,
    /// Molecules whose local positions changed this frame (torsions
    /// turned, undone, reset or settled), with the atoms that changed.
    pub reshaped: Vec<Reshaped>,
    /// A settle this frame ran, for the window to animate (the session is
    /// already at its end).
    pub settled: Option<Arc<SettlePath>>,
}

impl FrameOutcome {
    /// Books one collision query that began at `t0`.
    fn collision_timed(&mut self, t0: Instant) {
        let us = t0.elapsed().as_secs_f64() * 1e6;
        self.collision_calls.push(us);
        self.collision_us = Some(self.collision_us.unwrap_or(0.0) + us);
    }
}

/// A session that cannot start.
#[derive(Debug, Error, PartialEq)]
pub enum SessionError {
    /// No molecule was given.
    #[error("a session needs at least one molecule")]
    Empty,
}

/// A frame's time step, made safe: finite and within [0, 1] s.
fn dt_clamped(dt: f64) -> f64 {
    if dt.is_finite() {
        dt.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The docking session.
#[derive(Debug, Clone)]
pub struct Session {
    bodies: Vec<Body>,
    selected: usize,
    mode: Mode,
    settings: Settings,
    camera: Camera,
    home: Camera,
    history: History,
    env: Option<Environment>,
    /// Per molecule: its collider in its own frame, once built (see the
    /// module documentation); shared by clones of the session.
    own_colliders: Vec<Option<Arc<Collider>>>,
    /// Per molecule: its atoms set up to move (for the largest receptor
    /// radius they were set up against), once built.
    moving_atoms: Vec<Option<(f32, Arc<DrugAtoms>)>>,
    /// Per molecule, per atom: in contact now.
    /// Per molecule, each atom's highlight level ([`Session::highlight_level`]).
    highlighted: Vec<Vec<u8>>,
    contacts: Vec<Contact>,
    rock: Rock,
    /// The motion keys held and their clock.
    keys: KeySteps,
    /// Per molecule: what it is (read once, when it arrives).
    roles: Vec<Role>,
    /// Per molecule: its pose when it was loaded or last saved.
    saved: Vec<Pose>,
    /// The live score (off until [`Session::enable_score`]).
    live: score::LiveScoring,
    /// Per molecule: its conformation, when it is a flexible drug.
    flex: Vec<Option<torsion::Flex>>,
    /// The receptor's typed atoms for settle: (molecule, its shape
    /// generation, the atoms).
    typed_receptor: Option<(usize, u64, Arc<crate::score::Receptor>)>,
    /// The selected molecule's latest pose and torsions at which it
    /// overlapped nothing under the contact rule (neither the receptor nor
    /// its own atoms), as its contacts were last found (molecule, pose,
    /// torsions): where settle starts when it cannot free the drug from a
    /// pose pressed into the `soft` band.
    last_clear: Option<(usize, Pose, Vec<f64>)>,
}

impl Session {
    /// A session over `molecules` at their file poses. The last molecule is
    /// selected (the drug, when loaded as receptor then drug); the camera
    /// frames them all.
    ///
    /// # Errors
    /// [`SessionError::Empty`] when `molecules` is empty (use
    /// [`Session::empty`] for a session that waits for files).
    pub fn new(molecules: Vec<Molecule>, settings: Settings) -> Result<Self, SessionError> {
        if molecules.is_empty() {
            return Err(SessionError::Empty);
        }
        Ok(Self::with(molecules, settings))
    }

    /// A session with no molecule yet (files still loading): only the view,
    /// the settings and quitting respond until [`Session::add_molecule`].
    pub fn empty(settings: Settings) -> Self {
        Self::with(Vec::new(), settings)
    }

    fn with(molecules: Vec<Molecule>, settings: Settings) -> Self {
        let bodies: Vec<Body> = molecules
            .into_iter()
            .map(|m| {
                let pose = Pose::from_translation(m.centre);
                Body {
                    molecule: m,
                    pose,
                    loaded: pose,
                }
            })
            .collect();
        let (centre, radius) = framing::bounds(&bodies).unwrap_or((DVec3::ZERO, 1.0));
        let camera = Camera::framing(centre, radius);
        let highlighted = bodies.iter().map(|b| vec![0; b.molecule.len()]).collect();
        let selected = bodies.len().saturating_sub(1);
        let own_colliders = vec![None; bodies.len()];
        let moving_atoms = vec![None; bodies.len()];
        let roles = bodies.iter().map(|b| Role::of(&b.molecule)).collect();
        let saved = bodies.iter().map(|b| b.pose).collect();
        let flex = bodies
            .iter()
            .map(|b| torsion::Flex::of(&b.molecule))
            .collect();
        Self {
            bodies,
            selected,
            mode: Mode::View,
            settings,
            camera,
            home: camera,
            history: History::default(),
            env: None,
            own_colliders,
            moving_atoms,
            highlighted,
            contacts: Vec::new(),
            rock: Rock::default(),
            keys: KeySteps::default(),
            roles,
            saved,
            live: score::LiveScoring::default(),
            flex,
            typed_receptor: None,
            last_clear: None,
        }
    }

    /// Points the camera at all molecules where they are now, keeping its
    /// turn, and makes that the home view ([`Command::ResetView`]).
    pub fn frame_all(&mut self) {
        if let Some(c) = framing::fit_all(&self.bodies, self.camera.rotation) {
            self.camera = c;
            self.home = c;
        }
    }

    /// What molecule `b` is: a receptor (more than one residue), or a drug
    /// (one residue), except that in a scene of small molecules only, the
    /// largest is the receptor (the built-in scene's rings).
    pub fn role(&self, b: usize) -> Option<Role> {
        let own = *self.roles.get(b)?;
        let polymer = self.roles.contains(&Role::Receptor);
        if own == Role::Drug && !polymer && self.bodies.len() > 1 {
            let largest = (0..self.bodies.len())
                .max_by_key(|&k| (self.bodies[k].molecule.len(), std::cmp::Reverse(k)));
            if largest == Some(b) {
                return Some(Role::Receptor);
            }
        }
        Some(own)
    }

    /// Molecule `b` in a chemist's words, in its role in this scene:
    /// `drug: TOP X 201 (trimethoprim.sdf)`.
    pub fn describe(&self, b: usize) -> Option<String> {
        let role = self.role(b)?;
        Some(labels::describe(&self.bodies[b].molecule, role))
    }

    /// The drug the view centres on: the selected molecule when it is a
    /// drug, else the last drug loaded, else the selected molecule; `None`
    /// with no molecule.
    pub fn drug(&self) -> Option<usize> {
        if self.bodies.is_empty() {
            return None;
        }
        if self.role(self.selected) == Some(Role::Drug) {
            return Some(self.selected);
        }
        let last = (0..self.bodies.len())
            .rev()
            .find(|&k| self.roles[k] == Role::Drug);
        Some(last.unwrap_or(self.selected))
    }

    /// The molecules moved (or turned at a torsion) since they were loaded
    /// or last saved.
    pub fn unsaved(&self) -> Vec<usize> {
        let turned = |k: usize| {
            self.flex
                .get(k)
                .and_then(Option::as_ref)
                .is_some_and(|f| f.saved != f.torsions)
        };
        (0..self.bodies.len())
            .filter(|&k| self.saved.get(k) != Some(&self.bodies[k].pose) || turned(k))
            .collect()
    }

    /// Notes that molecule `b` was saved where it stands now, as it is now.
    pub fn mark_saved(&mut self, b: usize) {
        if let (Some(s), Some(body)) = (self.saved.get_mut(b), self.bodies.get(b)) {
            *s = body.pose;
        }
        if let Some(Some(f)) = self.flex.get_mut(b) {
            f.saved.clone_from(&f.torsions);
        }
    }

    /// Adds a molecule at its file pose (e.g. a file dropped on the window)
    /// and selects it.
    pub fn add_molecule(&mut self, molecule: Molecule) {
        let pose = Pose::from_translation(molecule.centre);
        self.highlighted.push(vec![0; molecule.len()]);
        self.roles.push(Role::of(&molecule));
        self.flex.push(torsion::Flex::of(&molecule));
        self.bodies.push(Body {
            molecule,
            pose,
            loaded: pose,
        });
        self.own_colliders.push(None);
        self.moving_atoms.push(None);
        self.saved.push(pose);
        self.live.reset();
        self.selected = self.bodies.len() - 1;
        self.env = None;
        self.history.close();
    }

    /// The molecules.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Index of the selected molecule.
    pub fn selected(&self) -> usize {
        self.selected
    }

    /// View or object mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The collision settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The camera, to change directly (framing options, mouse drags): a
    /// user move, so rocking pauses with its angle kept in the camera.
    pub fn camera_mut(&mut self) -> &mut Camera {
        self.pause_rocking();
        &mut self.camera
    }

    /// The camera as drawn: [`Session::camera`] turned by the rocking angle
    /// about the screen's vertical axis.
    pub fn view_camera(&self) -> Camera {
        let mut c = self.camera;
        let a = self.rock.angle();
        if a != 0.0 {
            c.rotation = (glam::DQuat::from_rotation_y(a) * c.rotation).normalize();
        }
        c
    }

    /// The motion keys held (the window keeps stepping while one is).
    pub fn keys(&self) -> &KeySteps {
        &self.keys
    }

    /// The rocking state.
    pub fn rock(&self) -> &Rock {
        &self.rock
    }

    /// Keeps the view where it is and pauses rocking (the user moves).
    fn pause_rocking(&mut self) {
        let a = self.rock.pause();
        self.bake_rock(a);
    }

    fn bake_rock(&mut self, angle: f64) {
        if angle != 0.0 {
            self.camera.move_scene(DVec3::ZERO, DVec3::Y * angle);
        }
    }

    /// Contacts of the selected molecule after the last frame.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// Whether atom `atom` of molecule `body` is highlighted as in contact.
    pub fn is_highlighted(&self, body: usize, atom: usize) -> bool {
        self.highlight_level(body, atom) > 0
    }

    /// The highlight level of atom `atom` of molecule `body`: 0 when it is
    /// in no contact, 1 when it touches (or presses, under a response other
    /// than `soft`), and under `soft` 2 to [`PRESS_LEVELS`] by how deep its
    /// deepest pair presses into the band, in equal steps up to the limit.
    pub fn highlight_level(&self, body: usize, atom: usize) -> u8 {
        self.highlighted
            .get(body)
            .and_then(|h| h.get(atom))
            .copied()
            .unwrap_or(0)
    }

    /// The undo history.
    pub fn history(&self) -> &History {
        &self.history
    }

    /// Advances one frame of `dt` seconds.
    ///
    /// In order: rocking, the commands, the motion keys' steps (each one
    /// step through the collision response, see [`keys`]), then the
    /// continuous motions and one-off nudges.
    pub fn step(&mut self, input: &FrameInput, dt: f64) -> FrameOutcome {
        let mut out = FrameOutcome {
            t: 1.0,
            ..FrameOutcome::default()
        };
        // Rocking pauses while the user moves anything, keeping the view.
        let user_moves = input.has_motion()
            || !input.keys.is_empty()
            || self.keys.any_held()
            || input.commands.iter().any(Command::moves_something);
        if user_moves && self.rock.is_on() {
            self.pause_rocking();
        }
        out.changed |= self.rock.advance(dt_clamped(dt));
        for c in &input.commands {
            self.command(*c, &mut out);
        }
        for s in self.keys.advance(&input.keys, dt) {
            self.key_step(&s, &mut out);
        }
        let dt = dt_clamped(dt);
        let motion = input.velocity.scaled(dt).plus(&input.nudge);
        let object_mode = self.mode == Mode::Object && !self.bodies.is_empty();
        let (mut view, mut object) = if object_mode {
            (Motion6::ZERO, motion)
        } else {
            (motion, Motion6::ZERO)
        };
        view = view
            .plus(&input.view_velocity.scaled(dt))
            .plus(&input.view_nudge);
        object = object
            .plus(&input.object_velocity.scaled(dt))
            .plus(&input.object_nudge);
        self.move_view(&view, input.zoom, &mut out);
        let turn = input.torsion_velocity * dt + input.torsion_nudge;
        let turning = turn != 0.0 && !self.bodies.is_empty();
        if self.bodies.is_empty() {
            // Nothing to move but the view.
        } else if !object.is_finite() {
            out.messages.push("ignored a non-finite motion".into());
        } else if object.is_zero() {
            // A held key's repeats are one gesture, and so is a turn
            // held: undo takes them back together.
            if !self.keys.any_held() && !turning {
                self.history.close();
            }
        } else {
            let (translate, axis, angle) = self.to_world(&object);
            self.move_selected(translate, axis, angle, &mut out);
        }
        if turning {
            self.turn_torsion(turn.to_radians(), &mut out);
        }
        self.update_score(&mut out);
        out
    }

    /// With collision on, builds what the next frames' response needs now
    /// (the selected molecule's environment, and for `soft` its loosened
    /// index) and waits for their colliders' clearance maps, so that no
    /// frame of a run pays for them: for steering runs and benchmarks.
    pub fn prepare_response(&mut self) {
        if !self.settings.collision {
            return;
        }
        if self.settings.response == crate::collide::Response::Soft
            && let Some(soft) = self.soft_index()
        {
            soft.collider.wait_for_clearance();
        }
        self.wait_for_collider();
    }

    /// Scores the drug if it moved relative to the receptor this frame.
    fn update_score(&mut self, out: &mut FrameOutcome) {
        if !self.live.is_on() {
            return;
        }
        let drug = self.drug();
        let roles: Vec<Option<Role>> = (0..self.bodies.len()).map(|k| self.role(k)).collect();
        out.score = self.live.update(
            out.changed,
            &self.bodies,
            &self.flex,
            drug,
            |k| roles.get(k).copied().flatten(),
            &mut out.messages,
        );
    }

    /// Switches the live score on: from the next frame on, every frame in
    /// which the drug moves relative to the receptor is scored
    /// ([`FrameOutcome::score`]).
    pub fn enable_score(&mut self) {
        self.live.enable();
    }

    /// The last live score, if any.
    pub fn live_score(&self) -> Option<&Arc<LiveScore>> {
        self.live.last()
    }

    /// Pins the drug's current pose (relative to the receptor) as the
    /// reference for the RMSD and the ghost; `false` when there is no live
    /// score yet. The next frame scores again.
    pub fn pin_reference(&mut self) -> bool {
        self.live.pin(&self.bodies, &self.flex)
    }

    /// The reference pose: (drug, receptor, the drug's pose relative to the
    /// receptor), once the live score has prepared the pair.
    pub fn reference_pose(&self) -> Option<(usize, usize, Pose)> {
        self.live.reference(&self.bodies)
    }

    /// Molecule `d`'s torsions at the reference: the pinned ones when `d`
    /// is the drug pinned, else the file's (all zero). Empty when `d` is not
    /// a flexible drug.
    pub fn reference_torsions(&self, d: usize) -> Vec<f64> {
        let n = self.torsion_angles(d).len();
        match self.live.pinned_torsions(d) {
            Some(t) if t.len() == n => t.to_vec(),
            _ => vec![0.0; n],
        }
    }

    /// One motion key's step: the view, or the selected molecule in object
    /// mode (through the collision response); a press starts a new undo
    /// entry.
    fn key_step(&mut self, s: &Step, out: &mut FrameOutcome) {
        let m = s.motion();
        if self.mode == Mode::Object && !self.bodies.is_empty() {
            if s.first {
                self.history.close();
            }
            let (translate, axis, angle) = self.to_world(&m);
            self.move_selected(translate, axis, angle, out);
        } else {
            self.move_view(&m, 0.0, out);
        }
    }

    /// Moves the camera by `view` (screen axes) and zooms by `zoom` steps.
    fn move_view(&mut self, view: &Motion6, zoom: f64, out: &mut FrameOutcome) {
        if !view.is_finite() || !zoom.is_finite() {
            out.messages.push("ignored a non-finite view motion".into());
            return;
        }
        if !view.is_zero() {
            self.camera.move_scene(view.translate, view.rotate);
            out.changed = true;
        }
        if zoom != 0.0 {
            self.camera.zoom(zoom);
            out.changed = true;
        }
    }

    /// A motion in screen or object axes as a world translation and turn.
    fn to_world(&self, m: &Motion6) -> (DVec3, DVec3, f64) {
        let frame = match self.settings.space {
            Space::Screen => self.camera.rotation.conjugate(),
            Space::Object => self.bodies[self.selected].pose.rotation,
        };
        let translate = frame * m.translate;
        let angle = m.rotate.length();
        let axis = if angle > 0.0 {
            frame * (m.rotate / angle)
        } else {
            DVec3::X
        };
        (translate, axis, angle)
    }

    /// The world pose of molecule `b` expressed in molecule `frame`'s file
    /// coordinates (e.g. the drug in the receptor's frame, for saving).
    pub fn pose_in_frame_of(&self, b: usize, frame: usize) -> Option<Pose> {
        let body = self.bodies.get(b)?;
        let reference = self.bodies.get(frame)?;
        // file coords of `frame` = loaded ∘ pose⁻¹ applied to world points.
        let world_to_file = reference.loaded.compose(&reference.pose.inverse());
        Some(world_to_file.compose(&body.pose))
    }
}
