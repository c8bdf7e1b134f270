//! winit's events: keys through the key table, the mouse (drags, clicks
//! that mark atoms, Ctrl+click or double click that selects, the wheel that
//! zooms towards the pointer), files dropped, quitting (asking first when
//! moves are unsaved), and the wake-ups between frames.

use std::time::{Duration, Instant};

use glam::DVec3;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::WindowId;

use super::dialogs::{self, Dialog, Quit, QuitChoice};
use super::keymap::{self, Action, Mods, ShellAction};
use super::{App, TimedKey, gfx::Gfx, overlay, pick};
use crate::session::{Command, Motion6};

/// Mouse travel (pixels) below which a press-release is a click, not a drag.
const CLICK_SLOP: f64 = 3.0;
/// Two clicks this close in time (and within [`CLICK_SLOP`]) are a double click.
const DOUBLE_CLICK: Duration = Duration::from_millis(400);
/// Turn of the selected rotatable bond per pixel of an Alt+drag, degrees.
const TORSION_PER_PIXEL: f64 = 0.5;
/// Zoom of one wheel notch, in the session's zoom steps (0.9 each): about 5 %.
const WHEEL_ZOOM: f64 = 0.5;

impl App {
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
        self.hud.step = self.mods.step_size().unwrap_or_default();
        if !pressed {
            self.release_step(key);
            return;
        }
        if repeat {
            return; // the session repeats held motion keys itself
        }
        if self.player.is_some() {
            // A replay takes no live input, but the user may stop it.
            if matches!(key, KeyCode::Escape | KeyCode::KeyQ) {
                self.pending.commands.push(Command::Quit);
            }
            return;
        }
        if self.dialogs.is_open(Dialog::ConfirmQuit) {
            if let Some(choice) = dialogs::confirm_key(key) {
                self.answer_quit(choice);
            }
            return;
        }
        match keymap::lookup(key, self.mods) {
            Some((Action::Step(k), Some(size))) => self.press_step(key, k, size),
            Some((Action::Session(c), _)) => self.pending.commands.push(c),
            Some((Action::Shell(a), _)) => self.shell_action(a),
            _ => {}
        }
    }

    fn press_step(
        &mut self,
        code: KeyCode,
        key: crate::session::StepKey,
        size: crate::session::StepSize,
    ) {
        if self.held_steps.iter().any(|(c, _)| *c == code) {
            return;
        }
        self.held_steps.push((code, key));
        self.pending_keys.push(TimedKey {
            at: Instant::now(),
            key,
            size,
            pressed: true,
        });
    }

    fn release_step(&mut self, code: KeyCode) {
        let Some(k) = self.held_steps.iter().position(|(c, _)| *c == code) else {
            return;
        };
        let (_, key) = self.held_steps.remove(k);
        self.pending_keys.push(TimedKey {
            at: Instant::now(),
            key,
            size: crate::session::StepSize::Normal,
            pressed: false,
        });
    }

    /// Releases every motion key (the window lost the keyboard, so their
    /// releases would never come).
    fn release_all_steps(&mut self) {
        let codes: Vec<KeyCode> = self.held_steps.iter().map(|(c, _)| *c).collect();
        for c in codes {
            self.release_step(c);
        }
    }

    pub(super) fn shell_action(&mut self, a: ShellAction) {
        match a {
            ShellAction::ToggleHelp => self.dialogs.toggle(Dialog::Help),
            ShellAction::ToggleLight => {
                self.hud.light_mode = !self.hud.light_mode;
                let state = if self.hud.light_mode { "on" } else { "off" };
                self.hud.say(format!("light mode {state}"));
            }
            ShellAction::ToggleFlash => self.hud.flash = !self.hud.flash,
            ShellAction::Screenshot => self.screenshot(),
            ShellAction::SavePose => {
                self.save_pose(self.session.selected());
            }
            ShellAction::Open => {
                self.open_dialog
                    .show_at(std::env::current_dir().unwrap_or_default());
                self.dialogs.open(Dialog::Open);
            }
            ShellAction::Quit => self.request_quit(),
            ShellAction::Escape => match self.dialogs.escape() {
                Some(Dialog::Open) => self.open_dialog.open = false,
                Some(_) => {}
                None => self.request_quit(),
            },
            ShellAction::Cue(c) => {
                let msg = self.hud.view.apply(c);
                self.hud.say(msg);
            }
            ShellAction::ToggleContribution => {
                let on = !self.hud.score.by_contribution;
                self.hud.score.by_contribution = on;
                self.hud
                    .say(format!("colour by contribution {}", on_off(on)));
            }
            ShellAction::ToggleHBonds => {
                let on = !self.hud.score.hbonds;
                self.hud.score.hbonds = on;
                self.hud.say(format!("hydrogen bonds {}", on_off(on)));
                if on && !self.hud.score.pocket.on {
                    // The next frame turns ball-and-stick on (PocketPanel::sync).
                    self.hud.say("the pocket in ball-and-stick shows them (P)");
                }
            }
            ShellAction::TogglePocket => {
                let p = &mut self.hud.score.pocket;
                p.on = !p.on;
                let msg = format!(
                    "pocket in ball-and-stick {} (residues within {:.1} Å)",
                    on_off(p.on),
                    p.distance
                );
                self.hud.say(msg);
            }
            ShellAction::ToggleTorsionStick => {
                self.hud.torsion_stick = !self.hud.torsion_stick;
                let msg = if self.hud.torsion_stick {
                    "torsion mode on: the joystick's rotation turns the selected bond (Tab selects)"
                } else {
                    "torsion mode off: the joystick's rotation turns again"
                };
                self.hud.say(msg);
            }
            ShellAction::ToggleResidueLabels => {
                let p = &mut self.hud.score.pocket;
                p.labels = !p.labels;
                if p.labels && !p.on {
                    p.on = true;
                }
                let msg = format!("residue labels {}", on_off(p.labels));
                self.hud.say(msg);
            }
        }
    }

    /// Q, Escape with no dialog, the window's close button: quit, or ask
    /// first when a molecule moved since it was saved.
    pub(super) fn request_quit(&mut self) {
        let unsaved = self.player.is_none() && !self.session.unsaved().is_empty();
        if self.dialogs.quit(unsaved) == Quit::Now {
            self.pending.commands.push(Command::Quit);
        }
    }

    /// The confirmation's answer.
    pub(super) fn answer_quit(&mut self, choice: QuitChoice) {
        if !self.dialogs.answer(choice) {
            return;
        }
        if choice == QuitChoice::SaveAndQuit && !self.save_unsaved() {
            self.hud.say("not quitting: a pose could not be saved");
            return;
        }
        self.pending.commands.push(Command::Quit);
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
        let (w, h) = self.size();
        let per_px = self.angstroms_per_pixel(h);
        let pan = DVec3::new(dx * per_px, -dy * per_px, 0.0);
        let turn = DVec3::new(dy, dx, 0.0) * (std::f64::consts::PI / w.max(1.0));
        let only = |translate: DVec3, rotate: DVec3| Motion6 { translate, rotate };
        if self.mods.alt && self.mouse.left {
            // Alt+drag turns the selected rotatable bond: right turns it on.
            self.pending.torsion_nudge += dx * TORSION_PER_PIXEL;
        } else if self.mods.ctrl && self.mouse.left {
            // Modifier-drag moves the selected molecule (through collisions).
            let m = if self.mods.shift {
                only(DVec3::ZERO, turn)
            } else {
                only(pan, DVec3::ZERO)
            };
            self.pending.object_nudge = self.pending.object_nudge.plus(&m);
        } else {
            // Camera moves go through the session too, so a recording holds them.
            let m = if self.mouse.middle || (self.mouse.left && self.mods.shift) {
                only(pan, DVec3::ZERO)
            } else {
                only(DVec3::ZERO, turn)
            };
            self.pending.view_nudge = self.pending.view_nudge.plus(&m);
        }
        self.request_redraw();
    }

    /// The window's size in pixels.
    fn size(&self) -> (f64, f64) {
        self.gfx.as_ref().map_or((1.0, 1.0), |g| {
            (f64::from(g.config.width), f64::from(g.config.height))
        })
    }

    /// Å per pixel at the view centre's depth.
    fn angstroms_per_pixel(&self, height: f64) -> f64 {
        let cam = *self.session.camera();
        2.0 * cam.distance * (0.5 * cam.fov_y).tan() / height.max(1.0)
    }

    /// The wheel: zoom by `notches`, keeping the point under the pointer
    /// (at the view centre's depth) where it is on screen.
    fn wheel(&mut self, notches: f64) {
        let steps = notches * WHEEL_ZOOM;
        let (w, h) = self.size();
        let per_px = self.angstroms_per_pixel(h);
        let (x, y) = self.mouse.pos;
        let s = DVec3::new((x - 0.5 * w) * per_px, (0.5 * h - y) * per_px, 0.0);
        // The distance becomes k times as far; moving the camera centre by
        // s(1 − k) keeps the point at screen offset s in place.
        let k = 0.9f64.powf(steps);
        let m = Motion6 {
            translate: -s * (1.0 - k),
            rotate: DVec3::ZERO,
        };
        self.pending.view_nudge = self.pending.view_nudge.plus(&m);
        self.pending.zoom += steps;
        self.request_redraw();
    }

    /// A click: marks the atom under the pointer (or clears the mark);
    /// with Ctrl, or a second click at the same place, also selects its
    /// molecule; with Alt, selects its molecule and the rotatable bond
    /// nearest to it.
    fn click(&mut self) {
        let Some(g) = &self.gfx else { return };
        let (x, y) = self.mouse.pos;
        let now = Instant::now();
        let double = self.mouse.last_click.is_some_and(|(t, (px, py))| {
            now.duration_since(t) < DOUBLE_CLICK && (x - px).hypot(y - py) <= CLICK_SLOP
        });
        self.mouse.last_click = Some((now, (x, y)));
        let plan = self
            .hud
            .view
            .stereo
            .plan(g.config.width, g.config.height, self.hud.view.frame);
        let views = overlay::viewports(&plan, g.config.width, g.config.height);
        let hit = views
            .iter()
            .find(|&&(vx, vy, vw, vh, _)| x >= vx && x < vx + vw && y >= vy && y < vy + vh)
            .and_then(|&(vx, vy, vw, vh, aspect)| {
                let view = &self.hud.view;
                let slab = view.slab_on.then(|| view.slab.planes(&self.session));
                pick::pick_clipped(&self.session, x - vx, y - vy, vw, vh, aspect, slab)
            });
        self.hud.picked = hit;
        let Some((b, atom)) = hit else { return };
        let other = b != self.session.selected();
        if self.mods.ctrl || double || (self.mods.alt && other) {
            self.pending.commands.push(Command::Select(b));
        }
        if self.mods.alt {
            self.pending.commands.push(Command::SelectTorsionNear(atom));
        }
    }

    /// Wakes the loop for a due frame, the loader and the joysticks.
    fn wake_ups(&mut self, event_loop: &ActiveEventLoop) {
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
        if let Some(p) = &self.player {
            let due = p.next_at(now);
            if due <= now {
                redraw = true;
            } else {
                soon(due);
            }
        }
        if let Some(t) = self.wake_at {
            if t <= now {
                self.wake_at = None;
                redraw = true;
            } else {
                soon(t);
            }
        }
        if redraw {
            self.request_redraw();
        }
        event_loop.set_control_flow(match wake {
            Some(t) => ControlFlow::WaitUntil(t),
            None => ControlFlow::Wait,
        });
    }

    fn mouse_button(&mut self, button: MouseButton, down: bool) {
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
}

impl ApplicationHandler for App {
    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.wake_ups(event_loop);
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match Gfx::new(event_loop, &self.title(), &self.session) {
            Ok(g) => {
                self.hud.say(format!("rendering with {}", g.gpu.describe()));
                self.hud.view.refresh_millihertz = g
                    .window
                    .current_monitor()
                    .and_then(|m| m.refresh_rate_millihertz());
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
                // egui-winit takes every Tab (to move its focus); here Tab
                // selects the drug's next rotatable bond (hud_pass keeps it
                // from egui), unless a text field has the keyboard.
                let tab = matches!(
                    &event,
                    WindowEvent::KeyboardInput { event: k, .. }
                        if k.physical_key == PhysicalKey::Code(KeyCode::Tab)
                );
                let consumed = if tab {
                    g.egui_ctx.egui_wants_keyboard_input()
                } else {
                    r.consumed
                };
                // egui asks to repaint for every RedrawRequested, the frame
                // this event is about to draw: asking again for it would
                // redraw for ever (the window never idled: 40–80 % of a
                // core under Xvfb with nothing moving).
                let redrawing = matches!(event, WindowEvent::RedrawRequested);
                if r.repaint && !redrawing {
                    self.request_redraw();
                }
                consumed
            }
            None => false,
        };
        match event {
            WindowEvent::CloseRequested => {
                self.request_quit();
                self.request_redraw();
            }
            WindowEvent::Resized(size) => {
                if let Some(g) = &mut self.gfx {
                    g.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested if self.frame() => event_loop.exit(),
            WindowEvent::Focused(false) => {
                self.release_all_steps();
                self.mods = Mods::default();
                self.request_redraw();
            }
            WindowEvent::ModifiersChanged(m) => {
                let s = m.state();
                self.mods = Mods {
                    shift: s.shift_key(),
                    ctrl: s.control_key(),
                    alt: s.alt_key(),
                };
                self.hud.step = self.mods.step_size().unwrap_or_default();
            }
            WindowEvent::KeyboardInput { event, .. } => {
                // A release always counts (a key pressed before a text field
                // took the keyboard must not stay held).
                let pressed = event.state == ElementState::Pressed;
                if let PhysicalKey::Code(code) = event.physical_key
                    && (!consumed || !pressed)
                {
                    self.key(code, pressed, event.repeat);
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
                self.mouse_button(button, state == ElementState::Pressed);
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                if self.mods.alt {
                    let msg = self.hud.view.slab_thicker(notches.round());
                    self.hud.say(msg);
                    self.request_redraw();
                } else {
                    self.wheel(notches);
                }
            }
            WindowEvent::DroppedFile(path) => self.open_file(path),
            _ => {}
        }
    }
}

fn on_off(on: bool) -> &'static str {
    if on { "on" } else { "off" }
}
