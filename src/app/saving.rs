//! Names for what the window writes, never over an existing file: a saved
//! pose is `NAME-docked.pdb` and `.sdf`, then `NAME-docked-2.*`, `-3`, …
//! (the first number free for both files); a screenshot is
//! `bump-SCENE-YYYY-MM-DD-HHMM-SS.png` in local time, numbered the same way
//! when two fall in one second.
//!
//! A name is free when no file of that name exists when the window looks,
//! just before writing.

use std::io;
use std::path::{Path, PathBuf};

/// How many numbered names are tried before giving up.
const MAX_NUMBER: u32 = 10_000;

/// A file name from any text: letters, digits, `.`, `-` and `_` kept,
/// anything else `_`.
pub fn file_stem(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "molecule".into() } else { s }
}

/// `stem` or `stem-N` (N ≥ 2) for the first N at which no file of any
/// extension in `exts` exists in `dir`.
///
/// # Errors
/// `AlreadyExists` when 10 000 numbered names are taken.
pub fn free_names(dir: &Path, stem: &str, exts: &[&str]) -> io::Result<Vec<PathBuf>> {
    for n in 1..=MAX_NUMBER {
        let base = if n == 1 {
            stem.to_string()
        } else {
            format!("{stem}-{n}")
        };
        let paths: Vec<PathBuf> = exts
            .iter()
            .map(|e| dir.join(format!("{base}.{e}")))
            .collect();
        if !paths.iter().any(|p| p.exists()) {
            return Ok(paths);
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        format!("{stem}: {MAX_NUMBER} numbered names are taken"),
    ))
}

/// The scene's short name for a screenshot: the first molecule's file name
/// up to its first `_` or `.` (`6xg5_tmp_prepared.pdb` → `6xg5`).
pub fn scene_name(first_molecule: Option<&str>) -> String {
    let Some(name) = first_molecule else {
        return "empty".into();
    };
    let file = name.split(' ').next().unwrap_or(name);
    let short = file.split(['_', '.']).next().unwrap_or(file);
    file_stem(short)
}

/// `bump-SCENE-YYYY-MM-DD-HHMM-SS` for a screenshot taken at `time`.
pub fn screenshot_stem<Tz: chrono::TimeZone>(scene: &str, time: &chrono::DateTime<Tz>) -> String
where
    Tz::Offset: std::fmt::Display,
{
    format!("bump-{scene}-{}", time.format("%Y-%m-%d-%H%M-%S"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono::TimeZone;

    #[test]
    fn saved_names_are_numbered_never_overwritten() {
        let dir = std::env::temp_dir().join(format!("bump-saving-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let first = free_names(&dir, "tmp-docked", &["pdb", "sdf"]).expect("claim");
        assert_eq!(first[0], dir.join("tmp-docked.pdb"));
        std::fs::write(&first[0], "kept").expect("write");
        std::fs::write(&first[1], "kept").expect("write");
        let second = free_names(&dir, "tmp-docked", &["pdb", "sdf"]).expect("claim");
        assert_eq!(second[1], dir.join("tmp-docked-2.sdf"));
        // A name taken for one extension only skips that number for both.
        std::fs::write(dir.join("tmp-docked-3.sdf"), "x").expect("write");
        std::fs::write(&second[0], "x").expect("write");
        let fourth = free_names(&dir, "tmp-docked", &["pdb", "sdf"]).expect("claim");
        assert_eq!(fourth[0], dir.join("tmp-docked-4.pdb"));
        assert_eq!(
            std::fs::read_to_string(&first[0]).expect("read"),
            "kept",
            "never overwritten"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn screenshot_names_say_scene_and_local_time() {
        assert_eq!(scene_name(Some("6xg5_tmp_prepared.pdb receptor")), "6xg5");
        assert_eq!(scene_name(Some("1s3v_protein.pdb receptor")), "1s3v");
        assert_eq!(scene_name(Some("rings")), "rings");
        assert_eq!(scene_name(None), "empty");
        let t = chrono::FixedOffset::east_opt(3600)
            .expect("offset")
            .with_ymd_and_hms(2026, 11, 26, 21, 51, 3)
            .single()
            .expect("time");
        assert_eq!(screenshot_stem("6xg5", &t), "bump-6xg5-2026-11-26-2151-03");
        assert_eq!(file_stem("a b/c"), "a_b_c");
    }
}
