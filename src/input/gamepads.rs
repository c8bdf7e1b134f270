//! The device layer: gilrs events become [`RawEvent`]s, and contacts become a
//! short rumble. Everything else about joysticks is pure and lives in
//! [`super::controllers`] and [`super::map`].
//!
//! gilrs's own dead-zone and jitter filters are off: the map's dead zones
//! apply, and what `bump devices` shows is the raw value. Each axis or button
//! value is reported under its gilrs name (`LeftStickX`) and under its raw
//! event code (`code:196608`), so a map can name either. No controller, or no
//! gilrs backend at all, is a message, never an error.

use gilrs::ff::{BaseEffect, BaseEffectType, Effect, EffectBuilder, Replay, Ticks};
use gilrs::{Axis, Button, EventType, GamepadId, Gilrs, GilrsBuilder, MappingSource};

use super::controllers::{DeviceInfo, RawEvent};

/// The gilrs context, when there is one.
pub struct Gamepads {
    gilrs: Gilrs,
    rumble: Option<Effect>,
}

impl std::fmt::Debug for Gamepads {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gamepads").finish_non_exhaustive()
    }
}

/// How gilrs sees a device.
pub fn describe(gilrs: &Gilrs, id: GamepadId) -> DeviceInfo {
    let gp = gilrs.gamepad(id);
    let mapped = match gp.mapping_source() {
        MappingSource::SdlMappings => true,
        // A driver mapping counts as a gamepad only with both sticks.
        MappingSource::Driver => {
            gp.axis_code(Axis::LeftStickX).is_some() && gp.axis_code(Axis::RightStickX).is_some()
        }
        MappingSource::None => false,
    };
    DeviceInfo {
        id: usize::from(id),
        name: gp.name().to_string(),
        mapped,
    }
}

/// The raw events one gilrs event stands for.
pub fn translate(gilrs: &Gilrs, id: GamepadId, event: &EventType) -> Vec<RawEvent> {
    let device = usize::from(id);
    let value = |name: Option<String>, code: u32, v: f32| {
        let mut out = Vec::with_capacity(2);
        if let Some(n) = name {
            out.push(RawEvent::Value {
                device,
                source: n,
                value: f64::from(v),
            });
        }
        out.push(RawEvent::Value {
            device,
            source: format!("code:{code}"),
            value: f64::from(v),
        });
        out
    };
    match *event {
        EventType::Connected => vec![RawEvent::Connected(describe(gilrs, id))],
        EventType::Disconnected => vec![RawEvent::Disconnected(device)],
        EventType::AxisChanged(axis, v, code) => {
            let name = (axis != Axis::Unknown).then(|| format!("{axis:?}"));
            value(name, code.into_u32(), v)
        }
        EventType::ButtonChanged(button, v, code) => {
            let name = (button != Button::Unknown).then(|| format!("{button:?}"));
            value(name, code.into_u32(), v)
        }
        _ => Vec::new(),
    }
}

impl Gamepads {
    /// Opens gilrs. Returns `None` and the reason when there is no backend
    /// (the program goes on with keyboard and mouse).
    pub fn open() -> (Option<Self>, Option<String>) {
        match GilrsBuilder::new().with_default_filters(false).build() {
            Ok(gilrs) => (
                Some(Self {
                    gilrs,
                    rumble: None,
                }),
                None,
            ),
            Err(gilrs::Error::NotImplemented(_)) => (
                None,
                Some("joysticks: not supported on this platform (keyboard and mouse only)".into()),
            ),
            Err(e) => (
                None,
                Some(format!(
                    "joysticks unavailable: {e} (keyboard and mouse only)"
                )),
            ),
        }
    }

    /// Devices already connected at start, as connect events.
    pub fn connected(&self) -> Vec<RawEvent> {
        self.gilrs
            .gamepads()
            .map(|(id, _)| RawEvent::Connected(describe(&self.gilrs, id)))
            .collect()
    }

    /// Every event since the last call.
    pub fn poll(&mut self) -> Vec<RawEvent> {
        let mut out = Vec::new();
        while let Some(ev) = self.gilrs.next_event() {
            out.extend(translate(&self.gilrs, ev.id, &ev.event));
        }
        out
    }

    /// A short rumble on every connected controller that supports it.
    /// Returns a message when it fails (once; then rumble stays off).
    pub fn rumble(&mut self) -> Option<String> {
        let ids: Vec<GamepadId> = self
            .gilrs
            .gamepads()
            .filter(|(_, g)| g.is_ff_supported())
            .map(|(id, _)| id)
            .collect();
        if ids.is_empty() {
            return None;
        }
        let effect = EffectBuilder::new()
            .add_effect(BaseEffect {
                kind: BaseEffectType::Strong { magnitude: 40_000 },
                scheduling: Replay {
                    after: Ticks::from_ms(0),
                    play_for: Ticks::from_ms(120),
                    with_delay: Ticks::from_ms(0),
                },
                ..BaseEffect::default()
            })
            .gamepads(&ids)
            .finish(&mut self.gilrs);
        match effect.and_then(|e| e.play().map(|()| e)) {
            Ok(e) => {
                // Dropping an effect stops it: keep it until the next one.
                self.rumble = Some(e);
                None
            }
            Err(e) => Some(format!("rumble failed: {e}")),
        }
    }
}
