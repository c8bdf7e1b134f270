//! The contact beep (rodio). With no audio device there is no beep and one
//! message saying so; nothing fails.

use std::time::Duration;

use rodio::Source;

/// Plays a short tone on demand, or does nothing without audio output.
pub struct Beeper {
    sink: Option<rodio::MixerDeviceSink>,
}

impl Beeper {
    /// Opens the default audio output; on failure returns a silent beeper and
    /// the reason, to show once.
    pub fn open() -> (Self, Option<String>) {
        match rodio::DeviceSinkBuilder::open_default_sink() {
            Ok(mut sink) => {
                sink.log_on_drop(false);
                (Self { sink: Some(sink) }, None)
            }
            Err(e) => (
                Self { sink: None },
                Some(format!("no audio output ({e}): contacts will not beep")),
            ),
        }
    }

    /// A silent beeper (before the audio device is opened).
    pub fn open_quietly() -> Self {
        Self { sink: None }
    }

    /// True when a beep can be heard.
    pub fn has_audio(&self) -> bool {
        self.sink.is_some()
    }

    /// A 120 ms tone at 880 Hz.
    pub fn beep(&self) {
        if let Some(s) = &self.sink {
            let tone = rodio::source::SineWave::new(880.0)
                .take_duration(Duration::from_millis(120))
                .fade_in(Duration::from_millis(5))
                .amplify(0.25);
            s.mixer().add(tone);
        }
    }
}
