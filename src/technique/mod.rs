//! Layer 2: the technique. One module per pass; each pass owns its pipelines and descriptor
//! sets and records into a command buffer that the caller gives it. Nothing here creates a
//! device, submits or waits: the caller drives the frame (see `crate::render`).
//!
//! A frame: [`CollectionPass`] fills a [`TemporalShadowMap`] with prism fragments,
//! [`GenerationPass`] turns them into depth-time ranges, [`LightingPass`] renders the camera
//! view with stochastic rasterization and tests each sample against the ranges.
//! [`CoveragePass`] (between collection and generation) adds the 2017 paper's coverage map;
//! [`PlainShadowPass`] renders ordinary shadow maps at given times, for the time-dependent
//! shadow maps and the brute-force reference that the papers compare against.

mod collection;
mod coverage;
mod generation;
mod geometry;
pub mod gpu_types;
mod lighting;
mod plain_shadow;
pub mod shaders;
mod shadow_map;
mod view;

pub use collection::CollectionPass;
pub use coverage::{CoverageMap, CoveragePass, MAX_COVERAGE_TRIANGLES};
pub use generation::GenerationPass;
pub use geometry::{FrameInputs, SceneGeometry};
pub use gpu_types::{
    Counters, DepthFormat, FIXED_TIME, FrameParams, MAX_LIST_NODES, Node, PassConstants, Range,
    SceneVertex, ShadowMode, TRIANGLE_CLOSED, TRIANGLE_MOVING, TriangleInfo, USE_COVERAGE,
};
pub use lighting::{LightingPass, LightingTarget, MAX_SAMPLES_PER_CHUNK, Samples, ShadowSource};
pub use plain_shadow::{PlainShadowMap, PlainShadowPass};
pub use shadow_map::{ShadowMapContents, TemporalShadowMap};
pub use view::{CameraView, FrameSettings, LightKind, LightView};
