//! The session's commands: a [`Command`] applied to the session state (mode,
//! selection, undo and redo, collision settings, the view, the soft
//! limit, torsions and settle), and selecting a molecule.

use super::*;

impl Session {
    pub(super) fn command(&mut self, c: Command, out: &mut FrameOutcome) {
        out.changed = true;
        let molecule_command = matches!(
            c,
            Command::NextMolecule
                | Command::Select(_)
                | Command::Undo
                | Command::Redo
                | Command::ResetMolecule
                | Command::MoveBy { .. }
                | Command::SelectTorsion(_)
                | Command::NextTorsion
                | Command::PreviousTorsion
                | Command::SelectTorsionNear(_)
                | Command::TurnTorsion { .. }
                | Command::Settle
        );
        if molecule_command && self.bodies.is_empty() {
            out.messages.push("no molecule loaded yet".into());
            return;
        }
        match c {
            Command::ToggleMode => {
                self.mode = match self.mode {
                    Mode::View => Mode::Object,
                    Mode::Object => Mode::View,
                };
            }
            Command::NextMolecule => self.select((self.selected + 1) % self.bodies.len(), out),
            Command::Select(n) => {
                if n < self.bodies.len() {
                    self.select(n, out);
                } else {
                    out.messages.push(format!("no molecule {n}"));
                }
            }
            Command::ToggleCollision => {
                self.settings.collision = !self.settings.collision;
                if self.settings.collision {
                    self.refresh_contacts(out);
                    if self.contacts.iter().any(|c| c.gap() <= 0.0) {
                        out.messages.push(
                            "the molecules already overlap: only moves that do not deepen the overlap are allowed"
                                .into(),
                        );
                    }
                } else {
                    self.set_contacts(Vec::new(), out);
                }
            }
            Command::SetResponse(r) => {
                self.settings.response = r;
                self.regrade_contacts(out);
            }
            Command::CycleResponse => {
                let all = Response::ALL;
                let k = all
                    .iter()
                    .position(|r| *r == self.settings.response)
                    .unwrap_or(0);
                self.settings.response = all[(k + 1) % all.len()];
                self.regrade_contacts(out);
            }
            Command::ToggleSpace => {
                self.settings.space = match self.settings.space {
                    Space::Screen => Space::Object,
                    Space::Object => Space::Screen,
                };
            }
            Command::Undo => match self.history.undo() {
                Some(m) => self.place_shape(m.body, m.from, &m.from_torsions, out),
                None => out.messages.push("nothing to undo".into()),
            },
            Command::Redo => match self.history.redo() {
                Some(m) => self.place_shape(m.body, m.to, &m.to_torsions, out),
                None => out.messages.push("nothing to redo".into()),
            },
            Command::ResetMolecule => {
                let b = self.selected;
                let (from, to) = (self.bodies[b].pose, self.bodies[b].loaded);
                let from_torsions = self.torsion_angles(b).to_vec();
                let file = vec![0.0; from_torsions.len()];
                self.history.close();
                self.history
                    .record_shape(b, (from, &from_torsions), (to, &file));
                self.history.close();
                self.place_shape(b, to, &file, out);
            }
            Command::ResetView => self.camera = self.home,
            Command::ViewDrug => self.view_drug(),
            Command::CentreOnDrug => {
                if let Some(c) = self
                    .drug()
                    .and_then(|d| framing::centre_on(&self.bodies, d, self.camera.rotation))
                {
                    self.camera = c;
                }
            }
            Command::FitAll => {
                if let Some(c) = framing::fit_all(&self.bodies, self.camera.rotation) {
                    self.camera = c;
                }
            }
            Command::MoveBy {
                translate,
                axis,
                degrees,
            } => {
                if translate.is_finite() && axis.is_finite() && degrees.is_finite() {
                    self.history.close();
                    let angle = if axis.length_squared() > 0.0 {
                        degrees.to_radians()
                    } else {
                        0.0
                    };
                    self.move_selected(translate, axis, angle, out);
                    self.history.close();
                } else {
                    out.messages.push("ignored a non-finite move".into());
                }
            }
            Command::Quit => out.quit = true,
            Command::ToggleRocking => {
                let a = self.rock.toggle();
                self.bake_rock(a);
                let deg = self.rock.target_amplitude().to_degrees();
                out.messages.push(if self.rock.is_on() {
                    format!("rocking on (±{deg:.0}°)")
                } else {
                    "rocking off".into()
                });
            }
            Command::SetSoftLimit(x) => self.set_soft_limit(x, out),
            Command::SelectTorsion(k) => self.select_torsion(k, out),
            Command::NextTorsion => self.cycle_torsion(true, out),
            Command::PreviousTorsion => self.cycle_torsion(false, out),
            Command::SelectTorsionNear(atom) => self.select_torsion_near(atom, out),
            Command::TurnTorsion { degrees } => {
                self.history.close();
                self.turn_torsion(degrees.to_radians(), out);
                self.history.close();
            }
            Command::Settle => self.settle_selected(out),
            Command::SoftLimitMore => {
                self.set_soft_limit(self.settings.soft_limit + input::SOFT_LIMIT_STEP, out);
            }
            Command::SoftLimitLess => {
                self.set_soft_limit(self.settings.soft_limit - input::SOFT_LIMIT_STEP, out);
            }
            Command::PinReference => {
                out.messages
                    .push(if self.live.pin(&self.bodies, &self.flex) {
                        "reference pinned: the RMSD and the ghost follow this pose".into()
                    } else {
                        "no reference to pin: the live score is not running".into()
                    })
            }
            Command::RockMore | Command::RockLess => {
                if c == Command::RockMore {
                    self.rock.more();
                } else {
                    self.rock.less();
                }
                let deg = self.rock.target_amplitude().to_degrees();
                out.messages.push(format!("rocking ±{deg:.1}°"));
            }
        }
    }

    /// Sets the soft limit, clamped to [0, [`crate::collide::soft::MAX_LIMIT`]]
    /// (its loosened index is rebuilt on the next soft step).
    pub(super) fn set_soft_limit(&mut self, limit: f64, out: &mut FrameOutcome) {
        if !limit.is_finite() {
            out.messages
                .push("ignored a soft limit that is not a number".into());
            return;
        }
        let limit = limit.clamp(0.0, crate::collide::soft::MAX_LIMIT);
        self.settings.soft_limit = limit;
        self.regrade_contacts(out);
        out.messages.push(format!("soft limit {limit:.2} Å"));
    }

    /// [`Command::ViewDrug`]: a new home view that shows the drug; the
    /// camera goes there only while it is at home.
    pub(super) fn view_drug(&mut self) {
        let view = match self.drug() {
            Some(d) if self.bodies.len() > 1 => framing::drug_view(&self.bodies, d),
            _ => framing::fit_all(&self.bodies, self.camera.rotation),
        };
        if let Some(v) = view {
            if self.camera == self.home {
                self.camera = v;
            }
            self.home = v;
        }
    }

    pub(super) fn select(&mut self, n: usize, out: &mut FrameOutcome) {
        // The environment holds the other molecules' poses, which change only
        // while one of them is selected: re-selecting the selected molecule
        // (a click on it) keeps it instead of rebuilding its collider.
        if n != self.selected {
            self.env = None;
        }
        self.selected = n;
        self.history.close();
        self.refresh_contacts(out);
    }
}
