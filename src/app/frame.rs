//! One frame of the window, in named steps: `input` (what the devices, the
//! HUD's widgets and a replayed log ask for), `step` (the session, and the
//! cues its outcome calls for), `paint` (scene, HUD and marks) and
//! `schedule` (whether and when the next frame comes: none while nothing
//! changes).

use std::time::{Duration, Instant};

use glam::DQuat;

use super::dialogs::{self, Dialog};
use super::gfx::Paint;
use super::player::Due;
use super::{App, overlay};
use crate::render::colors::BACKGROUND;
use crate::session::{Command, FrameInput, FrameOutcome, KeyEvent};

/// How long the background flashes on a new contact.
const FLASH: Duration = Duration::from_millis(150);

/// egui's output for a frame, kept between the input and paint steps.
struct HudPass {
    shapes: Vec<egui::epaint::ClippedShape>,
    pixels_per_point: f32,
    /// egui wants another pass within this time (an animation, a tooltip).
    repaint_after: Option<Duration>,
}

impl App {
    /// One frame; `true` when the user asked to quit.
    pub(super) fn frame(&mut self) -> bool {
        let now = Instant::now();
        let Some((input, dt, hud)) = self.input(now) else {
            return self.player_done;
        };
        let out = match &input {
            Some(i) => self.step(i, dt, now),
            None => FrameOutcome::default(),
        };
        if out.quit {
            return true;
        }
        self.paint(&out, hud, now);
        if let Some(i) = &input {
            self.timing
                .frame(now.elapsed().as_secs_f64() * 1e6, &out.collision_calls);
            self.schedule(i, &out, now);
        }
        false
    }

    /// Gathers the frame's input: the HUD's requests of the last pass, the
    /// keys (with their times into the frame) and joysticks, this pass of
    /// the HUD, and, when replaying, the recorded frame instead. `None`
    /// when there is no window; the input is `None` when a replay has no
    /// frame due yet.
    fn input(&mut self, now: Instant) -> Option<(Option<FrameInput>, f64, HudPass)> {
        self.take_hud_requests();
        let start = if self.idle {
            self.woke_at.unwrap_or(now)
        } else {
            self.last_frame
        };
        self.idle = false;
        self.woke_at = None;
        self.last_frame = now;
        let dt = now.saturating_duration_since(start).as_secs_f64();
        let mut input = std::mem::take(&mut self.pending);
        self.route_keys(&mut input, start, dt);
        if let Some(j) = &self.joysticks {
            let intents = j.intents();
            if self.hud.torsion_stick {
                let (rest, turn) = intents.turning_torsion();
                rest.add_to(&mut input);
                input.torsion_velocity += turn;
            } else {
                intents.add_to(&mut input);
            }
        }
        let hud = self.hud_pass(&mut input)?;
        // A replay ignores live input and steps only when a recorded frame is due.
        if let Some(p) = &mut self.player {
            if input.commands.contains(&Command::Quit) {
                self.player_done = true;
                return None; // the user stops the replay
            }
            return match p.due(now) {
                Due::Frame(recorded, dt) => {
                    self.hud.replay = Some(p.progress());
                    Some((Some(*recorded), dt, hud))
                }
                Due::Wait => Some((None, 0.0, hud)),
                Due::End => {
                    self.player_done = true;
                    None
                }
            };
        }
        if let Some(w) = &mut self.recorder
            && let Err(e) = w.frame(dt, &input)
        {
            self.hud.say(format!("recording stopped: {e}"));
            self.recorder = None;
            self.hud.replay = None;
        }
        Some((Some(input), dt, hud))
    }

    /// The HUD buttons pressed in the last pass (egui reports a click in
    /// the pass after it).
    fn take_hud_requests(&mut self) {
        if std::mem::take(&mut self.hud.save_requested) {
            self.save_pose(self.session.selected());
        }
        if std::mem::take(&mut self.hud.open_requested) {
            self.shell_action(super::keymap::ShellAction::Open);
        }
        if std::mem::take(&mut self.hud.help_requested) {
            self.dialogs.toggle(Dialog::Help);
        }
        if let Some(path) = self.hud.chosen_file.take() {
            self.open_file(path);
        }
    }

    /// Motion keys since the last frame, as times into this frame's
    /// interval (from `start`, `dt` long): to the session, or in light mode
    /// the turn keys to the light.
    fn route_keys(&mut self, input: &mut FrameInput, start: Instant, dt: f64) {
        let keys: Vec<KeyEvent> = self
            .pending_keys
            .drain(..)
            .map(|k| KeyEvent {
                key: k.key,
                size: k.size,
                pressed: k.pressed,
                at: k.at.saturating_duration_since(start).as_secs_f64().min(dt),
            })
            .collect();
        // In light mode the turn keys turn the light and the others do
        // nothing; a release goes to whichever took the press.
        let (mut scene, mut light) = (Vec::new(), Vec::new());
        for k in keys {
            let lit = self.light_keys.held().any(|(h, _)| h == k.key);
            match (k.pressed, self.hud.light_mode) {
                (true, false) => scene.push(k),
                (true, true) if k.key.turn => light.push(k),
                (true, true) => {}
                (false, _) if lit => light.push(k),
                (false, _) => scene.push(k),
            }
        }
        input.keys = scene;
        for s in self.light_keys.advance(&light, dt) {
            let a = s.motion().rotate;
            self.light = DQuat::from_scaled_axis(a) * self.light;
        }
    }

    /// This frame's pass of the HUD, the dialogs and the marks; their
    /// commands join `input`. `None` when there is no window.
    fn hud_pass(&mut self, input: &mut FrameInput) -> Option<HudPass> {
        let g = self.gfx.as_mut()?;
        let mut raw = g.egui_state.take_egui_input(&g.window);
        // Tab selects the drug's next rotatable bond: egui never sees it,
        // so it neither moves the HUD's focus nor takes the keys after it.
        raw.events.retain(|e| {
            !matches!(
                e,
                egui::Event::Key {
                    key: egui::Key::Tab,
                    ..
                }
            )
        });
        let session = &self.session;
        let hud = &mut self.hud;
        let open = &mut self.open_dialog;
        let dialogs = &mut self.dialogs;
        let picked = hud.picked;
        let labels: Vec<(String, usize, usize)> = if hud.score.pocket.labels {
            hud.score
                .pocket
                .view
                .labels()
                .into_iter()
                .map(|(l, k, a)| (l.to_string(), k, a))
                .collect()
        } else {
            Vec::new()
        };
        let plan = hud
            .view
            .stereo
            .plan(g.config.width, g.config.height, hud.view.frame);
        let views = overlay::viewports(&plan, g.config.width, g.config.height);
        let mut cmds = Vec::new();
        let mut choice = None;
        let unsaved: Vec<String> = session
            .unsaved()
            .into_iter()
            .filter_map(|b| session.describe(b))
            .collect();
        let mut full = g.egui_ctx.run_ui(raw, |ui| {
            let ppp = f64::from(ui.ctx().pixels_per_point());
            overlay::draw(ui.ctx(), session, &views, picked, &labels, ppp);
            let mut help = dialogs.is_open(Dialog::Help);
            cmds = super::hud::show(ui, session, hud, &mut help);
            dialogs.set(Dialog::Help, help);
            if let Some(path) = open.ui(ui.ctx()) {
                hud.chosen_file = Some(path);
            }
            dialogs.set(Dialog::Open, open.open);
            if dialogs.is_open(Dialog::ConfirmQuit) {
                choice = dialogs::confirm_quit_ui(ui.ctx(), &unsaved);
            }
        });
        input.commands.extend(cmds);
        g.textures
            .0
            .append(std::mem::take(&mut full.textures_delta));
        g.egui_state
            .handle_platform_output(&g.window, std::mem::take(&mut full.platform_output));
        let repaint_after = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map(|v| v.repaint_delay)
            .filter(|d| *d < Duration::from_secs(3600));
        if let Some(c) = choice {
            self.answer_quit(c);
        }
        Some(HudPass {
            shapes: std::mem::take(&mut full.shapes),
            pixels_per_point: full.pixels_per_point,
            repaint_after,
        })
    }

    /// Steps the session and answers its outcome: messages, the contact
    /// beep, flash and rumble.
    fn step(&mut self, input: &FrameInput, dt: f64, now: Instant) -> FrameOutcome {
        let out = self.session.step(input, dt);
        if !out.reshaped.is_empty() {
            // A bond turned (or undo, reset, settle): the atoms that moved
            // within the drug go to the GPU, nothing else.
            if let Some(g) = self.gfx.as_mut() {
                g.spheres
                    .set_positions(&g.gpu.queue, &self.session, &out.reshaped);
                g.window.request_redraw();
            }
        }
        if let Some(p) = &out.settled {
            self.settle_show = Some(super::settle_show::SettleShow::new(p.clone(), now));
        }
        if let Some(s) = &out.score {
            self.hud.score.push(s.clone());
        }
        for m in &out.messages {
            self.hud.say(m.clone());
        }
        if out.collision_us.is_some() {
            self.hud.collision_us = out.collision_us;
        }
        // The rumble follows the resistance where the drug stands: a frame
        // without a query keeps it, unless soft contacts are off.
        let s = self.session.settings();
        let soft = s.collision && s.response == crate::collide::Response::Soft;
        let resistance = if out.collision_us.is_some() || !soft {
            Some(out.resistance)
        } else {
            None
        };
        if let Some(msg) =
            resistance.and_then(|r| self.joysticks.as_mut().and_then(|j| j.resist(r)))
        {
            self.hud.say(msg);
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
        out
    }

    /// Draws the scene with the outcome's highlight changes, then the HUD.
    fn paint(&mut self, out: &FrameOutcome, hud: HudPass, now: Instant) {
        let flashing = self.flash_until.is_some_and(|t| now < t);
        let params = self.hud.view.params(self.light);
        let Some(g) = self.gfx.as_mut() else { return };
        g.spheres
            .apply_highlights(&g.gpu.queue, &out.highlight_changes);
        // Colours by contribution: only when the score or the toggle changed,
        // and then only the atoms whose colour changed.
        let panel = &mut self.hud.score;
        if panel.by_contribution != panel.colors.shown || out.score.is_some() {
            let score = panel.last.as_deref().filter(|_| panel.by_contribution);
            let changes = panel.colors.update(score);
            g.spheres.set_colors(&g.gpu.queue, &changes);
            panel.colors.shown = panel.by_contribution;
        }
        if let Some(show) = &self.settle_show {
            let b = show.path.body;
            // A move, undo or turn during the animation ends it at once.
            let moved = self.session.bodies().get(b).map(|x| x.pose) != Some(show.path.to)
                || self.session.torsion_angles(b) != show.path.to_torsions.as_slice();
            let shape = if show.done(now) || moved {
                g.spheres.show_pose(None);
                self.settle_show = None;
                self.session
                    .bodies()
                    .get(b)
                    .map(|x| x.molecule.local.clone())
            } else {
                let (pose, torsions) = show.at(show.share(now));
                g.spheres.show_pose(Some((b, pose)));
                self.session.shape_at(b, &torsions).map(|(atoms, _)| atoms)
            };
            if let Some(local) = shape {
                g.spheres.set_local_positions(&g.gpu.queue, b, &local);
            }
        }
        let panel = &mut self.hud.score;
        let hbonds = panel.last.as_deref().filter(|_| panel.hbonds);
        panel.pocket.sync(
            &g.gpu.device,
            &g.gpu.queue,
            &mut g.spheres,
            &self.session,
            out.changed,
            hbonds,
            out.score.is_some(),
        );
        let background = if flashing {
            [0.35, 0.02, 0.05]
        } else {
            BACKGROUND
        };
        let painted = g.paint(
            &self.session,
            Paint {
                params: &params,
                background,
                shapes: hud.shapes,
                pixels_per_point: hud.pixels_per_point,
            },
        );
        if painted {
            self.hud.view.frame += 1;
            self.hud.frame_ms = now.elapsed().as_secs_f64() * 1e3;
        }
        self.hud_repaint = hud.repaint_after;
    }

    /// Whether the next frame comes at once (something animates), at a
    /// known time (a held key's repeat, the end of a flash, a status
    /// message's expiry, egui's own timers), or only on the next event.
    fn schedule(&mut self, input: &FrameInput, out: &FrameOutcome, now: Instant) {
        let animating = self.hud.view.animating()
            || self.session.rock().is_on()
            || input.has_velocity()
            || self.loader.is_some()
            || self.settle_show.is_some();
        let mut at: Vec<Instant> = Vec::new();
        if let Some(s) = self.session.keys().next_repeat_in() {
            at.push(now + Duration::from_secs_f64(s));
        }
        if let Some(s) = self.light_keys.next_repeat_in() {
            at.push(now + Duration::from_secs_f64(s));
        }
        if let Some(t) = self.flash_until.filter(|t| *t > now) {
            at.push(t);
        }
        if let Some(t) = self.hud.status_expires(now) {
            at.push(t);
        }
        if let Some(d) = self.hud_repaint {
            at.push(now + d);
        }
        let keys_held = self.session.keys().any_held() || self.light_keys.any_held();
        self.idle = !(animating || keys_held);
        self.wake_at = at.into_iter().min();
        if animating || out.changed && input.has_velocity() {
            self.request_redraw();
        }
    }
}
