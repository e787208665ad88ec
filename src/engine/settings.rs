//! Everything an engine chooses for one light's shadow, in one struct with defaults.

use super::light::Light;
use crate::technique::{Lookup, Pruning, RangeStorage};
use ash::vk;

/// Whether the still meshes' nearest triangles (the static layer) are kept across frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum StaticLayer {
    /// Redrawn every frame: never wrong, whatever the host does to its still meshes.
    #[default]
    Redrawn,
    /// Kept while the light and the still meshes' descriptions stay the same, from the frame
    /// after the one that drew it completed ([`crate::Context::collect`]): only moving
    /// meshes are drawn then. Only if still meshes' buffer contents do not change under the
    /// same description (else [`super::LightShadow::forget_static_layer`]).
    Kept,
    /// No static layer: still meshes go into the lists like moving ones (the papers' maps).
    Off,
}

/// One light's shadow settings. Build with [`ShadowSettings::new`] and change fields with
/// struct update syntax: `ShadowSettings { map_size: (2048, 2048), ..ShadowSettings::new(light) }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowSettings {
    /// The light whose shadow this is (its map follows its projection).
    pub light: Light,
    /// Texels of the map: finer shadow edges for more memory and collection time.
    pub map_size: (u32, u32),
    /// How ranges are stored: sorted (default) makes lookups read consecutive memory.
    pub range_storage: RangeStorage,
    /// Which ranges the sort drops: the default saves memory at no cost in the images.
    pub pruning: Pruning,
    /// Kept saves redrawing still meshes each frame; redrawn (default) is always right.
    pub static_layer: StaticLayer,
    /// What the map answers: depth lines (default, `ms_lit_fraction`) or the exact lookup
    /// (the mask only; no texels, no bias).
    pub lookup: Lookup,
    /// Record the visibility mask (the host's G-buffer in, a lit fraction per pixel out)
    /// after the map: needs mask inputs at each frame.
    pub mask: bool,
    /// Frames the host has in flight: one map per frame, so that recording one never waits
    /// for another.
    pub frames_in_flight: u32,
    /// The shader stages your own shaders read the map from (`ms_visibility`,
    /// `ms_lit_fraction`): what [`super::ShadowFrame::lookups`] declares to your render
    /// graph. Empty when only the mask reads the map. Vertex, geometry, fragment and compute
    /// by default (the stages the generation makes the map visible to); any other stage is
    /// refused.
    pub lookup_stages: vk::PipelineStageFlags2,
}

impl ShadowSettings {
    /// The defaults for `light`: a 1024 x 1024 map, sorted ranges, the default pruning, the
    /// static layer redrawn, depth-line lookups, no mask, two frames in flight.
    pub fn new(light: Light) -> Self {
        Self {
            light,
            map_size: (1024, 1024),
            range_storage: RangeStorage::default(),
            pruning: Pruning::default(),
            static_layer: StaticLayer::default(),
            lookup: Lookup::default(),
            mask: false,
            frames_in_flight: 2,
            lookup_stages: crate::gpu::Access::ANY_SHADER_READ.stages,
        }
    }
}
