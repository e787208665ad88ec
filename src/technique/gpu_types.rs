//! Rust mirrors of the structs in `glsl/motion_shadows.glsl` (public) and `glsl/shared.glsl`
//! (internal). Sizes and field offsets are checked against the compiled shaders without a
//! device (`shaders/layout_check.rs`) and with one by `tests/gpu/layout.rs`. All are `repr(C)` with std430 layout: glam's `Vec4` and `Mat4` are
//! 16-byte aligned like GLSL's `vec4` and `mat4`.

use glam::{Mat4, UVec4, Vec4};

/// One fragment of a prism (16 bytes): linear light depth, shutter time, triangle id, link.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Node {
    /// Linear distance along the light's view axis.
    pub depth: f32,
    /// Shutter time in [0, 1].
    pub time: f32,
    /// Global triangle id.
    pub id: u32,
    /// Index + 1 of the next node of the same pixel; 0 ends the list.
    pub next: u32,
}

/// A depth-time range (24 bytes, `MsRange` in GLSL): the triangle `id` covers the texel
/// from `t_s` to `t_e`, at a depth going linearly from `d_s` to `d_e`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Range {
    /// Start of the interval (t_s <= t_e).
    pub t_s: f32,
    /// End of the interval.
    pub t_e: f32,
    /// Depth at `t_s`.
    pub d_s: f32,
    /// Depth at `t_e`.
    pub d_e: f32,
    /// Global triangle id.
    pub id: u32,
    /// Index + 1 of the next range of the same texel; 0 ends the list.
    pub next: u32,
}

/// The head of a map's long-pixel list, `LongListHeader` in `glsl/shared.glsl`: the pixels
/// whose lists the generation's first tier leaves to the second, and the second tier's
/// indirect dispatch, whose x group count the first tier raises as it appends.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LongListHeader {
    /// Pixels in the list.
    pub count: u32,
    /// The second tier's workgroups (x, y, z): an indirect dispatch's arguments.
    pub groups: [u32; 3],
}

impl LongListHeader {
    /// An empty list; its dispatch starts at 0 x 1 x 1 groups.
    pub const EMPTY: Self = Self {
        count: 0,
        groups: [0, 1, 1],
    };
    /// The byte offset of the dispatch's arguments.
    pub const GROUPS_OFFSET: u64 = std::mem::offset_of!(Self, groups) as u64;
}

/// Fragment and range counts (written by shaders) and capacities (written when recording).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Counters {
    /// Fragments the collection pass produced (stored up to `node_capacity`; with
    /// `ranges_direct`, two per covered run and none stored).
    pub node_count: u32,
    /// Room in the fragment buffer.
    pub node_capacity: u32,
    /// Ranges the generation pass produced, or with `ranges_direct` the collection pass
    /// (stored up to `range_capacity`).
    pub range_count: u32,
    /// Room in the range buffer.
    pub range_capacity: u32,
    /// Shadow-map pixels holding more than [`MAX_LIST_NODES`] fragments: not turned into
    /// ranges (with `ranges_direct`: not all of them), so such a frame is an error.
    pub overlong_pixels: u32,
    /// The longest fragment list of the frame (counted up to 8 x [`MAX_LIST_NODES`], or
    /// exactly with `ranges_direct`).
    pub longest_list: u32,
    /// What `range_count` would be without the coverage map (equal to it without one).
    pub ranges_without_coverage: u32,
    /// Triangles not drawn because an index pointed past their draw's vertex count.
    pub invalid_triangles: u32,
    /// 1 if the fragment count passed 2^32 - 1 (the 32-bit counter wrapped): the frame's
    /// figures are meaningless and it is an error.
    pub wrapped: u32,
    /// 1 if the collection pass stored each covered run as its range directly (the exact
    /// construction with the static layer, see
    /// [`super::TemporalShadowMap::collects_ranges`]): no node is stored, and the generation
    /// pass has nothing to do.
    pub ranges_direct: u32,
    /// Where the map sorts the collected ranges ([`super::RangeStorage::Sorted`]): the
    /// ranges the sorted buffer holds, `range_count` less those pruned (docs/src/pruning.md);
    /// 0 otherwise.
    pub sorted_count: u32,
    /// With [`super::Lookup::Exact`] and the static layer: the names the static name lists
    /// hold, as counted when they were last drawn (stored up to
    /// [`super::TemporalShadowMap::static_name_capacity`]); 0 otherwise.
    pub static_names: u32,
}

pub use super::gpu_constants::{
    COUNT_INVALID, DRAW_CLOSED, DRAW_STATIC, DRAW_UNTRANSFORMED, FIXED_TIME, INDEX_NONE, INDEX_U16,
    INDEX_U32, MAX_LIST_NODES,
};
use super::gpu_constants::{
    DEPTH_AND_ID, DEPTH_ONLY, DRAW_RECORD_WORDS, SHADOW_NONE, SHADOW_PLAIN, SHADOW_TEMPORAL,
    SHADOW_TSM,
};

/// The light a shadow map is rendered for, as shaders read it (`MsLight`, 192 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuLight {
    /// World -> light view (right-handed, looking down -z).
    pub view: Mat4,
    /// Light view -> clip (Vulkan: z in [0, w], y down).
    pub proj: Mat4,
    /// xyz; w = 1 for a spot light, 0 for a directional light.
    pub position: Vec4,
    /// xyz unit; w = cos(cone half angle), -1 for a directional light.
    pub direction: Vec4,
    /// x = radiant intensity (W/sr, spot) or irradiance (W/m^2, directional); y = 1 where
    /// the light moves during the shutter (a temporal map's header then holds its pose at
    /// t = 1, [`GpuLightEnd`]), 0 for a still light.
    pub emission: Vec4,
    /// x = receiver offset along its normal in shadow texels, y = relative depth bias,
    /// z = world size of a texel per unit depth (spot) or absolute (directional).
    pub bias: Vec4,
}

/// A moving light's pose at t = 1 as shaders read it (`MsLightEnd` in glsl/light_motion.glsl,
/// 160 bytes), at the end of a temporal map's header; zeros for a still light.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuLightEnd {
    /// World -> light view at t = 1.
    pub view: Mat4,
    /// The t = 0 view's inverse times the t = 1 view: a world point at t = 1 as the t = 0
    /// view must see it to see it where the t = 1 view does.
    pub frame: Mat4,
    /// xyz: position at t = 1 (see [`super::LightEnd::position`]); w = 1.
    pub position: Vec4,
    /// xyz: unit direction at t = 1; w = the cone's cosine, as in [`GpuLight::direction`].
    pub direction: Vec4,
}

/// A moving camera's pose at t = 1 as the lighting pass reads it (`CameraEnd` in
/// glsl/shared.glsl, 80 bytes), right after [`CameraParams`] in a lighting target's header
/// ([`CameraParams::camera_end`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuCameraEnd {
    /// The t = 0 view's inverse times the t = 1 view: a world point at t = 1 as the t = 0
    /// camera must see it to see it where the t = 1 camera does.
    pub frame: Mat4,
    /// xyz: the eye at t = 1; w = 1.
    pub position: Vec4,
}

/// The header of a temporal shadow map (`MsShadowMap` in GLSL, then `MsLightEnd` at byte 320:
/// 480 bytes): what a host
/// shader reads through the address [`super::TemporalShadowMap::header_address`].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowMapHeader {
    /// The light of the frame.
    pub light: GpuLight,
    /// x, y = texels.
    pub size: UVec4,
    /// Per texel: index + 1 of its first range (u32).
    pub range_heads: u64,
    /// The ranges ([`Range`]).
    pub ranges: u64,
    /// 0, or the coverage map (u32 per texel: the covering triangle or u32::MAX).
    pub coverage: u64,
    /// The covering triangle's depth at t = 0 and t = 1 (two f32 per texel).
    pub cover_depth: u64,
    /// Per texel: index + 1 of its newest fragment.
    pub heads: u64,
    /// The fragments ([`Node`]).
    pub nodes: u64,
    /// The [`Counters`].
    pub counters: u64,
    /// The generation pass's list of pixels with long fragment lists.
    pub long_pixels: u64,
    /// The coverage map's nearest map (u64 per texel), 0 without one.
    pub nearest: u64,
    /// The static layer (u64 per texel: the nearest static triangle, depth key << 32 | id),
    /// 0 where static triangles are in the lists (the papers' prisms, the coverage map).
    pub static_nearest: u64,
    /// The generation pass's indirect dispatches: over the map's 8x8-texel tiles (every
    /// tile, or none where the collection stored the ranges itself), then the sorting's
    /// ([`super::RangeStorage::Sorted`]).
    pub tiles: u64,
    /// Where the collection links the ranges it stores itself: `ranges`, or with
    /// [`super::RangeStorage::Sorted`] the lists the generation pass sorts into `ranges`.
    pub list_ranges: u64,
    /// 0, or with [`super::Lookup::Exact`] the triangle records ([`TriangleRecord`], by
    /// global triangle id): what the exact lookup tests each named triangle with.
    pub triangles: u64,
    /// 0, or with [`super::Lookup::Exact`] and the static layer the static name lists (the
    /// map's `static names` buffer: a count and a capacity, 2 unused words, a head per texel
    /// (index + 1 of its first name, 0 for none), then the names, (triangle id, next) pairs):
    /// per texel, the static triangles whose shadow touches it, kept across frames as the
    /// static layer is.
    pub static_names: u64,
    /// The light's pose at t = 1 where it moves ([`GpuLight::emission`] y = 1), zeros
    /// otherwise.
    pub light_end: GpuLightEnd,
}

/// One triangle as the exact lookup reads it (`MsTriangle` in GLSL, 96 bytes), written by
/// the collection pass at the triangle's global id: its world-space corners at t = 0 and at
/// t = 1 (w unused).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleRecord {
    /// Corners 0, 1, 2 at shutter open.
    pub at0: [Vec4; 3],
    /// Corners 0, 1, 2 at shutter close.
    pub at1: [Vec4; 3],
}

/// The header of ordinary shadow maps (224 bytes); starts like [`ShadowMapHeader`].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlainMapHeader {
    /// The light of the frame.
    pub light: GpuLight,
    /// x, y = texels, z = layers, w = a [`DepthFormat`].
    pub size: UVec4,
    /// The layers' depths as the depth attachment held them (post-projection z/w in [0, 1],
    /// 1 where no triangle was drawn: floats), layer after layer.
    pub depths: u64,
    /// [`DepthFormat::DepthAndId`]: the layers' triangle ids, layer after layer
    /// ([`NO_TRIANGLE`] where none was drawn); 0 for depth-only maps.
    pub ids: u64,
}

/// One draw of host geometry as shaders read it (160 bytes). Built from a
/// [`super::Draw`] by [`super::DrawList`].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DrawRecord {
    /// Address of vertex 0's position at shutter open (3 floats).
    pub positions0: u64,
    /// Address of vertex 0's position at shutter close.
    pub positions1: u64,
    /// Address of index 0, or 0.
    pub indices: u64,
    /// Bytes between consecutive positions at shutter open.
    pub stride0: u32,
    /// Bytes between consecutive positions at shutter close.
    pub stride1: u32,
    /// [`INDEX_NONE`], [`INDEX_U16`] or [`INDEX_U32`].
    pub index_kind: u32,
    /// Vertices in each position stream (larger indices drop their triangle).
    pub vertex_count: u32,
    /// Global id of the draw's first triangle.
    pub first_id: u32,
    /// Triangles in the draw.
    pub triangle_count: u32,
    /// rgb albedo for the library's own lighting pass; w = `DRAW_*` flags (as a float).
    pub albedo_flags: Vec4,
    /// Rows of the object's 3x4 affine transform at t = 0.
    pub model0: [Vec4; 3],
    /// Rows of the object's 3x4 affine transform at t = 1.
    pub model1: [Vec4; 3],
}

impl DrawRecord {
    /// The `DRAW_*` flags.
    pub fn flags(&self) -> u32 {
        self.albedo_flags.w as u32
    }
}

/// The camera and targets of the lighting pass (`CameraParams`, 208 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CameraParams {
    /// World -> camera clip.
    pub view_proj: Mat4,
    /// xyz; w = near plane distance.
    pub position: Vec4,
    /// xyz unit; w = far plane distance.
    pub forward: Vec4,
    /// Ray direction through the image's top-left corner, with unit component along the view
    /// axis; `ray_dx`/`ray_dy` are its change per pixel right and down.
    pub ray00: Vec4,
    /// Change of the ray direction per pixel to the right.
    pub ray_dx: Vec4,
    /// Change of the ray direction per pixel down.
    pub ray_dy: Vec4,
    /// xy = image size, z = samples per pixel, w = seed.
    pub image: UVec4,
    /// x = ambient radiance factor; y, z, w = 0. (The estimator, the filter and the loop
    /// budget are specialization constants of the shading pipeline the pass picks.)
    pub shading: Vec4,
    /// The per-sample visibility buffer.
    pub visibility: u64,
    /// The accumulated radiance (RGBA32F per pixel).
    pub radiance: u64,
    /// The target's counters (u32: triangles dropped for an invalid index; pixels whose
    /// lookups ran past the loop budget).
    pub counters: u64,
    /// A moving camera's [`GpuCameraEnd`], right after this header in
    /// the target's header buffer; 0 for a still camera.
    pub camera_end: u64,
}

/// What an ordinary shadow map stores per texel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum DepthFormat {
    /// 8 bytes: a depth (D32) and a triangle id (R32_UINT colour attachment, written by a
    /// fragment shader): lets the shadow test skip the receiver's own triangle.
    DepthAndId = DEPTH_AND_ID,
    /// 4 bytes: depth alone (D32, no fragment shader), as the papers' time-dependent shadow
    /// maps store it.
    DepthOnly = DEPTH_ONLY,
}

impl DepthFormat {
    /// Bytes per texel.
    pub fn bytes(self) -> u64 {
        match self {
            Self::DepthAndId => 8,
            Self::DepthOnly => 4,
        }
    }
}

/// The lighting pass's shadow test (its shading pipeline's specialization constant).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum ShadowMode {
    /// The depth-time ranges of a [`super::TemporalShadowMap`] (and its coverage map, if the
    /// collection pass built one).
    Temporal = SHADOW_TEMPORAL,
    /// One ordinary shadow map ([`super::PlainShadowMap`]) for every sample.
    Plain = SHADOW_PLAIN,
    /// No shadows at all.
    None = SHADOW_NONE,
    /// Time-dependent shadow maps: a sample in time stratum s tests map s (depth only).
    Tsm = SHADOW_TSM,
}

/// The visibility buffer's "no triangle" id (and the plain shadow map's).
pub const NO_TRIANGLE: u32 = u32::MAX;

const _: () = {
    assert!(std::mem::size_of::<Node>() == 16);
    assert!(std::mem::size_of::<Range>() == 24);
    assert!(std::mem::size_of::<Counters>() == 48);
    assert!(std::mem::size_of::<LongListHeader>() == 16);
    assert!(std::mem::size_of::<GpuLight>() == 192);
    assert!(std::mem::size_of::<ShadowMapHeader>() == 480);
    assert!(std::mem::offset_of!(ShadowMapHeader, light_end) == 320);
    assert!(std::mem::size_of::<GpuLightEnd>() == 160);
    assert!(std::mem::size_of::<TriangleRecord>() == 96);
    assert!(std::mem::size_of::<PlainMapHeader>() == 224);
    assert!(std::mem::size_of::<DrawRecord>() == 160);
    assert!(std::mem::size_of::<DrawRecord>() == 8 * DRAW_RECORD_WORDS as usize);
    assert!(std::mem::size_of::<CameraParams>() == 208);
    assert!(std::mem::size_of::<GpuCameraEnd>() == 80);
};
