//! The real structures the tests and benchmarks read: `../shared/pdb`
//! beside the repository, never copied into it.

use std::path::PathBuf;

/// The folder of test structures (`../shared/pdb` from the repository's
/// root), whether or not it exists.
pub fn shared_pdb_dir() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    // tests/testkit -> the repository's root -> its parent.
    let up = root.ancestors().nth(3).map_or(root.clone(), PathBuf::from);
    up.join("shared/pdb")
}

/// `../shared/pdb`, or `None` (with a message) when it is absent outside
/// CI.
///
/// # Panics
/// Under `CI=true` when the folder is missing: CI must have it.
pub fn shared_pdb() -> Option<PathBuf> {
    let dir = shared_pdb_dir();
    if dir.join("MANIFEST.md").is_file() {
        return Some(dir);
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("{} is missing: CI must have ../shared/pdb", dir.display());
    }
    eprintln!(
        "SKIP: {} not found; tests on real structures skipped",
        dir.display()
    );
    None
}
