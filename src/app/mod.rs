//! The docking window: winit events → session steps → wgpu frames + egui HUD.
//!
//! A thin layer over the core: keys and mouse become [`FrameInput`]s (through
//! the pure [`keymap`]), the session decides everything about docking, and
//! the renderer draws what the session holds. Nothing is drawn when nothing
//! changed: the loop waits for events, and keeps redrawing only while a key is
//! held, the background is flashing or the HUD asks for it.

pub mod beep;
pub mod hud;
pub mod joysticks;
pub mod keymap;
pub mod open_dialog;
pub mod pick;
pub mod stereo;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::{DQuat, DVec3};
use thiserror::Error;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::input::JoystickMap;
use crate::model::{self, LoadOptions};
use crate::render::colors::BACKGROUND;
use crate::render::offscreen::{render_image, save_png};
use crate::render::spheres::{color_pass, depth_view};
use crate::render::{Gpu, RenderError, SphereRenderer, ViewParams};
use crate::session::{Command, FrameInput, LogWriter, Motion6, Session, SessionLog, Timing};

use hud::HudState;
use keymap::{KeyAction, Mods, ShellAction};

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

/// How long the background flashes on a new contact.
const FLASH: Duration = Duration::from_millis(150);
/// Mouse travel (pixels) below which a press-release is a click, not a drag.
const CLICK_SLOP: f64 = 3.0;

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

/// A log being replayed in the window, paced at its recorded times.
#[derive(Debug)]
struct Player {
    log: SessionLog,
    next: usize,
    started: Option<Instant>,
    elapsed: f64,
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
    let event_loop = EventLoop::new().map_err(|e| AppError::EventLoop(e.to_string()))?;
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
    }
    app.recorder = options.record;
    if app.recorder.is_some() {
        app.hud.replay = Some("REC".into());
    }
    app.player = options.play.map(|log| Player {
        log,
        next: 0,
        started: None,
        elapsed: 0.0,
    });
    event_loop
        .run_app(&mut app)
        .map_err(|e| AppError::EventLoop(e.to_string()))?;
    if let Some(e) = app.fatal.take() {
        return Err(e);
    }
    let mut ended = Ended {
        replayed: app.player.as_ref().map(|p| p.next),
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

struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    gpu: Gpu,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    spheres: SphereRenderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    textures: PendingTextures,
}

/// egui's texture changes (glyph atlas, images) not yet given to the
/// renderer. A frame that draws nothing (a lost surface, a quit) keeps them
/// for the next, so no glyph goes missing; dropped, they are cleared, since
/// egui asserts in debug builds that every change it made was applied.
#[derive(Default)]
struct PendingTextures(egui::TexturesDelta);

impl Drop for PendingTextures {
    fn drop(&mut self) {
        self.0.clear();
    }
}

#[derive(Default)]
struct Mouse {
    pos: (f64, f64),
    left: bool,
    middle: bool,
    press_at: (f64, f64),
    dragged: bool,
}

struct App {
    session: Session,
    gfx: Option<Gfx>,
    hud: HudState,
    held: Vec<KeyCode>,
    mods: Mods,
    mouse: Mouse,
    pending: FrameInput,
    light: DVec3,
    flash_until: Option<Instant>,
    last_frame: Instant,
    fatal: Option<AppError>,
    beeper: beep::Beeper,
    open_dialog: open_dialog::OpenDialog,
    loader: Option<(std::sync::mpsc::Receiver<LoadEvent>, Instant)>,
    joysticks: Option<joysticks::Joysticks>,
    recorder: Option<LogWriter>,
    player: Option<Player>,
    timing: Timing,
}

impl App {
    fn new(session: Session) -> Self {
        Self {
            session,
            gfx: None,
            hud: HudState {
                flash: true,
                ..HudState::default()
            },
            held: Vec::new(),
            mods: Mods::default(),
            mouse: Mouse::default(),
            pending: FrameInput::default(),
            light: ViewParams::default().light,
            flash_until: None,
            last_frame: Instant::now(),
            fatal: None,
            beeper: beep::Beeper::open_quietly(),
            open_dialog: open_dialog::OpenDialog::default(),
            loader: None,
            joysticks: None,
            recorder: None,
            player: None,
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

    fn init_gfx(&mut self, event_loop: &ActiveEventLoop) -> Result<Gfx, AppError> {
        let attrs = Window::default_attributes()
            .with_title(self.title())
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| AppError::EventLoop(e.to_string()))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let gpu = Gpu::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| RenderError::Device("the surface offers no format".into()))?;
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| RenderError::Device("the surface cannot be configured".into()))?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(&gpu.device, &config);
        let depth = depth_view(&gpu.device, config.width, config.height);
        let mut spheres = SphereRenderer::new(&gpu.device, format, &self.session);
        spheres.sync_highlights(&gpu.queue, &self.session);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer =
            egui_wgpu::Renderer::new(&gpu.device, format, egui_wgpu::RendererOptions::default());
        self.hud.say(format!("rendering with {}", gpu.describe()));
        self.hud.view.refresh_millihertz = window
            .current_monitor()
            .and_then(|m| m.refresh_rate_millihertz());
        Ok(Gfx {
            window,
            surface,
            gpu,
            config,
            depth,
            spheres,
            egui_ctx,
            egui_state,
            egui_renderer,
            textures: PendingTextures::default(),
        })
    }

    fn request_redraw(&self) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }

    fn key(&mut self, key: KeyCode, pressed: bool, repeat: bool) {
        // Modifier keys are also tracked from their own key events: they are
        // ordered with the keys they modify, which ModifiersChanged is not
        // always (synthetic input, some X servers).
        match key {
            KeyCode::ShiftLeft | KeyCode::ShiftRight => self.mods.shift = pressed,
            KeyCode::ControlLeft | KeyCode::ControlRight => self.mods.ctrl = pressed,
            KeyCode::AltLeft | KeyCode::AltRight => self.mods.alt = pressed,
            _ => {}
        }
        if !pressed {
            self.held.retain(|k| *k != key);
            return;
        }
        if repeat {
            return;
        }
        if self.player.is_some() {
            // A replay takes no live input, but the user may stop it.
            if matches!(key, KeyCode::Escape | KeyCode::KeyQ) {
                self.pending.commands.push(Command::Quit);
            }
            return;
        }
        match keymap::action(key, self.mods) {
            Some(KeyAction::Session(c)) => self.pending.commands.push(c),
            Some(KeyAction::Shell(a)) => self.shell_action(a),
            None => {}
        }
        if keymap::motion_of(key, self.mods).is_some() && !self.held.contains(&key) {
            // A tap moves one step at once; holding the key goes on at the
            // key's velocity.
            if let Some(step) = keymap::tap(key, self.mods) {
                self.pending.nudge = self.pending.nudge.plus(&step);
            }
            self.held.push(key);
        }
    }

    fn shell_action(&mut self, a: ShellAction) {
        match a {
            ShellAction::ToggleHelp => self.hud.help = !self.hud.help,
            ShellAction::ToggleLight => {
                self.hud.light_mode = !self.hud.light_mode;
                let state = if self.hud.light_mode { "on" } else { "off" };
                self.hud.say(format!("light mode {state}"));
            }
            ShellAction::ToggleFlash => self.hud.flash = !self.hud.flash,
            ShellAction::Screenshot => self.screenshot(),
            ShellAction::SavePose => self.save_pose(),
            ShellAction::Open => self
                .open_dialog
                .show_at(std::env::current_dir().unwrap_or_default()),
            ShellAction::Cue(c) => {
                let msg = self.hud.view.apply(c);
                self.hud.say(msg);
            }
        }
    }

    /// Writes the selected molecule, in the first molecule's (the
    /// receptor's) file frame, as `<name>-docked.pdb` and `.sdf`.
    fn save_pose(&mut self) {
        let b = self.session.selected();
        let Some(pose) = self.session.pose_in_frame_of(b, 0) else {
            return;
        };
        let mol = &self.session.bodies()[b].molecule;
        let stem: String = mol
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let mut said = Vec::new();
        let pdb = PathBuf::from(format!("{stem}-docked.pdb"));
        let sdf = PathBuf::from(format!("{stem}-docked.sdf"));
        match model::write::write_pdb(mol, &pose, &pdb) {
            Ok(()) => said.push(pdb.display().to_string()),
            Err(e) => self.hud.say(e.to_string()),
        }
        match model::write::write_sdf(mol, &pose, &sdf) {
            Ok(()) => said.push(sdf.display().to_string()),
            Err(e) => self.hud.say(e.to_string()),
        }
        if !said.is_empty() {
            self.hud.say(format!(
                "saved {} in the receptor's frame",
                said.join(" and ")
            ));
        }
    }

    fn screenshot(&mut self) {
        let Some(g) = &self.gfx else { return };
        let name = format!(
            "bump-{}.png",
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0)
        );
        let params = self.hud.view.params(self.light);
        let result = render_image(
            &g.gpu,
            &self.session,
            g.config.width,
            g.config.height,
            &params,
        )
        .and_then(|img| save_png(&img, &PathBuf::from(&name)));
        match result {
            Ok(()) => self.hud.say(format!("saved {name}")),
            Err(e) => self.hud.say(format!("screenshot failed: {e}")),
        }
    }

    fn open_file(&mut self, path: PathBuf) {
        if self.recorder.is_some() || self.player.is_some() {
            // A log replays inputs on a fixed scene; a file opened now would
            // not be in it.
            self.hud.say(format!(
                "{}: opening files is off while recording or replaying",
                path.display()
            ));
            return;
        }
        let opts = LoadOptions::default();
        let loaded = model::load(&path, &opts).and_then(|l| {
            let m = model::receptor_only(&l.structure)?;
            Ok((l.warnings, m))
        });
        match loaded {
            Ok((warnings, m)) => {
                for w in warnings {
                    self.hud.say(w);
                }
                let atoms = if m.len() == 1 { "atom" } else { "atoms" };
                self.hud
                    .say(format!("opened {} ({} {atoms})", m.name, m.len()));
                self.session.add_molecule(m);
                let title = self.title();
                if let Some(g) = &mut self.gfx {
                    let mut spheres =
                        SphereRenderer::new(&g.gpu.device, g.config.format, &self.session);
                    spheres.sync_highlights(&g.gpu.queue, &self.session);
                    g.spheres = spheres;
                    g.window.set_title(&title);
                }
            }
            Err(e) => self.hud.say(format!("{e}")),
        }
    }

    /// Adds molecules to the session and the GPU.
    fn add_molecules(&mut self, molecules: Vec<crate::model::Molecule>) {
        let first = self.session.bodies().is_empty();
        for m in molecules {
            self.session.add_molecule(m);
        }
        if first {
            self.session.frame_all();
        }
        let title = self.title();
        if let Some(g) = &mut self.gfx {
            let mut spheres = SphereRenderer::new(&g.gpu.device, g.config.format, &self.session);
            spheres.sync_highlights(&g.gpu.queue, &self.session);
            g.spheres = spheres;
            g.window.set_title(&title);
            g.window.request_redraw();
        }
    }

    /// Takes what the loading thread has sent; `true` while it is still at work.
    fn poll_loader(&mut self) -> bool {
        let Some((rx, _)) = &self.loader else {
            return false;
        };
        let mut events = Vec::new();
        let mut finished = false;
        loop {
            match rx.try_recv() {
                Ok(e) => events.push(e),
                Err(std::sync::mpsc::TryRecvError::Empty) => break,
                Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                    finished = true;
                    break;
                }
            }
        }
        for e in events {
            match e {
                LoadEvent::Reading(label) => {
                    self.hud.loading = Some(label);
                    self.hud.loading_since = Some(Instant::now());
                }
                LoadEvent::Loaded {
                    label,
                    molecules,
                    warnings,
                    seconds,
                } => {
                    for w in warnings {
                        self.hud.say(w);
                    }
                    let atoms: usize = molecules.iter().map(|m| m.len()).sum();
                    self.hud
                        .say(format!("loaded {label}: {atoms} atoms in {seconds:.2} s"));
                    self.add_molecules(molecules);
                }
                LoadEvent::Failed(msg) => self.hud.say(msg),
            }
        }
        if finished {
            self.loader = None;
            self.hud.loading = None;
            if self.session.bodies().is_empty() {
                self.hud.say(
                    "nothing could be loaded: showing the built-in scene (Ctrl+O opens a file)",
                );
                let (r, d) = crate::model::builtin::scene(crate::model::RadiiSet::Bondi);
                self.add_molecules(vec![r, d]);
            }
        }
        !finished
    }

    fn mouse_moved(&mut self, x: f64, y: f64) {
        let (dx, dy) = (x - self.mouse.pos.0, y - self.mouse.pos.1);
        self.mouse.pos = (x, y);
        if !(self.mouse.left || self.mouse.middle) {
            return;
        }
        let (px, py) = self.mouse.press_at;
        if (x - px).hypot(y - py) > CLICK_SLOP {
            self.mouse.dragged = true;
        }
        let (w, h) = self.gfx.as_ref().map_or((1.0, 1.0), |g| {
            (f64::from(g.config.width), f64::from(g.config.height))
        });
        // Å per pixel at the view centre's depth.
        let cam = *self.session.camera();
        let per_px = 2.0 * cam.distance * (0.5 * cam.fov_y).tan() / h.max(1.0);
        let pan = DVec3::new(dx * per_px, -dy * per_px, 0.0);
        let turn = DVec3::new(dy, dx, 0.0) * (std::f64::consts::PI / w.max(1.0));
        if self.mods.ctrl && self.mouse.left {
            // Modifier-drag moves the selected molecule (through collisions).
            let m = if self.mods.shift {
                Motion6 {
                    translate: DVec3::ZERO,
                    rotate: turn,
                }
            } else {
                Motion6 {
                    translate: pan,
                    rotate: DVec3::ZERO,
                }
            };
            self.pending.object_nudge = self.pending.object_nudge.plus(&m);
        } else {
            // Camera moves go through the session too, so a recording holds them.
            let m = if self.mouse.middle || (self.mouse.left && self.mods.shift) {
                Motion6 {
                    translate: pan,
                    rotate: DVec3::ZERO,
                }
            } else {
                Motion6 {
                    translate: DVec3::ZERO,
                    rotate: turn,
                }
            };
            self.pending.view_nudge = self.pending.view_nudge.plus(&m);
        }
        self.request_redraw();
    }

    fn click(&mut self) {
        let Some(g) = &self.gfx else { return };
        let (x, y) = self.mouse.pos;
        // In side-by-side and top-bottom stereo, pick in the eye's viewport
        // under the pointer (through the mono camera: the eyes agree at the
        // convergence plane); composed modes cover the whole frame.
        let plan = self
            .hud
            .view
            .stereo
            .plan(g.config.width, g.config.height, self.hud.view.frame);
        let full = (
            0.0,
            0.0,
            f64::from(g.config.width),
            f64::from(g.config.height),
            f64::from(g.config.width) / f64::from(g.config.height.max(1)),
        );
        let (vx, vy, vw, vh, aspect) = if plan.compose.is_some() {
            full
        } else {
            plan.eyes
                .iter()
                .map(|e| {
                    let [ex, ey, ew, eh] = e.viewport.map(f64::from);
                    (ex, ey, ew, eh, e.aspect)
                })
                .find(|&(ex, ey, ew, eh, _)| x >= ex && x < ex + ew && y >= ey && y < ey + eh)
                .unwrap_or(full)
        };
        match pick::pick_in(&self.session, x - vx, y - vy, vw, vh, aspect) {
            Some((b, i)) => {
                let m = &self.session.bodies()[b].molecule;
                let a = &m.atoms[i];
                self.hud.picked = Some(format!(
                    "{} {} {}{} {} #{} ({}, r {:.2} Å) in {}",
                    a.name,
                    a.residue,
                    a.chain,
                    a.residue_number(),
                    a.element,
                    a.serial,
                    a.element,
                    a.radius,
                    m.name
                ));
                self.pending.commands.push(Command::Select(b));
            }
            None => self.hud.picked = None,
        }
    }

    /// One frame: step the session, update the GPU, draw scene and HUD.
    /// Returns `true` when the user asked to quit.
    fn frame(&mut self) -> bool {
        // Buttons of the previous frame (egui repaints after a click).
        if std::mem::take(&mut self.hud.save_requested) {
            self.save_pose();
        }
        if std::mem::take(&mut self.hud.open_requested) {
            self.shell_action(ShellAction::Open);
        }
        if let Some(path) = self.hud.chosen_file.take() {
            self.open_file(path);
        }
        let now = Instant::now();
        let mut dt = now.duration_since(self.last_frame).as_secs_f64().min(0.1);
        self.last_frame = now;
        let mut input = std::mem::take(&mut self.pending);
        let v = keymap::velocity(&self.held, self.mods);
        if self.hud.light_mode {
            // Rotation keys turn the light; translation keys do nothing.
            let a = v.rotate * dt;
            if a.length() > 0.0 {
                self.light = DQuat::from_scaled_axis(a) * self.light;
            }
        } else {
            input.velocity = v;
        }
        if let Some(j) = &self.joysticks {
            j.intents().add_to(&mut input);
        }
        let Some(g) = self.gfx.as_mut() else {
            return false;
        };
        // The HUD runs first: its widgets add commands to this frame.
        let raw = g.egui_state.take_egui_input(&g.window);
        let session = &self.session;
        let hud = &mut self.hud;
        let dialog = &mut self.open_dialog;
        let mut hud_cmds = Vec::new();
        let mut full = g.egui_ctx.run_ui(raw, |ui| {
            hud_cmds = hud::show(ui, session, hud);
            if let Some(path) = dialog.ui(ui.ctx()) {
                hud.chosen_file = Some(path);
            }
        });
        input.commands.extend(hud_cmds);
        g.textures
            .0
            .append(std::mem::take(&mut full.textures_delta));
        // A replay ignores live input and steps only when a recorded frame is due.
        let mut step = true;
        if let Some(p) = &mut self.player {
            if input.commands.contains(&Command::Quit) {
                return true; // the user stops the replay
            }
            let started = *p.started.get_or_insert(now);
            let due = p
                .log
                .frames
                .get(p.next)
                .map(|f| p.elapsed + f.dt <= now.duration_since(started).as_secs_f64());
            match due {
                Some(true) => {
                    let f = &p.log.frames[p.next];
                    input = f.input.clone();
                    dt = f.dt;
                    p.elapsed += f.dt;
                    p.next += 1;
                    self.hud.replay = Some(format!("Playing {}/{}", p.next, p.log.frames.len()));
                }
                Some(false) => step = false,
                None => return true,
            }
        }
        if let Some(w) = &mut self.recorder
            && let Err(e) = w.frame(dt, &input)
        {
            self.hud.say(format!("recording stopped: {e}"));
            self.recorder = None;
            self.hud.replay = None;
        }
        let out = if step {
            self.session.step(&input, dt)
        } else {
            crate::session::FrameOutcome::default()
        };
        for m in &out.messages {
            self.hud.say(m.clone());
        }
        if out.quit {
            return true;
        }
        if out.collision_us.is_some() {
            self.hud.collision_us = out.collision_us;
        }
        if out.new_contact {
            if self.hud.flash {
                self.flash_until = Some(now + FLASH);
            }
            self.beeper.beep();
            if let Some(msg) = self.joysticks.as_mut().and_then(|j| j.contact()) {
                self.hud.say(msg);
            }
            self.hud.say(match out.contacts.len() {
                1 => "contact: 1 pair".to_string(),
                n => format!("contact: {n} pairs"),
            });
        }
        g.egui_state
            .handle_platform_output(&g.window, std::mem::take(&mut full.platform_output));
        let flashing = self.flash_until.is_some_and(|t| now < t);
        g.spheres
            .apply_highlights(&g.gpu.queue, &out.highlight_changes);
        let params = self.hud.view.params(self.light);
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(&g.gpu.device, &g.config);
                g.window.request_redraw();
                return false;
            }
            _ => return false,
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let bg = if flashing {
            [0.35, 0.02, 0.05]
        } else {
            BACKGROUND
        };
        let mut encoder = g
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        g.spheres.draw_scene(
            &g.gpu.device,
            &g.gpu.queue,
            &mut encoder,
            &view,
            &g.depth,
            (g.config.width, g.config.height),
            &self.session,
            &params,
            bg,
        );
        // The HUD on top.
        let ppp = full.pixels_per_point;
        let jobs = g.egui_ctx.tessellate(std::mem::take(&mut full.shapes), ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [g.config.width, g.config.height],
            pixels_per_point: ppp,
        };
        // This frame's texture changes and those of frames that drew nothing.
        let mut textures = std::mem::take(&mut g.textures.0);
        for (id, deltas) in textures.set.drain() {
            for delta in deltas {
                g.egui_renderer
                    .update_texture(&g.gpu.device, &g.gpu.queue, id, &delta);
            }
        }
        let extra = g.egui_renderer.update_buffers(
            &g.gpu.device,
            &g.gpu.queue,
            &mut encoder,
            &jobs,
            &screen,
        );
        {
            let pass = color_pass(&mut encoder, "hud", &view, wgpu::LoadOp::Load);
            g.egui_renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        for id in textures.free.drain() {
            g.egui_renderer.free_texture(&id);
        }
        g.gpu
            .queue
            .submit(extra.into_iter().chain(Some(encoder.finish())));
        g.gpu.queue.present(frame);
        self.hud.view.frame += 1;
        self.hud.frame_ms = now.elapsed().as_secs_f64() * 1e3;
        if step {
            self.timing
                .frame(now.elapsed().as_secs_f64() * 1e6, &out.collision_calls);
        }
        // Keep going only while something is moving or animating.
        let egui_wants = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.repaint_delay < Duration::from_millis(100));
        let animating = self.hud.view.animating() || self.session.rock().is_on();
        if input.has_velocity() || flashing || egui_wants || out.changed || animating {
            g.window.request_redraw();
        }
        false
    }
}

impl ApplicationHandler for App {
    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let mut wake: Option<Instant> = None;
        let mut soon = |t: Instant| wake = Some(wake.map_or(t, |w: Instant| w.min(t)));
        if self.poll_loader() {
            // Keep the progress display moving and look again soon.
            soon(now + Duration::from_millis(100));
            self.request_redraw();
        }
        let mut redraw = false;
        if let Some(j) = &mut self.joysticks {
            let said = j.poll();
            if !said.is_empty() {
                self.hud.joysticks = Some(j.describe());
                for m in said {
                    self.hud.say(m);
                }
                redraw = true;
            }
            if j.any() {
                // gilrs does not wake the event loop: poll at ~100 Hz.
                soon(now + Duration::from_millis(10));
                redraw |= !j.intents().is_zero();
            }
        }
        if redraw {
            self.request_redraw();
        }
        if let Some(p) = &self.player {
            let due = p.started.map_or(now, |s| {
                let ahead = p.log.frames.get(p.next).map_or(0.0, |f| p.elapsed + f.dt);
                s + Duration::from_secs_f64(ahead)
            });
            if due <= now {
                self.request_redraw();
            } else {
                soon(due);
            }
        }
        event_loop.set_control_flow(match wake {
            Some(t) => winit::event_loop::ControlFlow::WaitUntil(t),
            None => winit::event_loop::ControlFlow::Wait,
        });
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.init_gfx(event_loop) {
            Ok(g) => {
                g.window.request_redraw();
                self.gfx = Some(g);
            }
            Err(e) => {
                self.fatal = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let consumed = match &mut self.gfx {
            Some(g) => {
                let r = g.egui_state.on_window_event(&g.window, &event);
                if r.repaint {
                    g.window.request_redraw();
                }
                r.consumed
            }
            None => false,
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(g) = &mut self.gfx {
                    g.config.width = size.width.max(1);
                    g.config.height = size.height.max(1);
                    g.surface.configure(&g.gpu.device, &g.config);
                    g.depth = depth_view(&g.gpu.device, g.config.width, g.config.height);
                    g.window.request_redraw();
                }
            }
            WindowEvent::RedrawRequested if self.frame() => event_loop.exit(),
            WindowEvent::ModifiersChanged(m) => {
                let s = m.state();
                self.mods = Mods {
                    shift: s.shift_key(),
                    ctrl: s.control_key(),
                    alt: s.alt_key(),
                };
            }
            WindowEvent::KeyboardInput { event, .. } if !consumed => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.key(code, event.state == ElementState::Pressed, event.repeat);
                    self.request_redraw();
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if !consumed {
                    self.mouse_moved(position.x, position.y);
                } else {
                    self.mouse.pos = (position.x, position.y);
                }
            }
            WindowEvent::MouseInput { state, button, .. } if !consumed => {
                let down = state == ElementState::Pressed;
                match button {
                    MouseButton::Left => {
                        if down {
                            self.mouse.press_at = self.mouse.pos;
                            self.mouse.dragged = false;
                        } else if !self.mouse.dragged {
                            self.click();
                        }
                        self.mouse.left = down;
                    }
                    MouseButton::Middle => self.mouse.middle = down,
                    _ => {}
                }
                self.request_redraw();
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.pending.zoom += steps;
                self.request_redraw();
            }
            WindowEvent::DroppedFile(path) => {
                self.open_file(path);
                self.request_redraw();
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::PendingTextures;

    /// Texture changes kept for a frame that never came (the window closed)
    /// are dropped without tripping egui's debug assertion, which a bare
    /// `TexturesDelta` would (a quit right after a message with new glyphs
    /// did, in a debug build).
    #[test]
    fn texture_changes_never_drawn_are_dropped_quietly() {
        let mut pending = PendingTextures::default();
        let mut delta = egui::TexturesDelta::default();
        delta.set.insert(
            egui::TextureId::Managed(0),
            [egui::epaint::ImageDelta::full(
                egui::ColorImage::filled([2, 2], egui::Color32::WHITE),
                egui::TextureOptions::LINEAR,
            )]
            .into_iter()
            .collect(),
        );
        pending.0.append(delta);
        assert_eq!(pending.0.set.len(), 1);
        drop(pending);
    }
}
