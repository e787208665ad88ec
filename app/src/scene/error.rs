//! The one error type of the scene module. Every message names the file and, where it
//! applies, the object or field, because scene files are written by hand.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// serde_json's message carries the line and column.
    #[error("{}: {source}", path.display())]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("cannot load OBJ {}: {message}", path.display())]
    Obj { path: PathBuf, message: String },
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error("unknown built-in scene {name:?} (available: {})", available.join(", "))]
    UnknownBuiltin {
        name: String,
        available: Vec<String>,
    },
}
