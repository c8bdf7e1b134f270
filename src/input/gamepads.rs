//! The device layer: gilrs events become [`RawEvent`]s, and contacts become a
//! short rumble, the soft response's resistance a continuous one whose
//! strength follows it. Everything else about joysticks is pure and lives in
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
    /// The continuous rumble that follows the soft response's resistance,
    /// and its level (see [`resistance_level`]).
    resisting: Option<(u16, Effect)>,
}

/// Levels of the continuous rumble: the resistance is quantised so that a
/// new effect is made only when the level changes, not every frame.
pub const RESISTANCE_LEVELS: u16 = 8;

/// The level (0 = off … [`RESISTANCE_LEVELS`]) of a resistance in [0, 1].
pub fn resistance_level(resistance: f64) -> u16 {
    if resistance.is_finite() && resistance > 0.0 {
        let top = f64::from(RESISTANCE_LEVELS);
        (resistance.min(1.0) * top).ceil().clamp(1.0, top) as u16
    } else {
        0
    }
}

/// The strong motor's magnitude at a level: a quarter of full strength at
/// the first level, full at the top, in equal steps.
pub fn level_magnitude(level: u16) -> u16 {
    if level == 0 {
        return 0;
    }
    let level = level.min(RESISTANCE_LEVELS);
    let quarter = u32::from(u16::MAX) / 4;
    let rest = u32::from(u16::MAX) - quarter;
    (quarter + rest * u32::from(level) / u32::from(RESISTANCE_LEVELS)) as u16
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
                    resisting: None,
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

    /// The connected controllers that can rumble.
    fn rumbling_pads(&self) -> Vec<GamepadId> {
        self.gilrs
            .gamepads()
            .filter(|(_, g)| g.is_ff_supported())
            .map(|(id, _)| id)
            .collect()
    }

    /// A short rumble on every connected controller that supports it.
    /// Returns a message when it fails (once; then rumble stays off).
    pub fn rumble(&mut self) -> Option<String> {
        let ids = self.rumbling_pads();
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

    /// A continuous rumble whose strength follows `resistance` (in
    /// [0, 1]; 0 stops it): the effect repeats until the level changes.
    /// Returns a message when it fails.
    pub fn resist(&mut self, resistance: f64) -> Option<String> {
        let level = resistance_level(resistance);
        if self.resisting.as_ref().map_or(0, |(l, _)| *l) == level {
            return None;
        }
        // Dropping the effect stops it.
        self.resisting = None;
        if level == 0 {
            return None;
        }
        let ids = self.rumbling_pads();
        if ids.is_empty() {
            return None;
        }
        let effect = EffectBuilder::new()
            .add_effect(BaseEffect {
                kind: BaseEffectType::Strong {
                    magnitude: level_magnitude(level),
                },
                scheduling: Replay {
                    after: Ticks::from_ms(0),
                    play_for: Ticks::from_ms(1000),
                    with_delay: Ticks::from_ms(0),
                },
                ..BaseEffect::default()
            })
            .repeat(gilrs::ff::Repeat::Infinitely)
            .gamepads(&ids)
            .finish(&mut self.gilrs);
        match effect.and_then(|e| e.play().map(|()| e)) {
            Ok(e) => {
                self.resisting = Some((level, e));
                None
            }
            Err(e) => Some(format!("rumble failed: {e}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rumble_grows_with_the_resistance_in_levels() {
        assert_eq!(resistance_level(0.0), 0);
        assert_eq!(resistance_level(f64::NAN), 0);
        assert_eq!(resistance_level(1e-9), 1);
        assert_eq!(resistance_level(1.0), RESISTANCE_LEVELS);
        assert_eq!(resistance_level(7.0), RESISTANCE_LEVELS);
        let mut last = 0;
        for k in 0..=100 {
            let level = resistance_level(f64::from(k) / 100.0);
            let m = level_magnitude(level);
            assert!(m >= last, "magnitude falls at {k}");
            last = m;
        }
        assert_eq!(level_magnitude(RESISTANCE_LEVELS), u16::MAX);
        assert_eq!(level_magnitude(0), 0);
    }
}
