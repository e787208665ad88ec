//! The app's error type: the library's errors plus what only the app does (scene files,
//! images, benchmarks).

/// Everything that can go wrong in the app.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The library (device, passes, buffers) failed.
    #[error(transparent)]
    Library(#[from] motion_shadows::Error),

    /// The scene could not be loaded or is invalid.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),

    /// Writing an output image failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),

    /// A benchmark could not write its results.
    #[error("bench: {0}")]
    Bench(String),

    /// A caller-supplied value is out of range.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// The app's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
