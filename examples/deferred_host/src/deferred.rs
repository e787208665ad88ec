//! A small deferred engine that uses motion-shadows as a renderer would, written from the
//! README and the book (docs/src/integration.md). It owns its device (`crate::gpu`), its
//! gpu-allocator (shared with the library, whose thin layer `research::gpu` makes the
//! engine's buffers, images and pipelines on it), its GLSL (`glsl/`) and a frame loop with
//! three frames in flight. Per light a `LightShadow` records the shadow into the engine's
//! command buffers from the meshes described once (`motion_shadows::Mesh`, with the CPU copy
//! the room is reserved from). Frame f, in slot f % 3: the G-buffer at shutter time 1
//! (depth, normal, albedo, world motion, triangle ids); per light `record_frame` (the map,
//! then the mask, which follows each receiver along its motion); the shading, albedo / pi *
//! sum(E cos falloff mask) + ambient with each light read from its map's header; after the
//! fence, `ctx.collect` and `finish_frame`. Reading order: `world`, `engine`, `frames`,
//! `record`.

use crate::gpu::Gpu;
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DMat4, Mat4, UVec4, Vec3, Vec4};
use motion_shadows::research::gpu::{Buffer, BufferUsage, Image, ImageBindings, Pipeline};
use motion_shadows::{AccessData, Context, CpuGeometry, IndexStream, Indices, LightShadow};
use motion_shadows::{GLSL_INCLUDE, MaskInputs, MotionImage, NormalEncoding, NormalImage};
use motion_shadows::{Mesh as ShadowMesh, PassAccesses, PositionStream};
use motion_shadows::{ShadowSettings, StaticLayer, TemporalShadowMap, TriangleIdImage};
use std::ops::Range;
use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};

pub type Error = Box<dyn std::error::Error + Send + Sync>;
pub type Result<T> = std::result::Result<T, Error>;
/// Which frames `Engine::render` reads back, and those it returns.
pub type Keep<'a> = &'a dyn Fn(u32) -> bool;
pub type Frames = Vec<FrameOutput>;

/// Frames the CPU may record ahead of the GPU, each with its own copy of what a frame writes.
pub const FRAMES_IN_FLIGHT: usize = 3;
/// Lights the shading handles (one mask binding each in glsl/shade.comp).
pub const MAX_LIGHTS: usize = 2;

mod engine;
mod frames;
mod pipelines;
mod record;
mod world;

pub use engine::*;
use pipelines::*;
pub use world::*;
