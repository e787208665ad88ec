//! Which ranges the sort of a map with [`super::RangeStorage::Sorted`] leaves out
//! (`docs/src/pruning.md`). Every rule drops only ranges that decide no lookup: the images are
//! the same whichever is chosen; the map's memory and the sort's time are not.

/// The pruning rule a [`super::TemporalShadowMap`] asks of the generation pass's sort
/// ([`super::TemporalShadowMap::with_pruning`]). It has no effect on a map whose ranges are
/// not sorted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Pruning {
    /// Ranges behind the texel's static-layer triangle all along, where receivers are tested
    /// at their plane's depth (`LightView::receiver_plane`). Cheap: one comparison per range
    /// as the sort loads it.
    #[default]
    StaticLayer,
    /// The static rule, and also, with either receiver test, a moving range that at every
    /// time of its interval nearer ranges of two other triangles (or the static layer's
    /// triangle) cover. It drops far more on deep scenes (lavapipe: random-cubes' map 95 to
    /// 56 MiB, 16 stacked plates 141 to 38 MiB), but its sweep makes the sort slower
    /// (lavapipe: the default scene's generation pass 1.8x, the stacked plates' 6x; figures
    /// in `docs/src/pruning.md`): a choice for memory, not for speed.
    Cover,
}

impl Pruning {
    /// The sort pipelines' specialization constant `COVER_RULE` (`range_sort_lists.glsl`):
    /// a variant, not a push constant, so that the static rule's pipelines hold no code of
    /// the cover rule and cost what they cost before it existed.
    pub(crate) fn cover_rule(self) -> u32 {
        u32::from(self == Self::Cover)
    }
}
