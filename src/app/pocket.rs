//! The pocket in ball-and-stick (key P), its residue labels (Shift+P) and
//! the hydrogen bonds as dashed sticks (key N) in the window: the toggles,
//! the distance in the HUD, and bringing the renderer up to date.
//!
//! The renderer is touched only after a frame in which something moved or
//! a toggle changed, and then uploads only what changed
//! ([`crate::render::sticks::StickView`]): the bond list when the pocket's
//! set of residues changed, the dashes when the hydrogen bonds did.

use crate::render::SphereRenderer;
use crate::render::sticks::{DEFAULT_DISTANCE, DISTANCE_RANGE, StickView};
use crate::session::{LiveScore, Session};

/// The toggles and what the renderer shows now.
#[derive(Debug, Clone)]
pub struct PocketPanel {
    /// Ball-and-stick on.
    pub on: bool,
    /// Residues within this distance of the drug are shown, Å.
    pub distance: f64,
    /// Residue labels shown.
    pub labels: bool,
    /// What the renderer shows.
    pub view: StickView,
    /// The distance the renderer shows (`None`: off).
    shown: Option<f64>,
    /// The renderer shows hydrogen bonds.
    hbonds_shown: bool,
}

impl Default for PocketPanel {
    fn default() -> Self {
        Self {
            on: false,
            distance: DEFAULT_DISTANCE,
            labels: false,
            view: StickView::default(),
            shown: None,
            hbonds_shown: false,
        }
    }
}

impl PocketPanel {
    /// Brings `spheres` up to date after a frame: `moved` when something
    /// moved in it, `hbonds` the hydrogen bonds to draw (`None`: none) and
    /// `new_score` when they were computed in this frame.
    #[allow(clippy::too_many_arguments)] // one frame's inputs, all needed
    pub fn sync(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        spheres: &mut SphereRenderer,
        session: &Session,
        moved: bool,
        hbonds: Option<&LiveScore>,
        new_score: bool,
    ) {
        // Hydrogen bonds lie inside their atoms' full spheres: turning them
        // on (key N or the HUD) shows the pocket in ball-and-stick too.
        if hbonds.is_some() && !self.hbonds_shown {
            self.on = true;
        }
        let want = self.on.then_some(self.distance);
        if moved || want != self.shown {
            self.view.show_pocket(device, queue, spheres, session, want);
            self.shown = want;
        }
        if new_score || hbonds.is_some() != self.hbonds_shown {
            self.view
                .show_hbonds(device, queue, spheres, session, hbonds);
            self.hbonds_shown = hbonds.is_some();
        }
    }

    /// Forgets what the renderer showed (a new renderer after loading).
    pub fn renderer_replaced(&mut self) {
        self.view = StickView::default();
        self.shown = None;
        self.hbonds_shown = false;
    }
}

/// The HUD's ball-and-stick toggles and distance.
pub fn controls(ui: &mut egui::Ui, p: &mut PocketPanel) {
    ui.horizontal(|ui| {
        ui.checkbox(&mut p.on, "Ball-and-stick pocket")
            .on_hover_text("the drug and the residues near it in ball-and-stick (P)");
        let drag = egui::DragValue::new(&mut p.distance)
            .range(DISTANCE_RANGE)
            .speed(0.1)
            .fixed_decimals(1)
            .suffix(" Å");
        ui.add_enabled(p.on, drag)
            .on_hover_text("residues with an atom within this distance of the drug");
    });
    ui.add_enabled(p.on, egui::Checkbox::new(&mut p.labels, "Residue labels"))
        .on_hover_text("the pocket's residues by name and number (Shift+P)");
}
