//! Undo and redo of molecule moves.
//!
//! A continuous gesture (a held key, a joystick deflection, a mouse drag) is
//! one entry, not one per frame: the session extends the open entry while the
//! same molecule keeps moving and closes it when the input stops. An entry
//! that turned a drug's torsions carries its torsion angles before and after
//! (a rigid move carries none), so undo restores the conformation too.

use crate::motion::Pose;

/// One undoable move: a molecule went from one pose (and conformation) to
/// another.
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    /// Which molecule.
    pub body: usize,
    /// Its pose before.
    pub from: Pose,
    /// Its pose after.
    pub to: Pose,
    /// Its torsion angles before (radians from the file's), when the move
    /// turned any; empty for a rigid move.
    pub from_torsions: Vec<f64>,
    /// Its torsion angles after; empty for a rigid move.
    pub to_torsions: Vec<f64>,
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
        self.done.push(Move {
            body,
            from,
            to,
            from_torsions: Vec::new(),
            to_torsions: Vec::new(),
        });
        self.open = true;
    }

    /// Records that `body` moved from `from` to `to` and its torsions
    /// turned from `from_torsions` to `to_torsions`, extending the open
    /// gesture when it is the same molecule.
    pub fn record_shape(
        &mut self,
        body: usize,
        (from, from_torsions): (Pose, &[f64]),
        (to, to_torsions): (Pose, &[f64]),
    ) {
        self.record(body, from, to);
        if let Some(last) = self.done.last_mut() {
            if last.from_torsions.is_empty() {
                // The entry's rigid moves so far left the torsions as they
                // were before this turn.
                last.from_torsions = from_torsions.to_vec();
            }
            last.to_torsions = to_torsions.to_vec();
        }
    }

    /// Ends the open gesture: the next move starts a new entry.
    pub fn close(&mut self) {
        self.open = false;
    }

    /// The move to undo (its `from` is the pose to restore), if any.
    pub fn undo(&mut self) -> Option<Move> {
        self.open = false;
        let m = self.done.pop()?;
        self.undone.push(m.clone());
        Some(m)
    }

    /// The move to redo (its `to` is the pose to restore), if any.
    pub fn redo(&mut self) -> Option<Move> {
        self.open = false;
        let m = self.undone.pop()?;
        self.done.push(m.clone());
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
