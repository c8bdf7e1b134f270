//! What a frame asks of the session: a 6-DOF motion and discrete commands.
//!
//! Devices (keyboard, mouse, joysticks, a recorded log) are translated into a
//! [`FrameInput`] by the shell; the session never sees a device.

use glam::DVec3;

use super::keys::KeyEvent;
use crate::collide::Response;

/// A rigid motion request: translation in Å and rotation as axis × angle (rad),
/// in screen coordinates (x right, y up, z towards the viewer) or in the
/// moved thing's own axes, as the session's [`super::Space`] says.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Motion6 {
    /// Translation, Å.
    pub translate: DVec3,
    /// Rotation vector: unit axis times angle in radians.
    pub rotate: DVec3,
}

impl Motion6 {
    /// No motion.
    pub const ZERO: Motion6 = Motion6 {
        translate: DVec3::ZERO,
        rotate: DVec3::ZERO,
    };

    /// True when both parts are exactly zero.
    pub fn is_zero(&self) -> bool {
        self.translate == DVec3::ZERO && self.rotate == DVec3::ZERO
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.translate.is_finite() && self.rotate.is_finite()
    }

    /// This motion scaled by `k` (a velocity times a time step).
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            translate: self.translate * k,
            rotate: self.rotate * k,
        }
    }

    /// Component-wise sum.
    pub fn plus(&self, o: &Motion6) -> Self {
        Self {
            translate: self.translate + o.translate,
            rotate: self.rotate + o.rotate,
        }
    }
}

/// A discrete request (a key, a menu item, a typed command).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Space: switch between view and object mode.
    ToggleMode,
    /// `j`: select the next molecule.
    NextMolecule,
    /// Select molecule `n` (0-based), e.g. after clicking one of its atoms.
    Select(usize),
    /// `c`: collision detection on/off.
    ToggleCollision,
    /// Use this collision response.
    SetResponse(Response),
    /// Cycle stop → touch → slide → soft → pass.
    CycleResponse,
    /// Screen-space or object-space motion.
    ToggleSpace,
    /// Undo the last molecule move.
    Undo,
    /// Redo the last undone move.
    Redo,
    /// Put the selected molecule back at its loaded pose (undoable).
    ResetMolecule,
    /// Put the camera back where it started.
    ResetView,
    /// Turn the view so that the drug (the selected molecule) is in front
    /// of the other molecules, centred, with every molecule in view, and
    /// make that the home view (the window asks for it when files arrive;
    /// the camera moves only while it is at home, i.e. the user has not
    /// moved the view).
    ViewDrug,
    /// Centre the view on the drug (the selected molecule), keeping the
    /// camera's turn, close enough to fill the view with it.
    CentreOnDrug,
    /// Frame every molecule where it is now, keeping the camera's turn.
    FitAll,
    /// Move the selected molecule by an exact amount (Å and a turn about its
    /// centre, axis in world coordinates), through the collision response.
    MoveBy {
        /// Translation of the centre, world Å.
        translate: DVec3,
        /// Turn axis, world coordinates (any non-zero length).
        axis: DVec3,
        /// Turn angle, degrees.
        degrees: f64,
    },
    /// `q`, Escape, window closed.
    Quit,
    /// Rocking of the view on/off.
    ToggleRocking,
    /// Rock with a wider swing.
    RockMore,
    /// Rock with a narrower swing.
    RockLess,
    /// Set the `soft` response's limit, Å beyond the contact rule.
    SetSoftLimit(f64),
    /// Let `soft` press deeper (one step of [`SOFT_LIMIT_STEP`]).
    SoftLimitMore,
    /// Let `soft` press less deep.
    SoftLimitLess,
    /// Select rotatable bond `k` of the selected molecule's torsion tree
    /// ([`super::Session::rotatable_bonds`]), or none.
    SelectTorsion(Option<usize>),
    /// Select the next rotatable bond (the first when none is selected).
    NextTorsion,
    /// Select the previous rotatable bond (the last when none is selected).
    PreviousTorsion,
    /// Select the rotatable bond nearest to atom `k` of the selected
    /// molecule (a click on an atom): the bond whose middle is closest to
    /// the atom, the lower index on a tie.
    SelectTorsionNear(usize),
    /// Turn the selected rotatable bond by an angle (its torsion grows by
    /// it: the child side turns right-handed about the axis from the
    /// parent atom to the child atom, relative to the parent side; the
    /// smaller side is the one that moves), through the collision response.
    TurnTorsion {
        /// The turn, degrees.
        degrees: f64,
    },
    /// Settle the selected drug: a local minimisation of its score over
    /// its pose and torsions that never collides ([`crate::score::settle()`]);
    /// one undoable move.
    Settle,
}

/// How much [`Command::SoftLimitMore`] and [`Command::SoftLimitLess`]
/// change the soft limit, Å.
pub const SOFT_LIMIT_STEP: f64 = 0.25;

impl Command {
    /// Whether the command moves a molecule or the view (rocking pauses).
    pub fn moves_something(&self) -> bool {
        matches!(
            self,
            Command::Undo
                | Command::Redo
                | Command::ResetMolecule
                | Command::ResetView
                | Command::ViewDrug
                | Command::CentreOnDrug
                | Command::FitAll
                | Command::MoveBy { .. }
                | Command::TurnTorsion { .. }
                | Command::Settle
        )
    }
}

/// Everything one frame asks for.
///
/// `velocity` and `nudge` move what the mode says (one joystick box, the
/// keyboard); the `view_*` fields always move the camera and the `object_*`
/// fields always the selected molecule (the thesis's second joystick box,
/// mouse drags).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameInput {
    /// Continuous motion per second (joystick deflection, held keys); scaled by `dt`.
    pub velocity: Motion6,
    /// A one-off motion applied this frame as is (a key press step).
    pub nudge: Motion6,
    /// Continuous camera motion per second whatever the mode (the view box).
    pub view_velocity: Motion6,
    /// A one-off camera motion whatever the mode (a mouse drag), screen axes.
    pub view_nudge: Motion6,
    /// Continuous motion per second of the selected molecule whatever the
    /// mode (the object box), screen or object axes as for `velocity`.
    pub object_velocity: Motion6,
    /// A one-off motion of the selected molecule whatever the mode (a
    /// modifier-drag of the mouse), screen or object axes as for `nudge`.
    pub object_nudge: Motion6,
    /// Zoom in mouse-wheel steps: the camera distance is multiplied by
    /// 0.9^zoom (positive comes closer).
    pub zoom: f64,
    /// Continuous turn of the selected rotatable bond, degrees per second
    /// (a held key, a joystick's torsion mode); scaled by `dt`.
    pub torsion_velocity: f64,
    /// A one-off turn of the selected rotatable bond, degrees (a mouse
    /// drag); the turn of a frame is `torsion_velocity · dt +
    /// torsion_nudge`, applied after the rigid motion.
    pub torsion_nudge: f64,
    /// Discrete commands, applied in order before the motion.
    pub commands: Vec<Command>,
    /// Motion keys pressed and released in this frame, with their times:
    /// each press is one step, a held key repeats (see [`super::keys`]).
    /// The steps move what the mode says, as `nudge` does.
    pub keys: Vec<KeyEvent>,
}

impl FrameInput {
    /// A frame that only gives `commands`, in order.
    pub fn with_commands(commands: &[Command]) -> Self {
        Self {
            commands: commands.to_vec(),
            ..Self::default()
        }
    }

    /// The frame that takes a new session (view mode, collision off) to
    /// docking: object mode, collision on.
    pub fn docking() -> Self {
        Self::with_commands(&[Command::ToggleMode, Command::ToggleCollision])
    }

    /// A frame that only nudges the view or the selected molecule (as the
    /// mode says) once by `translate` (Å) and `rotate` (an axis-angle
    /// vector, radians).
    pub fn nudged(translate: DVec3, rotate: DVec3) -> Self {
        Self {
            nudge: Motion6 { translate, rotate },
            ..Self::default()
        }
    }

    /// True when the frame asks for nothing at all.
    pub fn is_empty(&self) -> bool {
        !self.has_motion() && self.commands.is_empty() && self.keys.is_empty()
    }

    /// True when the frame asks to move something (the view, a molecule, the
    /// zoom), continuously or once; commands aside.
    pub fn has_motion(&self) -> bool {
        !(self.velocity.is_zero()
            && self.nudge.is_zero()
            && self.view_velocity.is_zero()
            && self.view_nudge.is_zero()
            && self.object_velocity.is_zero()
            && self.object_nudge.is_zero()
            && self.zoom == 0.0
            && self.torsion_velocity == 0.0
            && self.torsion_nudge == 0.0)
    }

    /// True while something moves continuously (a key held, a stick deflected).
    pub fn has_velocity(&self) -> bool {
        !(self.velocity.is_zero()
            && self.view_velocity.is_zero()
            && self.object_velocity.is_zero()
            && self.torsion_velocity == 0.0)
    }
}
