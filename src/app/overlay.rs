//! Marks drawn over the scene with egui's painter: the atom the user
//! clicked (a ring and its name), the drug (corner brackets and its
//! name, always on, so a drug hidden inside the receptor is still found),
//! the selected rotatable bond (a thick orange line along it, with its
//! number and angle) and, when asked, the names of the pocket's residues at their alpha
//! carbons (Shift+P). Hydrogen bonds are drawn by the renderer, as dashed
//! sticks.
//!
//! Points are projected through the session's view camera as the renderer
//! does, in each eye's viewport when stereo splits the frame (through the
//! mono camera: the eyes agree at the convergence plane).

use glam::DVec3;

use crate::render::stereo::Plan;
use crate::session::{Camera, Session, labels};

/// A viewport in pixels: x, y, width, height and its projection's aspect.
pub type Viewport = (f64, f64, f64, f64, f64);

/// The viewports a frame of `plan` shows the scene in (the whole frame
/// when the eyes are composed into it).
pub fn viewports(plan: &Plan, width: u32, height: u32) -> Vec<Viewport> {
    let (w, h) = (f64::from(width), f64::from(height.max(1)));
    if plan.compose.is_some() || plan.eyes.is_empty() {
        return vec![(0.0, 0.0, w, h, w / h)];
    }
    let mut out: Vec<Viewport> = Vec::new();
    for e in &plan.eyes {
        let [x, y, vw, vh] = e.viewport.map(f64::from);
        let v = (x, y, vw, vh, e.aspect);
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// Where world point `p` falls in viewport `v` (pixels) and how many pixels
/// a length of `radius` Å there spans; `None` behind the eye.
pub fn project(cam: &Camera, v: Viewport, p: DVec3, radius: f64) -> Option<(f64, f64, f64)> {
    let (x, y, w, h, aspect) = v;
    let q = cam.view_matrix().transform_point3(p);
    let depth = -q.z;
    if depth <= 1e-6 {
        return None;
    }
    let f = 1.0 / (0.5 * cam.fov_y).tan();
    let ndc_x = q.x / depth * f / aspect;
    let ndc_y = q.y / depth * f;
    let sx = x + (ndc_x + 1.0) * 0.5 * w;
    let sy = y + (1.0 - ndc_y) * 0.5 * h;
    let r = radius / depth * f * 0.5 * h;
    Some((sx, sy, r))
}

const DRUG: egui::Color32 = egui::Color32::from_rgb(255, 214, 64);
const PICKED: egui::Color32 = egui::Color32::from_rgb(90, 220, 255);
/// The selected rotatable bond: orange, apart from every element colour.
const BOND: egui::Color32 = egui::Color32::from_rgb(255, 140, 0);
/// Residue labels: light grey, as ChimeraX writes them.
const RESIDUE: egui::Color32 = egui::Color32::from_rgb(225, 225, 225);

/// Draws the marks for `session` into `ctx`'s foreground: the drug, the
/// picked atom (molecule, atom) and the residue `labels` (text, molecule,
/// the atom it is written at), in each of `views`; `ppp` is egui's pixels
/// per point.
pub fn draw(
    ctx: &egui::Context,
    session: &Session,
    views: &[Viewport],
    picked: Option<(usize, usize)>,
    labels: &[(String, usize, usize)],
    ppp: f64,
) {
    let painter = ctx.layer_painter(egui::LayerId::background());
    let cam = session.view_camera();
    let pt = |x: f64, y: f64| egui::pos2((x / ppp) as f32, (y / ppp) as f32);
    let font = egui::FontId::proportional(13.0);
    let small = egui::FontId::proportional(11.0);
    for &v in views {
        for (text, k, i) in labels {
            let Some(p) = session
                .bodies()
                .get(*k)
                .and_then(|b| Some(b.pose.transform_point(b.molecule.local.get(*i)?.as_dvec3())))
            else {
                continue;
            };
            if let Some((x, y, _)) = project(&cam, v, p, 0.0) {
                painter.text(
                    pt(x, y),
                    egui::Align2::CENTER_BOTTOM,
                    text,
                    small.clone(),
                    RESIDUE,
                );
            }
        }
        if let Some(d) = session.drug().filter(|_| session.bodies().len() > 1) {
            let b = &session.bodies()[d];
            let r = b.molecule.bounding_radius();
            if let Some((x, y, pr)) = project(&cam, v, b.pose.translation, r) {
                let half = (pr / ppp).clamp(8.0, 400.0) as f32;
                brackets(&painter, pt(x, y), half, DRUG);
                let label = session.describe(d).unwrap_or_default();
                painter.text(
                    pt(x, y) + egui::vec2(-half, -half - 3.0),
                    egui::Align2::LEFT_BOTTOM,
                    label,
                    font.clone(),
                    DRUG,
                );
            }
        }
        selected_bond(&painter, session, &cam, v, ppp, &font);
        let Some((k, i)) = picked else { continue };
        let Some(b) = session.bodies().get(k) else {
            continue;
        };
        let (Some(local), Some(atom)) = (b.molecule.local.get(i), b.molecule.atoms.get(i)) else {
            continue;
        };
        let p = b.pose.transform_point(local.as_dvec3());
        if let Some((x, y, pr)) = project(&cam, v, p, f64::from(atom.radius)) {
            let r = (pr / ppp).max(4.0) as f32;
            painter.circle_stroke(pt(x, y), r, egui::Stroke::new(2.0, PICKED));
            let name = labels::atom(&b.molecule, i).unwrap_or_default();
            painter.text(
                pt(x, y) + egui::vec2(r + 4.0, 0.0),
                egui::Align2::LEFT_CENTER,
                name.trim_start_matches("atom: "),
                font.clone(),
                PICKED,
            );
        }
    }
}

/// The selected molecule's selected rotatable bond in viewport `v`: a
/// thick line between its two atoms and, beside its middle, which bond of
/// how many it is and its torsion (degrees from the file's angle).
fn selected_bond(
    painter: &egui::Painter,
    session: &Session,
    cam: &Camera,
    v: Viewport,
    ppp: f64,
    font: &egui::FontId,
) {
    let b = session.selected();
    let (Some(k), Some(body)) = (session.selected_torsion(), session.bodies().get(b)) else {
        return;
    };
    let bonds = session.rotatable_bonds(b);
    let Some(bond) = bonds.get(k) else { return };
    let at = |i: u32| {
        let p = body.molecule.local.get(i as usize)?;
        project(cam, v, body.pose.transform_point(p.as_dvec3()), 0.0)
    };
    let (Some((x0, y0, _)), Some((x1, y1, _))) = (at(bond.atoms[0]), at(bond.atoms[1])) else {
        return;
    };
    let pt = |x: f64, y: f64| egui::pos2((x / ppp) as f32, (y / ppp) as f32);
    painter.line_segment([pt(x0, y0), pt(x1, y1)], egui::Stroke::new(4.0, BOND));
    let angle = session
        .torsion_angles(b)
        .get(k)
        .map_or(0.0, |a| a.to_degrees());
    painter.text(
        pt(0.5 * (x0 + x1), 0.5 * (y0 + y1)) + egui::vec2(6.0, -6.0),
        egui::Align2::LEFT_BOTTOM,
        format!("bond {}/{} {angle:+.0}°", k + 1, bonds.len()),
        font.clone(),
        BOND,
    );
}

/// Four corner brackets of a square of half-size `half` around `c`.
fn brackets(painter: &egui::Painter, c: egui::Pos2, half: f32, color: egui::Color32) {
    let stroke = egui::Stroke::new(1.5, color);
    let arm = (half * 0.35).max(4.0);
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        let corner = c + egui::vec2(sx * half, sy * half);
        painter.line_segment([corner, corner - egui::vec2(sx * arm, 0.0)], stroke);
        painter.line_segment([corner, corner - egui::vec2(0.0, sy * arm)], stroke);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_centre_projects_to_the_viewport_centre() {
        let cam = Camera::framing(DVec3::new(5.0, 0.0, 0.0), 10.0);
        let v = (100.0, 0.0, 400.0, 300.0, 4.0 / 3.0);
        let (x, y, r) = project(&cam, v, cam.centre, 1.0).expect("in front");
        assert!((x - 300.0).abs() < 1e-9 && (y - 150.0).abs() < 1e-9);
        assert!(r > 0.0);
        // A point up the screen is drawn higher (smaller y).
        let (_, y_up, _) = project(&cam, v, cam.centre + DVec3::Y, 1.0).expect("in front");
        assert!(y_up < y);
        assert!(project(&cam, v, cam.eye() + cam.to_world(DVec3::Z), 1.0).is_none());
    }

    #[test]
    fn projection_agrees_with_picking() {
        use crate::model::{RadiiSet, builtin};
        let (rings, e) = builtin::scene(RadiiSet::Bondi);
        let s = Session::new(vec![rings, e], crate::session::Settings::default()).expect("session");
        let (w, h) = (800.0, 600.0);
        let b = &s.bodies()[0];
        let p = b.pose.transform_point(b.molecule.local[4].as_dvec3());
        let (x, y, _) = project(&s.view_camera(), (0.0, 0.0, w, h, w / h), p, 1.0).expect("seen");
        let hit = super::super::pick::pick(&s, x, y, w, h).map(|h| h.0);
        assert_eq!(hit, Some(0), "a ring atom, not the E behind");
    }
}
