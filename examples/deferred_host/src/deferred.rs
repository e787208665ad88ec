//! A small deferred engine that uses motion-shadows the way a renderer would, written from the
//! README and the book (docs/src/integration.md). It owns its device (`crate::gpu`), its
//! gpu-allocator (shared with the library), its buffers, images, pipelines and shaders
//! (`glsl/`), and its frame loop with three frames in flight; the library gets the device
//! and the allocator (`Context::from_raw_with_allocator`) and, per light, one `LightShadow`
//! records the shadow into the engine's command buffers from the meshes described once
//! (`motion_shadows::Mesh`, with their CPU copy for the room each frame reserves):
//!
//! ```text
//! per frame f (slot f % 3: its own command buffer, fence, images and buffers):
//!   G-buffer       depth, normal, albedo at shutter time t = 1, world motion over the
//!                  shutter (this frame's position minus last frame's) and triangle ids
//!   per light      record_frame: the map's collection and generation, then the mask from
//!                  the G-buffer (each receiver followed along its motion; the ids keep its
//!                  own triangle from shadowing it)
//!   shading        radiance = albedo / pi * sum(E cos falloff mask) + ambient
//! after the fence: ctx.collect, per light finish_frame (room held, mask not cut short)
//! ```
//!
//! Its parts, in reading order: `world` (what it draws), `engine` (setup, slots, teardown),
//! `frames` (the frame loop), `record` (one frame's commands and barriers), `pipelines`,
//! `resources` (buffers and images on the shared allocator).

use crate::gpu::Gpu;
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DMat4, Mat4, UVec4, Vec3, Vec4};
use motion_shadows::{
    Context, CpuGeometry, IndexStream, Indices, LightShadow, MaskInputs, Mesh as ShadowMesh,
    MotionImage, NormalEncoding, NormalImage, PositionStream, ShadowSettings, StaticLayer,
    TemporalShadowMap, TriangleIdImage,
};

/// The engine's errors: the library's, Vulkan's, shaderc's, or a sentence.
pub type Error = Box<dyn std::error::Error + Send + Sync>;
pub type Result<T> = std::result::Result<T, Error>;

/// Frames the CPU may record ahead of the GPU: each has its own copy of everything a frame
/// writes.
pub const FRAMES_IN_FLIGHT: usize = 3;
/// Lights the shading shader handles (`MAX_LIGHTS` in glsl/frame.glsl).
pub const MAX_LIGHTS: usize = 2;

mod engine;
mod frames;
mod pipelines;
mod record;
mod resources;
mod world;

pub use engine::*;
use pipelines::*;
pub use resources::*;
pub use world::*;
