//! The lighting raster's push constants: [`PassConstants`] followed by the camera that its
//! fragment shader needs (`RasterCamera` in glsl/raster_camera.glsl).
//!
//! Why push constants and not the target's header: the fragment shader runs for every pixel
//! of every triangle's hull, and a CPU device (lavapipe) loads from a device address lane by
//! lane; those camera loads were about half of the fragment shader's time there. Push
//! constants are read once per invocation group, on CPU and GPU devices alike.

use super::gpu_types::{CameraParams, PassConstants};

/// The camera of the lighting raster's fragment shader (68 bytes, 4-byte members only so
/// that it packs right after [`PassConstants`] within the 128 bytes every device offers).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct RasterCamera {
    origin: [f32; 3],
    near: f32,
    far: f32,
    ray00: [f32; 3],
    ray_dx: [f32; 3],
    ray_dy: [f32; 3],
    width: u32,
    spp: u32,
    seed: u32,
}

impl RasterCamera {
    /// The same values as the target's header holds, so the raster's ray tests are unchanged.
    pub(crate) fn new(header: &CameraParams) -> Self {
        Self {
            origin: header.position.truncate().to_array(),
            near: header.position.w,
            far: header.forward.w,
            ray00: header.ray00.truncate().to_array(),
            ray_dx: header.ray_dx.truncate().to_array(),
            ray_dy: header.ray_dy.truncate().to_array(),
            width: header.image.x,
            spp: header.image.z,
            seed: header.image.w,
        }
    }
}

/// What the lighting raster pushes. Its `pass.map` holds the visibility buffer's address: the
/// raster reads no shadow map, and the address does not fit after the camera.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct RasterConstants {
    pub(crate) pass: PassConstants,
    pub(crate) camera: RasterCamera,
    /// Zero: the tail padding up to the u64 alignment, explicit so that it is plain data.
    pub(crate) padding: u32,
}

/// Bytes of the raster pipeline's push constant range.
pub(crate) const RASTER_PUSH_BYTES: u32 = std::mem::size_of::<RasterConstants>() as u32;

const _: () = assert!(std::mem::size_of::<PassConstants>() == 56);
const _: () = assert!(std::mem::size_of::<RasterCamera>() == 68);
// Vulkan guarantees 128 bytes of push constants.
const _: () = assert!(RASTER_PUSH_BYTES <= 128);
const _: () = assert!(RASTER_PUSH_BYTES == 128);
