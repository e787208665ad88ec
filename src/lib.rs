//! Motion-blurred shadows with the temporal (depth-time ranges) shadow map of Hong & Oh.
//!
//! Two layers, each usable without the one above it:
//! 1. [`gpu`]: a thin layer over ash (context, buffers, pipelines, submission, timestamps).
//! 2. [`technique`]: the passes. Each owns its pipelines and records into a command buffer
//!    the caller gives it; none creates a device, submits or waits.
//!
//! The app (scenes, the standalone renderer, image output, the `motion-shadows` command
//! line) is the `motion-shadows-app` crate in `app/`, a client of this public API.

#![warn(missing_docs)]

pub mod error;
pub mod gpu;
pub mod technique;

pub use error::{Error, Result};
/// The ash (Vulkan) and glam (math) versions the library's API uses.
pub use {ash, glam};
