//! Motion-blurred shadows with the temporal (depth-time ranges) shadow map of Hong & Oh.
//!
//! Three layers, each usable without the one above it:
//! 1. [`gpu`]: a thin layer over ash (context, buffers, pipelines, submission, timestamps).
//! 2. [`technique`]: the passes. Each owns its pipelines and records into a command buffer
//!    the caller gives it; none creates a device, submits or waits.
//! 3. The app: [`scene`], [`render`] (a standalone renderer that drives the passes),
//!    [`output`] (EXR/PNG), and the `motion-shadows` binary.

pub mod bench;
pub mod chart;
pub mod cli;
pub mod compare;
pub mod error;
pub mod gpu;
pub mod output;
pub mod render;
pub mod scene;
pub mod technique;

pub use error::{Error, Result};
