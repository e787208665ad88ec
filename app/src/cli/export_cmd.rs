//! `motion-shadows scene export`: a built-in scene as a scene file, on stdout or at `--out`.

use std::path::Path;

use super::args::RandomCubesArgs;
use super::shared::builtin_options;
use crate::output::write_file_atomically;
use crate::scene::limits::MAX_SCENE_FILE_BYTES;
use crate::scene::{builtin_file, scene_to_json};

/// Writes the scene's JSON to `out` (through a temporary file: a failed export leaves an
/// older file intact) or prints it. A file larger than the loader reads is refused: it
/// would be written only for `render --scene-file` to refuse it (`walker-toward-light
/// --subdivide 4` is 346 MiB).
pub fn run(name: &str, out: Option<&Path>, random: &RandomCubesArgs) -> anyhow::Result<()> {
    let json = scene_to_json(&builtin_file(name, &builtin_options(random))?);
    let bytes = json.len() as u64;
    anyhow::ensure!(
        bytes <= MAX_SCENE_FILE_BYTES,
        "the exported scene {name} would be {:.1} MiB, more than the {} MiB a scene file may \
         have (docs/src/scene-format.md, \"Limits\"), so `render --scene-file` could not read \
         it; nothing was written{}",
        bytes as f64 / f64::from(1 << 20),
        MAX_SCENE_FILE_BYTES >> 20,
        if random.subdivide > 0 {
            " (use a lower --subdivide)"
        } else {
            ""
        }
    );
    match out {
        Some(path) => Ok(write_file_atomically(path, json.as_bytes())?),
        None => {
            println!("{json}");
            Ok(())
        }
    }
}
