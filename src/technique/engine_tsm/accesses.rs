//! What the engine TSM pass reads and writes, the one source of its entry barrier and of a
//! host's: the map's header (rewritten by transfer each record, read by the depth draws'
//! vertex shader and the mask's compute shader, both by device address), the draw list and
//! the host's streams (read by the vertex shader), and the host's G-buffer and output images
//! (the host's barriers, as the temporal mask's).

use super::EngineTsmPass;
use super::map::EngineTsmMap;
use crate::gpu::Access;
use crate::technique::accesses::{PassAccesses, Resource, mask_image_uses};
use crate::technique::declared_barriers::Barrier;
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
