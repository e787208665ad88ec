//! SPIR-V compiled from `glsl/` by build.rs, for hosts that build their own pipelines.

use crate::gpu::Spirv;

macro_rules! spirv {
    ($name:literal) => {
        Spirv::trusted(include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv")))
    };
}

/// SPIR-V of `glsl/scene.vert`.
pub const SCENE_VERT: Spirv<'static> = spirv!("scene.vert");
/// SPIR-V of `glsl/collection.geom`.
pub const COLLECTION_GEOM: Spirv<'static> = spirv!("collection.geom");
/// SPIR-V of `glsl/collection.frag`.
pub const COLLECTION_FRAG: Spirv<'static> = spirv!("collection.frag");
/// SPIR-V of `glsl/collection_exact.geom`.
pub const COLLECTION_EXACT_GEOM: Spirv<'static> = spirv!("collection_exact.geom");
/// SPIR-V of `glsl/collection_conservative.geom`.
pub const COLLECTION_CONSERVATIVE_GEOM: Spirv<'static> = spirv!("collection_conservative.geom");
/// SPIR-V of `glsl/collection_conservative.frag`.
pub const COLLECTION_CONSERVATIVE_FRAG: Spirv<'static> = spirv!("collection_conservative.frag");
/// SPIR-V of `glsl/collection_exact.frag`.
pub const COLLECTION_EXACT_FRAG: Spirv<'static> = spirv!("collection_exact.frag");
/// SPIR-V of `glsl/collection_ranges.frag`.
pub const COLLECTION_RANGES_FRAG: Spirv<'static> = spirv!("collection_ranges.frag");
/// SPIR-V of `glsl/collection_static.vert`.
pub const COLLECTION_STATIC_VERT: Spirv<'static> = spirv!("collection_static.vert");
/// SPIR-V of `glsl/collection_static.frag`.
pub const COLLECTION_STATIC_FRAG: Spirv<'static> = spirv!("collection_static.frag");
/// SPIR-V of `glsl/generation.comp`.
pub const GENERATION_COMP: Spirv<'static> = spirv!("generation.comp");
/// SPIR-V of `glsl/generation_long.comp`.
pub const GENERATION_LONG_COMP: Spirv<'static> = spirv!("generation_long.comp");
/// SPIR-V of `glsl/range_sort.comp`.
pub const RANGE_SORT_COMP: Spirv<'static> = spirv!("range_sort.comp");
/// SPIR-V of `glsl/range_sort_long.comp`.
pub const RANGE_SORT_LONG_COMP: Spirv<'static> = spirv!("range_sort_long.comp");
/// SPIR-V of `glsl/lighting.geom`.
pub const LIGHTING_GEOM: Spirv<'static> = spirv!("lighting.geom");
/// SPIR-V of `glsl/lighting_camera_moves.geom` (the lighting raster for a moving camera).
pub const LIGHTING_CAMERA_MOVES_GEOM: Spirv<'static> = spirv!("lighting_camera_moves.geom");
/// SPIR-V of `glsl/lighting.frag`.
pub const LIGHTING_FRAG: Spirv<'static> = spirv!("lighting.frag");
/// SPIR-V of `glsl/resolve.comp`.
pub const RESOLVE_COMP: Spirv<'static> = spirv!("resolve.comp");
/// SPIR-V of `glsl/shadow_depth.vert`.
pub const SHADOW_DEPTH_VERT: Spirv<'static> = spirv!("shadow_depth.vert");
/// SPIR-V of `glsl/shadow_depth.frag`.
pub const SHADOW_DEPTH_FRAG: Spirv<'static> = spirv!("shadow_depth.frag");
/// SPIR-V of `glsl/coverage_caps.vert`.
pub const COVERAGE_CAPS_VERT: Spirv<'static> = spirv!("coverage_caps.vert");
/// SPIR-V of `glsl/coverage.frag`.
pub const COVERAGE_FRAG: Spirv<'static> = spirv!("coverage.frag");
/// SPIR-V of `glsl/coverage_reset.frag`.
pub const COVERAGE_RESET_FRAG: Spirv<'static> = spirv!("coverage_reset.frag");
/// SPIR-V of `glsl/coverage_reset_exact.frag`.
pub const COVERAGE_RESET_EXACT_FRAG: Spirv<'static> = spirv!("coverage_reset_exact.frag");
/// SPIR-V of `glsl/coverage_reset_static.frag`.
pub const COVERAGE_RESET_STATIC_FRAG: Spirv<'static> = spirv!("coverage_reset_static.frag");
/// SPIR-V of `glsl/visibility_mask.comp`.
pub const VISIBILITY_MASK_COMP: Spirv<'static> = spirv!("visibility_mask.comp");
/// SPIR-V of `glsl/tsm_mask.comp`.
pub const TSM_MASK_COMP: Spirv<'static> = spirv!("tsm_mask.comp");
/// SPIR-V of `glsl/radiance_to_image.comp`.
pub const RADIANCE_TO_IMAGE_COMP: Spirv<'static> = spirv!("radiance_to_image.comp");
/// SPIR-V of `glsl/gbuffer.vert`.
pub const GBUFFER_VERT: Spirv<'static> = spirv!("gbuffer.vert");
/// SPIR-V of `glsl/gbuffer.frag`.
pub const GBUFFER_FRAG: Spirv<'static> = spirv!("gbuffer.frag");

#[cfg(test)]
mod layout_check;
#[cfg(test)]
mod rust_structs;
#[cfg(test)]
mod spirv_structs;
