//! The window's joysticks: polls gilrs, keeps the controller state, turns it
//! into the frame's velocities, rumbles on contact, and says what happens
//! (connects, disconnects, failures) in the status line.

use crate::input::gamepads::Gamepads;
use crate::input::{Controllers, Intents, JoystickMap};

/// Joystick state of the window.
#[derive(Debug)]
pub struct Joysticks {
    gamepads: Option<Gamepads>,
    controllers: Controllers,
    map: JoystickMap,
    two_boxes: bool,
    rumble: bool,
}

impl Joysticks {
    /// Opens the devices (a message when there are none or no backend).
    pub fn open(map: JoystickMap, two_boxes: bool, rumble: bool) -> (Self, Vec<String>) {
        let (gamepads, why) = Gamepads::open();
        let mut me = Self {
            gamepads,
            controllers: Controllers::default(),
            rumble: rumble && map.rumble,
            map,
            two_boxes,
        };
        let mut messages: Vec<String> = why.into_iter().collect();
        if let Some(g) = &me.gamepads {
            for e in g.connected() {
                messages.extend(me.controllers.apply(&me.map, e));
            }
        }
        if me.gamepads.is_some() && me.controllers.is_empty() {
            messages.push(
                "no joystick or gamepad connected (one plugged in later is picked up)".into(),
            );
        }
        (me, messages)
    }

    /// Takes the devices' events; returns messages for the status line.
    pub fn poll(&mut self) -> Vec<String> {
        let Some(g) = &mut self.gamepads else {
            return Vec::new();
        };
        let mut said = Vec::new();
        for e in g.poll() {
            said.extend(self.controllers.apply(&self.map, e));
        }
        if !said.is_empty() && self.two_boxes {
            said.push(self.describe());
        }
        said
    }

    /// The velocities the sticks ask for now.
    pub fn intents(&self) -> Intents {
        self.controllers.intents(&self.map, self.two_boxes)
    }

    /// True while a device is connected (the window then polls).
    pub fn any(&self) -> bool {
        !self.controllers.is_empty()
    }

    /// A new contact: rumble, if on.
    pub fn contact(&mut self) -> Option<String> {
        if !self.rumble {
            return None;
        }
        let g = self.gamepads.as_mut()?;
        let failed = g.rumble();
        if failed.is_some() {
            self.rumble = false;
        }
        failed
    }

    /// The soft response's resistance now: a continuous rumble of that
    /// strength, if on (0 stops it).
    pub fn resist(&mut self, resistance: f64) -> Option<String> {
        if !self.rumble {
            return None;
        }
        let g = self.gamepads.as_mut()?;
        let failed = g.resist(resistance);
        if failed.is_some() {
            self.rumble = false;
        }
        failed
    }

    /// The boxes, for the HUD: e.g. `view: Pad A | object: Pad B`.
    pub fn describe(&self) -> String {
        let boxes = self.controllers.describe_boxes(&self.map);
        if boxes.is_empty() {
            return "joysticks: none".into();
        }
        let parts: Vec<String> = boxes
            .iter()
            .enumerate()
            .map(|(k, names)| {
                let role = match (self.two_boxes, k) {
                    (false, _) => "box",
                    (true, 0) => "view",
                    (true, 1) => "object",
                    (true, _) => "unused",
                };
                format!("{role}: {}", names.join(" + "))
            })
            .collect();
        format!("joysticks: {}", parts.join(" | "))
    }
}
