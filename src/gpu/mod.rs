//! Layer 1: a thin, honest layer over ash. Nothing here knows about shadows.
//!
//! [`Context`] owns (or borrows, see [`Context::from_raw`]) the instance, device and queue,
//! and a gpu-allocator; [`DeviceRequirements`] is what a host enables on its device for it. [`Buffer`]s free themselves. [`OneShot`] records and submits a
//! command buffer and waits for it. [`TimestampQueries`] times passes.

mod access_check;
mod barrier;
mod buffer;
mod commands;
mod context;
pub(crate) use context::new_allocator;
mod debug;
mod device_select;
mod image;
mod image_bindings;
mod pipeline;
mod requirements;
mod retire;
mod timestamps;
mod variants;

pub(crate) use access_check::TrackedUse;
pub use access_check::{AccessCheck, ReportedBarrier};
pub use barrier::{Access, image_barrier, memory_barrier};
pub use buffer::{Buffer, BufferUsage};
pub use commands::OneShot;
// For the passes' objects that hold the device without a Context (the research passes'
// retired handles, the image passes' pipelines made at first use).
pub(crate) use context::Shared;
pub use context::{Context, ContextOptions, DeviceInfo};
pub use image::Image;
pub use image_bindings::{ImageBindingLayout, ImageBindings};
pub(crate) use pipeline::compute_of_module;
pub use pipeline::{
    Attachments, Pipeline, ShaderModule, Spirv, attachmentless_pipeline, begin_attachmentless,
    begin_rendering, begin_rendering_colors, compute_pipeline, compute_pipeline_with_sets,
    graphics_pipeline, pipeline_layout, pipeline_layout_with_sets, specialized_compute_pipeline,
};
pub use requirements::{DeviceFeatures, DeviceRequirements};
#[cfg(feature = "research")]
pub(crate) use retire::{Doomed, Handle};
pub use timestamps::TimestampQueries;
pub use variants::ComputeVariants;
