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

    /// The work asked for would need more host memory than this process can still get
    /// (the message has the figures).
    #[error("{0}")]
    Memory(String),

    /// The deferred mask: `pixels` pixels walked more texels' ranges than the device's shader
    /// loop `limit` lets the mask run (one texel's list in one invocation, a moving
    /// receiver's whole path in its follow-up rounds), so their lit share could be wrong.
    #[error(
        "{pixels} pixel(s) of the deferred mask need more shader loop iterations than this device runs ({limit} per invocation, lavapipe's loop limiter, even with a moving receiver's path walked over follow-up rounds): their lit share could be wrong. One shadow texel's ranges, or all the texels a moving receiver crosses, are too many: let receivers stand still (render --static-receivers: one texel each), use a coarser map (--shadow-size: fewer texels crossed), {fewer_ranges}, use --method tsm, or a device without the limit"
    )]
    MaskLoopLimit {
        /// Pixels over the budget.
        pixels: u32,
        /// The device's limit.
        limit: u32,
        /// What stores fewer ranges per texel for the map's lookup.
        fewer_ranges: &'static str,
    },
}

/// The app's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
