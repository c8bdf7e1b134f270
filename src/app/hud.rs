//! The heads-up display (egui): the thesis's text screen as an overlay.
//!
//! Top bar: mode, selected molecule, collision on/off and response, motion
//! space, contact count, frame and collision times, and a toggle for every
//! option. Right panel: the contacting pairs. Bottom: a typed exact move and
//! the status line. F1 opens the key help.

use crate::collide::Response;
use crate::session::{Command, Mode, Session, Space};

use super::keymap::HELP;

/// Window-side state the HUD shows and edits.
#[derive(Debug, Clone, Default)]
pub struct HudState {
    /// Help overlay visible.
    pub help: bool,
    /// Light mode (rotation keys turn the light).
    pub light_mode: bool,
    /// Background flash on new contacts.
    pub flash: bool,
    /// Milliseconds of the last frame.
    pub frame_ms: f64,
    /// Microseconds of the last collision query.
    pub collision_us: Option<f64>,
    /// Status lines, newest last.
    pub status: Vec<String>,
    /// The typed move, e.g. `1 0 0` or `0 0 0 0 1 0 30`.
    pub typed: String,
    /// The last picked atom's description.
    pub picked: Option<String>,
    /// Set by the Save button; the window writes the files.
    pub save_requested: bool,
    /// Set by the Open button; the window shows the Open dialog.
    pub open_requested: bool,
    /// A file chosen in the Open dialog, to open next frame.
    pub chosen_file: Option<std::path::PathBuf>,
    /// The file being read in the background, if any.
    pub loading: Option<String>,
    /// When the current load started.
    pub loading_since: Option<std::time::Instant>,
    /// The joysticks and their boxes, when joysticks are in use.
    pub joysticks: Option<String>,
    /// Recording or replay progress.
    pub replay: Option<String>,
    /// Depth cues and stereo.
    pub view: super::stereo::ViewState,
}

impl HudState {
    /// Adds a status message (also printed to stderr).
    pub fn say(&mut self, msg: impl Into<String>) {
        let m = msg.into();
        eprintln!("bump: {m}");
        self.status.push(m);
        if self.status.len() > 50 {
            self.status.remove(0);
        }
    }
}

/// Parses a typed move: `dx dy dz` (Å) optionally followed by `ax ay az deg`.
pub fn parse_typed(text: &str) -> Result<Command, String> {
    let nums: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().map_err(|e| format!("`{s}`: {e}")))
        .collect::<Result<_, _>>()?;
    if nums.iter().any(|v| !v.is_finite()) {
        return Err("numbers must be finite".into());
    }
    let v = |i: usize| glam::DVec3::new(nums[i], nums[i + 1], nums[i + 2]);
    match nums.len() {
        3 => Ok(Command::MoveBy {
            translate: v(0),
            axis: glam::DVec3::Z,
            degrees: 0.0,
        }),
        7 => Ok(Command::MoveBy {
            translate: v(0),
            axis: v(3),
            degrees: nums[6],
        }),
        n => Err(format!(
            "expected `dx dy dz` or `dx dy dz ax ay az deg`, got {n} numbers"
        )),
    }
}

/// Draws the HUD into the root `ui`; returns the commands its widgets asked for.
pub fn show(ui: &mut egui::Ui, session: &Session, hud: &mut HudState) -> Vec<Command> {
    let mut cmds = Vec::new();
    let s = session.settings();
    let ctx = ui.ctx().clone();
    egui::Panel::top("hud-top").show(ui, |ui| {
        ui.horizontal_wrapped(|ui| {
            let mode = match session.mode() {
                Mode::View => "View",
                Mode::Object => "Object",
            };
            if let Some(f) = &hud.loading {
                ui.spinner();
                let t = hud
                    .loading_since
                    .map(|t| t.elapsed().as_secs_f64())
                    .unwrap_or(0.0);
                ui.label(format!("Loading {f} … {t:.1} s"));
                ui.separator();
            }
            ui.strong(format!("Mode: {mode}"));
            ui.separator();
            let sel = session
                .bodies()
                .get(session.selected())
                .map(|b| b.molecule.name.as_str())
                .unwrap_or("-");
            ui.label(format!("Selected: {sel}"));
            ui.separator();
            let mut on = s.collision;
            if ui.checkbox(&mut on, "Collision").changed() {
                cmds.push(Command::ToggleCollision);
            }
            let mut response = s.response;
            egui::ComboBox::from_id_salt("response")
                .selected_text(response.name())
                .show_ui(ui, |ui| {
                    for r in Response::ALL {
                        ui.selectable_value(&mut response, r, r.name());
                    }
                });
            if response != s.response {
                cmds.push(Command::SetResponse(response));
            }
            let mut object_space = s.space == Space::Object;
            if ui.checkbox(&mut object_space, "Object space").changed() {
                cmds.push(Command::ToggleSpace);
            }
            ui.checkbox(&mut hud.flash, "Flash");
            ui.checkbox(&mut hud.light_mode, "Light mode");
            ui.separator();
            let (c, said) = super::stereo::controls(ui, &mut hud.view, session.rock().is_on());
            cmds.extend(c);
            said.into_iter().for_each(|m| hud.say(m));
            ui.separator();
            ui.label(format!("Contacts: {}", session.contacts().len()));
            ui.separator();
            if let Some(r) = &hud.replay {
                ui.strong(r);
                ui.separator();
            }
            if let Some(j) = &hud.joysticks {
                ui.label(j);
                ui.separator();
            }
            ui.label(format!("Frame {:.1} ms", hud.frame_ms));
            match hud.collision_us {
                Some(us) => ui.label(format!("Collision {us:.1} µs")),
                None => ui.label("Collision –"),
            };
            ui.separator();
            if ui.button("Undo").clicked() {
                cmds.push(Command::Undo);
            }
            if ui.button("Redo").clicked() {
                cmds.push(Command::Redo);
            }
            if ui.button("Reset").clicked() {
                cmds.push(Command::ResetMolecule);
            }
            if ui.button("Open…").clicked() {
                hud.open_requested = true;
            }
            if ui.button("Save pose").clicked() {
                hud.save_requested = true;
            }
            if ui.button("Help (F1)").clicked() {
                hud.help = !hud.help;
            }
        });
    });
    egui::Panel::bottom("hud-bottom").show(ui, |ui| {
        ui.horizontal(|ui| {
            ui.label("Move dx dy dz [ax ay az deg]:");
            let edit = ui.add(egui::TextEdit::singleline(&mut hud.typed).desired_width(200.0));
            if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                match parse_typed(&hud.typed) {
                    Ok(c) => {
                        cmds.push(c);
                        hud.typed.clear();
                    }
                    Err(e) => hud.say(format!("typed move: {e}")),
                }
            }
            ui.separator();
            if let Some(p) = &hud.picked {
                ui.label(p);
                ui.separator();
            }
            if let Some(last) = hud.status.last() {
                ui.label(last);
            }
        });
    });
    if session.settings().collision && !session.contacts().is_empty() {
        egui::Panel::right("contacts")
            .default_size(280.0)
            .show(ui, |ui| {
                ui.strong("Contacts (distance, overlap)");
                egui::ScrollArea::vertical().show(ui, |ui| {
                    for c in session.contacts().iter().take(200) {
                        let a = &session.bodies()[c.moving.0].molecule.atoms[c.moving.1];
                        let b = &session.bodies()[c.other.0].molecule.atoms[c.other.1];
                        let overlap = a.radius + b.radius - c.distance;
                        ui.monospace(format!(
                            "{:<4}{:<4} – {:<4}{}{} {:<4} {:.2} {:+.2}",
                            a.name,
                            a.residue,
                            b.residue,
                            b.chain,
                            b.residue_number(),
                            b.name,
                            c.distance,
                            overlap
                        ));
                    }
                });
            });
    }
    if hud.help {
        egui::Window::new("Keys and mouse").show(&ctx, |ui| {
            egui::Grid::new("help").striped(true).show(ui, |ui| {
                for (k, what) in HELP {
                    ui.monospace(*k);
                    ui.label(*what);
                    ui.end_row();
                }
            });
        });
    }
    cmds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_moves() {
        assert!(
            matches!(parse_typed("1 2 3"), Ok(Command::MoveBy { degrees, .. }) if degrees == 0.0)
        );
        assert!(
            matches!(parse_typed("0,0,0, 0,1,0, 30"), Ok(Command::MoveBy { degrees, .. }) if degrees == 30.0)
        );
        assert!(parse_typed("1 2").is_err());
        assert!(parse_typed("a b c").is_err());
        assert!(parse_typed("nan 0 0").is_err());
    }
}
