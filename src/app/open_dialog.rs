//! The Open dialog: an egui file browser (no native toolkit needed, so it
//! works the same under X11, Wayland and Xvfb). It lists folders and the
//! structure files bump reads; a click on a folder enters it, a click on a
//! file opens it.

use std::path::{Path, PathBuf};

/// Extensions bump reads (optionally followed by `.gz`).
const READABLE: &[&str] = &[
    ".pdb", ".ent", ".cif", ".mmcif", ".pdbqt", ".sdf", ".sd", ".mol", ".mol2",
];

/// True when `name` looks like a structure file bump reads.
pub fn is_readable(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    let stem = lower.strip_suffix(".gz").unwrap_or(&lower);
    READABLE.iter().any(|e| stem.ends_with(e))
}

/// One line of the listing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// File or folder name.
    pub name: String,
    /// True for a folder.
    pub is_dir: bool,
}

/// The folders and readable files of `dir`, folders first, each sorted by
/// name; hidden entries are left out.
///
/// # Errors
/// The I/O error of reading `dir`.
pub fn list(dir: &Path) -> std::io::Result<Vec<Entry>> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir)? {
        let Ok(e) = e else { continue };
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let is_dir = e.path().is_dir();
        if is_dir || is_readable(&name) {
            out.push(Entry { name, is_dir });
        }
    }
    out.sort_by(|a, b| (!a.is_dir, &a.name).cmp(&(!b.is_dir, &b.name)));
    Ok(out)
}

/// The dialog's state.
#[derive(Debug, Clone, Default)]
pub struct OpenDialog {
    /// Shown.
    pub open: bool,
    dir: PathBuf,
    entries: Vec<Entry>,
    error: Option<String>,
}

impl OpenDialog {
    /// Shows the dialog on `dir` (the current folder when empty).
    pub fn show_at(&mut self, dir: PathBuf) {
        self.open = true;
        self.enter(dir);
    }

    fn enter(&mut self, dir: PathBuf) {
        match list(&dir) {
            Ok(entries) => {
                self.entries = entries;
                self.error = None;
                self.dir = dir;
            }
            Err(e) => self.error = Some(format!("{}: {e}", dir.display())),
        }
    }

    /// Draws the dialog; returns the file chosen, if any.
    pub fn ui(&mut self, ctx: &egui::Context) -> Option<PathBuf> {
        if !self.open {
            return None;
        }
        let mut chosen = None;
        let mut go = None;
        let mut open = self.open;
        egui::Window::new("Open")
            .open(&mut open)
            .default_size([420.0, 360.0])
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    if ui.button("Up").clicked() {
                        go = self.dir.parent().map(Path::to_path_buf);
                    }
                    ui.monospace(self.dir.display().to_string());
                });
                if let Some(e) = &self.error {
                    ui.colored_label(egui::Color32::LIGHT_RED, e);
                }
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| {
                    for e in &self.entries {
                        let label = if e.is_dir {
                            format!("{}/", e.name)
                        } else {
                            e.name.clone()
                        };
                        if ui.selectable_label(false, label).clicked() {
                            let p = self.dir.join(&e.name);
                            if e.is_dir {
                                go = Some(p);
                            } else {
                                chosen = Some(p);
                            }
                        }
                    }
                    if self.entries.is_empty() {
                        ui.label("(no folders or structure files here)");
                    }
                });
            });
        if let Some(d) = go {
            self.enter(d);
        }
        self.open = open && chosen.is_none();
        chosen
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_folders_first_and_only_readable_files() {
        let tmp = std::env::temp_dir().join(format!("bump-open-{}", std::process::id()));
        std::fs::create_dir_all(tmp.join("zdir")).expect("dir");
        std::fs::create_dir_all(tmp.join(".hidden")).expect("dir");
        for f in ["b.pdb", "a.cif.gz", "c.txt", "d.SDF", ".e.pdb"] {
            std::fs::write(tmp.join(f), "x").expect("file");
        }
        let names: Vec<String> = list(&tmp)
            .expect("list")
            .into_iter()
            .map(|e| e.name)
            .collect();
        assert_eq!(names, ["zdir", "a.cif.gz", "b.pdb", "d.SDF"]);
        assert!(list(&tmp.join("missing")).is_err());
        let _ = std::fs::remove_dir_all(&tmp);
    }
}
