//! The one error type of the scene module. Every message names the file and, where it
//! applies, the object or field, because scene files are written by hand. Every piece of
//! user text in a message (paths, names, the JSON parser's quotes of the input) is clipped,
//! so no message is longer than `limits::MAX_ERROR_CHARS`.

use std::path::PathBuf;

use super::clip::{clip, quoted, quoted_path};

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read {}: {}", quoted_path(path), quoted(&source.to_string()))]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// serde_json's message carries the line and column.
    #[error("{}: {}", quoted_path(path), quoted(&source.to_string()))]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("cannot load OBJ {}: {}", quoted_path(path), clip(message, 500))]
    Obj { path: PathBuf, message: String },
    #[error("cannot load glTF {}: {}", quoted_path(path), clip(message, 500))]
    Gltf { path: PathBuf, message: String },
    #[error("invalid scene: {}", clip(.0, 960))]
    Invalid(String),
    #[error("unknown built-in scene {:?} (available: {})", quoted(name), available.join(", "))]
    UnknownBuiltin {
        name: String,
        available: Vec<String>,
    },
}
