//! Running the `bump` binary from a test: its output, its JSON, its errors.

use std::process::{Command, Output};

use serde_json::Value;

/// Runs `bump ARGS` and returns what it did.
pub fn bump(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bump"))
        .args(args)
        .output()
        .expect("run bump")
}

/// Runs `bump ARGS` (which must succeed) and parses its standard output as
/// JSON.
pub fn json(args: &[&str]) -> Value {
    let out = bump(args);
    assert!(
        out.status.success(),
        "bump {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON output")
}

/// A run's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}
