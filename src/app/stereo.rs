//! The window's depth-cue and stereo settings (shell state: they change
//! pixels, never docking, so they live outside the session), the keys that
//! change them, and their HUD controls.
//!
//! Frame-sequential stereo shows one eye per vertical blank, so it needs a
//! display of at least [`MIN_SEQUENTIAL_HZ`]; at 60 Hz each eye would
//! flicker at 30 Hz. The window refuses it, with a message, when the
//! monitor's refresh rate is lower or unknown.

use crate::render::ghost::Ghost;
use crate::render::slab::Slab;
use crate::render::{Cues, Stereo, StereoMode};
use crate::session::Command;

/// Lowest refresh rate for frame-sequential stereo, Hz.
pub const MIN_SEQUENTIAL_HZ: f64 = 100.0;

/// A key's change to the cues or the stereo settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CueAction {
    /// Next stereo mode (mono, side by side, …).
    CycleStereo,
    /// Eyes further apart.
    EyesApart,
    /// Eyes closer together.
    EyesCloser,
    /// Zero-parallax plane nearer.
    ConvergeNearer,
    /// Zero-parallax plane farther.
    ConvergeFarther,
    /// Swap left and right.
    SwapEyes,
    /// Depth cueing on/off.
    DepthCue,
    /// Stronger depth cueing.
    DepthCueMore,
    /// Weaker depth cueing.
    DepthCueLess,
    /// Outlines on/off.
    Outline,
    /// Ambient occlusion on/off.
    Occlusion,
    /// Shadows on/off.
    Shadow,
    /// Translucent receptor on/off.
    Translucent,
    /// The ghost of the drug's reference pose on/off.
    Ghost,
    /// The clipping slab on/off.
    Slab,
    /// A thinner slab (one step).
    SlabThinner,
    /// A thicker slab (one step).
    SlabThicker,
}

/// Cues, stereo and the frame counter of the window.
#[derive(Debug, Clone, Default)]
pub struct ViewState {
    /// The depth cues drawn.
    pub cues: Cues,
    /// Stereo settings.
    pub stereo: Stereo,
    /// Frames presented (frame-sequential stereo alternates on it).
    pub frame: u64,
    /// The monitor's refresh rate in mHz, when known.
    pub refresh_millihertz: Option<u32>,
    /// The ghost of the drug's reference pose is drawn.
    pub ghost: bool,
    /// The clipping slab is on.
    pub slab_on: bool,
    /// The slab's thickness (kept while it is off).
    pub slab: Slab,
}

fn on_off(b: bool) -> &'static str {
    if b { "on" } else { "off" }
}

impl ViewState {
    /// How the scene is drawn now, lit from `light`.
    pub fn params(&self, light: glam::DVec3) -> crate::render::ViewParams {
        crate::render::ViewParams {
            light,
            cues: self.cues,
            stereo: self.stereo,
            frame: self.frame,
            ghost: self.ghost.then(Ghost::default),
            slab: self.slab_on.then_some(self.slab),
            ..crate::render::ViewParams::default()
        }
    }

    /// Why frame-sequential stereo cannot run here, if it cannot.
    pub fn sequential_refused(&self) -> Option<String> {
        match self.refresh_millihertz {
            None => Some(
                "frame-sequential stereo refused: the display's refresh rate is unknown (it needs 100 Hz or more)"
                    .into(),
            ),
            Some(mhz) if f64::from(mhz) / 1000.0 < MIN_SEQUENTIAL_HZ => Some(format!(
                "frame-sequential stereo refused: the display runs at {:.0} Hz; shutter glasses need {MIN_SEQUENTIAL_HZ:.0} Hz or more",
                f64::from(mhz) / 1000.0
            )),
            Some(_) => None,
        }
    }

    /// Switches to `mode`; returns the message to show.
    pub fn set_mode(&mut self, mode: StereoMode) -> String {
        if mode == StereoMode::FrameSequential
            && let Some(why) = self.sequential_refused()
        {
            return why;
        }
        self.stereo.mode = mode;
        format!("stereo: {}", mode.name())
    }

    /// Applies `a`; returns the message to show.
    pub fn apply(&mut self, a: CueAction) -> String {
        let s = &mut self.stereo;
        let c = &mut self.cues;
        match a {
            CueAction::CycleStereo => {
                let mut next = s.mode.next();
                let mut skipped = None;
                if next == StereoMode::FrameSequential
                    && let Some(why) = self.sequential_refused()
                {
                    skipped = Some(why);
                    next = next.next();
                }
                let msg = self.set_mode(next);
                match skipped {
                    Some(why) => format!("{why}; {msg}"),
                    None => msg,
                }
            }
            CueAction::EyesApart | CueAction::EyesCloser => {
                let k = if a == CueAction::EyesApart { 1.25 } else { 0.8 };
                s.separation = (s.separation * k).clamp(0.002, 0.2);
                format!(
                    "eye separation {:.1} % of the convergence distance",
                    s.separation * 100.0
                )
            }
            CueAction::ConvergeNearer | CueAction::ConvergeFarther => {
                let k = if a == CueAction::ConvergeFarther {
                    1.1
                } else {
                    1.0 / 1.1
                };
                s.convergence = (s.convergence * k).clamp(0.2, 5.0);
                format!(
                    "convergence at {:.2} × the view centre's distance",
                    s.convergence
                )
            }
            CueAction::SwapEyes => {
                s.swap = !s.swap;
                format!("eyes swapped: {}", on_off(s.swap))
            }
            CueAction::DepthCue => {
                c.depth = !c.depth;
                format!("depth cueing {}", on_off(c.depth))
            }
            CueAction::DepthCueMore | CueAction::DepthCueLess => {
                let d = if a == CueAction::DepthCueMore {
                    0.1
                } else {
                    -0.1
                };
                c.depth_strength = (c.depth_strength + d).clamp(0.0, 1.0);
                c.depth = true;
                format!("depth cueing {:.0} %", c.depth_strength * 100.0)
            }
            CueAction::Outline => {
                c.outline = !c.outline;
                format!("outlines {}", on_off(c.outline))
            }
            CueAction::Occlusion => {
                c.ao = !c.ao;
                format!("ambient occlusion {}", on_off(c.ao))
            }
            CueAction::Shadow => {
                c.shadow = !c.shadow;
                format!("shadows {}", on_off(c.shadow))
            }
            CueAction::Translucent => {
                c.translucent = !c.translucent;
                format!("translucent receptor {}", on_off(c.translucent))
            }
            CueAction::Ghost => {
                self.ghost = !self.ghost;
                format!("ghost of the reference pose {}", on_off(self.ghost))
            }
            CueAction::Slab => {
                self.slab_on = !self.slab_on;
                format!(
                    "clipping slab {} ({:.0} Å)",
                    on_off(self.slab_on),
                    self.slab.thickness
                )
            }
            CueAction::SlabThinner => self.slab_thicker(-1.0),
            CueAction::SlabThicker => self.slab_thicker(1.0),
        }
    }

    /// Makes the slab `steps` steps thicker (negative: thinner) and turns
    /// it on; returns the message to show.
    pub fn slab_thicker(&mut self, steps: f64) -> String {
        self.slab = self.slab.thicker(steps);
        self.slab_on = true;
        format!("clipping slab {:.0} Å", self.slab.thickness)
    }

    /// Whether the window must keep drawing with no input (frame-sequential
    /// stereo alternates eyes every frame).
    pub fn animating(&self) -> bool {
        self.stereo.mode == StereoMode::FrameSequential
    }
}

/// HUD controls for the cues, stereo and rocking; returns session commands
/// (rocking) and status messages.
pub fn controls(
    ui: &mut egui::Ui,
    view: &mut ViewState,
    rocking: bool,
) -> (Vec<Command>, Vec<String>) {
    let mut cmds = Vec::new();
    let mut said = Vec::new();
    let mut mode = view.stereo.mode;
    egui::ComboBox::from_id_salt("stereo")
        .selected_text(format!("Stereo: {}", mode.name()))
        .show_ui(ui, |ui| {
            for m in StereoMode::ALL {
                ui.selectable_value(&mut mode, m, m.name());
            }
        });
    if mode != view.stereo.mode {
        said.push(view.set_mode(mode));
    }
    let c = &mut view.cues;
    ui.checkbox(&mut c.depth, "Depth cue");
    ui.checkbox(&mut c.outline, "Outline");
    ui.checkbox(&mut c.ao, "AO");
    ui.checkbox(&mut c.shadow, "Shadow");
    ui.checkbox(&mut c.translucent, "Translucent");
    ui.checkbox(&mut view.ghost, "Ghost");
    ui.checkbox(&mut view.slab_on, "Slab");
    if view.slab_on {
        let mut t = view.slab.thickness;
        let slider = egui::Slider::new(
            &mut t,
            crate::render::slab::MIN_THICKNESS..=crate::render::slab::MAX_THICKNESS,
        )
        .logarithmic(true)
        .suffix(" Å")
        .max_decimals(0);
        if ui.add(slider).changed() {
            view.slab = Slab::new(t);
        }
    }
    let mut rock = rocking;
    if ui.checkbox(&mut rock, "Rock").changed() {
        cmds.push(Command::ToggleRocking);
    }
    (cmds, said)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_sequential_needs_a_fast_display() {
        let mut v = ViewState::default();
        assert!(v.set_mode(StereoMode::FrameSequential).contains("unknown"));
        assert_eq!(v.stereo.mode, StereoMode::Mono);
        v.refresh_millihertz = Some(60_000);
        assert!(v.set_mode(StereoMode::FrameSequential).contains("60 Hz"));
        assert_eq!(v.stereo.mode, StereoMode::Mono);
        v.refresh_millihertz = Some(120_000);
        v.set_mode(StereoMode::FrameSequential);
        assert_eq!(v.stereo.mode, StereoMode::FrameSequential);
        assert!(v.animating());
    }

    #[test]
    fn cycling_skips_a_refused_mode_and_comes_back_to_mono() {
        let mut v = ViewState {
            refresh_millihertz: Some(60_000),
            ..ViewState::default()
        };
        let mut seen = Vec::new();
        for _ in 0..StereoMode::ALL.len() - 1 {
            v.apply(CueAction::CycleStereo);
            seen.push(v.stereo.mode);
        }
        assert!(!seen.contains(&StereoMode::FrameSequential));
        assert_eq!(seen.last(), Some(&StereoMode::Mono));
    }

    #[test]
    fn keys_toggle_each_cue_and_bound_the_eyes() {
        let mut v = ViewState::default();
        assert!(v.cues.depth);
        for (a, get) in [
            (
                CueAction::DepthCue,
                (|c: &Cues| c.depth) as fn(&Cues) -> bool,
            ),
            (CueAction::Outline, |c| c.outline),
            (CueAction::Occlusion, |c| c.ao),
            (CueAction::Shadow, |c| c.shadow),
            (CueAction::Translucent, |c| c.translucent),
        ] {
            let before = get(&v.cues);
            v.apply(a);
            assert_ne!(get(&v.cues), before, "{a:?}");
        }
        for _ in 0..100 {
            v.apply(CueAction::EyesApart);
        }
        assert!(v.stereo.separation <= 0.2);
        v.apply(CueAction::SwapEyes);
        assert!(v.stereo.swap);
    }

    #[test]
    fn ghost_and_slab_keys_reach_the_render_settings() {
        let mut v = ViewState::default();
        let p = v.params(glam::DVec3::Z);
        assert!(p.ghost.is_none() && p.slab.is_none());
        v.apply(CueAction::Ghost);
        assert!(v.params(glam::DVec3::Z).ghost.is_some());
        assert!(v.apply(CueAction::Slab).contains("10 Å"));
        v.apply(CueAction::SlabThinner);
        v.apply(CueAction::SlabThinner);
        let slab = v.params(glam::DVec3::Z).slab.expect("slab on");
        assert_eq!(slab.thickness, 8.0);
        v.apply(CueAction::Slab);
        assert!(v.params(glam::DVec3::Z).slab.is_none());
        // Thicker turns it on again, from the kept thickness.
        assert!(v.apply(CueAction::SlabThicker).contains("9 Å"));
        assert!(v.slab_on);
    }
}
