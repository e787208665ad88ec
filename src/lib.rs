//! Motion-blurred shadows with the temporal (depth-time ranges) shadow map of Hong & Oh.
//!
//! # For engines
//!
//! The crate root is the engine API: describe each mesh once ([`Mesh`]: positions at both
//! ends of the shutter, or one for a still mesh, indices, transforms, and its CPU geometry or
//! a cheap [`MeshBound`]), choose a light's settings ([`ShadowSettings`], built from a
//! [`Light`]), make a [`LightShadow`] per light, and each frame record it into your command
//! buffer. Your shaders test visibility with [`GLSL_INCLUDE`] (`ms_visibility`,
//! `ms_lit_fraction`), or the shadow records the visibility mask from your G-buffer
//! ([`MaskInputs`]). The book's integration page (`docs/src/integration.md`) covers frames in
//! flight, teardown and the conventions; `examples/minimal_host.rs` is a whole host.
//!
//! ```no_run
//! use motion_shadows::ash::vk;
//! use motion_shadows::glam::Vec3;
//! use motion_shadows::{
//!     Context, DeviceFeatures, Indices, IndexStream, Light, LightShadow, Mesh, MeshBound,
//!     PositionStream, ShadowSettings,
//! };
//!
//! /// The host's mesh: device addresses of last frame's and this frame's positions (stride
//! /// 16) and of 32-bit indices, as its skinning pass left them, and a box holding it.
//! struct HostMesh { previous: u64, current: u64, indices: u64, vertices: u32, triangles: u32 }
//!
//! # fn host_objects() -> (motion_shadows::ash::Instance, vk::PhysicalDevice,
//! #     motion_shadows::ash::Device, u32, vk::Queue, vk::CommandBuffer, HostMesh,
//! #     DeviceFeatures) {
//! #     unimplemented!()
//! # }
//! fn main() -> motion_shadows::Result<()> {
//!     // `enabled`: the features the host created `device` with, e.g. those of
//!     // `DeviceRequirements::for_device(&instance, physical)` chained into its
//!     // VkDeviceCreateInfo.
//!     let (instance, physical, device, family, queue, cmd, mesh, enabled) = host_objects();
//!     // SAFETY: the host created `device` from `physical` with the features in `enabled`
//!     // and keeps it alive longer than `ctx`.
//!     let ctx = unsafe {
//!         Context::from_raw(&instance, physical, device.clone(), family, queue, &enabled)?
//!     };
//!     // Once per light: its settings, its maps (one per frame in flight) and passes.
//!     let light = Light::spot(Vec3::new(0.0, 8.0, 0.0), Vec3::NEG_Y)
//!         .cone_half_angle(40.0)
//!         .depth_range(0.5, 50.0);
//!     let mut shadow = LightShadow::new(&ctx, ShadowSettings::new(light))?;
//!     // Each frame (here frame 1): describe the meshes, record into the host's command
//!     // buffer (recording, outside any render pass).
//!     // SAFETY: the addresses point at live buffers with SHADER_DEVICE_ADDRESS usage holding
//!     // `vertices` positions (and 3 * `triangles` indices), unchanged until `cmd` completes.
//!     let (previous, current, indices) = unsafe {
//!         (PositionStream::from_device_address(mesh.previous, 16),
//!          PositionStream::from_device_address(mesh.current, 16),
//!          IndexStream::from_device_address(mesh.indices))
//!     };
//!     let character = Mesh::moving(previous, current, mesh.vertices)
//!         .indexed(Indices::U32(indices), mesh.triangles)
//!         .bound(MeshBound::box_all_shutter(Vec3::splat(-1.0), Vec3::splat(1.0)));
//!     // SAFETY: `cmd` is the host's, recording outside rendering on ctx's queue.
//!     let frame = unsafe { shadow.record_frame(&ctx, cmd, 1, &[character], None)? };
//!     // ... the host's shading passes `frame.map_header` to `ms_visibility` ...
//!     // After the frame's fence: destroy what was dropped while it was in flight, and check
//!     // the frame's shadow was complete.
//!     // SAFETY: frame 1's fence has signalled.
//!     unsafe { ctx.collect(1) };
//!     shadow.finish_frame(&ctx, 1)?;
//!     Ok(())
//! }
//! ```
//!
//! # Under the engine API
//!
//! [`research`] holds the layers the engine API is built on, for the app and the papers'
//! experiments: the passes one by one (`research::passes`: collection, generation, the
//! papers' lighting, plain and coverage passes) and the thin layer over ash
//! (`research::gpu`). The app (scenes, the standalone renderer, the `motion-shadows`
//! command line) is the `motion-shadows-app` crate in `app/`, a client of both.

// Every public item of the library is documented; the lint table (Cargo.toml) is shared with
// the app, whose items are internal, so this one holds here.
#![deny(missing_docs)]

mod engine;
#[doc(hidden)]
pub mod error;
#[doc(hidden)]
pub mod gpu;
pub mod research;
#[doc(hidden)]
pub mod technique;

pub use engine::{CpuGeometry, HostBarrier, HostImage, Light, LightShadow, Mesh, MeshBound};
pub use engine::{ShadowFrame, ShadowSettings, StaticLayer};
pub use error::{Error, Result};
pub use gpu::{Context, DeviceFeatures, DeviceRequirements};
pub use technique::{
    AccessData, GLSL_EXACT_LOOKUP_INCLUDE, GLSL_EXACT_SHADOW_INCLUDE, GLSL_INCLUDE,
    GLSL_LIGHT_MOTION_INCLUDE, IndexStream, Indices, LightView, Lookup, MaskInputs, MotionImage,
    NormalEncoding, NormalImage, PassAccesses, PositionImage, PositionStream, Pruning,
    RangeStorage, Resource, ResourceUse, TemporalShadowMap, TriangleIdImage,
};

// The README's Rust snippets are doctests of this item, compiled from the README itself (their
// setup in hidden `#` lines); `no_run`, since they need a host's device.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeSnippets;
/// The ash (Vulkan), glam (math) and gpu-allocator versions the library's API uses.
pub use {ash, glam, gpu_allocator};
