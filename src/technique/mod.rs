//! Layer 2: the technique. One module per pass; each pass owns its pipelines and records
//! into a command buffer that the caller gives it. Nothing here creates a device, submits or
//! waits: the caller drives the frame.
//!
//! Passes are immutable after creation. Per-frame and per-light state lives in its own
//! objects ([`DrawList`], [`TemporalShadowMap`], [`CoverageMap`], [`PlainShadowMap`],
//! [`LightingTarget`]), which shaders reach by device address through push constants, so
//! one set of passes serves N frames in flight and any number of lights.
//!
//! A frame: [`DrawList::record_update`] uploads the draws' descriptions (the host's own
//! vertex and index buffers, read in place), [`CollectionPass`] fills a [`TemporalShadowMap`]
//! with prism fragments, [`GenerationPass`] turns them into depth-time ranges. Then a host
//! shader tests visibility with the GLSL include [`GLSL_INCLUDE`] (`ms_visibility`), or the
//! papers' [`LightingPass`] renders the camera view with stochastic rasterization and tests
//! each sample against the ranges. [`CoveragePass`] (between collection and generation) adds
//! the 2017 paper's coverage map; [`PlainShadowPass`] renders ordinary shadow maps at given
//! times, for the time-dependent shadow maps and the brute-force reference that the papers
//! compare against.
//!
//! The engine core (draws, collection, generation, the temporal map, the mask, the views,
//! the G-buffer pass, the GLSL include) is always compiled; the papers' research passes
//! ([`LightingPass`], [`LightingImageOutput`], [`EngineTsmPass`], [`PlainShadowPass`],
//! [`CoveragePass`]) only with the default feature `research` (an engine may build with
//! `default-features = false`).

mod accesses;
mod camera_motion;
mod collection;
mod coverage;
#[cfg(feature = "research")]
mod coverage_pass;
#[cfg(feature = "research")]
mod coverage_steps;
mod declared_barriers;
mod draws;
#[cfg(feature = "research")]
mod engine_tsm;
mod gbuffer;
mod gbuffer_accesses;
mod generation;
#[cfg(test)]
mod glsl_files;
#[doc(hidden)]
pub mod gpu_constants;
pub mod gpu_types;
#[cfg(feature = "research")]
mod image_output;
mod image_pass;
mod image_transitions;
mod light_motion;
#[cfg(feature = "research")]
mod lighting;
mod mask;
mod mask_ids;
mod mask_queue;
mod own_barriers;
mod path_buffers;
#[cfg(feature = "research")]
mod plain_shadow;
#[cfg(feature = "research")]
mod plain_shadow_steps;
mod pruning;
#[doc(hidden)]
pub mod push_constants;
mod range_ceiling;
pub mod sampling;
#[doc(hidden)]
pub mod shaders;
mod shadow_map;
mod view;

pub use accesses::{AccessData, PassAccesses, Resource, ResourceUse};
pub use camera_motion::CameraEnd;
pub use collection::CollectionPass;
pub use coverage::{CoverageMap, MAX_COVERAGE_TRIANGLES};
#[cfg(feature = "research")]
pub use coverage_pass::CoveragePass;
pub use declared_barriers::Barrier;
pub use draws::{Draw, DrawList, IndexStream, Indices, PositionStream};
#[cfg(feature = "research")]
pub use engine_tsm::{
    EngineTsmBindings, EngineTsmMap, EngineTsmPass, MAX_TSM_LAYERS, MAX_TSM_MAPS, TsmStart,
};
pub use gbuffer::{
    GBUFFER_COLOR_FORMAT, GBUFFER_DEPTH_FORMAT, GBuffer, GBufferCamera, GBufferContents,
    GBufferPass,
};
pub use generation::GenerationPass;
pub use gpu_types::{
    CameraParams, Counters, DepthFormat, DrawRecord, FIXED_TIME, GpuCameraEnd, GpuLight,
    GpuLightEnd, LongListHeader, MAX_LIST_NODES, NO_TRIANGLE, Node, PlainMapHeader, Range,
    ShadowMapHeader, ShadowMode, TriangleRecord,
};
#[cfg(feature = "research")]
pub use image_output::LightingImageOutput;
pub use image_transitions::ImageTransition;
pub use light_motion::{LightEnd, MAX_LIGHT_TURN_DEG};
#[cfg(feature = "research")]
pub use lighting::{LightingPass, LightingTarget, MAX_SAMPLES_PER_CHUNK, Samples, ShadowSource};
pub use mask::{
    MaskBindings, MaskInputs, MotionImage, NormalEncoding, NormalImage, PositionImage,
    TriangleIdImage, VisibilityMaskPass,
};
pub use mask_queue::DEFAULT_MASK_FOLLOW_UP_ROUNDS;
#[cfg(feature = "research")]
pub use plain_shadow::{PlainShadowMap, PlainShadowPass};
pub use pruning::Pruning;
pub use range_ceiling::{HostDraw, RangeCeiling};
pub use sampling::{pixel_key, pixel_sample};
pub(crate) use shadow_map::Bounded;
pub use shadow_map::{RangeStorage, ShadowMapContents, TemporalShadowMap};
pub use view::{
    CameraView, DEFAULT_DEPTH_BIAS, DEFAULT_NORMAL_OFFSET_TEXELS, LightKind, LightView,
    LightingView, Lookup, PrismConstruction, ShadowEstimator, ShadowFilter,
};

/// `glsl/motion_shadows.glsl`: the GLSL include a host's own shaders use to test visibility
/// against a [`TemporalShadowMap`] (`ms_visibility(MsShadowMap(header_address), position,
/// normal, t, MS_NO_TRIANGLE)`). Write it next to your shaders or hand it to your compiler's
/// include callback under the name `motion_shadows.glsl`. With shaderc, target Vulkan 1.2
/// (`EnvVersion::Vulkan1_2`) unless the device has maintenance4: for 1.3 glslang declares
/// workgroup sizes with LocalSizeId.
///
/// The file includes its parts (`glsl/motion_shadows/`, one concept each); this string is
/// those parts concatenated in the file's order, so it includes nothing (a test holds the two
/// to the same parts).
pub const GLSL_INCLUDE: &str = concat!(
    include_str!("../../glsl/motion_shadows/map_layout.glsl"),
    include_str!("../../glsl/motion_shadows/receiver_projection.glsl"),
    include_str!("../../glsl/motion_shadows/point_lookups.glsl"),
    include_str!("../../glsl/motion_shadows/shutter_lookups.glsl"),
    include_str!("../../glsl/motion_shadows/receiver_path.glsl"),
    include_str!("../../glsl/motion_shadows/filtered_lookups.glsl"),
);

/// `glsl/light_motion.glsl`: a moving light's lookups ([`LightView::moving_to`]:
/// `ms_map_at` for a sample at its time, `ms_light_frame_end` for a moving receiver's path,
/// `MsLightEnd`), included after [`GLSL_INCLUDE`]. A still light's map needs none of it.
pub const GLSL_LIGHT_MOTION_INCLUDE: &str = include_str!("../../glsl/light_motion.glsl");

/// `glsl/exact_lookup.glsl`: the exact lookup ([`Lookup::Exact`]:
/// `ms_lit_fraction_exact`, `ms_lit_fraction_exact_moving`, `ms_visible_exact` for one time),
/// included after
/// [`GLSL_INCLUDE`]; it includes `exact_shadow.glsl` ([`GLSL_EXACT_SHADOW_INCLUDE`]).
pub const GLSL_EXACT_LOOKUP_INCLUDE: &str = include_str!("../../glsl/exact_lookup.glsl");

/// `glsl/exact_shadow.glsl`: the exact shadow test of one receiver against one moving
/// triangle (self-contained), included by [`GLSL_EXACT_LOOKUP_INCLUDE`].
pub const GLSL_EXACT_SHADOW_INCLUDE: &str = include_str!("../../glsl/exact_shadow.glsl");
