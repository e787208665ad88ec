//! Generation sub-pass (paper 4.3): fragments to depth-time ranges, once per shadow-map pixel
//! that holds fragments (an indirect dispatch over every 8x8-texel tile; the collection
//! cleared every range head). Two tiers:
//! every pixel with a short list (nearly all) is paired with small private arrays; the few
//! long lists go to a second, indirect dispatch with room for `MAX_LIST_NODES`. Where the
//! collection stored the ranges itself ([`TemporalShadowMap::collects_ranges`]) it set both
//! dispatches to zero groups; with [`super::RangeStorage::Sorted`] the pass then sorts each
//! texel's collected list into a contiguous run of the range buffer (one atomic per texel
//! takes its places; ranges that can decide no test are pruned by the map's
//! [`super::Pruning`] rule; two tiers again), visiting only the tiles the collection listed
//! as it stored their first range (`gpu_constants::SORT_TILE_ROW`: on lavapipe a workgroup
//! that finds nothing still costs its setup, about half the sort of the default frame), and
//! otherwise costs its barriers only.

use super::declared_barriers::record_own;
use super::gpu_constants::{DISPATCH_PAIRING, DISPATCH_SORT, DISPATCH_SORT_LONG};
use super::gpu_types::LongListHeader;
use super::pruning::Pruning;
use super::push_constants::{MapPush, PushBlock};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::Result;
use crate::gpu::{Access, ComputeVariants, Context, Pipeline, compute_pipeline, memory_barrier};
use ash::vk;
use std::sync::Arc;

/// The generation sub-pass. One serves every frame in flight and every light (the cover
/// rule's pipelines, made on first use, are made once, whoever asks first).
pub struct GenerationPass {
    pipeline: Pipeline,
    long_pipeline: Pipeline,
    /// The sorts with the default rule, [`Pruning::StaticLayer`].
    sort: Pipeline,
    sort_long: Pipeline,
    /// The sorts specialized for [`Pruning::Cover`] or [`Pruning::Coverage`], made on first
    /// use: a host that never asks for those rules never compiles them.
    specialized_sort: ComputeVariants,
    specialized_sort_long: ComputeVariants,
    /// Records its entry and exit barriers (off: the host issues them from
    /// [`Self::accesses`], see `accesses.rs`).
    pub(crate) outer_barriers: bool,
}

impl GenerationPass {
    /// Creates the compute pipelines.
    pub fn new(ctx: &Context) -> Result<Self> {
        let compute = |name, spirv| compute_pipeline(ctx, MapPush::BYTES, name, spirv);
        Ok(Self {
            sort: compute("range_sort.comp", shaders::RANGE_SORT_COMP)?,
            sort_long: compute("range_sort_long.comp", shaders::RANGE_SORT_LONG_COMP)?,
            specialized_sort: ComputeVariants::new(
                ctx,
                MapPush::BYTES,
                "range_sort.comp",
                shaders::RANGE_SORT_COMP,
            )?,
            specialized_sort_long: ComputeVariants::new(
                ctx,
                MapPush::BYTES,
                "range_sort_long.comp",
                shaders::RANGE_SORT_LONG_COMP,
            )?,
            pipeline: compute_pipeline(
                ctx,
                MapPush::BYTES,
                "generation.comp",
                shaders::GENERATION_COMP,
            )?,
            long_pipeline: compute_pipeline(
                ctx,
                MapPush::BYTES,
                "generation_long.comp",
                shaders::GENERATION_LONG_COMP,
            )?,
            outer_barriers: true,
        })
    }

    /// Makes the pipelines that sorting a map with `pruning` needs, if they are not made yet
    /// (only [`Pruning::Cover`] and [`Pruning::Coverage`] have any to make). [`Self::record`] makes them itself the first
    /// time a map asks for them; calling this first keeps the compilation out of the frame
    /// and reports an error where `record` cannot.
    pub fn prepare(&self, pruning: Pruning) -> Result<()> {
        self.specialized_sorts(pruning).map(|_| ())
    }

    /// The two tiers' sort pipelines for `pruning` made with the cover or coverage rule;
    /// None for the static rule (the pipelines made with the pass).
    fn specialized_sorts(&self, pruning: Pruning) -> Result<Option<[Arc<Pipeline>; 2]>> {
        if pruning == Pruning::StaticLayer {
            return Ok(None);
        }
        let constants = [pruning.cover_rule(), pruning.coverage_rule()];
        Ok(Some([
            self.specialized_sort.get(&constants)?,
            self.specialized_sort_long.get(&constants)?,
        ]))
    }

    /// Records the range generation of `map`. When the collection pass of this frame was
    /// recorded with a coverage map, [`super::CoveragePass`] must have been recorded in
    /// between: a covered pixel then stores no range (the coverage map holds what shadows
    /// there).
    ///
    /// # Safety
    /// - As [`super::CollectionPass::record`] for `cmd`; and [`super::CollectionPass::record`]
    ///   was recorded for `map` earlier in `cmd` (the ranges are made from its lists).
    ///
    /// Synchronization: waits for the previous generation's compute and indirect reads of
    /// the map (the collection's writes are its own closing barrier's); leaves the ranges
    /// written by the compute stage and made visible to storage reads in every shader stage
    /// (vertex, geometry, fragment, compute: a host's own passes may read the map with no
    /// barrier of their own, [`TemporalShadowMap::lookup_accesses`]). Both barriers are
    /// derived from [`Self::accesses`] (see `accesses.rs`). A pass made
    /// [`Self::with_host_barriers`] records neither the entry nor the exit barrier: the
    /// caller orders [`Self::accesses`] itself. State changed: the bound compute pipeline
    /// and its push constants.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        map: &TemporalShadowMap,
    ) {
        let header = LongListHeader::EMPTY;
        // Entry: earlier generations' reads of the long-pixel list and the dispatches (the
        // collection's writes: its exit barrier); the host's when `outer_barriers` is off.
        let own = super::own_barriers::generation(map);
        let check = map.header.access_check();
        if self.outer_barriers {
            // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue
            // (CollectionPass::record's contract, which this function takes), so compute, indirect
            // and transfer stages are supported.
            unsafe { record_own(device, cmd, check, "generation entry", own.entry.as_ref()) };
        }
        self.accesses(map).declare_run(check, "generation");
        // SAFETY: one LongListHeader into the map's long-pixel buffer, which starts with it;
        // outside rendering, and the buffer's earlier readers were waited for (above, or by the
        // host's barrier when outer_barriers is off).
        unsafe { map.long_pixels.record_write(device, cmd, &[header]) };
        // The collection's tile list is the first tier's indirect dispatch.
        // SAFETY: the same command buffer, outside rendering, on a queue with transfer and compute.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::TRANSFER_WRITE,
                Access::COMPUTE_RW.and(Access::INDIRECT_READ),
            )
        };
        let constants = MapPush {
            map: map.header_address(),
        };
        // SAFETY: this pass's pairing pipeline, alive as long as `self`; a compute bind outside
        // rendering.
        unsafe { self.pipeline.bind(device, cmd) };
        // SAFETY: MapPush is the push range every generation pipeline's layout was made with
        // (MapPush::BYTES).
        unsafe { self.pipeline.push(device, cmd, &constants) };
        // SAFETY: `map.tiles` is the map's buffer of indirect dispatch arguments (made with
        // indirect usage), DISPATCH_PAIRING's command lies within it, and the collection's writes
        // to it were made visible to indirect reads by the barrier above; the shader bounds every
        // index it derives from the group id by the map's sizes.
        unsafe { device.cmd_dispatch_indirect(cmd, map.tiles.raw(), word_bytes(DISPATCH_PAIRING)) };
        // SAFETY: outside rendering; compute and indirect stages are on this queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::COMPUTE_RW,
                Access::COMPUTE_RW.and(Access::INDIRECT_READ),
            )
        };
        // SAFETY: the long-pixel pipeline of this pass, alive as long as `self`; a compute bind.
        unsafe { self.long_pipeline.bind(device, cmd) };
        // SAFETY: the long-pixel pipeline's layout has MapPush's push range, like the pairing
        // pipeline's.
        unsafe { self.long_pipeline.push(device, cmd, &constants) };
        // SAFETY: the long-pixel buffer holds its header's group counts at GROUPS_OFFSET (written
        // by the pairing, made visible to indirect reads just above) and was made with indirect
        // usage.
        unsafe {
            device.cmd_dispatch_indirect(cmd, map.long_pixels.raw(), LongListHeader::GROUPS_OFFSET)
        };
        // Where the cover or coverage rule's pipelines cannot be made (`prepare` says why),
        // the static rule is as sound: the map keeps more ranges, and no lookup is wronged.
        let cover = self.specialized_sorts(map.pruning()).unwrap_or_else(|e| {
            log::warn!(
                "the {:?} rule's sort pipelines: {e}; pruning by the static rule",
                map.pruning()
            );
            None
        });
        let [sort, sort_long] = match &cover {
            Some([sort, sort_long]) => [&**sort, &**sort_long],
            None => [&self.sort, &self.sort_long],
        };
        // The sorting (zero groups unless the collection stored ranges for sorted storage;
        // the pairing above then ran none, so the long-pixel list is still empty): the short
        // lists (which append the long ones to the long-pixel list and count their groups),
        // then the long ones.
        for (pipeline, args, offset) in [
            (sort, &map.tiles, word_bytes(DISPATCH_SORT)),
            (sort_long, &map.tiles, word_bytes(DISPATCH_SORT_LONG)),
        ] {
            // SAFETY: outside rendering on the contract's compute queue.
            unsafe {
                memory_barrier(
                    device,
                    cmd,
                    Access::COMPUTE_RW,
                    Access::COMPUTE_RW.and(Access::INDIRECT_READ),
                )
            };
            // SAFETY: one of this pass's sort pipelines (or their specialized variants, owned by
            // `self`), alive as long as `self`.
            unsafe { pipeline.bind(device, cmd) };
            // SAFETY: every sort pipeline's layout has MapPush's push range.
            unsafe { pipeline.push(device, cmd, &constants) };
            // SAFETY: `args` is the map's tiles buffer (indirect usage) holding this sort's
            // dispatch command at `offset`, visible to indirect reads after the barrier above.
            unsafe { device.cmd_dispatch_indirect(cmd, args.raw(), offset) };
        }
        if self.outer_barriers {
            // SAFETY: outside rendering; compute and every shader stage are on the graphics and
            // compute queue.
            unsafe { record_own(device, cmd, check, "generation exit", own.exit.as_ref()) };
        }
    }
}

/// The byte offset of 32-bit word `word` (the indirect dispatches' places in `tiles`).
fn word_bytes(word: u32) -> u64 {
    u64::from(word) * 4
}
