//! SPIR-V compiled from `glsl/` by build.rs, for hosts that build their own pipelines.

macro_rules! spirv {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv"))
    };
}

pub const SCENE_VERT: &[u8] = spirv!("scene.vert");
pub const COLLECTION_GEOM: &[u8] = spirv!("collection.geom");
pub const COLLECTION_FRAG: &[u8] = spirv!("collection.frag");
pub const GENERATION_COMP: &[u8] = spirv!("generation.comp");
pub const GENERATION_LONG_COMP: &[u8] = spirv!("generation_long.comp");
pub const LIGHTING_GEOM: &[u8] = spirv!("lighting.geom");
pub const LIGHTING_FRAG: &[u8] = spirv!("lighting.frag");
pub const RESOLVE_COMP: &[u8] = spirv!("resolve.comp");
pub const SHADOW_DEPTH_VERT: &[u8] = spirv!("shadow_depth.vert");
pub const SHADOW_DEPTH_FRAG: &[u8] = spirv!("shadow_depth.frag");
pub const LAYOUT_PROBE_COMP: &[u8] = spirv!("layout_probe.comp");
pub const COVERAGE_FRAG: &[u8] = spirv!("coverage.frag");
pub const COVERAGE_RESET_FRAG: &[u8] = spirv!("coverage_reset.frag");
