//! What one recorded frame hands the host: the map's address for its shaders, and the
//! declared accesses of every pass recorded, for its render graph.

use crate::technique::{
    CollectionPass, DrawList, GenerationPass, LightView, MaskInputs, PassAccesses,
    TemporalShadowMap, VisibilityMaskPass,
};
use ash::vk;

/// One frame's shadow as recorded by [`super::LightShadow::record_frame`].
///
/// The passes record their own barriers between each other and before the collection
/// (waiting for every earlier read of the map, the host's lookups of the previous frame in
/// this map included). What the host orders itself: its writes to the meshes' positions
/// before [`Self::collection`]'s first access of `DrawStreams`; its G-buffer writes and
/// layouts before [`Self::mask`]'s first accesses, and the mask's output after its last;
/// nothing before its own lookups ([`Self::lookups`]), which the generation's closing
/// barrier makes visible to every shader stage.
#[derive(Debug, Clone)]
pub struct ShadowFrame {
    /// The device address of the map's header: `MsShadowMap(map_header)` in the host's
    /// shaders (`ms_visibility`, `ms_lit_fraction`).
    pub map_header: u64,
    /// What the collection read and wrote.
    pub collection: PassAccesses,
    /// What the generation read and wrote.
    pub generation: PassAccesses,
    /// What the mask read and wrote (with [`super::ShadowSettings::mask`]).
    pub mask: Option<PassAccesses>,
    /// Whether this frame's collection drew the still meshes' static layer (with
    /// [`super::StaticLayer::Kept`], only when the layer could not be kept: the first frame
    /// in a map, or after the light, the still meshes or the map's buffers changed).
    pub static_layer_drawn: bool,
    /// What the host's own shaders read when they test visibility against the map, in the
    /// stages [`super::ShadowSettings::lookup_stages`] names (nothing when it is empty).
    pub lookups: PassAccesses,
}

impl ShadowFrame {
    pub(super) fn new(
        collection: &CollectionPass,
        generation: &GenerationPass,
        mask: Option<(&VisibilityMaskPass, &MaskInputs)>,
        draws: &DrawList,
        light: &LightView,
        map: &TemporalShadowMap,
        static_layer_drawn: bool,
    ) -> Self {
        Self {
            map_header: map.header_address(),
            collection: collection.accesses(draws, light, map, None),
            generation: generation.accesses(map),
            mask: mask.map(|(pass, inputs)| pass.accesses(inputs, map)),
            static_layer_drawn,
            lookups: PassAccesses::default(),
        }
    }

    /// The frame with the host's lookups of `map` declared in `stages` (none when empty).
    pub(super) fn with_lookups(
        mut self,
        map: &TemporalShadowMap,
        stages: vk::PipelineStageFlags2,
    ) -> Self {
        if !stages.is_empty() {
            self.lookups = map.lookup_accesses(stages);
        }
        self
    }
}
