//! The live score in the HUD: a fixed box at the bottom left with the Vina
//! score (total and intermolecular), its weighted terms, the rotatable
//! bonds, the hydrogen bonds, the RMSD to the reference pose and a
//! sparkline of the score over the last scored frames, with the toggles of
//! the views that show the fit.
//!
//! The session computes the score ([`crate::session::LiveScore`], on frames
//! in which the drug moved); this only keeps the latest and the recent
//! totals. Values are written at fixed widths so that a new score never
//! changes the layout.

use std::collections::VecDeque;
use std::sync::Arc;

use crate::render::contrib::ContributionColors;
use crate::session::LiveScore;

/// Totals the sparkline keeps (about two seconds of continuous motion at
/// 60 frames a second; a frame in which the drug did not move adds none).
pub const SPARK_SAMPLES: usize = 120;

/// What the score box shows and its toggles.
#[derive(Debug, Clone, Default)]
pub struct ScorePanel {
    /// The latest score.
    pub last: Option<Arc<LiveScore>>,
    /// Recent totals, oldest first.
    pub totals: VecDeque<f64>,
    /// Atoms coloured by their contribution.
    pub by_contribution: bool,
    /// Hydrogen bonds drawn.
    pub hbonds: bool,
    /// The atoms the renderer has coloured by contribution now.
    pub colors: ContributionColors,
    /// The pocket in ball-and-stick, its labels, and the sticks drawn.
    pub pocket: super::pocket::PocketPanel,
}

impl ScorePanel {
    /// Takes a new score from the frame's outcome.
    pub fn push(&mut self, s: Arc<LiveScore>) {
        if self.totals.len() == SPARK_SAMPLES {
            self.totals.pop_front();
        }
        self.totals.push_back(s.score.total);
        self.last = Some(s);
    }
}

/// The score's lines: total and intermolecular, each weighted term, the
/// rotatable bonds, hydrogen bonds and RMSD.
pub fn lines(s: &LiveScore) -> Vec<String> {
    let sc = &s.score;
    let mut out = vec![
        format!("Vina     {:>8.3} kcal/mol", sc.total),
        format!("inter    {:>8.3}", sc.inter),
        format!("intra    {:>8.3}", sc.intra),
    ];
    for t in &sc.terms {
        out.push(format!("  {:<14} {:>8.3}", t.name, t.inter));
    }
    out.push(format!("rotatable bonds {:>3}", s.rotatable));
    out.push(format!("H-bonds         {:>3}", sc.hbonds.len()));
    let what = if s.pinned { "pinned" } else { "file pose" };
    out.push(format!("RMSD {:>6.2} Å to {what}", s.rmsd));
    out.push(format!("score {:>7.1} µs", s.micros));
    out
}

/// The sparkline's points in a `w`×`h` box: x spread over [`SPARK_SAMPLES`],
/// y from the lowest total (bottom) to the highest (top); a flat series
/// sits in the middle.
pub fn spark_points(totals: &VecDeque<f64>, w: f32, h: f32) -> Vec<[f32; 2]> {
    let (lo, hi) = totals
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let span = hi - lo;
    let step = w / (SPARK_SAMPLES - 1) as f32;
    let offset = SPARK_SAMPLES - totals.len();
    totals
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let f = if span > 0.0 { (v - lo) / span } else { 0.5 };
            [(offset + i) as f32 * step, h * (1.0 - f as f32)]
        })
        .collect()
}

/// Draws the score box.
pub fn show(ctx: &egui::Context, panel: &mut ScorePanel) {
    egui::Window::new("Score")
        .anchor(egui::Align2::LEFT_BOTTOM, [8.0, -40.0])
        .fixed_size([250.0, 320.0])
        .collapsible(true)
        .resizable(false)
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.checkbox(&mut panel.by_contribution, "Colour by contribution");
            });
            ui.checkbox(&mut panel.hbonds, "H-bonds");
            super::pocket::controls(ui, &mut panel.pocket);
            let Some(s) = panel.last.clone() else {
                ui.label("no score yet (needs a drug and a receptor)");
                return;
            };
            for l in lines(&s) {
                ui.monospace(l);
            }
            let (rect, _) = ui.allocate_exact_size(egui::vec2(230.0, 40.0), egui::Sense::hover());
            let painter = ui.painter_at(rect);
            painter.rect_stroke(
                rect,
                0.0,
                egui::Stroke::new(1.0, egui::Color32::from_gray(80)),
                egui::StrokeKind::Inside,
            );
            let pts: Vec<egui::Pos2> =
                spark_points(&panel.totals, rect.width() - 4.0, rect.height() - 4.0)
                    .into_iter()
                    .map(|[x, y]| rect.min + egui::vec2(x + 2.0, y + 2.0))
                    .collect();
            painter.add(egui::Shape::line(
                pts,
                egui::Stroke::new(1.5, egui::Color32::from_rgb(120, 200, 255)),
            ));
            if panel.by_contribution {
                legend(ui);
            }
        });
}

/// The colour scale's legend: favourable, neutral, unfavourable.
fn legend(ui: &mut egui::Ui) {
    use crate::render::colors::{CONTRIBUTION_RANGE, contribution};
    let (rect, _) = ui.allocate_exact_size(egui::vec2(230.0, 12.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let n = 46;
    for i in 0..n {
        let e = CONTRIBUTION_RANGE * (2.0 * (i as f64 + 0.5) / n as f64 - 1.0);
        let c = contribution(e);
        let x0 = rect.min.x + rect.width() * i as f32 / n as f32;
        let x1 = rect.min.x + rect.width() * (i + 1) as f32 / n as f32;
        painter.rect_filled(
            egui::Rect::from_min_max(egui::pos2(x0, rect.min.y), egui::pos2(x1, rect.max.y)),
            0.0,
            egui::Color32::from_rgb(
                (c[0].powf(1.0 / 2.2) * 255.0) as u8,
                (c[1].powf(1.0 / 2.2) * 255.0) as u8,
                (c[2].powf(1.0 / 2.2) * 255.0) as u8,
            ),
        );
    }
    ui.monospace(format!(
        "{:<+5.1} favourable  0  unfavourable {:>+4.1}",
        -CONTRIBUTION_RANGE, CONTRIBUTION_RANGE
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparkline_spans_the_box() {
        let t: VecDeque<f64> = [-5.0, -7.0, -6.0].into_iter().collect();
        let p = spark_points(&t, 119.0, 10.0);
        assert_eq!(p.len(), 3);
        // Newest at the right edge; lowest at the bottom, highest at the top.
        assert_eq!(p[2][0], 119.0);
        assert_eq!(p[0][1], 0.0);
        assert_eq!(p[1][1], 10.0);
        assert_eq!(p[2][1], 5.0);
        let flat: VecDeque<f64> = [1.0].into_iter().collect();
        assert_eq!(spark_points(&flat, 119.0, 10.0), vec![[119.0, 5.0]]);
    }
}
