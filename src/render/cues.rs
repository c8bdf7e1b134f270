//! Depth cues besides stereo and rocking (thesis chapter 4.3), each one
//! switch: depth cueing (far atoms fade to the background; on by default),
//! silhouette outlines where depth jumps, screen-space ambient occlusion,
//! shadows from the light (a shadow map of the impostors) and a translucent
//! receptor. A cue that is off costs nothing: the renderer picks pipeline
//! variants without its code and skips its passes and textures.

/// Which depth cues are drawn, and how strongly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cues {
    /// Fade with distance towards the background.
    pub depth: bool,
    /// How far the farthest atoms fade, 0..1.
    pub depth_strength: f32,
    /// Dark outlines where depth jumps.
    pub outline: bool,
    /// Darken atoms in crevices (screen-space ambient occlusion).
    pub ao: bool,
    /// Shadows from the light onto the molecules.
    pub shadow: bool,
    /// Draw the first molecule (the receptor) see-through.
    pub translucent: bool,
    /// Opacity of the translucent receptor, 0..1.
    pub opacity: f32,
}

impl Default for Cues {
    fn default() -> Self {
        // Depth cueing only, as ChimeraX and PyMOL start.
        Self {
            depth: true,
            ..Self::NONE
        }
    }
}

impl Cues {
    /// No cue at all.
    pub const NONE: Cues = Cues {
        depth: false,
        depth_strength: 0.6,
        outline: false,
        ao: false,
        shadow: false,
        translucent: false,
        opacity: 0.3,
    };

    /// The cue names [`Cues::parse`] accepts.
    pub const NAMES: [&'static str; 5] = ["depth", "outline", "ao", "shadow", "translucent"];

    /// Cues from a comma-separated list of [`Cues::NAMES`], or `none`
    /// (strengths keep their defaults).
    ///
    /// # Errors
    /// The unknown name and the names allowed.
    pub fn parse(list: &str) -> Result<Cues, String> {
        let mut c = Cues::NONE;
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match name {
                "none" => {}
                "depth" => c.depth = true,
                "outline" => c.outline = true,
                "ao" => c.ao = true,
                "shadow" => c.shadow = true,
                "translucent" => c.translucent = true,
                other => {
                    return Err(format!(
                        "unknown cue `{other}`: use none or any of {}",
                        Cues::NAMES.join(", ")
                    ));
                }
            }
        }
        Ok(c)
    }

    /// Whether the screen-space pass (outlines, occlusion) runs.
    pub fn needs_post(&self) -> bool {
        self.outline || self.ao
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_lists() {
        let c = Cues::parse("outline, shadow").expect("parse");
        assert!(c.outline && c.shadow && !c.depth && !c.ao && !c.translucent);
        assert_eq!(Cues::parse("none"), Ok(Cues::NONE));
        assert!(Cues::parse("fog").is_err());
        assert!(Cues::default().depth, "depth cueing is on by default");
        assert!(!Cues::NONE.needs_post() && Cues::parse("ao").expect("ao").needs_post());
    }
}
