//! Undo and redo of molecule moves.
//!
//! A continuous gesture (a held key, a joystick deflection, a mouse drag) is
//! one entry, not one per frame: the session extends the open entry while the
//! same molecule keeps moving and closes it when the input stops.

use crate::motion::Pose;

/// One undoable move: a molecule went from one pose to another.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Move {
    /// Which molecule.
    pub body: usize,
    /// Its pose before.
    pub from: Pose,
    /// Its pose after.
    pub to: Pose,
}

/// Undo and redo stacks with an open gesture.
#[derive(Debug, Clone, Default)]
pub struct History {
    done: Vec<Move>,
    undone: Vec<Move>,
    open: bool,
}

impl History {
    /// Records that `body` moved from `from` to `to`, extending the open
    /// gesture when it is the same molecule.
    pub fn record(&mut self, body: usize, from: Pose, to: Pose) {
        self.undone.clear();
        if self.open
            && let Some(last) = self.done.last_mut()
            && last.body == body
        {
            last.to = to;
            return;
        }
        self.done.push(Move { body, from, to });
        self.open = true;
    }

    /// Ends the open gesture: the next move starts a new entry.
    pub fn close(&mut self) {
        self.open = false;
    }

    /// The move to undo (its `from` is the pose to restore), if any.
    pub fn undo(&mut self) -> Option<Move> {
        self.open = false;
        let m = self.done.pop()?;
        self.undone.push(m);
        Some(m)
    }

    /// The move to redo (its `to` is the pose to restore), if any.
    pub fn redo(&mut self) -> Option<Move> {
        self.open = false;
        let m = self.undone.pop()?;
        self.done.push(m);
        Some(m)
    }

    /// Entries that can be undone.
    pub fn undo_len(&self) -> usize {
        self.done.len()
    }

    /// Entries that can be redone.
    pub fn redo_len(&self) -> usize {
        self.undone.len()
    }
}
