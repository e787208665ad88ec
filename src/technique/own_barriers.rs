//! The passes' own entry and exit barriers, each derived ([`Barrier::between`]) from what
//! may come before or after the pass and the pass's declared uses, and the declarations of
//! the passes that had none: the draw list's update, the counter readback and the host's
//! reads after them, the mask's own buffers. A host that records a pass's barriers itself
//! (`with_host_barriers`) issues what the same declarations give between the passes it
//! actually runs.
//!
//! What each pass's own barriers order against:
//! - the draw list's update: after and before every shader that reads the list
//!   ([`DrawList::read_accesses`]);
//! - the collection: after anything the map may have been used for since (an earlier
//!   collection, the generation, lookups from any shader stage, the counter readback);
//!   before the generation;
//! - the generation: after the previous generation; before lookups from any shader stage
//!   ([`TemporalShadowMap::lookup_accesses`] with every stage);
//! - the counter readback: after the generation; before the host's read;
//! - the mask: before the host's read of its over-budget counter (its map reads are the
//!   generation's exit barrier's, its images the host's).

use super::accesses::{PassAccesses, collection_uses, generation_uses};
use super::coverage::CoverageMap;
use super::declared_barriers::Barrier;
use super::draws::DrawList;
use super::mask::{MaskBindings, VisibilityMaskPass};
use super::shadow_map::TemporalShadowMap;
use super::view::LightView;
use crate::gpu::Access;

/// Shader stages a host may read the map from.
const ANY_SHADER_STAGE: Access = Access::ANY_SHADER_READ;

/// A pass's own entry and exit barriers (None: nothing to order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct OwnBarriers {
    pub entry: Option<Barrier>,
    pub exit: Option<Barrier>,
}

fn own(before: &PassAccesses, this: &PassAccesses, after: &PassAccesses) -> OwnBarriers {
    OwnBarriers {
        entry: Barrier::between(before, this),
        exit: Barrier::between(this, after),
    }
}

fn lookups(map: &TemporalShadowMap) -> PassAccesses {
    map.lookup_accesses(ANY_SHADER_STAGE.stages)
}

/// The collection's own barriers for these arguments.
pub(crate) fn collection(
    draws: &DrawList,
    light: &LightView,
    map: &TemporalShadowMap,
    coverage: Option<&CoverageMap>,
) -> OwnBarriers {
    let this = collection_uses(draws, light, map, coverage);
    let earlier = generation_uses(map)
        .and(&lookups(map))
        .and(&map.counter_readback_accesses())
        .and(&this);
    own(&earlier, &this, &generation_uses(map))
}

/// The generation's own barriers.
pub(crate) fn generation(map: &TemporalShadowMap) -> OwnBarriers {
    let this = generation_uses(map);
    own(&this, &this, &lookups(map))
}

/// The counter readback's own barriers.
pub(crate) fn counter_readback(map: &TemporalShadowMap) -> OwnBarriers {
    own(
        &generation_uses(map),
        &map.counter_readback_accesses(),
        &map.counter_read_accesses(),
    )
}

/// The draw list update's own barriers.
pub(crate) fn draw_list_update(list: &DrawList) -> OwnBarriers {
    let readers = list.read_accesses();
    own(&readers, &list.update_accesses(), &readers)
}

/// The mask's own exit barrier (it has no entry barrier: its bindings are not in use by a
/// pending command buffer, its contract).
pub(crate) fn mask(bindings: &MaskBindings) -> OwnBarriers {
    OwnBarriers {
        entry: None,
        exit: Barrier::between(&bindings.accesses(), &bindings.read_accesses()),
    }
}

impl DrawList {
    /// What [`Self::record_update`] writes: the list, by transfer.
    pub fn update_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let w = Access::TRANSFER_WRITE;
        a.buffer((self.buffer(), "draw list"), w, w, true);
        a
    }

    /// Every reader of the list together (shaders of any stage, storage or uniform reads):
    /// what the update waits for and makes its writes visible to.
    pub fn read_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let r = Access::ANY_SHADER_READ;
        a.buffer((self.buffer(), "draw list"), r, r, false);
        a
    }

    /// The same list with [`Self::record_update`] recording neither its entry nor its exit
    /// barrier: the host issues them from [`Self::update_accesses`].
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }
}

impl TemporalShadowMap {
    /// What [`Self::record_counter_readback`] reads and writes: the counters by transfer
    /// into the host-visible copy.
    pub fn counter_readback_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let (r, w) = (Access::TRANSFER_READ, Access::TRANSFER_WRITE);
        a.buffer((&self.counters, "counters"), r, r, false);
        a.buffer((self.counters_readback(), "counters readback"), w, w, true);
        a
    }

    /// What [`Self::read_counters`] reads: the copy, by the host.
    pub fn counter_read_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let r = Access::HOST_READ;
        a.buffer((self.counters_readback(), "counters readback"), r, r, false);
        a
    }

    /// The same map with [`Self::record_counter_readback`] recording neither its entry nor
    /// its exit barrier: the host issues them from [`Self::counter_readback_accesses`].
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }
}

impl MaskBindings {
    /// What [`VisibilityMaskPass::record`] writes of these bindings: the over-budget
    /// counter (cleared by transfer, counted by the compute shader) and the follow-up
    /// queues (reset by transfer, filled and read by the rounds, their group counts read
    /// as indirect arguments). Its own barriers between the rounds stay.
    pub fn accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let (w, rw) = (Access::TRANSFER_WRITE, Access::COMPUTE_RW);
        a.buffer(
            (self.over_budget_buffer(), "over-budget pixels"),
            w,
            rw,
            true,
        );
        a.buffer(
            (self.queue_buffer(), "mask follow-up queues"),
            w,
            rw.and(Access::INDIRECT_READ),
            true,
        );
        a
    }

    /// What [`Self::read_over_budget_pixels`] reads: the counter, by the host.
    pub fn read_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let r = Access::HOST_READ;
        a.buffer(
            (self.over_budget_buffer(), "over-budget pixels"),
            r,
            r,
            false,
        );
        a
    }
}

impl VisibilityMaskPass {
    /// The same pass without its exit barrier (the over-budget counter to the host's
    /// read): the host issues it from [`MaskBindings::accesses`] and
    /// [`MaskBindings::read_accesses`]. The barriers between its own steps stay.
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }
}
