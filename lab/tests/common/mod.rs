//! Shared pieces of the tests that run the `breakaway-lab` binary: running
//! it, files in the test scratch directory, the one-line error contract, and
//! the repository's model and data files.
#![allow(dead_code)] // each test file uses its own subset

use std::path::PathBuf;
use std::process::{Command, Output};

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_breakaway-lab");

/// The Fig. 5 model file, `lab/models/fig5.toml`.
pub fn fig5() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/models/fig5.toml").to_string()
}

/// `rel` in the shared data directory (`shared/data` beside the
/// repository; the tests that need a file there skip when it is absent).
pub fn shared_data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(rel)
}

/// Set (to anything) where the shared data must be present: `cargo xtask
/// test` sets it when it finds `shared/data` beside the repository, so that
/// a test looking in the wrong place fails instead of passing on nothing.
pub const REQUIRE_SHARED: &str = "BREAKAWAY_REQUIRE_SHARED";

/// `rel` in the shared data directory as a string, or `None` (after a note)
/// when it is absent: the test that needs it is then skipped, unless
/// [`REQUIRE_SHARED`] is set, where the absence fails the test.
pub fn shared_or_skip(rel: &str) -> Option<String> {
    let f = shared_data(rel);
    if f.exists() {
        Some(f.to_string_lossy().into_owned())
    } else {
        assert!(
            std::env::var_os(REQUIRE_SHARED).is_none(),
            "{} not found, and {REQUIRE_SHARED} is set: the test would compare nothing",
            f.display()
        );
        println!("note: {} not found; skipped", f.display());
        None
    }
}

/// Runs the binary with `args`.
pub fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("runs the binary")
}

/// `name` in the test scratch directory.
pub fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Writes `text` to `name` in the scratch directory; returns the path.
pub fn write(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// Asserts that the failed run `o` of `args` printed exactly one stderr
/// line `error: …`, no panic, containing every needle; returns the line.
pub fn error_line(args: &[&str], o: &Output, needles: &[&str]) -> String {
    let err = String::from_utf8(o.stderr.clone()).unwrap();
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: not one line: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(lines[0].contains(n), "{args:?}: `{}` lacks `{n}`", lines[0]);
    }
    lines[0].to_string()
}
