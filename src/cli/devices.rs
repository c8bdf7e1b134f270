//! `bump devices`: the joysticks and gamepads gilrs sees, which profile of
//! the joystick map each would use, and their raw axes and buttons live, to
//! help write a map file.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use bump::input::gamepads::Gamepads;
use bump::input::{Controllers, JoystickMap, RawEvent};
use clap::Args;

/// Options of `bump devices`.
#[derive(Debug, Args)]
pub struct DevicesArgs {
    /// Watch this many seconds (0: list and exit; at most 1e6).
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    seconds: f64,
    /// The joystick map whose profiles to show (default: the built-in one).
    #[arg(long, value_name = "FILE")]
    joystick_map: Option<PathBuf>,
}

/// Lists controllers, then prints raw values as they change.
pub fn run(a: &DevicesArgs) -> anyhow::Result<()> {
    let map = match &a.joystick_map {
        Some(p) => JoystickMap::read(p)?,
        None => JoystickMap::default(),
    };
    let seconds = bump::motion::range::check_seconds(a.seconds)
        .map_err(|e| anyhow::anyhow!("--seconds: {e}"))?;
    let (pads, why) = Gamepads::open();
    let Some(mut pads) = pads else {
        outln!("{}", why.unwrap_or_else(|| "no joystick support".into()));
        return Ok(());
    };
    let mut controllers = Controllers::default();
    let start = pads.connected();
    if start.is_empty() {
        outln!(
            "no joystick or gamepad connected (on Linux, gilrs sees devices udev tags ID_INPUT_JOYSTICK; check read access to /dev/input/event*)"
        );
    }
    for e in start {
        show_device(&e, &map);
        controllers.apply(&map, e);
    }
    if seconds == 0.0 {
        return Ok(());
    }
    outln!(
        "watching for {} s: move sticks, press buttons, plug devices in or out (Ctrl+C stops)",
        bump::text::short_number(seconds)
    );
    // Within range, so neither the duration nor the instant overflows.
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    while Instant::now() < end {
        for e in pads.poll() {
            match &e {
                RawEvent::Connected(_) => show_device(&e, &map),
                RawEvent::Disconnected(id) => outln!("device {id} disconnected"),
                RawEvent::Value {
                    device,
                    source,
                    value,
                } => outln!("device {device}  {source:<16} {value:+.3}"),
            }
            controllers.apply(&map, e);
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let ignored = controllers.ignored();
    if ignored > 0 {
        outln!("{ignored} non-finite or out-of-range values were ignored");
    }
    Ok(())
}

fn show_device(e: &RawEvent, map: &JoystickMap) {
    if let RawEvent::Connected(d) = e {
        let profile = map
            .profile_for(&d.name, d.mapped)
            .map_or("none: ignored", |p| map.profiles[p].name.as_str());
        outln!(
            "device {}: {}  (gamepad mapping: {}; profile: {profile})",
            d.id,
            d.name,
            if d.mapped { "yes" } else { "no" }
        );
    }
}
