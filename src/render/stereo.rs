//! Stereo: the two eyes' geometry and where each eye goes in the frame.
//!
//! The eyes are two parallel cameras at `∓separation/2` along the screen's
//! x axis, each with an asymmetric (off-axis) frustum whose window, at the
//! convergence distance, is exactly the mono camera's window there. So a
//! point at the convergence distance lands on the same pixel for both eyes
//! (zero parallax) and nothing is toed in (no vertical parallax). For a
//! point at view depth `z` the left image lies to the right of the right
//! image by `f/aspect · separation · (1/z − 1/D)` in NDC (`f = 1/tan(fov/2)`,
//! `D` the convergence distance): crossed parallax in front of the
//! convergence plane, uncrossed behind it.
//!
//! A [`StereoMode`] says how the eyes share the frame: side by side or top
//! and bottom (each eye in its half, drawn with its half's aspect — *full* —
//! or squeezed with the whole frame's aspect — *half*, for displays that
//! stretch each half back), interleaved rows or columns and red-cyan
//! anaglyph (each eye drawn whole, then composed), or frame-sequential (one
//! eye per frame, for shutter glasses). [`Stereo::plan`] turns a mode and a
//! frame size into viewports; the renderer follows the plan.

use glam::DMat4;

/// How the two eyes are shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum StereoMode {
    /// One eye in the middle: no stereo.
    #[default]
    Mono,
    /// Left and right eyes on alternate frames (shutter glasses, 120 Hz).
    FrameSequential,
    /// Left eye in the left half, each half drawn with its own aspect.
    SideBySide,
    /// Left eye in the left half, squeezed to half width (3-D TVs).
    SideBySideHalf,
    /// Left eye in the top half, each half drawn with its own aspect.
    TopBottom,
    /// Left eye in the top half, squeezed to half height (3-D TVs).
    TopBottomHalf,
    /// Left eye on even rows (counting from 0 at the top), right on odd
    /// rows: the thesis's scan lines, for passive polarised monitors.
    RowInterleaved,
    /// Left eye on even columns, right on odd columns.
    ColumnInterleaved,
    /// Red from the left eye, green and blue from the right (red-cyan glasses).
    Anaglyph,
}

impl StereoMode {
    /// Every mode, in the order a key cycles through them.
    pub const ALL: [StereoMode; 9] = [
        StereoMode::Mono,
        StereoMode::SideBySide,
        StereoMode::SideBySideHalf,
        StereoMode::TopBottom,
        StereoMode::TopBottomHalf,
        StereoMode::RowInterleaved,
        StereoMode::ColumnInterleaved,
        StereoMode::Anaglyph,
        StereoMode::FrameSequential,
    ];

    /// The name used on the command line and in the HUD.
    pub fn name(self) -> &'static str {
        match self {
            StereoMode::Mono => "mono",
            StereoMode::FrameSequential => "frame-sequential",
            StereoMode::SideBySide => "side-by-side",
            StereoMode::SideBySideHalf => "side-by-side-half",
            StereoMode::TopBottom => "top-bottom",
            StereoMode::TopBottomHalf => "top-bottom-half",
            StereoMode::RowInterleaved => "rows",
            StereoMode::ColumnInterleaved => "columns",
            StereoMode::Anaglyph => "anaglyph",
        }
    }

    /// The mode named `s` (as [`StereoMode::name`] gives).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }

    /// The next mode in [`StereoMode::ALL`].
    pub fn next(self) -> Self {
        let k = Self::ALL.iter().position(|m| *m == self).unwrap_or(0);
        Self::ALL[(k + 1) % Self::ALL.len()]
    }

    /// How many eyes one frame draws.
    pub fn eyes_per_frame(self) -> usize {
        match self {
            StereoMode::Mono | StereoMode::FrameSequential => 1,
            _ => 2,
        }
    }
}

/// Which camera draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Eye {
    /// The mono camera.
    Centre,
    /// The left eye.
    Left,
    /// The right eye.
    Right,
}

/// Stereo settings (window state, not part of the docking session).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stereo {
    /// How the eyes are shown.
    pub mode: StereoMode,
    /// Eye separation as a fraction of the convergence distance.
    pub separation: f64,
    /// Convergence distance as a fraction of the camera's distance to the
    /// view centre (1: the plane through the view centre has no parallax).
    pub convergence: f64,
    /// Show each eye where the other belongs (for reversed glasses).
    pub swap: bool,
}

impl Default for Stereo {
    fn default() -> Self {
        Self {
            mode: StereoMode::Mono,
            separation: 0.03,
            convergence: 1.0,
            swap: false,
        }
    }
}

/// A rectangle of pixels: x, y (top left), width, height.
pub type Rect = [u32; 4];

/// One eye of a frame's plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeView {
    /// Which camera.
    pub eye: Eye,
    /// Where it is drawn (in its own texture when the plan composes).
    pub viewport: Rect,
    /// Width / height of its projection.
    pub aspect: f64,
}

/// How the eye images are combined into the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Compose {
    /// First eye on even rows.
    Rows,
    /// First eye on even columns.
    Columns,
    /// Red from the first eye, green and blue from the second.
    Anaglyph,
}

/// What a frame draws: the eyes, and whether they are composed.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The eyes, in drawing order.
    pub eyes: Vec<EyeView>,
    /// `None`: each eye is drawn straight into its viewport of the frame.
    /// `Some`: each eye is drawn whole into its own texture, then composed.
    pub compose: Option<Compose>,
}

impl Stereo {
    /// Distance from the eyes to the zero-parallax plane, Å.
    pub fn convergence_distance(&self, camera_distance: f64) -> f64 {
        self.convergence * camera_distance
    }

    /// Where `eye` sits along the screen's x axis, Å from the mono camera.
    pub fn eye_x(&self, eye: Eye, camera_distance: f64) -> f64 {
        let half = 0.5 * self.separation * self.convergence_distance(camera_distance);
        match eye {
            Eye::Centre => 0.0,
            Eye::Left => -half,
            Eye::Right => half,
        }
    }

    /// The eyes of frame number `frame` of a `width`×`height` image.
    pub fn plan(&self, width: u32, height: u32, frame: u64) -> Plan {
        let (w, h) = (width.max(1), height.max(1));
        let aspect = |a: u32, b: u32| f64::from(a.max(1)) / f64::from(b.max(1));
        let (first, second) = if self.swap {
            (Eye::Right, Eye::Left)
        } else {
            (Eye::Left, Eye::Right)
        };
        let whole = |eye| EyeView {
            eye,
            viewport: [0, 0, w, h],
            aspect: aspect(w, h),
        };
        let direct = |eyes| Plan {
            eyes,
            compose: None,
        };
        let composed = |c| Plan {
            eyes: vec![whole(first), whole(second)],
            compose: Some(c),
        };
        let (hw, hh) = (w / 2, h / 2);
        match self.mode {
            StereoMode::Mono => direct(vec![whole(Eye::Centre)]),
            StereoMode::FrameSequential => direct(vec![whole(if frame.is_multiple_of(2) {
                first
            } else {
                second
            })]),
            StereoMode::SideBySide | StereoMode::SideBySideHalf => {
                let a = if self.mode == StereoMode::SideBySide {
                    aspect(hw, h)
                } else {
                    aspect(w, h)
                };
                direct(vec![
                    EyeView {
                        eye: first,
                        viewport: [0, 0, hw.max(1), h],
                        aspect: a,
                    },
                    EyeView {
                        eye: second,
                        viewport: [hw, 0, (w - hw).max(1), h],
                        aspect: a,
                    },
                ])
            }
            StereoMode::TopBottom | StereoMode::TopBottomHalf => {
                let a = if self.mode == StereoMode::TopBottom {
                    aspect(w, hh)
                } else {
                    aspect(w, h)
                };
                direct(vec![
                    EyeView {
                        eye: first,
                        viewport: [0, 0, w, hh.max(1)],
                        aspect: a,
                    },
                    EyeView {
                        eye: second,
                        viewport: [0, hh, w, (h - hh).max(1)],
                        aspect: a,
                    },
                ])
            }
            StereoMode::RowInterleaved => composed(Compose::Rows),
            StereoMode::ColumnInterleaved => composed(Compose::Columns),
            StereoMode::Anaglyph => composed(Compose::Anaglyph),
        }
    }
}

/// A right-handed perspective projection (depth 0 at `near`, 1 at `far`)
/// for an eye `eye_x` Å along the screen's x axis from the mono camera,
/// off-axis so that its window at `convergence` Å is the mono camera's.
/// `eye_x = 0` is the ordinary symmetric projection.
pub fn off_axis(
    fov_y: f64,
    aspect: f64,
    near: f64,
    far: f64,
    eye_x: f64,
    convergence: f64,
) -> DMat4 {
    let mut p = super::view::perspective(fov_y, aspect, near, far);
    let f = 1.0 / (0.5 * fov_y).tan();
    // x_clip gains (f/aspect)·(eye_x/D)·(−z): the window shifts with the eye.
    p.z_axis.x = -f / aspect * eye_x / convergence;
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    /// NDC x of centre-view point (x, z) seen by an eye at `e`.
    fn ndc_x(e: f64, x: f64, z: f64, conv: f64) -> f64 {
        let p = off_axis(0.6, 1.5, 1.0, 100.0, e, conv);
        let c = p * DVec4::new(x - e, 0.3, z, 1.0);
        c.x / c.w
    }

    #[test]
    fn zero_parallax_at_convergence_crossed_in_front_uncrossed_behind() {
        let (d, sep) = (40.0, 1.2);
        let (l, r) = (-sep / 2.0, sep / 2.0);
        // On the convergence plane both eyes agree with the mono camera.
        let mono = ndc_x(0.0, 3.0, -d, d);
        assert!((ndc_x(l, 3.0, -d, d) - mono).abs() < 1e-12);
        assert!((ndc_x(r, 3.0, -d, d) - mono).abs() < 1e-12);
        let f = 1.0 / 0.3f64.tan();
        for z in [10.0, 25.0, 60.0, 90.0] {
            let p = ndc_x(l, 3.0, -z, d) - ndc_x(r, 3.0, -z, d);
            let expected = f / 1.5 * sep * (1.0 / z - 1.0 / d);
            assert!((p - expected).abs() < 1e-12, "z {z}: {p} vs {expected}");
            // In front: the left image is to the right.
            assert_eq!(p > 0.0, z < d);
        }
    }

    #[test]
    fn no_vertical_parallax_and_same_depth() {
        let a = off_axis(0.6, 1.5, 1.0, 100.0, -0.5, 30.0) * DVec4::new(2.5, 1.0, -20.0, 1.0);
        let b = off_axis(0.6, 1.5, 1.0, 100.0, 0.5, 30.0) * DVec4::new(1.5, 1.0, -20.0, 1.0);
        assert!((a.y / a.w - b.y / b.w).abs() < 1e-15);
        assert!((a.z / a.w - b.z / b.w).abs() < 1e-15);
    }

    #[test]
    fn plans_put_each_eye_where_the_mode_says() {
        let s = |mode| Stereo {
            mode,
            ..Stereo::default()
        };
        let p = s(StereoMode::Mono).plan(640, 400, 0);
        assert_eq!(p.eyes.len(), 1);
        assert_eq!(p.eyes[0].eye, Eye::Centre);
        let p = s(StereoMode::SideBySide).plan(640, 400, 0);
        assert_eq!(p.eyes[0].eye, Eye::Left);
        assert_eq!(p.eyes[0].viewport, [0, 0, 320, 400]);
        assert_eq!(p.eyes[1].viewport, [320, 0, 320, 400]);
        assert!((p.eyes[0].aspect - 0.8).abs() < 1e-12);
        let p = s(StereoMode::SideBySideHalf).plan(640, 400, 0);
        assert!((p.eyes[1].aspect - 1.6).abs() < 1e-12);
        let p = s(StereoMode::TopBottom).plan(640, 400, 0);
        assert_eq!(p.eyes[1].viewport, [0, 200, 640, 200]);
        assert!((p.eyes[0].aspect - 3.2).abs() < 1e-12);
        let p = s(StereoMode::Anaglyph).plan(640, 400, 0);
        assert_eq!(p.compose, Some(Compose::Anaglyph));
        let seq: Vec<Eye> = (0..4)
            .map(|k| s(StereoMode::FrameSequential).plan(64, 64, k).eyes[0].eye)
            .collect();
        assert_eq!(seq, [Eye::Left, Eye::Right, Eye::Left, Eye::Right]);
        let swapped = Stereo {
            swap: true,
            ..s(StereoMode::SideBySide)
        };
        assert_eq!(swapped.plan(640, 400, 0).eyes[0].eye, Eye::Right);
    }

    #[test]
    fn names_round_trip_and_cycle_through_all() {
        let mut m = StereoMode::Mono;
        for _ in 0..StereoMode::ALL.len() {
            assert_eq!(StereoMode::parse(m.name()), Some(m));
            m = m.next();
        }
        assert_eq!(m, StereoMode::Mono);
        assert_eq!(StereoMode::parse("3d"), None);
    }
}
