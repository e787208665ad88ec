//! The push constants of each pass: one block per pass, mirrors of the GLSL structs of the
//! same names in `glsl/shared.glsl` (the passes over the technique's own buffers) and
//! `glsl/image_push.glsl` (the passes over a host's images).
//! `tests/gpu/layout.rs` probes every one of them against the shaders' layout, and
//! `shaders/layout_check.rs` compares them with the compiled SPIR-V without a device.
//!
//! The passes that draw the host's draw table begin with [`DrawPush`]: `scene.vert`, the
//! vertex shader those pipelines share, reads it, and [`DrawnPush::with_draw`] sets it per draw.

use super::gpu_types::CameraParams;
use glam::{Mat4, Vec4};

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

/// The temporal map's visibility mask, `visibility_mask.comp` (124 bytes of fields, 128 with
/// the padding up to `Mat4`'s 16-byte alignment).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaskPush {
    /// Camera clip to world (the host's matrices, Vulkan NDC).
    pub inv_view_proj: Mat4,
    /// The map's [`super::ShadowMapHeader`].
    pub map: u64,
    /// Pixels.
    pub size: [u32; 2],
    /// The depth buffer's clear value: no surface there.
    pub background_depth: f32,
    /// `MASK_*` of [`super::gpu_constants`].
    pub flags: u32,
    /// The u32 counting pixels past `loop_budget`.
    pub over_budget: u64,
    /// `ms_loop_iterations` a pixel may reach (0: no limit).
    pub loop_budget: u32,
    /// The shutter time the depth image shows (read for moving receivers).
    pub time: f32,
    /// The overflow queues (`mask_queue.rs`): where walks that stopped go on.
    pub queue: u64,
    /// 0: the dispatch over every pixel; r > 0: follow-up round r, over its queue's pixels.
    pub round: u32,
    /// Follow-up rounds recorded after round 0.
    pub rounds: u32,
    /// Entries per queue.
    pub capacity: u32,
    /// Iterations of the shader's probe of the device's loop limiter: 2 where the device has
    /// one, else 0.
    pub probe: u32,
}

/// The engine TSM's mask of one batch of maps, `tsm_mask.comp` (128 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TsmMaskPush {
    /// Camera clip to world (the host's matrices, Vulkan NDC).
    pub inv_view_proj: Mat4,
    /// The maps' light (the start of their [`super::PlainMapHeader`]).
    pub light: u64,
    /// Pixels.
    pub size: [u32; 2],
    /// The depth buffer's clear value: no surface there.
    pub background_depth: f32,
    /// `MASK_*` and `TSM_*` of [`super::gpu_constants`].
    pub flags: u32,
    /// Texels of a map.
    pub map_size: [u32; 2],
    /// The shutter time the G-buffer shows (read for moving receivers).
    pub time: f32,
    /// N, and 1 / N: map i is drawn at (i + 0.5) * (1 / N), in the shader as on the host.
    pub maps: f32,
    /// 1 / N.
    pub inv_maps: f32,
    /// The batch's first map (its layer 0).
    pub first_map: u32,
    /// Maps in the batch (layers 0..batch).
    pub batch: u32,
    /// Zero (the GLSL's `reserved` and the tail padding up to 16-byte alignment).
    pub reserved: [u32; 3],
}

/// The G-buffer, `gbuffer.vert` and `gbuffer.frag` (96 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GBufferPush {
    /// World to camera clip (Vulkan).
    pub view_proj: Mat4,
    /// xyz: the camera's position.
    pub eye: Vec4,
    /// The [`super::DrawRecord`] table.
    pub draws: u64,
    /// The draw being drawn.
    pub draw_index: u32,
    /// The shutter time drawn.
    pub time: f32,
}

/// The lighting target's radiance into a host image, `radiance_to_image.comp` (16 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RadiancePush {
    /// The lighting target's radiance buffer.
    pub radiance: u64,
    /// Pixels.
    pub size: [u32; 2],
}

impl PushBlock for MaskPush {}
impl PushBlock for TsmMaskPush {}
impl PushBlock for GBufferPush {}
impl PushBlock for RadiancePush {}
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
    assert!(std::mem::size_of::<MaskPush>() == 128);
    assert!(std::mem::size_of::<TsmMaskPush>() == 128);
    assert!(std::mem::size_of::<GBufferPush>() == 96);
    assert!(std::mem::size_of::<RadiancePush>() == 16);
    // Vulkan guarantees 128 bytes of push constants.
    assert!(RasterPush::BYTES <= 128);
};

#[cfg(test)]
mod tests {
    /// The structs `tests/gpu/layout.rs` probes against their Rust mirrors.
    const PROBED: [&str; 10] = [
        "DrawPush",
        "MapDrawPush",
        "MapPush",
        "LightingRasterPush",
        "ShadePush",
        "MaskPush",
        "TsmMaskPush",
        "GBufferPush",
        "RadiancePush",
        "RasterCamera",
    ];

    /// Every push-constant block of the library's shaders is made of probed structs, so no
    /// block's layout is written by hand in a shader where the layout test cannot see it.
    #[test]
    fn every_push_block_is_made_of_probed_structs() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl");
        let mut blocks = 0;
        for path in crate::technique::glsl_files::glsl_files(&dir) {
            let source = std::fs::read_to_string(&path).unwrap();
            for (at, _) in source.match_indices("layout(push_constant) uniform Push {") {
                blocks += 1;
                let body = &source[at..];
                let body = &body[body.find('{').unwrap() + 1..body.find('}').unwrap()];
                for member in body.split(';').map(str::trim).filter(|m| !m.is_empty()) {
                    let ty = member.split_whitespace().next().unwrap();
                    assert!(
                        PROBED.contains(&ty),
                        "{}: push member `{member}` is not one of the probed structs",
                        path.display()
                    );
                }
            }
        }
        // Every shader with push constants: a failure to find them is not a pass.
        assert!(blocks >= 20, "found only {blocks} push blocks");
    }
}
