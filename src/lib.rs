//! Motion-blurred shadows with the temporal (depth-time ranges) shadow map of Hong & Oh.
//!
//! Two layers, each usable without the one above it:
//! 1. [`gpu`]: a thin layer over ash (context, buffers, pipelines, submission, timestamps).
//! 2. [`technique`]: the passes. Each owns its pipelines and records into a command buffer
//!    the caller gives it; none creates a device, submits or waits.
//!
//! The app (scenes, the standalone renderer, image output, the `motion-shadows` command
//! line) is the `motion-shadows-app` crate in `app/`, a client of this public API.
//!
//! # One frame in a host engine
//!
//! The host owns the device, the command buffer and the geometry; the library reads the
//! host's position buffers in place and leaves a temporal shadow map that the host's shaders
//! query with `ms_visibility` / `ms_lit_fraction` from [`technique::GLSL_INCLUDE`] (or that
//! [`technique::VisibilityMaskPass`] turns into a mask). `examples/deferred_host/` is a
//! whole engine; the README's "Integrating into your engine" walks through it.
//!
//! ```no_run
//! use motion_shadows::ash::vk;
//! use motion_shadows::glam::Vec3;
//! use motion_shadows::gpu::{Context, DeviceFeatures};
//! use motion_shadows::technique::{
//!     CollectionPass, Draw, DrawList, GenerationPass, Indices, IndexStream, LightView,
//!     PositionStream, TemporalShadowMap,
//! };
//!
//! /// The host's mesh: device addresses of last frame's and this frame's positions (stride
//! /// 16) and of 32-bit indices, as its skinning pass left them.
//! struct HostMesh { previous: u64, current: u64, indices: u64, vertices: u32, triangles: u32 }
//!
//! # fn host_objects() -> (motion_shadows::ash::Instance, vk::PhysicalDevice,
//! #     motion_shadows::ash::Device, u32, vk::Queue, vk::CommandBuffer, HostMesh,
//! #     DeviceFeatures) {
//! #     unimplemented!()
//! # }
//! fn main() -> motion_shadows::Result<()> {
//!     // `enabled`: the features the host created `device` with, e.g. those of
//!     // `gpu::DeviceRequirements::for_device(&instance, physical)` chained into its
//!     // VkDeviceCreateInfo.
//!     let (instance, physical, device, family, queue, cmd, mesh, enabled) = host_objects();
//!     // SAFETY: the host created `device` from `physical` with the features in `enabled`
//!     // and keeps it alive longer than `ctx`.
//!     let ctx = unsafe {
//!         Context::from_raw(&instance, physical, device.clone(), family, queue, &enabled)?
//!     };
//!     // Once: the passes (shared by every frame in flight and light).
//!     let collection = CollectionPass::new(&ctx)?;
//!     let generation = GenerationPass::new(&ctx)?;
//!     // Per frame in flight and light: the draw list and the map.
//!     let mut draws = DrawList::new(&ctx, 16)?;
//!     let mut map = TemporalShadowMap::new(&ctx, 1024, 1024, 1 << 21, 1 << 20)?;
//!     let light = LightView::spot(Vec3::new(0.0, 8.0, 0.0), Vec3::NEG_Y, 40.0, 50.0, 0.5,
//!                                 50.0, (1024, 1024));
//!     // SAFETY: the addresses point at live buffers with SHADER_DEVICE_ADDRESS usage holding
//!     // `vertices` positions (and 3 * `triangles` indices), unchanged until `cmd` completes.
//!     let draw = unsafe {
//!         Draw::new(
//!             PositionStream::from_device_address(mesh.previous, 16),
//!             PositionStream::from_device_address(mesh.current, 16),
//!             mesh.vertices,
//!             Indices::U32(IndexStream::from_device_address(mesh.indices)),
//!             mesh.triangles,
//!             0,
//!         )
//!     };
//!     // Each frame (here frame 1), in the host's command buffer (recording, outside any
//!     // render pass):
//!     ctx.begin_frame(1);
//!     unsafe {
//!         draws.record_update(&device, cmd, &[draw])?;
//!         collection.record(&device, cmd, &draws, &light, &map, None)?;
//!         generation.record(&device, cmd, &map);
//!         map.record_counter_readback(&device, cmd);
//!     }
//!     // ... the host's shading passes `map.header_address()` to `ms_visibility` ...
//!     // After the frame's fence: destroy what was dropped while it was in flight (the old
//!     // buffers of a map that grows wait for this), and grow if this frame overflowed.
//!     // SAFETY: frame 1's fence has signalled.
//!     unsafe { ctx.collect(1) };
//!     let counts = map.read_counters()?;
//!     if map.needs_more_room(&counts) {
//!         map.reserve(&ctx, counts.node_count / 4 * 5, counts.range_count / 4 * 5)?;
//!     }
//!     map.check_complete(&counts)?;
//!     Ok(())
//! }
//! ```

// Every public item of the library is documented; the lint table (Cargo.toml) is shared with
// the app, whose items are internal, so this one holds here.
#![deny(missing_docs)]

pub mod error;
pub mod gpu;
pub mod technique;

pub use error::{Error, Result};

// The README's Rust snippets are doctests of this item, compiled from the README itself (their
// setup in hidden `#` lines); `no_run`, since they need a host's device.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeSnippets;
/// The ash (Vulkan), glam (math) and gpu-allocator versions the library's API uses.
pub use {ash, glam, gpu_allocator};
