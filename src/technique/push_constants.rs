//! The push constants of each pass: one block per pass, mirrors of the GLSL structs of the
//! same names in `glsl/shared.glsl` (and `RasterCamera` in `glsl/raster_camera.glsl`).
//! `tests/gpu/layout.rs` probes every one of them against the shaders' layout.
//!
//! The passes that draw the host's draw table begin with [`DrawPush`]: `scene.vert`, the
//! vertex shader those pipelines share, reads it, and [`DrawnPush::with_draw`] sets it per draw.

use super::gpu_types::CameraParams;

/// A pass's push-constant block: plain data within the 128 bytes every device offers.
pub trait PushBlock: bytemuck::Pod {
    /// Bytes of the pipeline layout's push-constant range.
    const BYTES: u32 = std::mem::size_of::<Self>() as u32;
}

/// A block that begins with [`DrawPush`], so a pass can push it once per draw.
pub trait DrawnPush: PushBlock {
    /// The same block for `draw`.
    fn with_draw(self, draw: DrawPush) -> Self;
}

/// Which draw of the draw table a pipeline draws (16 bytes, the prefix of every drawing
/// pass's block).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DrawPush {
    /// The [`super::DrawRecord`] table.
    pub draws: u64,
    /// The draw being drawn.
    pub draw_index: u32,
    /// Draws in the table.
    pub draw_count: u32,
}

/// The passes that draw into a map from the light: the collection, the coverage map's caps
/// and reset, ordinary shadow maps (32 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MapDrawPush {
    /// The draw.
    pub draw: DrawPush,
    /// The header of the map drawn: a [`super::ShadowMapHeader`], or a
    /// [`super::PlainMapHeader`] for ordinary maps.
    pub map: u64,
    /// The scene's time the map shows (ordinary maps, the coverage map's caps); else 0.
    pub time: f32,
    /// [`super::gpu_constants::COUNT_INVALID`] or 0.
    pub flags: u32,
}

/// The generation pass: pairing and sorting one map's lists (8 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MapPush {
    /// The map's [`super::ShadowMapHeader`].
    pub map: u64,
}

/// The lighting raster's own constants (48 bytes); its camera follows in [`RasterPush`].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightingRasterPush {
    /// The draw.
    pub draw: DrawPush,
    /// The chunk's visibility buffer (one 64-bit atomic per pixel sample).
    pub visibility: u64,
    /// The target's [`CameraParams`].
    pub target: u64,
    /// Index of the chunk's first sample.
    pub first_sample: u32,
    /// Samples in the chunk.
    pub sample_count: u32,
    /// Every sample's time when `flags` has [`super::FIXED_TIME`].
    pub time: f32,
    /// [`super::FIXED_TIME`], [`super::gpu_constants::COUNT_INVALID`].
    pub flags: u32,
}

/// The camera of the lighting raster's fragment shader (68 bytes, 4-byte members only so
/// that it packs right after [`LightingRasterPush`]).
///
/// Why push constants and not the target's header: the fragment shader runs for every pixel
/// of every triangle's hull, and a CPU device (lavapipe) loads from a device address lane by
/// lane; those camera loads were about half of the fragment shader's time there. Push
/// constants are read once per invocation group, on CPU and GPU devices alike.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RasterCamera {
    /// The camera's position.
    pub origin: [f32; 3],
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
    /// The ray through pixel (0, 0)'s corner.
    pub ray00: [f32; 3],
    /// The ray's step one pixel across.
    pub ray_dx: [f32; 3],
    /// The ray's step one pixel down.
    pub ray_dy: [f32; 3],
    /// Pixels across.
    pub width: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// The frame's sampling seed.
    pub seed: u32,
}

impl RasterCamera {
    /// The same values as the target's header holds, so the raster's ray tests are unchanged.
    pub fn new(header: &CameraParams) -> Self {
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

/// What the lighting raster pushes: its constants, then the camera (the GLSL block's two
/// members).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RasterPush {
    /// The raster's constants.
    pub pass: LightingRasterPush,
    /// Its camera.
    pub camera: RasterCamera,
    /// Zero: the tail padding up to the u64 alignment, explicit so that it is plain data.
    pub padding: u32,
}

/// The lighting shade, `resolve.comp` (40 bytes). Its samples per pixel and shadow test are
/// the pipeline's specialization constants.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadePush {
    /// The [`super::DrawRecord`] table (the hit triangle's draw).
    pub draws: u64,
    /// The shadow map tested: a [`super::ShadowMapHeader`] for the temporal test, a
    /// [`super::PlainMapHeader`] for the others.
    pub shadow: u64,
    /// The target's [`CameraParams`].
    pub target: u64,
    /// Draws in the table.
    pub draw_count: u32,
    /// Index of the chunk's first sample.
    pub first_sample: u32,
    /// Every sample's time when `flags` has [`super::FIXED_TIME`].
    pub time: f32,
    /// [`super::FIXED_TIME`] or 0.
    pub flags: u32,
}

impl PushBlock for MapDrawPush {}
impl PushBlock for MapPush {}
impl PushBlock for LightingRasterPush {}
impl PushBlock for RasterPush {}
impl PushBlock for ShadePush {}

impl DrawnPush for MapDrawPush {
    fn with_draw(self, draw: DrawPush) -> Self {
        Self { draw, ..self }
    }
}

/// The raster pushes its camera once per chunk and these first bytes per draw.
impl DrawnPush for LightingRasterPush {
    fn with_draw(self, draw: DrawPush) -> Self {
        Self { draw, ..self }
    }
}

const _: () = {
    assert!(std::mem::size_of::<DrawPush>() == 16);
    assert!(std::mem::size_of::<MapDrawPush>() == 32);
    assert!(std::mem::size_of::<MapPush>() == 8);
    assert!(std::mem::size_of::<LightingRasterPush>() == 48);
    assert!(std::mem::size_of::<RasterCamera>() == 68);
    assert!(std::mem::size_of::<ShadePush>() == 40);
    // Vulkan guarantees 128 bytes of push constants.
    assert!(RasterPush::BYTES <= 128);
};
