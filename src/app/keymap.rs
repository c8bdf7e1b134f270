//! The keyboard map: keys to session commands and to 6-DOF motion.
//!
//! Pure and unit-tested; the window feeds it winit key codes. Held motion keys
//! give a velocity (motion per second, so speed does not depend on the frame
//! rate); a tap moves one step. Shift is coarse (×5), Alt fine (×0.2).
//!
//! | key | action |
//! | --- | --- |
//! | Space | view mode ↔ object mode |
//! | J | select the next molecule |
//! | C | collision detection on/off |
//! | R | next collision response (stop, touch, slide, pass) |
//! | O | screen-space ↔ object-space motion |
//! | L | light mode: the rotation keys turn the light |
//! | B | background flash on contact on/off |
//! | ← → ↑ ↓ | translate x / y |
//! | Page Up / Page Down | translate towards / away from the viewer |
//! | W / S | rotate about the screen's x axis |
//! | A / D | rotate about the vertical axis |
//! | Z / X | twist about the depth axis |
//! | Ctrl+Z, Ctrl+Y (Ctrl+Shift+Z) | undo, redo |
//! | Ctrl+S | save the selected molecule (in the receptor's frame) as PDB and SDF |
//! | Ctrl+O | open a file (or drop one on the window) |
//! | Home | reset the selected molecule to its loaded pose |
//! | V | reset the view |
//! | K | rocking on/off; `,` `.` narrower / wider swing |
//! | 3 | next stereo mode (the thesis's S turns the view here) |
//! | [ ] | eyes closer / further apart; `-` `=` convergence nearer / farther |
//! | E | swap the eyes |
//! | F | depth cueing on/off; 9 / 0 weaker / stronger |
//! | I, M, H, T | outlines, ambient occlusion, shadows, translucent receptor |
//! | F1 or ? | help |
//! | F12 | screenshot (PNG) |
//! | Q, Escape | quit |

use glam::DVec3;
use winit::keyboard::KeyCode;

use super::stereo::CueAction;
use crate::session::{Command, Motion6};

/// Translation speed of a held key, Å per second (before modifiers).
pub const TRANSLATE_SPEED: f64 = 4.0;
/// Rotation speed of a held key, degrees per second (before modifiers).
pub const ROTATE_SPEED: f64 = 45.0;

/// Modifier keys held.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Mods {
    /// Shift.
    pub shift: bool,
    /// Control.
    pub ctrl: bool,
    /// Alt.
    pub alt: bool,
}

impl Mods {
    /// Speed factor: Shift coarse ×5, Alt fine ×0.2.
    pub fn scale(&self) -> f64 {
        if self.shift {
            5.0
        } else if self.alt {
            0.2
        } else {
            1.0
        }
    }
}

/// What a key press means outside the session.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShellAction {
    /// Show or hide the help overlay.
    ToggleHelp,
    /// Save a screenshot.
    Screenshot,
    /// Light mode on/off.
    ToggleLight,
    /// Background flash on contact on/off.
    ToggleFlash,
    /// Save the selected molecule, in the first molecule's frame, as PDB and SDF.
    SavePose,
    /// Show the Open dialog.
    Open,
    /// Change a depth cue or the stereo settings.
    Cue(CueAction),
}

/// A key press, translated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KeyAction {
    /// A session command.
    Session(Command),
    /// Something the window handles.
    Shell(ShellAction),
}

/// The discrete action of a key press, if any.
pub fn action(key: KeyCode, mods: Mods) -> Option<KeyAction> {
    use KeyAction::{Session as S, Shell};
    Some(match key {
        KeyCode::Space => S(Command::ToggleMode),
        KeyCode::KeyJ => S(Command::NextMolecule),
        KeyCode::KeyC => S(Command::ToggleCollision),
        KeyCode::KeyR => S(Command::CycleResponse),
        KeyCode::KeyO if !mods.ctrl => S(Command::ToggleSpace),
        KeyCode::KeyZ if mods.ctrl && mods.shift => S(Command::Redo),
        KeyCode::KeyZ if mods.ctrl => S(Command::Undo),
        KeyCode::KeyY if mods.ctrl => S(Command::Redo),
        KeyCode::KeyS if mods.ctrl => Shell(ShellAction::SavePose),
        KeyCode::KeyO if mods.ctrl => Shell(ShellAction::Open),
        KeyCode::Home => S(Command::ResetMolecule),
        KeyCode::KeyV => S(Command::ResetView),
        KeyCode::KeyQ | KeyCode::Escape => S(Command::Quit),
        KeyCode::F1 => Shell(ShellAction::ToggleHelp),
        KeyCode::Slash if mods.shift => Shell(ShellAction::ToggleHelp),
        KeyCode::F12 => Shell(ShellAction::Screenshot),
        KeyCode::KeyL => Shell(ShellAction::ToggleLight),
        KeyCode::KeyB => Shell(ShellAction::ToggleFlash),
        KeyCode::KeyK => S(Command::ToggleRocking),
        KeyCode::Comma => S(Command::RockLess),
        KeyCode::Period => S(Command::RockMore),
        // The thesis's `S` (a capital: Shift+S); plain S turns about x.
        KeyCode::KeyS if mods.shift => Shell(ShellAction::Cue(CueAction::CycleStereo)),
        KeyCode::Digit3 => Shell(ShellAction::Cue(CueAction::CycleStereo)),
        KeyCode::BracketLeft => Shell(ShellAction::Cue(CueAction::EyesCloser)),
        KeyCode::BracketRight => Shell(ShellAction::Cue(CueAction::EyesApart)),
        KeyCode::Minus => Shell(ShellAction::Cue(CueAction::ConvergeNearer)),
        KeyCode::Equal => Shell(ShellAction::Cue(CueAction::ConvergeFarther)),
        KeyCode::KeyE => Shell(ShellAction::Cue(CueAction::SwapEyes)),
        KeyCode::KeyF => Shell(ShellAction::Cue(CueAction::DepthCue)),
        KeyCode::Digit9 => Shell(ShellAction::Cue(CueAction::DepthCueLess)),
        KeyCode::Digit0 => Shell(ShellAction::Cue(CueAction::DepthCueMore)),
        KeyCode::KeyI => Shell(ShellAction::Cue(CueAction::Outline)),
        KeyCode::KeyM => Shell(ShellAction::Cue(CueAction::Occlusion)),
        KeyCode::KeyH => Shell(ShellAction::Cue(CueAction::Shadow)),
        KeyCode::KeyT => Shell(ShellAction::Cue(CueAction::Translucent)),
        _ => return None,
    })
}

/// The unit motion of a motion key: translation (Å) or rotation (unit axis),
/// screen axes. `None` for other keys, and for Z/X with Ctrl (undo/redo).
pub fn motion_of(key: KeyCode, mods: Mods) -> Option<Motion6> {
    let t = |v: DVec3| Motion6 {
        translate: v,
        rotate: DVec3::ZERO,
    };
    let r = |v: DVec3| Motion6 {
        translate: DVec3::ZERO,
        rotate: v,
    };
    if mods.ctrl || (mods.shift && key == KeyCode::KeyS) {
        return None;
    }
    Some(match key {
        KeyCode::ArrowLeft => t(-DVec3::X),
        KeyCode::ArrowRight => t(DVec3::X),
        KeyCode::ArrowUp => t(DVec3::Y),
        KeyCode::ArrowDown => t(-DVec3::Y),
        KeyCode::PageUp => t(DVec3::Z),
        KeyCode::PageDown => t(-DVec3::Z),
        KeyCode::KeyW => r(-DVec3::X),
        KeyCode::KeyS => r(DVec3::X),
        KeyCode::KeyA => r(-DVec3::Y),
        KeyCode::KeyD => r(DVec3::Y),
        KeyCode::KeyZ => r(DVec3::Z),
        KeyCode::KeyX => r(-DVec3::Z),
        _ => return None,
    })
}

/// The velocity from every motion key held: Å/s and rad/s, screen axes.
pub fn velocity(held: &[KeyCode], mods: Mods) -> Motion6 {
    let mut v = Motion6::ZERO;
    for k in held {
        if let Some(m) = motion_of(*k, mods) {
            v = v.plus(&m);
        }
    }
    let s = mods.scale();
    Motion6 {
        translate: v.translate * (TRANSLATE_SPEED * s),
        rotate: v.rotate * (ROTATE_SPEED.to_radians() * s),
    }
}

/// The one-step motion of a tap: what a held key does in 1/20 s.
pub fn tap(key: KeyCode, mods: Mods) -> Option<Motion6> {
    motion_of(key, mods).map(|_| velocity(&[key], mods).scaled(0.05))
}

/// Lines for the help overlay and the README.
pub const HELP: &[(&str, &str)] = &[
    ("Space", "view mode / object mode"),
    ("J", "select the next molecule (or click an atom)"),
    ("C", "collision detection on/off"),
    ("R", "next collision response: stop, touch, slide, pass"),
    ("O", "screen-space / object-space motion"),
    ("L", "light mode: W A S D Z X turn the light"),
    ("B", "background flash on contact on/off"),
    ("Arrows, Page Up/Down", "translate x, y, z (z towards you)"),
    ("W/S, A/D, Z/X", "rotate about x, y (vertical), z (depth)"),
    ("Shift / Alt", "coarse (×5) / fine (×0.2)"),
    ("Ctrl+Z, Ctrl+Y", "undo, redo"),
    (
        "Ctrl+S",
        "save the selected molecule's pose (receptor frame) as PDB and SDF",
    ),
    ("Ctrl+O", "open a file (or drop files on the window)"),
    ("Home / V", "reset molecule / reset view"),
    (
        "Mouse drag",
        "rotate the view; Shift or middle drag pans; wheel zooms",
    ),
    ("Ctrl+drag", "move the selected molecule"),
    ("Click", "select the molecule of an atom and show the atom"),
    ("K; , .", "rocking on/off; narrower / wider swing"),
    (
        "3 or Shift+S",
        "next stereo mode: side by side, top-bottom, rows, columns, anaglyph, frame-sequential, mono",
    ),
    (
        "[ ]; - =; E",
        "eye separation; convergence nearer / farther; swap eyes",
    ),
    ("F; 9 0", "depth cueing on/off; weaker / stronger"),
    ("I / M", "silhouette outlines / ambient occlusion on/off"),
    ("H / T", "shadows / translucent receptor on/off"),
    ("F12", "screenshot (PNG)"),
    ("F1 or ?", "this help"),
    ("Q or Escape", "quit"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_keys() {
        let none = Mods::default();
        assert_eq!(
            action(KeyCode::Space, none),
            Some(KeyAction::Session(Command::ToggleMode))
        );
        assert_eq!(
            action(KeyCode::KeyJ, none),
            Some(KeyAction::Session(Command::NextMolecule))
        );
        assert_eq!(
            action(KeyCode::KeyC, none),
            Some(KeyAction::Session(Command::ToggleCollision))
        );
        assert_eq!(
            action(KeyCode::KeyQ, none),
            Some(KeyAction::Session(Command::Quit))
        );
        assert_eq!(
            action(KeyCode::KeyL, none),
            Some(KeyAction::Shell(ShellAction::ToggleLight))
        );
    }

    #[test]
    fn shift_s_is_the_thesis_stereo_key_and_does_not_turn() {
        let shift = Mods {
            shift: true,
            ..Mods::default()
        };
        assert!(matches!(
            action(KeyCode::KeyS, shift),
            Some(KeyAction::Shell(ShellAction::Cue(CueAction::CycleStereo)))
        ));
        assert!(motion_of(KeyCode::KeyS, shift).is_none());
        assert!(velocity(&[KeyCode::KeyS], shift).is_zero());
        // Plain S still turns about x.
        assert!(motion_of(KeyCode::KeyS, Mods::default()).is_some());
        assert!(action(KeyCode::KeyS, Mods::default()).is_none());
    }

    #[test]
    fn cue_and_stereo_keys_are_not_motion_keys() {
        let none = Mods::default();
        for k in [
            KeyCode::KeyK,
            KeyCode::Digit3,
            KeyCode::BracketLeft,
            KeyCode::BracketRight,
            KeyCode::KeyE,
            KeyCode::KeyF,
            KeyCode::KeyI,
            KeyCode::KeyM,
            KeyCode::KeyH,
            KeyCode::KeyT,
        ] {
            assert!(action(k, none).is_some(), "{k:?}");
            assert!(motion_of(k, none).is_none(), "{k:?}");
        }
        assert_eq!(
            action(KeyCode::KeyK, none),
            Some(KeyAction::Session(Command::ToggleRocking))
        );
    }

    #[test]
    fn undo_redo_need_ctrl_and_do_not_move() {
        let ctrl = Mods {
            ctrl: true,
            ..Mods::default()
        };
        assert_eq!(
            action(KeyCode::KeyZ, ctrl),
            Some(KeyAction::Session(Command::Undo))
        );
        let ctrl_shift = Mods {
            shift: true,
            ..ctrl
        };
        assert_eq!(
            action(KeyCode::KeyZ, ctrl_shift),
            Some(KeyAction::Session(Command::Redo))
        );
        assert_eq!(motion_of(KeyCode::KeyZ, ctrl), None);
        assert!(motion_of(KeyCode::KeyZ, Mods::default()).is_some());
    }

    #[test]
    fn six_degrees_of_freedom_with_fine_and_coarse() {
        let held = [KeyCode::ArrowRight, KeyCode::PageUp, KeyCode::KeyD];
        let v = velocity(&held, Mods::default());
        assert_eq!(
            v.translate,
            DVec3::new(TRANSLATE_SPEED, 0.0, TRANSLATE_SPEED)
        );
        assert!((v.rotate.y - ROTATE_SPEED.to_radians()).abs() < 1e-12);
        let coarse = velocity(
            &held,
            Mods {
                shift: true,
                ..Mods::default()
            },
        );
        assert_eq!(coarse.translate, v.translate * 5.0);
        let fine = velocity(
            &held,
            Mods {
                alt: true,
                ..Mods::default()
            },
        );
        assert!((fine.translate - v.translate * 0.2).length() < 1e-12);
        // Opposite keys cancel; every axis has a key both ways.
        assert!(velocity(&[KeyCode::KeyW, KeyCode::KeyS], Mods::default()).is_zero());
        let all = [
            KeyCode::ArrowLeft,
            KeyCode::ArrowRight,
            KeyCode::ArrowUp,
            KeyCode::ArrowDown,
            KeyCode::PageUp,
            KeyCode::PageDown,
            KeyCode::KeyW,
            KeyCode::KeyS,
            KeyCode::KeyA,
            KeyCode::KeyD,
            KeyCode::KeyZ,
            KeyCode::KeyX,
        ];
        assert!(velocity(&all, Mods::default()).is_zero());
        let t = tap(KeyCode::ArrowUp, Mods::default()).expect("tap");
        assert!((t.translate.y - TRANSLATE_SPEED * 0.05).abs() < 1e-12);
    }
}
