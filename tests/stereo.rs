//! Stereo image tests on whatever adapter there is (Mesa's CPU Vulkan in
//! CI): where each stereo mode puts each eye (halves, rows, columns, colour
//! channels), the sign and size of the eye offset against the exact
//! off-axis geometry, the frame-sequential order, and that mono draws one
//! eye only.
//!
//! The scene is one grey atom at the view centre, distance `d`. With the
//! convergence plane at `D`, eye separation `s·D` and `f = 1/tan(fov/2)`,
//! each eye's image of the atom is shifted from the mono image by
//! `±(f/aspect)·s·(D/d − 1)/2` in NDC: to the right for the left eye when
//! the atom is in front of the convergence plane (`d < D`), to the left
//! when behind.

mod common;

use common::gpu;

use bump::model::Molecule;
use bump::render::offscreen::{Image, Offscreen};
use bump::render::{Cues, Gpu, Stereo, StereoMode, ViewParams};
use bump::session::{Session, Settings};
use glam::DVec3;

const W: u32 = 400;
const H: u32 = 200;
const DIST: f64 = 40.0;

fn session() -> Session {
    let m = Molecule::new("atom", vec![common::atom(1, "C", 1.0)], &[DVec3::ZERO]);
    let mut s = Session::new(vec![m], Settings::default()).expect("session");
    s.camera_mut().distance = DIST;
    s
}

fn params(mode: StereoMode, convergence: f64, swap: bool, frame: u64) -> ViewParams {
    ViewParams {
        cues: Cues::NONE,
        stereo: Stereo {
            mode,
            separation: 0.1,
            convergence,
            swap,
        },
        frame,
        ..ViewParams::default()
    }
}

/// Shift (pixels, + right) of the left eye's image from the mono image, in a
/// viewport `vp_w` wide drawn with `aspect`; the right eye's is the opposite.
fn left_shift(s: &Session, convergence: f64, aspect: f64, vp_w: u32) -> f64 {
    let f = 1.0 / (0.5 * s.camera().fov_y).tan();
    let ndc = f / aspect * 0.1 * (convergence * DIST / DIST - 1.0) / 2.0;
    ndc * f64::from(vp_w) / 2.0
}

fn background(img: &Image) -> [u8; 4] {
    img.pixel(0, 0).expect("corner")
}

/// Lit pixels of row `y` with x in `xs`.
fn lit_in_row(img: &Image, y: u32, xs: impl Iterator<Item = u32>) -> Vec<u32> {
    let bg = background(img);
    xs.filter(|&x| img.pixel(x, y).expect("px") != bg).collect()
}

/// Centre of the lit run of row `y` within `xs`.
fn centre_in_row(img: &Image, y: u32, xs: std::ops::Range<u32>) -> f64 {
    let lit = lit_in_row(img, y, xs);
    assert!(!lit.is_empty(), "row {y}: nothing drawn");
    (f64::from(lit[0]) + f64::from(*lit.last().expect("lit")) + 1.0) / 2.0
}

fn render(gpu: &Gpu, s: &Session, p: &ViewParams) -> (Image, bump::render::FrameStats) {
    let mut off = Offscreen::new(gpu, s, W, H).expect("target");
    let img = off.render(gpu, s, p).expect("render");
    (img, off.spheres.frame_stats())
}

fn near(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a:.2} vs expected {b:.2}");
}

#[test]
fn mono_draws_one_eye_centred() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    let (img, stats) = render(&gpu, &s, &params(StereoMode::Mono, 2.0, false, 0));
    assert_eq!((stats.eyes, stats.passes, stats.draws), (1, 1, 1));
    near(centre_in_row(&img, H / 2, 0..W), 200.0, 0.6, "mono centre");
}

#[test]
fn side_by_side_full_and_half_put_the_left_eye_left() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    for (mode, aspect) in [
        (StereoMode::SideBySide, 1.0),
        (StereoMode::SideBySideHalf, 2.0),
    ] {
        let (img, stats) = render(&gpu, &s, &params(mode, 2.0, false, 0));
        assert_eq!((stats.eyes, stats.passes, stats.draws), (2, 1, 2));
        let shift = left_shift(&s, 2.0, aspect, W / 2);
        assert!(shift > 5.0, "{shift}");
        // In front of the convergence plane: the left eye sees it right of
        // centre, the right eye left of centre.
        near(
            centre_in_row(&img, H / 2, 0..W / 2),
            100.0 + shift,
            1.0,
            "left half",
        );
        near(
            centre_in_row(&img, H / 2, W / 2..W),
            300.0 - shift,
            1.0,
            "right half",
        );
        // Full: each half has its own aspect (round atom); half: squeezed.
        let width = lit_in_row(&img, H / 2, 0..W / 2).len() as f64;
        let height = (0..H)
            .filter(|&y| img.pixel((100.0 + shift) as u32, y) != Some(background(&img)))
            .count() as f64;
        near(
            width / height,
            1.0 / (aspect * H as f64 / W as f64 * 2.0),
            0.12,
            "shape",
        );
        // Swapped: the right eye's image goes left.
        let (img, _) = render(&gpu, &s, &params(mode, 2.0, true, 0));
        near(
            centre_in_row(&img, H / 2, 0..W / 2),
            100.0 - shift,
            1.0,
            "swapped",
        );
    }
}

#[test]
fn top_bottom_puts_the_left_eye_on_top() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    for (mode, aspect) in [
        (StereoMode::TopBottom, 4.0),
        (StereoMode::TopBottomHalf, 2.0),
    ] {
        let (img, stats) = render(&gpu, &s, &params(mode, 2.0, false, 0));
        assert_eq!(stats.eyes, 2);
        let shift = left_shift(&s, 2.0, aspect, W);
        near(centre_in_row(&img, H / 4, 0..W), 200.0 + shift, 1.0, "top");
        near(
            centre_in_row(&img, 3 * H / 4, 0..W),
            200.0 - shift,
            1.0,
            "bottom",
        );
        // Nothing crosses the middle line: each eye stays in its half.
        assert!(lit_in_row(&img, H / 2 - 1, 0..W).is_empty());
    }
}

#[test]
fn rows_columns_and_anaglyph_interleave_as_documented() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    let shift = left_shift(&s, 2.0, 2.0, W);
    let (left_c, right_c) = (200.0 + shift, 200.0 - shift);
    let row = H / 2; // even
    // Rows: even rows (from 0 at the top) are the left eye's.
    let (img, stats) = render(&gpu, &s, &params(StereoMode::RowInterleaved, 2.0, false, 0));
    assert_eq!((stats.eyes, stats.passes), (2, 3));
    near(centre_in_row(&img, row, 0..W), left_c, 1.0, "even row");
    near(centre_in_row(&img, row + 1, 0..W), right_c, 1.0, "odd row");
    // Columns: even columns are the left eye's. The two images do not
    // overlap, so lit even columns lie around the left centre only.
    let (img, _) = render(
        &gpu,
        &s,
        &params(StereoMode::ColumnInterleaved, 2.0, false, 0),
    );
    let even = lit_in_row(&img, row, (0..W).step_by(2));
    let odd = lit_in_row(&img, row, (1..W).step_by(2));
    assert!(!even.is_empty() && !odd.is_empty());
    assert!(
        even.iter().all(|&x| (f64::from(x) - left_c).abs() < 12.0),
        "even columns {even:?} should be near {left_c}"
    );
    assert!(
        odd.iter().all(|&x| (f64::from(x) - right_c).abs() < 12.0),
        "odd columns {odd:?} should be near {right_c}"
    );
    // Anaglyph: red from the left eye, green and blue from the right.
    let (img, _) = render(&gpu, &s, &params(StereoMode::Anaglyph, 2.0, false, 0));
    let bg = background(&img);
    let only_left = img.pixel(left_c as u32 + 5, row).expect("px");
    let only_right = img.pixel(right_c as u32 - 5, row).expect("px");
    assert!(only_left[0] > bg[0] + 60, "{only_left:?}");
    assert_eq!(&only_left[1..3], &bg[1..3], "{only_left:?}");
    assert_eq!(only_right[0], bg[0], "{only_right:?}");
    assert!(only_right[1] > bg[1] + 60 && only_right[2] > bg[2] + 60);
}

#[test]
fn behind_the_convergence_plane_the_offset_reverses() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    let (img, _) = render(&gpu, &s, &params(StereoMode::SideBySide, 0.5, false, 0));
    let shift = left_shift(&s, 0.5, 1.0, W / 2);
    assert!(shift < -5.0, "{shift}");
    near(
        centre_in_row(&img, H / 2, 0..W / 2),
        100.0 + shift,
        1.0,
        "left",
    );
    near(
        centre_in_row(&img, H / 2, W / 2..W),
        300.0 - shift,
        1.0,
        "right",
    );
    // At the convergence plane there is no offset at all.
    let (img, _) = render(&gpu, &s, &params(StereoMode::SideBySide, 1.0, false, 0));
    near(
        centre_in_row(&img, H / 2, 0..W / 2),
        100.0,
        0.6,
        "zero parallax",
    );
}

#[test]
fn frame_sequential_alternates_left_first() {
    let Some(gpu) = gpu() else { return };
    let s = session();
    let shift = left_shift(&s, 2.0, 2.0, W);
    let mut off = Offscreen::new(&gpu, &s, W, H).expect("target");
    for (frame, swap, left) in [
        (0, false, true),
        (1, false, false),
        (2, false, true),
        (3, false, false),
        (0, true, false),
        (1, true, true),
    ] {
        let p = params(StereoMode::FrameSequential, 2.0, swap, frame);
        let img = off.render(&gpu, &s, &p).expect("render");
        let stats = off.spheres.frame_stats();
        assert_eq!((stats.eyes, stats.draws), (1, 1), "one eye per frame");
        let expected = if left { 200.0 + shift } else { 200.0 - shift };
        near(
            centre_in_row(&img, H / 2, 0..W),
            expected,
            1.0,
            &format!("frame {frame} swap {swap}"),
        );
    }
}
