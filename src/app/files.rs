//! Files in and out of the window: files opened or dropped, molecules the
//! loading thread sends, saved poses and screenshots (named by
//! [`super::saving`], never over an existing file).

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::{App, LoadEvent, saving};
use crate::model::{self, LoadOptions};
use crate::render::offscreen::{render_image, save_png};
use crate::session::{Command, labels};

impl App {
    /// Writes molecule `b`, in the first molecule's (the receptor's) file
    /// frame, as `<name>-docked.pdb` and `.sdf` (and `.pdbqt`, with its
    /// torsion tree, for a molecule read from a PDBQT) in the current folder
    /// (or `-2`, `-3`, … when taken); says what was written. `true` when
    /// every file was written.
    pub(super) fn save_pose(&mut self, b: usize) -> bool {
        let Some(pose) = self.session.pose_in_frame_of(b, 0) else {
            return false;
        };
        let mol = &self.session.bodies()[b].molecule;
        let stem = format!("{}-docked", saving::file_stem(&mol.name));
        let dir = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
        let extensions: &[&str] = if mol.autodock.is_some() {
            &["pdb", "sdf", "pdbqt"]
        } else {
            &["pdb", "sdf"]
        };
        let paths = match saving::free_names(&dir, &stem, extensions) {
            Ok(p) => p,
            Err(e) => {
                self.hud.say(format!("not saved: {e}"));
                return false;
            }
        };
        let mut said = Vec::new();
        let mut ok = true;
        for (k, path) in paths.iter().enumerate() {
            let written = match k {
                0 => model::write::write_pdb(mol, &pose, path),
                1 => model::write::write_sdf(mol, &pose, path),
                _ => model::write::write_pdbqt(mol, &pose, path),
            };
            match written {
                Ok(()) => said.push(shown(path)),
                Err(e) => {
                    ok = false;
                    self.hud.say(format!("not saved: {e}"));
                }
            }
        }
        if !said.is_empty() {
            let what = self.session.describe(b).unwrap_or_default();
            self.hud.say(format!(
                "saved {what} in the receptor's frame as {}",
                said.join(" and ")
            ));
        }
        if ok {
            self.session.mark_saved(b);
        }
        ok
    }

    /// Saves every molecule moved since it was saved; `true` when all were.
    pub(super) fn save_unsaved(&mut self) -> bool {
        let mut ok = true;
        for b in self.session.unsaved() {
            ok &= self.save_pose(b);
        }
        ok
    }

    /// Writes the window's view as `bump-SCENE-DATE-TIME.png` (local time;
    /// numbered when taken) in the current folder.
    pub(super) fn screenshot(&mut self) {
        let Some(g) = &self.gfx else { return };
        let scene = saving::scene_name(
            self.session
                .bodies()
                .first()
                .map(|b| b.molecule.name.as_str()),
        );
        let stem = saving::screenshot_stem(&scene, &chrono::Local::now());
        let dir = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
        let path = match saving::free_names(&dir, &stem, &["png"]) {
            Ok(mut p) => p.remove(0),
            Err(e) => {
                self.hud.say(format!("screenshot not saved: {e}"));
                return;
            }
        };
        let params = self.hud.view.params(self.light);
        let result = render_image(
            &g.gpu,
            &self.session,
            g.config.width,
            g.config.height,
            &params,
        )
        .and_then(|img| save_png(&img, &path));
        match result {
            Ok(()) => self.hud.say(format!("saved the view as {}", shown(&path))),
            Err(e) => self.hud.say(format!("screenshot failed: {e}")),
        }
    }

    /// Opens a file chosen in the Open dialog or dropped on the window.
    pub(super) fn open_file(&mut self, path: PathBuf) {
        if self.recorder.is_some() || self.player.is_some() {
            // A log replays inputs on a fixed scene; a file opened now would
            // not be in it.
            self.hud.say(format!(
                "{}: opening files is off while recording or replaying",
                path.display()
            ));
            return;
        }
        let opts = LoadOptions::default();
        let loaded = model::load(&path, &opts).and_then(|l| {
            let m = model::receptor_only(&l.structure)?;
            Ok((l.warnings, m))
        });
        match loaded {
            Ok((warnings, m)) => {
                for w in warnings {
                    self.hud.say(w);
                }
                self.hud.say(format!(
                    "opened {}",
                    labels::molecule(&m).replacen(": ", " ", 1)
                ));
                self.add_molecules(vec![m]);
            }
            Err(e) => self.hud.say(format!("{e}")),
        }
    }

    /// Adds molecules to the session and the GPU, and asks for the view
    /// that shows the drug (the camera moves only if the user has not
    /// moved it).
    pub(super) fn add_molecules(&mut self, molecules: Vec<crate::model::Molecule>) {
        for m in molecules {
            self.session.add_molecule(m);
        }
        self.pending.commands.push(Command::ViewDrug);
        let title = self.title();
        if let Some(g) = &mut self.gfx {
            g.reload(&self.session, &title);
            // The new renderer has element colours only.
            self.hud.score.colors = Default::default();
            self.hud.score.pocket.renderer_replaced();
        }
        self.request_redraw();
    }

    /// Takes what the loading thread has sent; `true` while it is still at work.
    pub(super) fn poll_loader(&mut self) -> bool {
        let Some((rx, _)) = &self.loader else {
            return false;
        };
        let mut events = Vec::new();
        let mut finished = false;
        loop {
            match rx.try_recv() {
                Ok(e) => events.push(e),
                Err(std::sync::mpsc::TryRecvError::Empty) => break,
                Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                    finished = true;
                    break;
                }
            }
        }
        for e in events {
            self.loaded(e);
        }
        if finished {
            self.loader = None;
            self.hud.loading = None;
            if self.session.bodies().is_empty() {
                self.hud.say(
                    "nothing could be loaded: showing the built-in scene (Ctrl+O opens a file)",
                );
                let (r, d) = crate::model::builtin::scene(crate::model::RadiiSet::Bondi);
                self.add_molecules(vec![r, d]);
            }
        }
        !finished
    }

    fn loaded(&mut self, e: LoadEvent) {
        match e {
            LoadEvent::Reading(label) => {
                self.hud.loading = Some(label);
                self.hud.loading_since = Some(Instant::now());
            }
            LoadEvent::Loaded {
                label,
                molecules,
                warnings,
                seconds,
            } => {
                for w in warnings {
                    self.hud.say(w);
                }
                let atoms: usize = molecules.iter().map(|m| m.len()).sum();
                self.hud.say(format!(
                    "loaded {label}: {} atoms in {seconds:.2} s",
                    labels::thousands(atoms)
                ));
                self.add_molecules(molecules);
            }
            LoadEvent::Failed(msg) => self.hud.say(msg),
        }
    }
}

/// A path as the status line shows it: the file name alone when it is in
/// the current folder.
fn shown(path: &Path) -> String {
    let here = std::env::current_dir().ok();
    match (here, path.parent(), path.file_name()) {
        (Some(h), Some(p), Some(f)) if p == h => f.to_string_lossy().into_owned(),
        _ => path.display().to_string(),
    }
}
