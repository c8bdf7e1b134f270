//! The views of the pocket in a real window under Xvfb (issue 45): P puts
//! the pocket in ball-and-stick (the picture changes where the drug is),
//! Shift+P writes the residues' names, N turns hydrogen bonds on (and
//! ball-and-stick with them), and turning everything off again gives back
//! the first picture (screenshots).
//!
//! DHFR with trimethoprim (6xg5, TOP), the receptor translucent. Needs `Xvfb`, `xdotool` and ImageMagick's `import` (CI installs them);
//! elsewhere a missing tool skips the test with a message.

mod common;

use std::thread::sleep;
use std::time::Duration;

use common::x11::{centre_difference, eventually, finish, screen, shot, tap, taps, wait_exit};

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
            centre_difference(&before, &sticks, 24) > 2000
        }),
        "P did not change the picture\n{}",
        text()
    );
    // Shift+P: residue names over the scene.
    tap(&d, "p", true);
    assert!(
        eventually(|| text().contains("residue labels on")),
        "Shift+P said nothing\n{}",
        text()
    );
    assert!(
        eventually(|| centre_difference(&sticks, &shot(&d, &dir.join("c.png")), 24) > 30),
        "Shift+P wrote no label\n{}",
        text()
    );
    // Both off: the first picture again.
    tap(&d, "p", true);
    taps(&d, "p", 1);
    assert!(
        eventually(|| text().contains("pocket in ball-and-stick off")),
        "P (off) said nothing\n{}",
        text()
    );
    assert!(
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("e.png")), 24) < 300),
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
        eventually(|| centre_difference(&before, &shot(&d, &dir.join("f.png")), 24) > 2000),
        "N did not show the pocket in ball-and-stick\n{}",
        text()
    );
    taps(&d, "q", 1);
    assert!(wait_exit(&mut app, 30).is_some(), "Q did not quit");
    let _ = finish(&mut app, &log, 5, "the window (sticks)");
}
