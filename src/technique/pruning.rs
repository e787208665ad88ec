//! Which ranges the sort of a map with [`super::RangeStorage::Sorted`] leaves out
//! (`docs/src/pruning.md`). The static and cover rules drop only ranges that decide no
//! lookup: the images are the same whichever is chosen; the map's memory and the sort's time
//! are not. The coverage rule is the 2017 paper's coverage map, made in the sort: it may
//! light a receiver on the covering triangle that the others would shadow (as the coverage
//! map does).

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
    /// triangle) cover. It drops far more on deep scenes, but its sweep makes the sort
    /// slower: a choice for memory, not for speed (the figures: `docs/src/pruning.md`,
    /// "Measured").
    Cover,
    /// The static rule, and also the 2017 paper's coverage map made in one pass (its future
    /// work): where one moving triangle C covers the texel all frame, nearer than every other
    /// range at every time (by the pruning margin), only C's range is kept. Lookups then
    /// answer as with the coverage map: a receiver on C is lit (its own range skipped), any
    /// other is compared with C's depth at its time. That is what the other rules answer
    /// too, except for a receiver on C tested behind C's own depth (the acne the
    /// receiver-plane test and the normal offset hide; a moving receiver on a turning C):
    /// there they may shadow it from a range behind C. One comparison pair per range, in the
    /// sort: no pass of its own and no per-texel maps.
    Coverage,
}

impl Pruning {
    /// The sort pipelines' specialization constant `COVER_RULE` (`range_sort_lists.glsl`):
    /// a variant, not a push constant, so that the static rule's pipelines hold no code of
    /// the cover rule and cost what they cost before it existed.
    pub(crate) fn cover_rule(self) -> u32 {
        u32::from(self == Self::Cover)
    }

    /// The specialization constant `COVERAGE_RULE` (`range_sort_lists.glsl`), likewise.
    pub(crate) fn coverage_rule(self) -> u32 {
        u32::from(self == Self::Coverage)
    }
}
