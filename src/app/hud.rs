//! The heads-up display (egui): the thesis's text screen as an overlay.
//!
//! Top bar: mode, what is selected (in a chemist's words), collision on/off
//! and response, motion space, the step sizes of the motion keys, contact
//! count, the last frame's time and collision time, and a toggle for every
//! option. Contacts: a fixed box at the top right, in columns, shown while
//! collision is on (it floats, so the layout never shifts). Bottom: a typed
//! exact move, the marked atom and the status line, whose messages expire
//! after [`STATUS_SECONDS`]. F1 opens the key help, generated from the key
//! table.
//!
//! Nothing here asks egui for frames: the frame time is written in a fixed
//! width, so a new value never changes the layout (a layout change would
//! make egui ask for another pass, and the window would never idle).

use std::time::{Duration, Instant};

use crate::collide::Response;
use crate::session::{Command, Mode, Session, Space, StepSize, labels};

use super::keymap::help_rows;

/// How long a status message stays on the status line.
pub const STATUS_SECONDS: f64 = 6.0;

/// Window-side state the HUD shows and edits.
#[derive(Debug, Clone, Default)]
pub struct HudState {
    /// Light mode (rotation keys turn the light).
    pub light_mode: bool,
    /// Background flash on new contacts.
    pub flash: bool,
    /// Milliseconds of the last frame.
    pub frame_ms: f64,
    /// Microseconds of the last collision query.
    pub collision_us: Option<f64>,
    /// Status messages with when they were said, newest last.
    pub status: Vec<(Instant, String)>,
    /// The typed move, e.g. `1 0 0` or `0 0 0 0 1 0 30`.
    pub typed: String,
    /// The marked atom: (molecule, atom).
    pub picked: Option<(usize, usize)>,
    /// The step size the modifiers held now give the motion keys.
    pub step: StepSize,
    /// Set by the Save button; the window writes the files.
    pub save_requested: bool,
    /// Set by the Open button; the window shows the Open dialog.
    pub open_requested: bool,
    /// Set by the Help button.
    pub help_requested: bool,
    /// A file chosen in the Open dialog, to open next frame.
    pub chosen_file: Option<std::path::PathBuf>,
    /// The file being read in the background, if any.
    pub loading: Option<String>,
    /// When the current load started.
    pub loading_since: Option<Instant>,
    /// The joysticks and their boxes, when joysticks are in use.
    pub joysticks: Option<String>,
    /// Recording or replay progress.
    pub replay: Option<String>,
    /// Depth cues and stereo.
    pub view: super::stereo::ViewState,
    /// The live score and the views of the fit.
    pub score: super::score_panel::ScorePanel,
    /// The torsion mode of the joysticks: their rotation turns the
    /// selected rotatable bond.
    pub torsion_stick: bool,
}

impl HudState {
    /// Adds a status message; it is also printed on stderr, once.
    pub fn say(&mut self, msg: impl Into<String>) {
        let m = msg.into();
        eprintln!("bump: {m}");
        self.status.push((Instant::now(), m));
        if self.status.len() > 50 {
            self.status.remove(0);
        }
    }

    /// The status message still shown at `now`, if any.
    pub fn current_status(&self, now: Instant) -> Option<&str> {
        self.status
            .last()
            .filter(|(t, _)| now.duration_since(*t).as_secs_f64() < STATUS_SECONDS)
            .map(|(_, m)| m.as_str())
    }

    /// When the status line next changes by itself (its message expires).
    pub fn status_expires(&self, now: Instant) -> Option<Instant> {
        let (t, _) = self.status.last()?;
        let end = *t + Duration::from_secs_f64(STATUS_SECONDS);
        (end > now).then_some(end)
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

/// The step sizes for the HUD: `step 0.2 Å 2.25° (Shift 1 Å 11.25°, Alt 0.04 Å 0.45°)`
/// with the size the modifiers give now first.
pub fn step_text(now: StepSize) -> String {
    let z = |s: StepSize| format!("{} Å {}°", s.angstroms(), s.degrees());
    format!(
        "step {} {} (Shift {}, Alt {})",
        now.name(),
        z(now),
        z(StepSize::Coarse),
        z(StepSize::Fine)
    )
}

/// What is selected, for the top bar.
pub fn selected_text(session: &Session) -> String {
    session
        .describe(session.selected())
        .unwrap_or_else(|| "nothing".into())
}

/// Draws the HUD into the root `ui`; `help` is whether the help is open
/// (its close button clears it). Returns the commands its widgets asked for.
pub fn show(
    ui: &mut egui::Ui,
    session: &Session,
    hud: &mut HudState,
    help: &mut bool,
) -> Vec<Command> {
    let mut cmds = Vec::new();
    let ctx = ui.ctx().clone();
    egui::Panel::top("hud-top").show(ui, |ui| {
        ui.horizontal_wrapped(|ui| top_bar(ui, session, hud, &mut cmds));
    });
    egui::Panel::bottom("hud-bottom").show(ui, |ui| {
        ui.horizontal(|ui| bottom_bar(ui, session, hud, &mut cmds));
    });
    if session.settings().collision {
        contacts_box(&ctx, session);
    }
    super::score_panel::show(&ctx, &mut hud.score);
    if *help {
        egui::Window::new("Keys and mouse (Escape closes)")
            .open(help)
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .default_height(560.0)
            .show(&ctx, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    egui::Grid::new("help").striped(true).show(ui, |ui| {
                        for (k, what) in help_rows() {
                            ui.monospace(k);
                            ui.label(what);
                            ui.end_row();
                        }
                    });
                });
            });
    }
    cmds
}

fn top_bar(ui: &mut egui::Ui, session: &Session, hud: &mut HudState, cmds: &mut Vec<Command>) {
    let s = session.settings();
    if let Some(f) = &hud.loading {
        ui.spinner();
        let t = hud
            .loading_since
            .map(|t| t.elapsed().as_secs_f64())
            .unwrap_or(0.0);
        ui.label(format!("Loading {f} … {t:.1} s"));
        ui.separator();
    }
    let mode = match session.mode() {
        Mode::View => "View",
        Mode::Object => "Object",
    };
    ui.strong(format!("Mode: {mode}"));
    ui.separator();
    ui.label(format!("Selected {}", selected_text(session)));
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
    if s.response == Response::Soft {
        let mut limit = s.soft_limit;
        let drag = egui::DragValue::new(&mut limit)
            .range(0.0..=crate::collide::soft::MAX_LIMIT)
            .speed(0.01)
            .suffix(" Å");
        if ui
            .add(drag)
            .on_hover_text(
                "soft limit: how far beyond the contact rule the drug may press (Shift+R, Alt+R)",
            )
            .changed()
        {
            cmds.push(Command::SetSoftLimit(limit));
        }
        press_legend(ui);
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
    torsion_controls(ui, session, hud, cmds);
    ui.label(step_text(hud.step));
    ui.separator();
    ui.monospace(format!("Contacts {:>4}", session.contacts().len()));
    ui.separator();
    if let Some(r) = &hud.replay {
        ui.strong(r);
        ui.separator();
    }
    if let Some(j) = &hud.joysticks {
        ui.label(j);
        ui.separator();
    }
    // Fixed widths: a new value never changes the layout.
    ui.monospace(format!("frame {:>7.1} ms", hud.frame_ms));
    match hud.collision_us {
        Some(us) => ui.monospace(format!("collision {us:>8.1} µs")),
        None => ui.monospace("collision        – µs"),
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
    if ui
        .button("Settle")
        .on_hover_text("minimise the drug's Vina score from here (G)")
        .clicked()
    {
        cmds.push(Command::Settle);
    }
    if ui.button("Open…").clicked() {
        hud.open_requested = true;
    }
    if ui.button("Save pose").clicked() {
        hud.save_requested = true;
    }
    if ui.button("Help (F1)").clicked() {
        hud.help_requested = true;
    }
}

/// The selected molecule's rotatable bonds: which is selected (with its
/// angle) and the joysticks' torsion mode; nothing for a rigid molecule.
fn torsion_controls(
    ui: &mut egui::Ui,
    session: &Session,
    hud: &mut HudState,
    cmds: &mut Vec<Command>,
) {
    let b = session.selected();
    let n = session.rotatable_bonds(b).len();
    if n == 0 {
        return;
    }
    if ui
        .button("<")
        .on_hover_text("previous rotatable bond (Shift+Tab)")
        .clicked()
    {
        cmds.push(Command::PreviousTorsion);
    }
    let text = match session.selected_torsion() {
        Some(k) => {
            let a = session
                .torsion_angles(b)
                .get(k)
                .map_or(0.0, |a| a.to_degrees());
            format!("bond {:>2}/{n} {a:>+5.0}°", k + 1)
        }
        None => format!("bond  –/{n}      "),
    };
    ui.monospace(text);
    if ui
        .button(">")
        .on_hover_text("next rotatable bond (Tab); ; and ' turn it")
        .clicked()
    {
        cmds.push(Command::NextTorsion);
    }
    ui.checkbox(&mut hud.torsion_stick, "Stick turns bond")
        .on_hover_text("the joystick's rotation turns the selected bond (\\)");
    ui.separator();
}

fn bottom_bar(ui: &mut egui::Ui, session: &Session, hud: &mut HudState, cmds: &mut Vec<Command>) {
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
    let picked = hud.picked.and_then(|(k, i)| {
        session
            .bodies()
            .get(k)
            .and_then(|b| labels::atom(&b.molecule, i))
    });
    if let Some(p) = picked {
        ui.label(p);
        ui.separator();
    }
    if let Some(m) = hud.current_status(Instant::now()) {
        ui.label(m);
    }
}

/// The contacting pairs in columns: drug atom, the other residue and atom,
/// distance and overlap.
fn contacts_box(ctx: &egui::Context, session: &Session) {
    egui::Window::new("Contacts")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 48.0])
        .fixed_size([330.0, 260.0])
        .collapsible(true)
        .resizable(false)
        .show(ctx, |ui| {
            let contacts = session.contacts();
            if contacts.is_empty() {
                ui.label("no contacts");
                return;
            }
            egui::ScrollArea::vertical().show(ui, |ui| {
                egui::Grid::new("contact-rows")
                    .striped(true)
                    .num_columns(5)
                    .show(ui, |ui| {
                        for h in ["drug atom", "residue", "atom", "d Å", "overlap Å"] {
                            ui.strong(h);
                        }
                        ui.end_row();
                        // Under soft, a pressed pair's overlap takes its
                        // atoms' graded colour.
                        let settings = session.settings();
                        let limit =
                            (settings.response == Response::Soft).then_some(settings.soft_limit);
                        for c in contacts.iter().take(200) {
                            let a = &session.bodies()[c.moving.0].molecule.atoms[c.moving.1];
                            let b = &session.bodies()[c.other.0].molecule.atoms[c.other.1];
                            let overlap = a.radius + b.radius - c.distance;
                            ui.monospace(format!("{} {}", a.name.trim(), a.residue));
                            ui.monospace(labels::residue(b));
                            ui.monospace(b.name.trim());
                            ui.monospace(format!("{:.2}", c.distance));
                            let mut text =
                                egui::RichText::new(format!("{overlap:+.2}")).monospace();
                            let level = crate::session::press_level(c.depth(), limit);
                            if level > 1 {
                                let [r, g, b] = crate::render::colors::contact_colour(level);
                                text = text.color(egui::Rgba::from_rgb(r, g, b));
                            }
                            ui.label(text);
                            ui.end_row();
                        }
                    });
            });
        });
}

/// The soft band's colours, touching to the limit, as small squares
/// (painted rather than written: egui draws symbols such as ■ from its
/// emoji font).
fn press_legend(ui: &mut egui::Ui) {
    use crate::render::colors::contact_colour;
    let side = ui.text_style_height(&egui::TextStyle::Body) * 0.7;
    let levels = crate::session::PRESS_LEVELS;
    let size = egui::vec2(side * f32::from(levels), side);
    let (rect, response) = ui.allocate_exact_size(size, egui::Sense::hover());
    for level in 1..=levels {
        let [r, g, b] = contact_colour(level);
        let x = rect.left() + side * f32::from(level - 1);
        let cell = egui::Rect::from_min_size(egui::pos2(x, rect.top()), egui::vec2(side, side));
        ui.painter()
            .rect_filled(cell, 0.0, egui::Rgba::from_rgb(r, g, b));
    }
    response.on_hover_text(
        "contact colours: magenta touching, graded by depth to yellow at the soft limit",
    );
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

    #[test]
    fn status_messages_expire() {
        let mut h = HudState::default();
        let t0 = Instant::now();
        assert_eq!(h.current_status(t0), None);
        h.say("saved x.pdb");
        assert_eq!(h.current_status(Instant::now()), Some("saved x.pdb"));
        let later = Instant::now() + Duration::from_secs_f64(STATUS_SECONDS + 0.1);
        assert_eq!(h.current_status(later), None);
        assert!(h.status_expires(Instant::now()).is_some());
        assert_eq!(h.status_expires(later), None);
    }

    #[test]
    fn the_step_sizes_are_shown() {
        assert_eq!(
            step_text(StepSize::Coarse),
            "step coarse 1 Å 11.25° (Shift 1 Å 11.25°, Alt 0.04 Å 0.45°)"
        );
    }
}
