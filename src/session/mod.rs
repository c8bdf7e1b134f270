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
//! rebuilds nothing. (With the 272k-atom 1f2n assembly as the receptor,
//! selecting the drug again took 113 ms in the frame, for a merged copy of
//! every atom and its grid, and then over a second of both cores for the
//! clearance map; now 0.06 ms.) A molecule's atoms set up to move are kept
//! likewise (for the assembly, 10 ms to set up). Two or more other
//! molecules are merged, at their current poses, into one collider,
//! rebuilt when the selection changes or one of them moves.

pub mod camera;
pub mod framing;
pub mod history;
pub mod input;
pub mod keys;
pub mod labels;
pub mod log;
pub mod replay;
pub mod timing;

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use thiserror::Error;

pub use camera::Camera;
pub use history::History;
pub use input::{Command, FrameInput, Motion6};
pub use keys::{KeyEvent, KeySteps, Step, StepAxis, StepKey, StepSize};
pub use labels::Role;
pub use log::{LogError, LogFrame, LogWriter, SessionLog};
pub use replay::{Replayed, replay};
pub use timing::{Summary, Timing};

use crate::collide::{
    Collider, ColliderKind, ContactRule, DrugAtoms, Method, Response, TouchOptions, respond,
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
    /// The other molecule and its atom.
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
    /// Atoms whose highlight changed: (molecule, atom, now in contact).
    pub highlight_changes: Vec<(usize, usize, bool)>,
    /// Time spent in collision detection this frame, µs (None: no query).
    pub collision_us: Option<f64>,
    /// Each collision query of this frame, µs (the thesis's per-call timing).
    pub collision_calls: Vec<f64>,
    /// Messages for the status line.
    pub messages: Vec<String>,
    /// The user asked to quit.
    pub quit: bool,
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

/// Makes a response's contacts those of the pose it leaves the drug at,
/// touching what stopped it.
///
/// `stop` reports the pairs its rejected step ran into, at a pose never
/// shown: the contacts shown are those where the drug stays. `slide` ends
/// with a leg along the tangent of what it touched, which curves away from
/// a round atom: a leg of 0.2 Å ends about 0.006 Å clear, beyond the
/// tolerance, so the drug pressed into the receptor showed "Contacts: 3",
/// then 0 every other frame while it could not move. When the push was
/// blocked and the slide ends touching nothing, the rest of the push (the
/// part the slide took off) is taken once more, through move-to-touch, so
/// the drug ends against what it slides along (never beyond the push
/// asked for, never overlapping).
fn shown_contacts(
    env: &Environment,
    start: &Pose,
    end: &Pose,
    touch: &TouchOptions,
    r: &mut crate::collide::StepResult,
) {
    match r.response {
        Response::Stop if r.t < 1.0 => {
            r.contacts =
                crate::collide::pairs_within(&env.collider, &env.drug, start, touch.tolerance as f32);
        }
        Response::Slide if r.t < 1.0 && r.contacts.is_empty() => {
            let rest = 1.0 - r.t;
            let q = (end.rotation * start.rotation.conjugate()).normalize();
            let (axis, angle) = q.to_axis_angle();
            let target = r.pose.moved(
                (end.translation - start.translation) * rest,
                axis,
                angle * rest,
            );
            let s = crate::collide::move_to_touch(&env.collider, &env.drug, &r.pose, &target, touch);
            r.pose = s.pose;
            r.contacts = s.contacts;
            r.colliding = s.colliding;
        }
        _ => {}
    }
}

/// The environment of the selected molecule: all others.
#[derive(Debug, Clone)]
struct Environment {
    selected: usize,
    /// Pose of the collider's frame in the world: the molecule's pose for
    /// one molecule, the merged atoms' centre (no rotation) for several.
    frame: Pose,
    collider: Arc<Collider>,
    drug: Arc<DrugAtoms>,
    owners: Owners,
}

/// Which molecule's atom each environment atom is.
#[derive(Debug, Clone)]
enum Owners {
    /// One molecule: atom `i` is its atom `i`.
    One(usize),
    /// Several, merged: (molecule, atom) of each.
    Merged(Vec<(usize, usize)>),
}

impl Owners {
    fn of(&self, i: usize) -> (usize, usize) {
        match self {
            Self::One(k) => (*k, i),
            Self::Merged(v) => v[i],
        }
    }
}

impl Environment {
    /// Pairs between the moving molecule `b` and the environment, as contacts
    /// between molecules.
    fn contacts(&self, b: usize, pairs: &[crate::collide::Pair]) -> Vec<Contact> {
        pairs
            .iter()
            .map(|p| Contact {
                moving: (b, p.drug as usize),
                other: self.owners.of(p.receptor as usize),
                distance: p.distance,
                contact: p.contact,
            })
            .collect()
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
    highlighted: Vec<Vec<bool>>,
    contacts: Vec<Contact>,
    rock: Rock,
    /// The motion keys held and their clock.
    keys: KeySteps,
    /// Per molecule: what it is (read once, when it arrives).
    roles: Vec<Role>,
    /// Per molecule: its pose when it was loaded or last saved.
    saved: Vec<Pose>,
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
        let highlighted = bodies
            .iter()
            .map(|b| vec![false; b.molecule.len()])
            .collect();
        let selected = bodies.len().saturating_sub(1);
        let own_colliders = vec![None; bodies.len()];
        let moving_atoms = vec![None; bodies.len()];
        let roles = bodies.iter().map(|b| Role::of(&b.molecule)).collect();
        let saved = bodies.iter().map(|b| b.pose).collect();
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

    /// What molecule `b` is (receptor or drug).
    pub fn role(&self, b: usize) -> Option<Role> {
        self.roles.get(b).copied()
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
        let last = (0..self.bodies.len()).rev().find(|&k| self.roles[k] == Role::Drug);
        Some(last.unwrap_or(self.selected))
    }

    /// The molecules moved since they were loaded or last saved.
    pub fn unsaved(&self) -> Vec<usize> {
        (0..self.bodies.len())
            .filter(|&k| self.saved.get(k) != Some(&self.bodies[k].pose))
            .collect()
    }

    /// Notes that molecule `b` was saved where it stands now.
    pub fn mark_saved(&mut self, b: usize) {
        if let (Some(s), Some(body)) = (self.saved.get_mut(b), self.bodies.get(b)) {
            *s = body.pose;
        }
    }

    /// Adds a molecule at its file pose (e.g. a file dropped on the window)
    /// and selects it.
    pub fn add_molecule(&mut self, molecule: Molecule) {
        let pose = Pose::from_translation(molecule.centre);
        self.highlighted.push(vec![false; molecule.len()]);
        self.roles.push(Role::of(&molecule));
        self.bodies.push(Body {
            molecule,
            pose,
            loaded: pose,
        });
        self.own_colliders.push(None);
        self.moving_atoms.push(None);
        self.saved.push(pose);
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
        self.highlighted
            .get(body)
            .and_then(|h| h.get(atom))
            .copied()
            .unwrap_or(false)
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
        if self.bodies.is_empty() {
            // Nothing to move but the view.
        } else if !object.is_finite() {
            out.messages.push("ignored a non-finite motion".into());
        } else if object.is_zero() {
            // A held key's repeats are one gesture: undo takes them back
            // together.
            if !self.keys.any_held() {
                self.history.close();
            }
        } else {
            let (translate, axis, angle) = self.to_world(&object);
            self.move_selected(translate, axis, angle, &mut out);
        }
        out
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

    fn command(&mut self, c: Command, out: &mut FrameOutcome) {
        out.changed = true;
        let molecule_command = matches!(
            c,
            Command::NextMolecule
                | Command::Select(_)
                | Command::Undo
                | Command::Redo
                | Command::ResetMolecule
                | Command::MoveBy { .. }
        );
        if molecule_command && self.bodies.is_empty() {
            out.messages.push("no molecule loaded yet".into());
            return;
        }
        match c {
            Command::ToggleMode => {
                self.mode = match self.mode {
                    Mode::View => Mode::Object,
                    Mode::Object => Mode::View,
                };
            }
            Command::NextMolecule => self.select((self.selected + 1) % self.bodies.len(), out),
            Command::Select(n) => {
                if n < self.bodies.len() {
                    self.select(n, out);
                } else {
                    out.messages.push(format!("no molecule {n}"));
                }
            }
            Command::ToggleCollision => {
                self.settings.collision = !self.settings.collision;
                if self.settings.collision {
                    self.refresh_contacts(out);
                    if self.contacts.iter().any(|c| c.gap() <= 0.0) {
                        out.messages.push(
                            "the molecules already overlap: only moves that do not deepen the overlap are allowed"
                                .into(),
                        );
                    }
                } else {
                    self.set_contacts(Vec::new(), out);
                }
            }
            Command::SetResponse(r) => self.settings.response = r,
            Command::CycleResponse => {
                let all = Response::ALL;
                let k = all
                    .iter()
                    .position(|r| *r == self.settings.response)
                    .unwrap_or(0);
                self.settings.response = all[(k + 1) % all.len()];
            }
            Command::ToggleSpace => {
                self.settings.space = match self.settings.space {
                    Space::Screen => Space::Object,
                    Space::Object => Space::Screen,
                };
            }
            Command::Undo => match self.history.undo() {
                Some(m) => self.place(m.body, m.from, out),
                None => out.messages.push("nothing to undo".into()),
            },
            Command::Redo => match self.history.redo() {
                Some(m) => self.place(m.body, m.to, out),
                None => out.messages.push("nothing to redo".into()),
            },
            Command::ResetMolecule => {
                let b = self.selected;
                let (from, to) = (self.bodies[b].pose, self.bodies[b].loaded);
                self.history.close();
                self.history.record(b, from, to);
                self.history.close();
                self.place(b, to, out);
            }
            Command::ResetView => self.camera = self.home,
            Command::ViewDrug => self.view_drug(),
            Command::CentreOnDrug => {
                if let Some(c) = self
                    .drug()
                    .and_then(|d| framing::centre_on(&self.bodies, d, self.camera.rotation))
                {
                    self.camera = c;
                }
            }
            Command::FitAll => {
                if let Some(c) = framing::fit_all(&self.bodies, self.camera.rotation) {
                    self.camera = c;
                }
            }
            Command::MoveBy {
                translate,
                axis,
                degrees,
            } => {
                if translate.is_finite() && axis.is_finite() && degrees.is_finite() {
                    self.history.close();
                    let angle = if axis.length_squared() > 0.0 {
                        degrees.to_radians()
                    } else {
                        0.0
                    };
                    self.move_selected(translate, axis, angle, out);
                    self.history.close();
                } else {
                    out.messages.push("ignored a non-finite move".into());
                }
            }
            Command::Quit => out.quit = true,
            Command::ToggleRocking => {
                let a = self.rock.toggle();
                self.bake_rock(a);
                let deg = self.rock.target_amplitude().to_degrees();
                out.messages.push(if self.rock.is_on() {
                    format!("rocking on (±{deg:.0}°)")
                } else {
                    "rocking off".into()
                });
            }
            Command::RockMore | Command::RockLess => {
                if c == Command::RockMore {
                    self.rock.more();
                } else {
                    self.rock.less();
                }
                let deg = self.rock.target_amplitude().to_degrees();
                out.messages.push(format!("rocking ±{deg:.1}°"));
            }
        }
    }

    /// [`Command::ViewDrug`]: a new home view that shows the drug; the
    /// camera goes there only while it is at home.
    fn view_drug(&mut self) {
        let view = match self.drug() {
            Some(d) if self.bodies.len() > 1 => framing::drug_view(&self.bodies, d),
            _ => framing::fit_all(&self.bodies, self.camera.rotation),
        };
        if let Some(v) = view {
            if self.camera == self.home {
                self.camera = v;
            }
            self.home = v;
        }
    }

    fn select(&mut self, n: usize, out: &mut FrameOutcome) {
        // The environment holds the other molecules' poses, which change only
        // while one of them is selected: re-selecting the selected molecule
        // (a click on it) keeps it instead of rebuilding its collider.
        if n != self.selected {
            self.env = None;
        }
        self.selected = n;
        self.history.close();
        self.refresh_contacts(out);
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

    /// With collision on, builds the selected molecule's environment now
    /// (if it is not built) and waits until its collider's clearance map is
    /// there, so the frames that follow run as every frame will from then
    /// on: for benchmarks. Frames never wait for the map (see
    /// [`Collider::wait_for_clearance`]).
    pub fn wait_for_collider(&mut self) {
        if self.settings.collision
            && let Some(env) = self.environment()
        {
            env.collider.wait_for_clearance();
        }
    }

    /// Builds (or reuses) the environment of the selected molecule.
    fn environment(&mut self) -> Option<&Environment> {
        let stale = self
            .env
            .as_ref()
            .is_none_or(|e| e.selected != self.selected);
        if stale {
            self.env = self.build_environment();
        }
        self.env.as_ref()
    }

    fn build_environment(&mut self) -> Option<Environment> {
        let selected = self.selected;
        let mut others = (0..self.bodies.len())
            .filter(|&k| k != selected && !self.bodies[k].molecule.is_empty());
        let (first, second) = (others.next(), others.next());
        let (frame, collider, owners) = match (first, second) {
            (None, _) => return None,
            (Some(k), None) => (self.bodies[k].pose, self.own_collider(k), Owners::One(k)),
            (Some(_), Some(_)) => {
                let (frame, collider, owners) = self.merged_environment();
                (frame, Arc::new(collider), Owners::Merged(owners))
            }
        };
        let drug = self.moving_atoms(selected, collider.max_radius());
        Some(Environment {
            selected,
            frame,
            collider,
            drug,
            owners,
        })
    }

    /// Molecule `k`'s collider in its own frame, built on first use.
    fn own_collider(&mut self, k: usize) -> Arc<Collider> {
        if let Some(Some(c)) = self.own_colliders.get(k) {
            return Arc::clone(c);
        }
        let c = Arc::new(Collider::build(
            &self.bodies[k].molecule,
            &self.settings.rule,
            self.settings.collider,
        ));
        if let Some(slot) = self.own_colliders.get_mut(k) {
            *slot = Some(Arc::clone(&c));
        }
        c
    }

    /// Molecule `k`'s atoms set up to move against receptor atoms of radius
    /// up to `max_radius`, kept for the next time (for the 272k-atom
    /// assembly they take about 20 ms to set up).
    fn moving_atoms(&mut self, k: usize, max_radius: f32) -> Arc<DrugAtoms> {
        if let Some(Some((r, atoms))) = self.moving_atoms.get(k)
            && r.to_bits() == max_radius.to_bits()
        {
            return Arc::clone(atoms);
        }
        let atoms = Arc::new(DrugAtoms::new(
            &self.bodies[k].molecule,
            &self.settings.rule,
            max_radius,
        ));
        if let Some(slot) = self.moving_atoms.get_mut(k) {
            *slot = Some((max_radius, Arc::clone(&atoms)));
        }
        atoms
    }

    /// Every molecule but the selected one, at its current pose, as one
    /// collider: its frame (the atoms' centre), the collider and each
    /// atom's (molecule, atom).
    fn merged_environment(&self) -> (Pose, Collider, Vec<(usize, usize)>) {
        let mut atoms = Vec::new();
        let mut positions = Vec::new();
        let mut owners = Vec::new();
        for (k, b) in self.bodies.iter().enumerate() {
            if k == self.selected {
                continue;
            }
            for (i, a) in b.molecule.atoms.iter().enumerate() {
                atoms.push(a.clone());
                positions.push(b.pose.transform_point(b.molecule.local[i].as_dvec3()));
                owners.push((k, i));
            }
        }
        let merged = Molecule::new("environment", atoms, &positions);
        let frame = Pose::from_translation(merged.centre);
        let collider = Collider::build(&merged, &self.settings.rule, self.settings.collider);
        (frame, collider, owners)
    }

    fn move_selected(&mut self, translate: DVec3, axis: DVec3, angle: f64, out: &mut FrameOutcome) {
        let b = self.selected;
        let from = self.bodies[b].pose;
        let to = from.moved(translate, axis, angle);
        if !to.within_range() {
            out.messages.push(format!(
                "refused: a molecule may not move more than {:e} Å from the origin",
                crate::motion::MAX_COORDINATE
            ));
            return;
        }
        if !self.settings.collision {
            self.bodies[b].pose = to;
            self.history.record(b, from, to);
            out.moved = true;
            out.changed = true;
            return;
        }
        let (response, touch) = (self.settings.response, self.settings.touch);
        let Some(env) = self.environment() else {
            // Nothing to collide with.
            self.bodies[b].pose = to;
            self.history.record(b, from, to);
            out.moved = true;
            out.changed = true;
            return;
        };
        let inv = env.frame.inverse();
        let (start, end) = (inv.compose(&from), inv.compose(&to));
        let t0 = Instant::now();
        let mut r = respond(&env.collider, &env.drug, &start, &end, response, &touch);
        shown_contacts(env, &start, &end, &touch, &mut r);
        out.collision_timed(t0);
        let frame = env.frame;
        let contacts = env.contacts(b, &r.contacts);
        out.t = r.t;
        let new_pose = frame.compose(&r.pose);
        if new_pose != from {
            self.bodies[b].pose = new_pose;
            self.history.record(b, from, new_pose);
            out.moved = true;
            out.changed = true;
        }
        if !r.start_colliding.is_empty() && r.t < 1.0 {
            out.messages
                .push("start pose overlaps: only moves that do not deepen it are allowed".into());
        }
        self.set_contacts(contacts, out);
    }

    /// Puts body `b` at `pose` (undo, redo, reset): a jump, not a motion, so
    /// collisions are reported at the new pose, not prevented.
    fn place(&mut self, b: usize, pose: Pose, out: &mut FrameOutcome) {
        self.bodies[b].pose = pose;
        out.changed = true;
        out.moved |= b == self.selected;
        if b != self.selected {
            self.env = None; // the environment held the old pose
        }
        self.refresh_contacts(out);
    }

    /// Recomputes the selected molecule's contacts where it stands.
    fn refresh_contacts(&mut self, out: &mut FrameOutcome) {
        if !self.settings.collision || self.bodies.is_empty() {
            self.set_contacts(Vec::new(), out);
            return;
        }
        let b = self.selected;
        let pose = self.bodies[b].pose;
        let tol = self.settings.touch.tolerance as f32;
        let Some(env) = self.environment() else {
            self.set_contacts(Vec::new(), out);
            return;
        };
        let rel = env.frame.inverse().compose(&pose);
        let t0 = Instant::now();
        let pairs = crate::collide::pairs_within(&env.collider, &env.drug, &rel, tol);
        out.collision_timed(t0);
        let contacts = env.contacts(b, &pairs);
        self.set_contacts(contacts, out);
    }

    /// Replaces the contact list, reporting highlight changes and new contacts.
    /// Replaces the contact list, reporting highlight changes and new
    /// contacts. Work is proportional to the contacts, not to the atoms: only
    /// atoms in the old or the new list can change.
    fn set_contacts(&mut self, contacts: Vec<Contact>, out: &mut FrameOutcome) {
        use std::collections::BTreeSet;
        let key = |c: &Contact| (c.moving, c.other);
        let old: BTreeSet<_> = self.contacts.iter().map(key).collect();
        out.new_contact |= contacts.iter().any(|c| !old.contains(&key(c)));
        let atoms = |list: &[Contact]| -> BTreeSet<(usize, usize)> {
            list.iter().flat_map(|c| [c.moving, c.other]).collect()
        };
        let was = atoms(&self.contacts);
        let now = atoms(&contacts);
        // Sorted (molecule, atom) order keeps the change list deterministic.
        for &(k, i) in was.union(&now) {
            let on = now.contains(&(k, i));
            if let Some(flag) = self.highlighted.get_mut(k).and_then(|h| h.get_mut(i))
                && *flag != on
            {
                *flag = on;
                out.highlight_changes.push((k, i, on));
            }
        }
        if !out.highlight_changes.is_empty() {
            out.changed = true;
        }
        self.contacts = contacts.clone();
        out.contacts = contacts;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{RadiiSet, builtin};

    /// One frame moving the selected molecule (object mode) by `v`.
    fn nudge(s: &mut Session, v: DVec3) {
        s.step(&FrameInput::nudged(v, DVec3::ZERO), 0.0);
    }

    fn env_collider(s: &Session) -> Arc<Collider> {
        Arc::clone(&s.env.as_ref().expect("an environment").collider)
    }

    fn env_drug(s: &Session) -> Arc<DrugAtoms> {
        Arc::clone(&s.env.as_ref().expect("an environment").drug)
    }

    #[test]
    fn a_molecules_collider_and_moving_atoms_are_built_once_whatever_is_selected_or_moved() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        nudge(&mut s, DVec3::new(0.0, 0.0, 1.0));
        let (rings_collider, e_atoms) = (env_collider(&s), env_drug(&s));
        // Select the rings and move them (the E's collider is built), then
        // the E again: the rings' collider is the one built first.
        s.step(&FrameInput::with_commands(&[Command::Select(0)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 2.0, 0.0));
        let (e_collider, rings_atoms) = (env_collider(&s), env_drug(&s));
        s.step(&FrameInput::with_commands(&[Command::Select(1)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 0.0, 1.0));
        assert!(Arc::ptr_eq(&env_collider(&s), &rings_collider));
        assert!(Arc::ptr_eq(&env_drug(&s), &e_atoms));
        assert_eq!(s.env.as_ref().map(|e| e.frame), Some(s.bodies[0].pose));
        s.step(&FrameInput::with_commands(&[Command::Select(0)]), 0.0);
        nudge(&mut s, DVec3::new(0.0, 1.0, 0.0));
        assert!(Arc::ptr_eq(&env_collider(&s), &e_collider));
        assert!(Arc::ptr_eq(&env_drug(&s), &rings_atoms));
    }

    #[test]
    fn two_or_more_other_molecules_are_merged_at_their_poses() {
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let (_, e2) = builtin::scene(RadiiSet::Bondi);
        let mut s = Session::new(vec![rings, e, e2], Settings::default()).expect("session");
        s.step(&FrameInput::docking(), 0.0);
        nudge(&mut s, DVec3::new(0.0, 30.0, 0.0));
        let env = s.env.as_ref().expect("an environment");
        let n = s.bodies[0].molecule.len() + s.bodies[1].molecule.len();
        assert_eq!(env.collider.len(), n);
        assert!(matches!(&env.owners, Owners::Merged(v) if v.len() == n));
        assert_eq!(env.frame.rotation, glam::DQuat::IDENTITY);
    }
}
