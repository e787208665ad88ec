//! What the engine TSM pass reads and writes, the one source of its entry barrier and of a
//! host's: the map's header (rewritten by transfer each record, read by the depth draws'
//! vertex shader and the mask's compute shader, both by device address), the draw list and
//! the host's streams (read by the vertex shader), and the host's G-buffer and output images
//! (the host's barriers, as the temporal mask's). And the declarations of the pass's own
//! steps, whose pairs give the barriers between them (the maps' layout transitions
//! included): no barrier of the pass is written out by hand.

use super::map::{EngineTsmMap, static_resting_layout};
use super::{EngineTsmPass, TsmStart};
use crate::gpu::Access;
use crate::technique::accesses::{PassAccesses, Resource, mask_image_uses};
use crate::technique::declared_barriers::{Barrier, record_within};
use crate::technique::draws::DrawList;
use crate::technique::mask::MaskInputs;
use ash::vk;

/// The header's name in declarations and in the access check's reports (its allocation's).
pub(super) const HEADER_NAME: &str = "time-dependent shadow maps' header";

/// The header's readers: the depth draws' vertex shader and the mask's compute shader.
const HEADER_READS: Access = Access {
    stages: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
            | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
    ),
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};

/// The depth draws' reads of the draw list and the host's streams.
const VERTEX_READ: Access = Access {
    stages: vk::PipelineStageFlags2::VERTEX_SHADER,
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};

/// The uses of the map's own resources: what one record must wait for from the last.
pub(super) fn map_uses(map: &EngineTsmMap) -> PassAccesses {
    let mut a = PassAccesses::default();
    a.buffer(
        (&map.header, HEADER_NAME),
        Access::TRANSFER_WRITE,
        HEADER_READS,
        true,
    );
    a
}

/// The pass's own entry barrier: after the previous record of the same map (its resources
/// are in no other hands, [`EngineTsmPass::record`]'s contract).
pub(super) fn entry_barrier(map: &EngineTsmMap) -> Option<Barrier> {
    let uses = map_uses(map);
    Barrier::between(&uses, &uses)
}

impl EngineTsmPass {
    /// The same pass without its entry barrier (the map's header, rewritten by each record,
    /// after the previous record's reads of it): the host issues it from [`Self::accesses`],
    /// `Barrier::between` the previous record's and this one's. The barriers between its own
    /// steps stay.
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }

    /// What [`Self::record`] with these arguments reads and writes: the map's header, the
    /// draw list and the host's position and index streams, and the host's images (the
    /// output read and written by the compute shader, in `GENERAL`). The images' barriers and
    /// layout transitions are always the host's (the record function's contract); the draw
    /// list's update orders itself against this pass's reads unless made
    /// [`DrawList::with_host_barriers`].
    pub fn accesses(
        &self,
        inputs: &MaskInputs,
        draws: &DrawList,
        map: &EngineTsmMap,
    ) -> PassAccesses {
        let mut a = map_uses(map);
        a.add(Resource::DrawStreams, VERTEX_READ, VERTEX_READ, false);
        a.buffer(
            (draws.buffer(), "draw list"),
            VERTEX_READ,
            VERTEX_READ,
            false,
        );
        mask_image_uses(&mut a, inputs, Access::COMPUTE_RW);
        a
    }
}

/// One of the pass's steps, as the barriers between them see it: which of the map's
/// resources it uses, in which layouts, with which accesses.
#[derive(Clone, Copy)]
pub(super) enum Step<'a> {
    /// The header written by transfer.
    HeaderWrite,
    /// The header read by the depth draws and the mask.
    HeaderReads,
    /// The static map drawn, cleared first (its contents discarded).
    StaticDraw,
    /// The static map at rest, read where its next use reads it: copied into the working
    /// layers ([`TsmStart::Copy`]) or sampled by the mask ([`TsmStart::SecondLookup`]).
    StaticReads,
    /// The working layers started (contents discarded): written by the static map's copy,
    /// or cleared by the moving draws' rendering.
    LayersStart,
    /// The moving draws into the working layers.
    MovingDraws,
    /// The working layers sampled by the mask.
    LayersRead,
    /// The mask's read-modify-write of the host's output.
    Dispatch(&'a MaskInputs),
}

impl Step<'_> {
    fn uses(self, map: &EngineTsmMap) -> PassAccesses {
        let mut a = PassAccesses::default();
        let depth = Access::DEPTH_ATTACHMENT;
        let sampled = Access::COMPUTE_SAMPLED_READ;
        let drawn = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
        let working = (&map.working, "time-dependent shadow maps' working maps");
        let static_map = (&map.static_map, "time-dependent shadow maps' static map");
        match self {
            Step::HeaderWrite => {
                let w = Access::TRANSFER_WRITE;
                a.buffer((&map.header, HEADER_NAME), w, w, true);
            }
            Step::HeaderReads => {
                let r = HEADER_READS;
                a.buffer((&map.header, HEADER_NAME), r, r, false);
            }
            Step::StaticDraw => a.image(static_map, drawn, true, depth, depth, true),
            Step::StaticReads => {
                let reads = match map.start {
                    TsmStart::SecondLookup => sampled,
                    TsmStart::Copy => Access::TRANSFER_READ,
                };
                let layout = static_resting_layout(map.start);
                a.image(static_map, layout, false, reads, reads, false);
            }
            Step::LayersStart => match map.start {
                TsmStart::Copy => {
                    let (w, layout) = (
                        Access::TRANSFER_WRITE,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    );
                    a.image(working, layout, true, w, w, true);
                }
                TsmStart::SecondLookup => a.image(working, drawn, true, depth, depth, true),
            },
            Step::MovingDraws => a.image(working, drawn, false, depth, depth, true),
            Step::LayersRead => {
                let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
                a.image(working, layout, false, sampled, sampled, false);
            }
            Step::Dispatch(inputs) => {
                let rw = Access::COMPUTE_RW;
                a.add(
                    Resource::ImageView {
                        view: inputs.output,
                        layout: vk::ImageLayout::GENERAL,
                    },
                    rw,
                    rw,
                    true,
                );
            }
        }
        a
    }
}

/// Records the barrier `later` needs after `earlier` (none if their declarations need none),
/// a barrier between the pass's own steps.
///
/// # Safety
/// `cmd` is recording, outside rendering, on a graphics and compute queue; the map's images
/// are in `earlier`'s layouts (or `later` discards them), in no other hands.
pub(super) unsafe fn step_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &EngineTsmMap,
    (earlier, later): (Step, Step),
) {
    if let Some(b) = Barrier::between(&earlier.uses(map), &later.uses(map)) {
        // SAFETY: the caller's contract.
        unsafe { record_within(device, cmd, &b) };
    }
}
