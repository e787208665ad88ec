//! What several of the cli binary's modules run the same way: the binary with `--out`, and a
//! per-process scratch folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `motion-shadows ARGS --out OUT` with the validation layer on; its output, whatever its
/// status (the caller asserts what it expects).
pub fn run_with_out(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .arg("--out")
        .arg(out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary")
}

/// A folder under the system's temporary one, named for the test and this process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("motion-shadows-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
