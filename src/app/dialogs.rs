//! The window's dialogs and what Escape and quitting do with them.
//!
//! Dialogs stack in the order they were opened (or brought back to the
//! top); Escape closes the topmost one, and only with none open does it
//! quit, as Q and closing the window do. Quitting while a molecule has moved
//! since it was loaded or saved opens a confirmation (save, quit without
//! saving, cancel) instead. The logic is pure, so tests drive it; the
//! confirmation's egui window is [`confirm_quit_ui`].

/// A dialog of the window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dialog {
    /// The key help (F1).
    Help,
    /// The Open dialog (Ctrl+O).
    Open,
    /// "Save before quitting?"
    ConfirmQuit,
}

/// The open dialogs, topmost last.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Dialogs {
    stack: Vec<Dialog>,
}

/// What a quit request does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quit {
    /// Quit now.
    Now,
    /// Ask first: the confirmation is now the topmost dialog.
    Ask,
}

/// The answer to the confirmation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuitChoice {
    /// Save the moved molecules, then quit.
    SaveAndQuit,
    /// Quit without saving.
    Discard,
    /// Do not quit.
    Cancel,
}

impl Dialogs {
    /// Whether `d` is open.
    pub fn is_open(&self, d: Dialog) -> bool {
        self.stack.contains(&d)
    }

    /// The topmost dialog.
    pub fn top(&self) -> Option<Dialog> {
        self.stack.last().copied()
    }

    /// Opens `d` (or brings it to the top).
    pub fn open(&mut self, d: Dialog) {
        self.close(d);
        self.stack.push(d);
    }

    /// Closes `d` if it is open.
    pub fn close(&mut self, d: Dialog) {
        self.stack.retain(|x| *x != d);
    }

    /// Opens `d`, or closes it when it is open.
    pub fn toggle(&mut self, d: Dialog) {
        if self.is_open(d) {
            self.close(d);
        } else {
            self.open(d);
        }
    }

    /// Sets whether `d` is open (a dialog closed by its own button).
    pub fn set(&mut self, d: Dialog, open: bool) {
        match (open, self.is_open(d)) {
            (true, false) => self.stack.push(d),
            (false, true) => self.close(d),
            _ => {}
        }
    }

    /// Escape: closes the topmost dialog and names it; `None` when none
    /// was open (then Escape quits).
    pub fn escape(&mut self) -> Option<Dialog> {
        self.stack.pop()
    }

    /// A request to quit (Q, Escape with no dialog, the window's close
    /// button) with `unsaved` molecules moved since they were saved.
    pub fn quit(&mut self, unsaved: bool) -> Quit {
        if unsaved {
            self.open(Dialog::ConfirmQuit);
            Quit::Ask
        } else {
            Quit::Now
        }
    }

    /// The confirmation's answer: `true` to quit (after saving, for
    /// [`QuitChoice::SaveAndQuit`]).
    pub fn answer(&mut self, choice: QuitChoice) -> bool {
        self.close(Dialog::ConfirmQuit);
        choice != QuitChoice::Cancel
    }
}

/// The keys of the confirmation: S saves and quits, D quits without saving
/// (macOS's "Don't Save"), Escape cancels.
pub fn confirm_key(key: winit::keyboard::KeyCode) -> Option<QuitChoice> {
    use winit::keyboard::KeyCode as K;
    match key {
        K::KeyS | K::Enter => Some(QuitChoice::SaveAndQuit),
        K::KeyD => Some(QuitChoice::Discard),
        K::Escape => Some(QuitChoice::Cancel),
        _ => None,
    }
}

/// Draws the confirmation naming the `moved` molecules; the choice made.
pub fn confirm_quit_ui(ctx: &egui::Context, moved: &[String]) -> Option<QuitChoice> {
    let mut choice = None;
    egui::Window::new("Quit bump?")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            ui.label("These molecules moved since they were loaded or saved:");
            for m in moved {
                ui.label(format!("  • {m}"));
            }
            ui.horizontal(|ui| {
                if ui.button("Save and quit (S)").clicked() {
                    choice = Some(QuitChoice::SaveAndQuit);
                }
                if ui.button("Quit without saving (D)").clicked() {
                    choice = Some(QuitChoice::Discard);
                }
                if ui.button("Cancel (Escape)").clicked() {
                    choice = Some(QuitChoice::Cancel);
                }
            });
        });
    choice
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_closes_the_topmost_dialog_then_quits() {
        let mut d = Dialogs::default();
        d.open(Dialog::Help);
        d.open(Dialog::Open);
        assert_eq!(d.escape(), Some(Dialog::Open));
        assert!(d.is_open(Dialog::Help));
        // Help again: brought to the top, not opened twice.
        d.open(Dialog::Open);
        d.open(Dialog::Help);
        assert_eq!(d.escape(), Some(Dialog::Help));
        assert_eq!(d.escape(), Some(Dialog::Open));
        assert_eq!(d.escape(), None, "nothing open: Escape quits");
        d.toggle(Dialog::Help);
        d.set(Dialog::Help, false);
        assert_eq!(d.top(), None);
    }

    #[test]
    fn quitting_with_unsaved_moves_asks_and_cancel_stays() {
        let mut d = Dialogs::default();
        assert_eq!(d.quit(false), Quit::Now);
        assert_eq!(d.quit(true), Quit::Ask);
        assert_eq!(d.top(), Some(Dialog::ConfirmQuit));
        // Escape cancels the confirmation (it is the topmost dialog).
        assert_eq!(d.escape(), Some(Dialog::ConfirmQuit));
        assert_eq!(d.quit(true), Quit::Ask);
        assert!(!d.answer(QuitChoice::Cancel));
        assert!(!d.is_open(Dialog::ConfirmQuit));
        d.quit(true);
        assert!(d.answer(QuitChoice::Discard));
        d.quit(true);
        assert!(d.answer(QuitChoice::SaveAndQuit));
        use winit::keyboard::KeyCode as K;
        assert_eq!(confirm_key(K::KeyS), Some(QuitChoice::SaveAndQuit));
        assert_eq!(confirm_key(K::KeyD), Some(QuitChoice::Discard));
        assert_eq!(confirm_key(K::Escape), Some(QuitChoice::Cancel));
        assert_eq!(confirm_key(K::KeyQ), None);
    }
}
