//! The views of the fit toggled by their keys in a real window under Xvfb
//! (issue 45), on DHFR with trimethoprim (6xg5/TOP): U (colour by
//! contribution), P (the pocket in ball-and-stick, when the window has it)
//! and N (hydrogen bonds) with the drug in its crystal pose;
//! then, with the drug moved out of its pose, Y (the ghost of that pose) and
//! 4 (the clipping slab; 5 thinner, 6 back). Each key changes the middle
//! of the screen, and pressing it again restores it pixel for pixel (the
//! renderer is deterministic). Then a rotatable bond: Tab selects it,
//! Shift+' turns it and Ctrl+Z turns it back. With the ghost and the slab
//! on, the window still idles.
//!
//! Needs `Xvfb`, `xdotool`, ImageMagick's `import` (CI installs them) and
//! `../shared/pdb`; elsewhere a missing one skips the test with a message.

mod common;

use std::path::Path;
use std::thread::sleep;
use std::time::Duration;

use common::x11::{centre_difference, cpu_seconds, screen, shot, tap, taps};

/// The ball-and-stick pocket's key, `p`, when the window has it: when the
/// key table (docs/keys.md, which a test keeps equal to it) binds P.
fn ball_and_stick_key() -> Option<&'static str> {
    let keys = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/keys.md"))
        .unwrap_or_default();
    keys.lines().any(|l| l.starts_with("| P |")).then_some("p")
}

/// The screen once it has stopped changing (two shots 1 s apart agree in
/// the middle; up to 20 s).
fn settled(display: &str, dir: &Path, name: &str) -> image::RgbImage {
    let mut last = shot(display, &dir.join(format!("{name}-0.png")));
    for k in 1..20 {
        sleep(Duration::from_millis(1000));
        let now = shot(display, &dir.join(format!("{name}-{k}.png")));
        if centre_difference(&last, &now, 0) == 0 {
            return now;
        }
        last = now;
    }
    last
}

/// Presses `key` and checks the middle of the screen changes from
/// `before`; presses it again and checks it comes back to `before`
/// exactly.
fn toggles(
    display: &str,
    dir: &Path,
    key: &str,
    before: &image::RgbImage,
    log: &dyn Fn() -> String,
) {
    taps(display, key, 1);
    let on = settled(display, dir, &format!("{key}-on"));
    let changed = centre_difference(before, &on, 0);
    eprintln!("{key}: {changed} pixels changed in the middle of the screen");
    assert!(
        changed > 20,
        "{key} changed only {changed} pixels\n{}",
        log()
    );
    taps(display, key, 1);
    let off = settled(display, dir, &format!("{key}-off"));
    let left = centre_difference(before, &off, 0);
    assert_eq!(left, 0, "{key} twice left {left} pixels changed\n{}", log());
}

#[test]
fn each_view_key_changes_the_picture_and_toggling_back_restores_it() {
    let Some(pdb) = common::shared_pdb() else {
        return;
    };
    let Some(mut x) = screen("window-views") else {
        return;
    };
    let d = x.display.clone();
    let dir = x.runtime.clone();
    let log = x.runtime.join("views.log");
    let complex = pdb.join("6xg5_tmp_prepared.pdb");
    let complex = complex.to_str().expect("path").to_string();
    let app = x.open(&[&complex, "--ligand", "TOP"], &log, false);
    let text = || std::fs::read_to_string(&log).unwrap_or_default();
    // Let the structure load and the start-up messages expire.
    sleep(Duration::from_secs(8));
    let crystal = settled(&d, &dir, "crystal");

    // In the crystal pose: contribution colours, the pocket in
    // ball-and-stick and hydrogen bonds. Where the pocket exists, H-bonds
    // are toggled over it (turning them on shows the pocket too, and
    // turning them off leaves it), and the pocket's key then hides it.
    toggles(&d, &dir, "u", &crystal, &text);
    match ball_and_stick_key() {
        Some(p) => {
            toggles(&d, &dir, p, &crystal, &text);
            taps(&d, p, 1);
            let pocket = settled(&d, &dir, "pocket");
            toggles(&d, &dir, "n", &pocket, &text);
            taps(&d, p, 1);
            let back = settled(&d, &dir, "pocket-off");
            assert_eq!(centre_difference(&crystal, &back, 0), 0, "{p} twice");
        }
        None => toggles(&d, &dir, "n", &crystal, &text),
    }

    // The drug 6 Å towards the eye and 4 Å right (object mode, coarse
    // steps), so that its ghost in the pocket is not hidden by it.
    taps(&d, "space", 1);
    sleep(Duration::from_millis(300));
    for _ in 0..6 {
        tap(&d, "Prior", true);
    }
    for _ in 0..4 {
        tap(&d, "Right", true);
    }
    let moved = settled(&d, &dir, "moved");
    assert!(
        centre_difference(&crystal, &moved, 0) > 200,
        "the drug did not move\n{}",
        text()
    );
    toggles(&d, &dir, "y", &moved, &text);
    toggles(&d, &dir, "4", &moved, &text);

    // The slab's thickness: 5 thins it (the picture changes), 6 brings it
    // back to 10 Å exactly.
    taps(&d, "4", 1);
    let slab = settled(&d, &dir, "slab");
    assert!(centre_difference(&moved, &slab, 0) > 200);
    taps(&d, "5", 1);
    let thin = settled(&d, &dir, "slab-thin");
    assert!(
        centre_difference(&slab, &thin, 0) > 50,
        "5 did not thin the slab\n{}",
        text()
    );
    taps(&d, "6", 1);
    let back = settled(&d, &dir, "slab-back");
    assert_eq!(
        centre_difference(&slab, &back, 0),
        0,
        "5 then 6 is not the same slab"
    );

    // The drug's torsions (issue 44), with the slab off: Tab selects a
    // rotatable bond (drawn over the drug in orange with its angle),
    // Shift+' turns it 30° through the collision response, and Ctrl+Z
    // takes the turn back to the picture before it.
    taps(&d, "4", 1);
    let plain = settled(&d, &dir, "slab-off");
    assert_eq!(centre_difference(&moved, &plain, 0), 0, "4 twice");
    taps(&d, "Tab", 1);
    let bond = settled(&d, &dir, "bond");
    let shown = centre_difference(&plain, &bond, 0);
    eprintln!("Tab: {shown} pixels changed in the middle of the screen");
    assert!(shown > 20, "Tab drew no bond\n{}", text());
    taps(&d, "shift+apostrophe", 1);
    let turned = settled(&d, &dir, "turned");
    let turn = centre_difference(&bond, &turned, 0);
    eprintln!("Shift+': {turn} pixels changed in the middle of the screen");
    assert!(turn > 20, "Shift+' turned nothing\n{}", text());
    taps(&d, "ctrl+z", 1);
    let undone = settled(&d, &dir, "undone");
    assert_eq!(
        centre_difference(&bond, &undone, 0),
        0,
        "Ctrl+Z did not take the turn back\n{}",
        text()
    );
    taps(&d, "4", 1);

    // Ghost and slab on: nothing moves, so the window idles.
    taps(&d, "y", 1);
    sleep(Duration::from_secs(6));
    let pid = app.0.id();
    let c0 = cpu_seconds(pid);
    sleep(Duration::from_secs(4));
    let idle = (cpu_seconds(pid) - c0) / 4.0 * 100.0;
    eprintln!("idle CPU with the ghost and the slab on: {idle:.1} % of a core");
    assert!(
        idle < 5.0,
        "the idle window used {idle:.1} % of a core\n{}",
        text()
    );
    drop(app);
}
