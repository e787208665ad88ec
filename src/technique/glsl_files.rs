//! The GLSL sources under a directory, its subdirectories included (the public include's parts
//! are in `glsl/motion_shadows/`), for the tests that read every shader's text.

use std::path::{Path, PathBuf};

/// Every file under `dir`, recursively, sorted; panics naming what it cannot read (tests only).
pub(crate) fn glsl_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let entries = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("reading directory {}: {e}", dir.display()));
        for entry in entries {
            let path = entry
                .unwrap_or_else(|e| panic!("listing {}: {e}", dir.display()))
                .path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}
