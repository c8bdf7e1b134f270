//! The keyboard map: one table of every binding, from which the window
//! looks keys up, the help (F1) lists them and `docs/keys.md` is written.
//!
//! A binding is a key with exactly the modifiers it names: Shift+S is not S.
//! Motion keys ([`Action::Step`]) are bound three times: alone (a normal
//! step), with Shift (coarse) and with Alt (fine); every other key is bound
//! once per row of the table. A test checks that no key and modifier pair
//! is bound twice, and that `docs/keys.md` is what the table says.

use winit::keyboard::KeyCode;

use super::stereo::CueAction;
use crate::session::keys::{REPEAT_DELAY, REPEAT_RATE};
use crate::session::{Command, StepAxis, StepKey, StepSize};

/// Modifier keys held.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Mods {
    /// Shift.
    pub shift: bool,
    /// Control.
    pub ctrl: bool,
    /// Alt.
    pub alt: bool,
}

impl Mods {
    /// No modifier.
    pub const NONE: Mods = Mods {
        shift: false,
        ctrl: false,
        alt: false,
    };
    /// Shift alone.
    pub const SHIFT: Mods = Mods {
        shift: true,
        ..Self::NONE
    };
    /// Control alone.
    pub const CTRL: Mods = Mods {
        ctrl: true,
        ..Self::NONE
    };
    /// Alt alone.
    pub const ALT: Mods = Mods {
        alt: true,
        ..Self::NONE
    };
    /// Control and Shift.
    pub const CTRL_SHIFT: Mods = Mods {
        ctrl: true,
        shift: true,
        alt: false,
    };

    /// The step size these modifiers give a motion key, if any.
    pub fn step_size(self) -> Option<StepSize> {
        match self {
            Self::NONE => Some(StepSize::Normal),
            Self::SHIFT => Some(StepSize::Coarse),
            Self::ALT => Some(StepSize::Fine),
            _ => None,
        }
    }

    /// `Ctrl+Shift+` and the like.
    fn prefix(self) -> String {
        let mut s = String::new();
        if self.ctrl {
            s.push_str("Ctrl+");
        }
        if self.alt {
            s.push_str("Alt+");
        }
        if self.shift {
            s.push_str("Shift+");
        }
        s
    }
}

/// What a key press means outside the session.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShellAction {
    /// Show or hide the help.
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
    /// Quit (asking first when moves are unsaved).
    Quit,
    /// Close the topmost dialog; with none open, quit as [`ShellAction::Quit`].
    Escape,
    /// Change a depth cue or the stereo settings.
    Cue(CueAction),
    /// Colour atoms by their score contribution on/off.
    ToggleContribution,
    /// Hydrogen bonds drawn on/off.
    ToggleHBonds,
    /// The pocket (the drug and the residues near it) in ball-and-stick on/off.
    TogglePocket,
    /// Labels of the pocket's residues on/off.
    ToggleResidueLabels,
    /// The torsion mode of the joysticks' rotation on/off: it turns the
    /// selected rotatable bond instead of the molecule or the view.
    ToggleTorsionStick,
}

/// What a binding does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// A session command.
    Session(Command),
    /// Something the window handles.
    Shell(ShellAction),
    /// A motion key: one step per press, repeating while held (the size
    /// comes from the modifiers).
    Step(StepKey),
}

/// One row of the table: keys (with their exact modifiers), what they do,
/// and the help text.
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// The keys, each with the modifiers it needs.
    pub keys: &'static [(KeyCode, Mods)],
    /// What they do.
    pub action: Action,
    /// The help line.
    pub help: &'static str,
}

const fn row(keys: &'static [(KeyCode, Mods)], action: Action, help: &'static str) -> Entry {
    Entry { keys, action, help }
}

const fn step(keys: &'static [(KeyCode, Mods)], k: StepKey, help: &'static str) -> Entry {
    // The table holds the plain key; Shift and Alt are added by `bindings`.
    Entry {
        keys,
        action: Action::Step(k),
        help,
    }
}

use Action::{Session as S, Shell as W};
use KeyCode as K;

const N: Mods = Mods::NONE;

/// One press of `;` or `'`: the selected bond's turn, degrees.
const TORSION_STEP: f64 = 5.0;
/// With Shift.
const TORSION_COARSE: f64 = 30.0;
/// With Alt.
const TORSION_FINE: f64 = 1.0;

/// Every binding, in the order the help lists them.
pub const TABLE: &[Entry] = &[
    row(
        &[(K::Space, N)],
        S(Command::ToggleMode),
        "switch between view mode and object mode (what the motion keys move)",
    ),
    step(
        &[(K::ArrowLeft, N)],
        StepKey::translate(StepAxis::X, false),
        "move left",
    ),
    step(
        &[(K::ArrowRight, N)],
        StepKey::translate(StepAxis::X, true),
        "move right",
    ),
    step(
        &[(K::ArrowUp, N)],
        StepKey::translate(StepAxis::Y, true),
        "move up",
    ),
    step(
        &[(K::ArrowDown, N)],
        StepKey::translate(StepAxis::Y, false),
        "move down",
    ),
    step(
        &[(K::PageUp, N)],
        StepKey::translate(StepAxis::Z, true),
        "move towards you",
    ),
    step(
        &[(K::PageDown, N)],
        StepKey::translate(StepAxis::Z, false),
        "move away from you",
    ),
    step(
        &[(K::KeyW, N)],
        StepKey::turn(StepAxis::X, false),
        "tilt: top away from you (about the screen's x axis)",
    ),
    step(
        &[(K::KeyS, N)],
        StepKey::turn(StepAxis::X, true),
        "tilt: top towards you",
    ),
    step(
        &[(K::KeyA, N)],
        StepKey::turn(StepAxis::Y, false),
        "turn left (about the vertical axis)",
    ),
    step(
        &[(K::KeyD, N)],
        StepKey::turn(StepAxis::Y, true),
        "turn right",
    ),
    step(
        &[(K::KeyZ, N)],
        StepKey::turn(StepAxis::Z, true),
        "twist anticlockwise (about the depth axis)",
    ),
    step(
        &[(K::KeyX, N)],
        StepKey::turn(StepAxis::Z, false),
        "twist clockwise",
    ),
    row(
        &[(K::KeyJ, N)],
        S(Command::NextMolecule),
        "select the next molecule (or Ctrl+click one of its atoms)",
    ),
    row(
        &[(K::KeyC, N)],
        S(Command::ToggleCollision),
        "collision detection on/off",
    ),
    row(
        &[(K::KeyR, N)],
        S(Command::CycleResponse),
        "next collision response: stop, touch, slide, soft (press in up to a limit against a growing resistance, gliding along the receptor's smoothed surface and turning as the contacts push it), pass",
    ),
    row(
        &[(K::KeyR, Mods::SHIFT)],
        S(Command::SoftLimitMore),
        "soft contacts: let the drug press deeper (+0.25 Å)",
    ),
    row(
        &[(K::KeyR, Mods::ALT)],
        S(Command::SoftLimitLess),
        "soft contacts: let the drug press less deep (−0.25 Å)",
    ),
    row(
        &[(K::KeyO, N)],
        S(Command::ToggleSpace),
        "switch between the screen's axes and the molecule's own axes",
    ),
    row(
        &[(K::KeyL, N)],
        W(ShellAction::ToggleLight),
        "light mode: the turn keys turn the light",
    ),
    row(
        &[(K::KeyB, N)],
        W(ShellAction::ToggleFlash),
        "background flash on contact on/off",
    ),
    row(&[(K::KeyZ, Mods::CTRL)], S(Command::Undo), "undo a move"),
    row(
        &[(K::KeyY, Mods::CTRL), (K::KeyZ, Mods::CTRL_SHIFT)],
        S(Command::Redo),
        "redo",
    ),
    row(
        &[(K::Home, N)],
        S(Command::ResetMolecule),
        "put the selected molecule back where it was loaded",
    ),
    row(
        &[(K::KeyG, Mods::SHIFT)],
        S(Command::CentreOnDrug),
        "centre the view on the drug",
    ),
    row(
        &[(K::Tab, N)],
        S(Command::NextTorsion),
        "select the drug's next rotatable bond",
    ),
    row(
        &[(K::Tab, Mods::SHIFT)],
        S(Command::PreviousTorsion),
        "select the drug's previous rotatable bond",
    ),
    row(
        &[(K::Semicolon, N)],
        S(Command::TurnTorsion {
            degrees: -TORSION_STEP,
        }),
        "turn the selected rotatable bond back (−5°; through collisions)",
    ),
    row(
        &[(K::Quote, N)],
        S(Command::TurnTorsion {
            degrees: TORSION_STEP,
        }),
        "turn the selected rotatable bond on (+5°; through collisions)",
    ),
    row(
        &[(K::Semicolon, Mods::SHIFT)],
        S(Command::TurnTorsion {
            degrees: -TORSION_COARSE,
        }),
        "turn the selected rotatable bond back, coarse (−30°)",
    ),
    row(
        &[(K::Quote, Mods::SHIFT)],
        S(Command::TurnTorsion {
            degrees: TORSION_COARSE,
        }),
        "turn the selected rotatable bond on, coarse (+30°)",
    ),
    row(
        &[(K::Semicolon, Mods::ALT)],
        S(Command::TurnTorsion {
            degrees: -TORSION_FINE,
        }),
        "turn the selected rotatable bond back, fine (−1°)",
    ),
    row(
        &[(K::Quote, Mods::ALT)],
        S(Command::TurnTorsion {
            degrees: TORSION_FINE,
        }),
        "turn the selected rotatable bond on, fine (+1°)",
    ),
    row(
        &[(K::Backslash, N)],
        W(ShellAction::ToggleTorsionStick),
        "torsion mode on/off: the joystick's rotation turns the selected rotatable bond (Alt+drag turns it with the mouse)",
    ),
    row(
        &[(K::KeyG, N)],
        S(Command::Settle),
        "settle the drug: a local minimisation of its Vina score over pose and torsions that ends free of overlaps (undoable)",
    ),
    row(
        &[(K::KeyV, Mods::SHIFT)],
        S(Command::FitAll),
        "fit everything in the view",
    ),
    row(
        &[(K::KeyV, N)],
        S(Command::ResetView),
        "reset the view (the drug in front, as on load)",
    ),
    row(
        &[(K::KeyS, Mods::CTRL)],
        W(ShellAction::SavePose),
        "save the selected molecule in the receptor's frame as NAME-docked.pdb and .sdf, and .pdbqt when it was read from one (never overwrites: -2, -3, …)",
    ),
    row(
        &[(K::KeyO, Mods::CTRL)],
        W(ShellAction::Open),
        "open a file (or drop files on the window)",
    ),
    row(&[(K::KeyK, N)], S(Command::ToggleRocking), "rocking on/off"),
    row(
        &[(K::Comma, N)],
        S(Command::RockLess),
        "rock with a narrower swing",
    ),
    row(
        &[(K::Period, N)],
        S(Command::RockMore),
        "rock with a wider swing",
    ),
    row(
        &[(K::Digit3, N)],
        W(ShellAction::Cue(CueAction::CycleStereo)),
        "next stereo mode: side by side, top-bottom, rows, columns, anaglyph, frame-sequential, mono",
    ),
    row(
        &[(K::BracketLeft, N)],
        W(ShellAction::Cue(CueAction::EyesCloser)),
        "eyes closer together",
    ),
    row(
        &[(K::BracketRight, N)],
        W(ShellAction::Cue(CueAction::EyesApart)),
        "eyes further apart",
    ),
    row(
        &[(K::Minus, N)],
        W(ShellAction::Cue(CueAction::ConvergeNearer)),
        "convergence nearer",
    ),
    row(
        &[(K::Equal, N)],
        W(ShellAction::Cue(CueAction::ConvergeFarther)),
        "convergence farther",
    ),
    row(
        &[(K::KeyE, N)],
        W(ShellAction::Cue(CueAction::SwapEyes)),
        "swap the eyes",
    ),
    row(
        &[(K::KeyF, N)],
        W(ShellAction::Cue(CueAction::DepthCue)),
        "depth cueing on/off",
    ),
    row(
        &[(K::Digit9, N)],
        W(ShellAction::Cue(CueAction::DepthCueLess)),
        "weaker depth cueing",
    ),
    row(
        &[(K::Digit0, N)],
        W(ShellAction::Cue(CueAction::DepthCueMore)),
        "stronger depth cueing",
    ),
    row(
        &[(K::KeyI, N)],
        W(ShellAction::Cue(CueAction::Outline)),
        "silhouette outlines on/off",
    ),
    row(
        &[(K::KeyM, N)],
        W(ShellAction::Cue(CueAction::Occlusion)),
        "ambient occlusion on/off",
    ),
    row(
        &[(K::KeyH, N)],
        W(ShellAction::Cue(CueAction::Shadow)),
        "shadows on/off",
    ),
    row(
        &[(K::KeyT, N)],
        W(ShellAction::Cue(CueAction::Translucent)),
        "translucent receptor on/off",
    ),
    row(
        &[(K::KeyY, N)],
        W(ShellAction::Cue(CueAction::Ghost)),
        "ghost of the drug's reference pose (the file's pose, or the pinned one) on/off",
    ),
    row(
        &[(K::KeyY, Mods::SHIFT)],
        S(Command::PinReference),
        "pin the drug's current pose as the reference (RMSD and ghost)",
    ),
    row(
        &[(K::Digit4, N)],
        W(ShellAction::Cue(CueAction::Slab)),
        "clipping slab through the drug's centre on/off",
    ),
    row(
        &[(K::Digit5, N)],
        W(ShellAction::Cue(CueAction::SlabThinner)),
        "thinner slab (−1 Å; or Alt+wheel)",
    ),
    row(
        &[(K::Digit6, N)],
        W(ShellAction::Cue(CueAction::SlabThicker)),
        "thicker slab (+1 Å; or Alt+wheel)",
    ),
    row(
        &[(K::KeyU, N)],
        W(ShellAction::ToggleContribution),
        "colour the drug and the pocket by score contribution (blue helps, red hurts) on/off",
    ),
    row(
        &[(K::KeyN, N)],
        W(ShellAction::ToggleHBonds),
        "hydrogen bonds (dashed sticks) on/off",
    ),
    row(
        &[(K::KeyP, N)],
        W(ShellAction::TogglePocket),
        "the pocket (the drug and the residues within the HUD's distance of it) in ball-and-stick on/off",
    ),
    row(
        &[(K::KeyP, Mods::SHIFT)],
        W(ShellAction::ToggleResidueLabels),
        "labels of the pocket's residues on/off",
    ),
    row(
        &[(K::F12, N)],
        W(ShellAction::Screenshot),
        "screenshot: bump-SCENE-DATE-TIME.png in the current folder",
    ),
    row(
        &[(K::F1, N), (K::Slash, Mods::SHIFT)],
        W(ShellAction::ToggleHelp),
        "this help",
    ),
    row(
        &[(K::Escape, N)],
        W(ShellAction::Escape),
        "close the topmost dialog (help, Open, …); with none open, quit",
    ),
    row(
        &[(K::KeyQ, N)],
        W(ShellAction::Quit),
        "quit (asks first when a molecule moved since it was saved)",
    ),
];

/// The mouse, for the help.
pub const MOUSE: &[(&str, &str)] = &[
    ("Drag", "turn the view"),
    ("Shift+drag, middle drag", "pan the view"),
    ("Wheel", "zoom towards the pointer"),
    ("Alt+wheel", "clipping slab thicker / thinner (1 Å a notch)"),
    (
        "Ctrl+drag",
        "move the selected molecule (through collisions)",
    ),
    ("Ctrl+Shift+drag", "turn the selected molecule"),
    ("Click", "mark an atom and name it"),
    (
        "Alt+click",
        "select the rotatable bond nearest the atom (and the atom's molecule)",
    ),
    (
        "Alt+drag",
        "turn the selected rotatable bond (through collisions; 0.5° a pixel)",
    ),
    ("Ctrl+click, double click", "select the atom's molecule"),
];

/// Every (key, modifiers) binding with its action and, for a motion key,
/// its step size.
pub fn bindings() -> Vec<(KeyCode, Mods, Action, Option<StepSize>)> {
    let mut out = Vec::new();
    for e in TABLE {
        for &(key, mods) in e.keys {
            match e.action {
                Action::Step(_) => {
                    for m in [Mods::NONE, Mods::SHIFT, Mods::ALT] {
                        out.push((key, m, e.action, m.step_size()));
                    }
                }
                a => out.push((key, mods, a, None)),
            }
        }
    }
    out
}

/// The action of `key` pressed with exactly `mods`, and the step size for
/// a motion key.
pub fn lookup(key: KeyCode, mods: Mods) -> Option<(Action, Option<StepSize>)> {
    for e in TABLE {
        for &(k, m) in e.keys {
            if k != key {
                continue;
            }
            match e.action {
                Action::Step(_) if m == Mods::NONE => {
                    if let Some(size) = mods.step_size() {
                        return Some((e.action, Some(size)));
                    }
                }
                a if m == mods => return Some((a, None)),
                _ => {}
            }
        }
    }
    None
}

/// A key's name as printed on keyboards.
pub fn key_name(key: KeyCode) -> String {
    let s = match key {
        K::ArrowLeft => "←",
        K::ArrowRight => "→",
        K::ArrowUp => "↑",
        K::ArrowDown => "↓",
        K::PageUp => "Page Up",
        K::PageDown => "Page Down",
        K::Space => "Space",
        K::Home => "Home",
        K::Escape => "Escape",
        K::Comma => ",",
        K::Period => ".",
        K::Slash => "/",
        K::BracketLeft => "[",
        K::BracketRight => "]",
        K::Minus => "-",
        K::Equal => "=",
        K::Semicolon => ";",
        K::Quote => "'",
        K::Backslash => "\\",
        other => {
            let d = format!("{other:?}");
            return d
                .strip_prefix("Key")
                .or_else(|| d.strip_prefix("Digit"))
                .unwrap_or(&d)
                .to_string();
        }
    };
    s.to_string()
}

/// `Ctrl+Shift+Z`, `?` for Shift+/.
pub fn chord_name(key: KeyCode, mods: Mods) -> String {
    if key == K::Slash && mods == Mods::SHIFT {
        return "?".into();
    }
    format!("{}{}", mods.prefix(), key_name(key))
}

/// The help: (keys, what they do), one row per table entry, then the step
/// sizes, then the mouse.
pub fn help_rows() -> Vec<(String, String)> {
    let mut rows: Vec<(String, String)> = TABLE
        .iter()
        .map(|e| {
            let keys: Vec<String> = e.keys.iter().map(|&(k, m)| chord_name(k, m)).collect();
            (keys.join(", "), e.help.to_string())
        })
        .collect();
    let z = |s: StepSize| format!("{} Å, {}°", s.angstroms(), s.degrees());
    let steps = (
        "Shift / Alt + a motion key".to_string(),
        format!(
            "coarse step ({}) / fine step ({}); alone: normal ({}). One press is one step; held, it repeats after {} s, {} steps a second",
            z(StepSize::Coarse),
            z(StepSize::Fine),
            z(StepSize::Normal),
            REPEAT_DELAY,
            REPEAT_RATE
        ),
    );
    let at = rows
        .iter()
        .position(|(_, h)| h == "twist clockwise")
        .map_or(0, |k| k + 1);
    rows.insert(at, steps);
    rows.extend(MOUSE.iter().map(|(k, h)| (k.to_string(), h.to_string())));
    rows
}

/// `docs/keys.md`: the help as a Markdown table.
pub fn markdown() -> String {
    let mut s = String::from(
        "# Keys and mouse\n\n\
         Generated from the window's key table (`src/app/keymap.rs`); a test\n\
         checks that this file matches it (`BUMP_BLESS=1 cargo test --lib keymap`\n\
         rewrites it). The same list is the window's help (F1). Motion keys move\n\
         the view in view mode and the selected molecule in object mode (Space).\n\n\
         | keys | action |\n| --- | --- |\n",
    );
    for (k, h) in help_rows() {
        s.push_str(&format!("| {} | {} |\n", escape_md(&k), escape_md(&h)));
    }
    s
}

fn escape_md(s: &str) -> String {
    s.replace('|', "\\|")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_key_and_modifiers_are_bound_twice() {
        let all = bindings();
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert!(
                    !(a.0 == b.0 && a.1 == b.1),
                    "{} is bound twice: {:?} and {:?}",
                    chord_name(a.0, a.1),
                    a.2,
                    b.2
                );
            }
        }
        // Every binding is found by the lookup as itself.
        for (k, m, action, size) in all {
            assert_eq!(lookup(k, m), Some((action, size)), "{}", chord_name(k, m));
        }
    }

    #[test]
    fn shift_s_tilts_coarsely_and_stereo_is_on_3() {
        assert_eq!(
            lookup(K::KeyS, Mods::SHIFT),
            Some((
                Action::Step(StepKey::turn(StepAxis::X, true)),
                Some(StepSize::Coarse)
            ))
        );
        assert_eq!(
            lookup(K::Digit3, Mods::NONE),
            Some((W(ShellAction::Cue(CueAction::CycleStereo)), None))
        );
        assert_eq!(
            lookup(K::KeyS, Mods::CTRL),
            Some((W(ShellAction::SavePose), None))
        );
        assert_eq!(
            lookup(K::KeyD, Mods::ALT).map(|a| a.1),
            Some(Some(StepSize::Fine))
        );
        // Ctrl with a motion key is nothing (Ctrl+Z aside).
        assert_eq!(lookup(K::ArrowLeft, Mods::CTRL), None);
        assert_eq!(lookup(K::KeyZ, Mods::CTRL), Some((S(Command::Undo), None)));
        assert_eq!(
            lookup(K::KeyV, Mods::SHIFT),
            Some((S(Command::FitAll), None))
        );
    }

    /// G settles the drug; Shift+G centres the view on it.
    #[test]
    fn g_settles_and_shift_g_centres_on_the_drug() {
        assert_eq!(
            lookup(K::KeyG, Mods::NONE),
            Some((S(Command::Settle), None))
        );
        assert_eq!(
            lookup(K::KeyG, Mods::SHIFT),
            Some((S(Command::CentreOnDrug), None))
        );
    }

    #[test]
    fn the_help_lists_every_binding() {
        let rows = help_rows();
        let text: String = rows.iter().map(|(k, h)| format!("{k} {h}\n")).collect();
        for e in TABLE {
            for &(k, m) in e.keys {
                assert!(text.contains(&chord_name(k, m)), "{}", chord_name(k, m));
            }
            assert!(text.contains(e.help));
        }
        assert!(text.contains("coarse step (1 Å, 11.25°)"), "{text}");
    }

    #[test]
    fn docs_keys_md_is_the_table() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/keys.md");
        let want = markdown();
        if std::env::var("BUMP_BLESS").is_ok() {
            std::fs::write(path, &want).expect("write docs/keys.md");
        }
        let have = std::fs::read_to_string(path).unwrap_or_default();
        assert!(
            have == want,
            "docs/keys.md differs from the key table: run `BUMP_BLESS=1 cargo test --lib keymap` and commit it"
        );
    }
}
