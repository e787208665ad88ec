//! Rust mirrors of the structs in `glsl/shared.glsl`. Sizes and field offsets are checked
//! against the shaders by `tests/gpu_layout.rs`.

use glam::{Mat4, UVec4, Vec4};

/// One fragment of a prism (16 bytes): linear light depth, shutter time, triangle id, link.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Node {
    pub depth: f32,
    pub time: f32,
    pub id: u32,
    /// Index + 1 of the next node of the same pixel; 0 ends the list.
    pub next: u32,
}

/// A depth-time range (24 bytes): the triangle `id` covers the pixel from `t_s` to `t_e`,
/// at a depth going linearly from `d_s` to `d_e`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Range {
    pub t_s: f32,
    pub t_e: f32,
    pub d_s: f32,
    pub d_e: f32,
    pub id: u32,
    pub next: u32,
}

/// A vertex's world positions at t = 0 and t = 1 (w = 1).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SceneVertex {
    pub p0: Vec4,
    pub p1: Vec4,
}

/// Per-triangle shading data: rgb albedo, w = [`TRIANGLE_CLOSED`] | [`TRIANGLE_MOVING`] flags
/// (as a float).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TriangleInfo {
    pub albedo_flags: Vec4,
}

/// The triangle's mesh is closed: a triangle facing away all frame may be culled.
pub const TRIANGLE_CLOSED: u32 = 1;
/// Some vertex of the triangle moves during the frame.
pub const TRIANGLE_MOVING: u32 = 2;

impl TriangleInfo {
    pub fn new(albedo: glam::Vec3, flags: u32) -> Self {
        Self {
            albedo_flags: albedo.extend(flags as f32),
        }
    }
}

/// Fragment and range counts (written by shaders) and capacities (written when recording).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    pub node_count: u32,
    pub node_capacity: u32,
    pub range_count: u32,
    pub range_capacity: u32,
    /// Shadow-map pixels holding more than [`MAX_LIST_NODES`] fragments: not turned into
    /// ranges, so such a frame is an error.
    pub overlong_pixels: u32,
    /// The longest fragment list of the frame (counted up to 8 x [`MAX_LIST_NODES`]).
    pub longest_list: u32,
    /// What `range_count` would be without the coverage map (equal to it without one).
    pub ranges_without_coverage: u32,
    pub reserved: u32,
}

/// The most fragments one shadow-map pixel may hold (`MAX_LIST_NODES` in shared.glsl).
pub const MAX_LIST_NODES: u32 = 512;

/// Everything a frame's shaders need to know about the camera, light and sampling (std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameParams {
    pub light_view: Mat4,
    pub light_proj: Mat4,
    pub camera_view_proj: Mat4,
    pub camera_inv_view_proj: Mat4,
    /// xyz; w = near plane distance.
    pub camera_position: Vec4,
    /// xyz unit; w = far plane distance.
    pub camera_forward: Vec4,
    /// xyz; w = 1 spot, 0 directional.
    pub light_position: Vec4,
    /// xyz unit; w = cos(cone half angle).
    pub light_direction: Vec4,
    /// x = intensity or irradiance, y = ambient, z = normal offset (texels), w = depth bias.
    pub light_params: Vec4,
    /// x = world size of a shadow texel per unit depth (spot) or absolute (directional).
    pub light_texel: Vec4,
    /// Ray direction through the image's top-left corner, with unit component along the view
    /// axis; `camera_ray_dx`/`dy` are its change per pixel right and down.
    pub camera_ray00: Vec4,
    pub camera_ray_dx: Vec4,
    pub camera_ray_dy: Vec4,
    /// xy = shadow map size, zw = image size.
    pub sizes: UVec4,
    /// x = samples per pixel, y = seed.
    pub sampling: UVec4,
}

/// What every pass pushes (48 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PassConstants {
    pub first_triangle: u32,
    /// First sample of a lighting chunk; the layer of an ordinary shadow map.
    pub first_sample: u32,
    pub sample_count: u32,
    /// Lighting: a [`ShadowMode`]; ordinary shadow maps: a [`DepthFormat`].
    pub mode: u32,
    /// Ordinary shadow maps: the scene's time; lighting: the time of every sample when
    /// `flags` has [`FIXED_TIME`].
    pub time: f32,
    pub flags: u32,
    pub reserved: [u32; 2],
    /// Device address of the fragment (node) buffer, for passes that read or write it.
    pub node_address: u64,
    /// Device address of the range buffer.
    pub range_address: u64,
}

/// `PassConstants::flags` of the lighting pass: every sample at `PassConstants::time`.
pub const FIXED_TIME: u32 = 1;
/// `PassConstants::flags` of collection and generation: build / use the coverage map.
pub const USE_COVERAGE: u32 = 2;

/// What an ordinary shadow map stores per texel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum DepthFormat {
    /// 8 bytes: depth bits << 32 | triangle id (lets the shadow test skip the receiver's own
    /// triangle).
    DepthAndId = 0,
    /// 4 bytes: depth alone, as the papers' time-dependent shadow maps store it.
    DepthOnly = 1,
}

impl DepthFormat {
    pub fn bytes(self) -> u64 {
        match self {
            Self::DepthAndId => 8,
            Self::DepthOnly => 4,
        }
    }
}

/// `PassConstants::mode` of the resolve pass: which shadow test it applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum ShadowMode {
    /// The depth-time ranges of a [`super::TemporalShadowMap`].
    Temporal = 0,
    /// One ordinary shadow map ([`super::PlainShadowMap`]) for every sample.
    Plain = 1,
    /// No shadows at all.
    None = 2,
    /// Time-dependent shadow maps: a sample in time stratum s tests map s (depth only).
    Tsm = 3,
    /// The coverage map, then the depth-time ranges (2017 paper's extension).
    Coverage = 4,
}

/// The visibility buffer's "no triangle" id (and the plain shadow map's).
pub const NO_TRIANGLE: u32 = u32::MAX;

const _: () = {
    assert!(std::mem::size_of::<Node>() == 16);
    assert!(std::mem::size_of::<Range>() == 24);
    assert!(std::mem::size_of::<SceneVertex>() == 32);
    assert!(std::mem::size_of::<FrameParams>() == 4 * 64 + 11 * 16);
    assert!(std::mem::size_of::<PassConstants>() == 48);
    assert!(std::mem::size_of::<Counters>() == 32);
};
