//! The views of the pocket in a real window under Xvfb (issue 45): P puts
//! the pocket in ball-and-stick (the picture changes where the drug is),
//! Shift+P writes the residues' names, N turns hydrogen bonds on (and
//! ball-and-stick with them), and turning everything off again gives back
//! the first picture (screenshots).
//!
//! DHFR with trimethoprim (6xg5, TOP), the receptor translucent. Needs `Xvfb`, `xdotool` and ImageMagick's `import` (CI installs them);
//! elsewhere a missing tool skips the test with a message.

mod common;

use std::path::Path;
use std::process::Command;
use std::thread::sleep;
use std::time::Duration;

use common::x11::{finish, screen, taps, wait_exit, xdotool};

/// A screenshot of the whole screen, as RGB pixels.
fn shot(display: &str, path: &Path) -> image::RgbImage {
    let ok = Command::new("import")
        .args(["-window", "root", path.to_str().expect("path")])
        .env("DISPLAY", display)
        .status()
        .expect("import");
    assert!(ok.success(), "screenshot failed");
    image::open(path).expect("read screenshot").to_rgb8()
}

/// Pixels that differ between `a` and `b` in the middle of the screen
/// (the scene; the HUD's bars and boxes, whose values change, are outside it).
fn centre_difference(a: &image::RgbImage, b: &image::RgbImage) -> usize {
    let (w, h) = a.dimensions();
    let mut n = 0;
    for y in h / 4..3 * h / 4 {
        for x in w / 4..3 * w / 4 {
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            if p.iter().zip(q).any(|(u, v)| u.abs_diff(v) > 24) {
                n += 1;
            }
        }
    }
    n
}

/// Presses `key` with Shift for 100 ms.
fn shift_tap(display: &str, key: &str) {
    xdotool(display, &["keydown", "shift"]);
    xdotool(display, &["keydown", key]);
    sleep(Duration::from_millis(100));
    xdotool(display, &["keyup", key]);
    xdotool(display, &["keyup", "shift"]);
    sleep(Duration::from_millis(250));
}

/// Waits until `f` holds (checked every 0.5 s, up to 20 s).
fn eventually(mut f: impl FnMut() -> bool) -> bool {
    for _ in 0..40 {
        if f() {
            return true;
        }
        sleep(Duration::from_millis(500));
    }
    false
}

#[test]
fn p_shift_p_and_n_toggle_ball_and_stick_labels_and_hydrogen_bonds() {
    let Some(data) = common::shared_pdb() else {
        return;
    };
    let Some(mut x) = screen("window-sticks") else {
        return;
    };
    let d = x.display.clone();
    let log = x.runtime.join("sticks.log");
    let pdb = data.join("6xg5_tmp_prepared.pdb");
    let pdb = pdb.to_str().expect("path");
    let mut app = x.open(&[pdb, "--ligand", "TOP"], &log, true);
    let text = || std::fs::read_to_string(&log).unwrap_or_default();
    let dir = x.runtime.clone();
    // The receptor translucent (T), so the pocket shows.
    taps(&d, "t", 1);
    assert!(
        eventually(|| text().contains("translucent")),
        "T said nothing\n{}",
        text()
    );
    sleep(Duration::from_secs(3));
    let before = shot(&d, &dir.join("a.png"));

    // P: the drug and the rings near it become balls and sticks.
    taps(&d, "p", 1);
    assert!(
        eventually(|| text().contains("pocket in ball-and-stick on")),
        "P said nothing\n{}",
        text()
    );
    let mut sticks = before.clone();
    assert!(
        eventually(|| {
            sticks = shot(&d, &dir.join("b.png"));
            centre_difference(&before, &sticks) > 2000
        }),
        "P did not change the picture\n{}",
        text()
    );
    // Shift+P: residue names over the scene.
    shift_tap(&d, "p");
    assert!(
        eventually(|| text().contains("residue labels on")),
        "Shift+P said nothing\n{}",
        text()
    );
    assert!(
        eventually(|| centre_difference(&sticks, &shot(&d, &dir.join("c.png"))) > 30),
        "Shift+P wrote no label\n{}",
        text()
    );
    // Both off: the first picture again.
    shift_tap(&d, "p");
    taps(&d, "p", 1);
    assert!(
        eventually(|| text().contains("pocket in ball-and-stick off")),
        "P (off) said nothing\n{}",
        text()
    );
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("e.png"))) < 300),
        "turning ball-and-stick off did not give back the spheres\n{}",
        text()
    );
    // N: hydrogen bonds, with the pocket in ball-and-stick.
    taps(&d, "n", 1);
    assert!(
        eventually(|| text().contains("hydrogen bonds on")),
        "N said nothing\n{}",
        text()
    );
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("f.png"))) > 2000),
        "N did not show the pocket in ball-and-stick\n{}",
        text()
    );
    taps(&d, "q", 1);
    assert!(wait_exit(&mut app, 30).is_some(), "Q did not quit");
    let _ = finish(&mut app, &log, 5, "the window (sticks)");
}
