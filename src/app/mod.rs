//! The docking window: winit events → session steps → wgpu frames + egui HUD.
//!
//! A thin layer over the core: keys and mouse become [`FrameInput`]s (through
//! the pure [`keymap`]; motion keys as timed press and release events the
//! session turns into exact steps), the session decides everything about
//! docking, and the renderer draws what the session holds. Each frame runs
//! three steps (`frame`): *input* (devices, the HUD's widgets, a replayed
//! or recorded log), *step* (the session) and *paint* (scene, HUD, markers).
//!
//! Nothing is drawn when nothing changed: the loop sleeps until an event,
//! and asks for frames on its own only while something animates (rocking,
//! a stereo mode that alternates eyes, a held joystick, a load in progress,
//! a settle's animation)
//! or at a known time (a held key's next repeat, a status message that
//! expires, the end of a contact flash).
//!
//! | module | what |
//! | --- | --- |
//! | `events` | winit's events: keys, mouse, files dropped, quitting |
//! | `frame` | one frame: input, step, paint, and when the next is due |
//! | [`gfx`] | the window's GPU state and the painting of scene and HUD |
//! | `files` | opening, loading in the background, saving poses, screenshots |
//! | [`hud`], [`overlay`], [`dialogs`] | what is drawn over the scene |
//! | [`keymap`], [`saving`], [`stereo`], [`pick`], [`settle_show`] | pure parts, unit-tested |

pub mod beep;
pub mod dialogs;
mod events;
mod files;
mod frame;
pub mod gfx;
pub mod hud;
pub mod joysticks;
pub mod keymap;
pub mod open_dialog;
pub mod overlay;
pub mod pick;
pub mod player;
pub mod pocket;
pub mod saving;
pub mod score_panel;
pub mod settle_show;
pub mod stereo;

use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;
use thiserror::Error;

use crate::input::JoystickMap;
use crate::render::{RenderError, ViewParams};
use crate::session::{FrameInput, KeySteps, LogWriter, Session, SessionLog, Timing};

use dialogs::Dialogs;
use hud::HudState;
use keymap::Mods;
use player::Player;

/// Why the window could not run.
#[derive(Debug, Error)]
pub enum AppError {
    /// No display or event loop.
    #[error(
        "cannot open a window: {0} (is DISPLAY or WAYLAND_DISPLAY set? `bump render` works without one)"
    )]
    EventLoop(String),
    /// The GPU failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The session log could not be written.
    #[error("recording: {0}")]
    Recording(String),
}

/// What the file-loading thread reports.
#[derive(Debug)]
pub enum LoadEvent {
    /// Starting to read a file.
    Reading(String),
    /// Molecules read from one file.
    Loaded {
        /// The file.
        label: String,
        /// Its molecules (a complex gives receptor and drug).
        molecules: Vec<crate::model::Molecule>,
        /// Loader warnings.
        warnings: Vec<String>,
        /// Seconds taken.
        seconds: f64,
    },
    /// A file that could not be used.
    Failed(String),
}

/// How the window takes input beyond keyboard and mouse.
#[derive(Debug, Default)]
pub struct Options {
    /// The joystick map.
    pub joystick_map: JoystickMap,
    /// Two joystick boxes: the first moves the view, the second the molecule.
    pub two_boxes: bool,
    /// Rumble gamepads on contact.
    pub rumble: bool,
    /// Record every frame's input here.
    pub record: Option<LogWriter>,
    /// Replay this log instead of live input, then quit.
    pub play: Option<SessionLog>,
}

/// What a window session did, for the caller to report.
#[derive(Debug, Default)]
pub struct Ended {
    /// Frame and collision times.
    pub timing: Timing,
    /// The recording's file, when one was written.
    pub recorded: Option<PathBuf>,
    /// The session at the end.
    pub session: Option<Session>,
    /// Frames replayed from a log (when playing).
    pub replayed: Option<usize>,
}

/// Opens the window on `session` and runs until the user quits. Molecules
/// that `loader` sends (files read on another thread) join the session as
/// they arrive; the window stays interactive meanwhile and shows progress.
///
/// # Errors
/// [`AppError`] when no window or GPU can be had, or the recording cannot
/// be finished.
pub fn run(
    session: Session,
    messages: Vec<String>,
    loader: Option<std::sync::mpsc::Receiver<LoadEvent>>,
    options: Options,
) -> Result<Ended, AppError> {
    let event_loop =
        winit::event_loop::EventLoop::new().map_err(|e| AppError::EventLoop(e.to_string()))?;
    let mut app = App::new(session);
    app.loader = loader.map(|rx| (rx, Instant::now()));
    for m in messages {
        app.hud.say(m);
    }
    let (beeper, why) = beep::Beeper::open();
    app.beeper = beeper;
    if let Some(w) = why {
        app.hud.say(w);
    }
    if options.play.is_none() {
        let (sticks, said) =
            joysticks::Joysticks::open(options.joystick_map, options.two_boxes, options.rumble);
        for m in said {
            app.hud.say(m);
        }
        app.hud.joysticks = Some(sticks.describe());
        app.joysticks = Some(sticks);
        if !app.session.bodies().is_empty() {
            // The first frame turns the view to show the drug (recorded, so
            // a replay starts from the same view).
            app.pending.commands.push(crate::session::Command::ViewDrug);
        }
    }
    app.recorder = options.record;
    if app.recorder.is_some() {
        app.hud.replay = Some("REC".into());
    }
    app.player = options.play.map(Player::new);
    event_loop
        .run_app(&mut app)
        .map_err(|e| AppError::EventLoop(e.to_string()))?;
    if let Some(e) = app.fatal.take() {
        return Err(e);
    }
    let mut ended = Ended {
        replayed: app.player.as_ref().map(Player::played),
        ..Ended::default()
    };
    if let Some(w) = app.recorder.take() {
        let finals: Vec<_> = app.session.bodies().iter().map(|b| b.pose).collect();
        let path = w
            .finish(&finals)
            .map_err(|e| AppError::Recording(e.to_string()))?;
        ended.recorded = Some(path);
    }
    ended.timing = std::mem::take(&mut app.timing);
    ended.session = Some(app.session);
    Ok(ended)
}

/// The mouse as the window tracks it.
#[derive(Debug, Default)]
struct Mouse {
    pos: (f64, f64),
    left: bool,
    middle: bool,
    press_at: (f64, f64),
    dragged: bool,
    /// When and where the last click was (for double clicks).
    last_click: Option<(Instant, (f64, f64))>,
}

/// A motion key pressed or released, with when it happened (the frame
/// gives the session its time into the frame).
#[derive(Debug, Clone, Copy)]
struct TimedKey {
    at: Instant,
    key: crate::session::StepKey,
    size: crate::session::StepSize,
    pressed: bool,
}

/// The window's state.
struct App {
    session: Session,
    gfx: Option<gfx::Gfx>,
    hud: HudState,
    dialogs: Dialogs,
    mods: Mods,
    mouse: Mouse,
    /// What the next frame gives the session (commands, nudges, zoom).
    pending: FrameInput,
    /// Motion keys pressed or released since the last frame.
    pending_keys: Vec<TimedKey>,
    /// Physical keys held that are motion keys, with the key each pressed
    /// (the modifiers may change before the release).
    held_steps: Vec<(winit::keyboard::KeyCode, crate::session::StepKey)>,
    /// Light mode's own motion keys (they turn the light, not the scene).
    light_keys: KeySteps,
    light: DVec3,
    flash_until: Option<Instant>,
    /// A settle being animated.
    settle_show: Option<settle_show::SettleShow>,
    /// When the last frame was drawn.
    last_frame: Instant,
    /// The last frame asked for no other: the next frame's interval starts
    /// at the event that woke the loop, not at the last frame.
    idle: bool,
    /// The first event after an idle spell.
    woke_at: Option<Instant>,
    /// A frame is due at this time (a key's repeat, a message's expiry).
    wake_at: Option<Instant>,
    fatal: Option<AppError>,
    beeper: beep::Beeper,
    open_dialog: open_dialog::OpenDialog,
    loader: Option<(std::sync::mpsc::Receiver<LoadEvent>, Instant)>,
    joysticks: Option<joysticks::Joysticks>,
    recorder: Option<LogWriter>,
    player: Option<Player>,
    /// The replay ended or the user stopped it.
    player_done: bool,
    /// egui asked for another pass after this long.
    hud_repaint: Option<std::time::Duration>,
    timing: Timing,
}

impl App {
    fn new(mut session: Session) -> Self {
        session.enable_score();
        Self {
            session,
            gfx: None,
            hud: HudState {
                flash: true,
                ..HudState::default()
            },
            dialogs: Dialogs::default(),
            mods: Mods::default(),
            mouse: Mouse::default(),
            pending: FrameInput::default(),
            pending_keys: Vec::new(),
            held_steps: Vec::new(),
            light_keys: KeySteps::default(),
            light: ViewParams::default().light,
            flash_until: None,
            settle_show: None,
            last_frame: Instant::now(),
            idle: true,
            woke_at: None,
            wake_at: None,
            fatal: None,
            beeper: beep::Beeper::open_quietly(),
            open_dialog: open_dialog::OpenDialog::default(),
            loader: None,
            joysticks: None,
            recorder: None,
            player: None,
            player_done: false,
            hud_repaint: None,
            timing: Timing::default(),
        }
    }

    fn title(&self) -> String {
        let names: Vec<&str> = self
            .session
            .bodies()
            .iter()
            .map(|b| b.molecule.name.as_str())
            .collect();
        format!("bump — {}", names.join(" + "))
    }

    fn request_redraw(&mut self) {
        if self.idle && self.woke_at.is_none() {
            self.woke_at = Some(Instant::now());
        }
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }
}
