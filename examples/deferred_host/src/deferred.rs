//! A small deferred engine that uses motion-shadows the way a real renderer would.
//!
//! The engine owns everything a renderer owns: the device (`Gpu`, created with what the
//! library asks for), its allocator, its vertex and index buffers, its images, its pipelines
//! and shaders, its frame loop with three frames in flight, and its lighting. The library is
//! handed the device and the allocator (`Context::from_raw_with_allocator`); per light one `LightShadow` (one map per frame in flight) records
//! the shadow into the engine's command buffers from the meshes described once
//! (`motion_shadows::Mesh`, with their CPU copy for the room each frame reserves):
//!
//! ```text
//! per frame (slot = frame % 3, with its own command buffer, fence and resources):
//!   G-buffer (the engine's own)      depth, world normal, albedo at shutter time t = 1,
//!                                    world motion over the shutter (this frame's position
//!                                    minus last frame's, as engines keep for motion vectors)
//!                                    and each pixel's triangle id
//!   per light: record_frame          the map's collection and generation from the meshes,
//!                                    then the visibility mask: G-buffer depth + normals +
//!                                    motion + ids -> lit fraction of the shutter, each
//!                                    receiver followed along its path (the ids keep its own
//!                                    triangle from shadowing it)
//!   shading (the engine's own)       radiance = albedo / pi * sum(E cos falloff mask) + ambient
//! after the frame's fence: per light finish_frame (room held, mask not cut short)
//! ```
//!
//! The shutter of frame f runs from frame f - 1 (t = 0) to frame f (t = 1): an engine keeps
//! last frame's positions for its motion vectors anyway, and that is exactly what the shadow
//! pass needs. Nothing here uses the app crate (the tests use it as a reference only).
//!
//! The `deferred_host` example's engine (`main.rs` runs it), a module of its crate so that
//! the tests (`tests/gpu/deferred_host.rs`, `app/tests/gpu/deferred_host.rs`) drive the same
//! code; `gpu` is the engine's device. Its parts, in reading order: `world` (what it draws),
//! `engine` (settings, slots, setup), `frames` (the frame loop), `record` (one frame's
//! commands), `frame_data` (what its shaders read), `shaders`, `pipelines`, `resources`.

use crate::gpu::Gpu;
use bytemuck::{Pod, Zeroable};
// Links shaderc (compiled into this program to build the host's own shaders) where the
// distribution's libshaderc.so cannot be linked as it is; see build-support/shaderc-link.
use ash::vk;
use glam::{DMat4, Mat4, UVec4, Vec3, Vec4};
use motion_shadows::{
    Context, CpuGeometry, GLSL_INCLUDE, IndexStream, Indices, LightShadow, MaskInputs,
    Mesh as ShadowMesh, MotionImage, NormalEncoding, NormalImage, PositionStream, ShadowSettings,
    StaticLayer, TemporalShadowMap, TriangleIdImage,
};
use motion_shadows_shaderc_link as _;

/// Errors of the engine: the library's, Vulkan's (with the call), shaderc's, or a sentence.
pub type Error = Box<dyn std::error::Error + Send + Sync>;
/// The engine's result type.
pub type Result<T> = std::result::Result<T, Error>;

/// Frames the CPU may record ahead of the GPU: each has its own copy of everything that a
/// frame writes (command buffer, fence, draw list, shadow maps, images, uniform buffer).
pub const FRAMES_IN_FLIGHT: usize = 3;
/// Lights the shading shader handles (`MAX_LIGHTS` in `glsl/frame.glsl`).
pub const MAX_LIGHTS: usize = 2;

mod engine;
mod frame_data;
mod frames;
mod pipelines;
mod record;
mod resources;
mod shaders;
mod world;

pub use engine::*;
use frame_data::*;
use pipelines::*;
pub use resources::*;
pub use shaders::*;
pub use world::*;
