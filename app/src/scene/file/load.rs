//! Reading and parsing a scene file: its size bounded, its text UTF-8, its `"format"`
//! checked before its fields, and writing one back as pretty JSON.

use std::path::Path;
use std::path::PathBuf;

use serde::Deserialize;

use super::format::{SCENE_FORMAT, SceneFile};
use crate::scene::limits::MAX_SCENE_FILE_BYTES;
use crate::scene::name::name_from_file_stem;
use crate::scene::pretty::pretty_json;
use crate::scene::read::read_bounded;
use crate::scene::{Scene, SceneError};

/// Only checks the version, ignoring everything else, so a file from another format
/// version reports that rather than a confusing unknown-field error.
#[derive(Deserialize)]
struct FormatProbe {
    format: Option<serde_json::Value>,
}

/// Reads and converts a scene file; OBJ paths are resolved against its directory. The file
/// may be a pipe; either way at most `MAX_SCENE_FILE_BYTES` are read.
pub fn load_scene_file(path: &Path) -> Result<Scene, SceneError> {
    read_scene_file(path)?.to_scene()
}

/// A scene file read and parsed but not yet converted, so it can be changed first
/// (`animate` poses its glTF models at each frame's time).
#[derive(Debug, Clone)]
pub struct SceneSource {
    pub file: SceneFile,
    /// Where relative model paths are resolved.
    pub base_dir: PathBuf,
    /// The scene's name when the file has no `"name"`.
    pub fallback_name: String,
}

impl SceneSource {
    pub fn to_scene(&self) -> Result<Scene, SceneError> {
        self.file.to_scene(&self.base_dir, &self.fallback_name)
    }
}

/// `load_scene_file` without the conversion.
pub fn read_scene_file(path: &Path) -> Result<SceneSource, SceneError> {
    let io_error = |source| SceneError::Io {
        path: path.to_owned(),
        source,
    };
    let bytes = read_bounded(path, MAX_SCENE_FILE_BYTES, true).map_err(|e| {
        io_error(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            e.to_string(),
        ))
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let message = format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to());
        io_error(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ))
    })?;
    let base_dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let (file, fallback_name) = parse_file(&text, path)?;
    Ok(SceneSource {
        file,
        base_dir: base_dir.to_owned(),
        fallback_name,
    })
}

/// Parses scene JSON. `name` labels the source in error messages (e.g. a file name) and,
/// minus any extension, names the scene when the JSON has no `"name"`. OBJ paths are
/// resolved against `base_dir`.
pub fn parse_scene_json(text: &str, base_dir: &Path, name: &str) -> Result<Scene, SceneError> {
    parse(text, base_dir, Path::new(name))
}

fn parse(text: &str, base_dir: &Path, source: &Path) -> Result<Scene, SceneError> {
    let (file, fallback_name) = parse_file(text, source)?;
    file.to_scene(base_dir, &fallback_name)
}

/// The file's contents and the name its source gives a scene without `"name"`.
fn parse_file(text: &str, source: &Path) -> Result<(SceneFile, String), SceneError> {
    let json_error = |e| SceneError::Json {
        path: source.to_owned(),
        source: e,
    };
    let probe: FormatProbe = serde_json::from_str(text).map_err(json_error)?;
    match probe.format {
        Some(serde_json::Value::String(f)) if f == SCENE_FORMAT => {}
        Some(other) => {
            return Err(SceneError::Invalid(format!(
                "{}: unsupported \"format\" {other}, expected {SCENE_FORMAT:?}",
                source.display()
            )));
        }
        None => {
            return Err(SceneError::Invalid(format!(
                "{}: missing field \"format\" (expected {SCENE_FORMAT:?})",
                source.display()
            )));
        }
    }
    let file: SceneFile = serde_json::from_str(text).map_err(json_error)?;
    let stem = source
        .file_stem()
        .map_or_else(|| source.to_string_lossy(), |s| s.to_string_lossy());
    Ok((file, name_from_file_stem(&stem)))
}

/// Pretty JSON that `parse_scene_json` reads back to an equal scene (f32 values are
/// written in their shortest exact form).
pub fn scene_to_json(scene_file: &SceneFile) -> String {
    // Cannot fail: every map key is a string and every value is plain data.
    let compact = serde_json::to_string(scene_file).expect("SceneFile serialises to JSON");
    let mut text = pretty_json(&compact);
    text.push('\n');
    text
}
