//! What the G-buffer pass reads and writes, the one source of its entry and exit barriers
//! (layout transitions included) and of a host's: the draw list and the host's streams, read
//! by the vertex shader, and the G-buffer's six images, overwritten whole as attachments; and
//! the G-buffer's uses around the pass (sampled by compute shaders, copied by its readback),
//! in their read layouts.

use super::accesses::{PassAccesses, Resource};
use super::draws::DrawList;
use super::gbuffer::{GBuffer, GBufferPass};
use crate::gpu::{Access, Image};
use ash::vk;

/// The vertex shader's reads of the draw list and the host's streams.
const VERTEX_READ: Access = Access {
    stages: vk::PipelineStageFlags2::VERTEX_SHADER,
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};

/// An image's attachment layout and accesses while the pass draws into it.
fn attachment(image: &Image) -> (vk::ImageLayout, Access) {
    if image.aspect() == vk::ImageAspectFlags::DEPTH {
        (
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            Access::DEPTH_ATTACHMENT,
        )
    } else {
        (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            Access::COLOR_ATTACHMENT_WRITE,
        )
    }
}

impl GBufferPass {
    /// The same pass without its entry and exit barriers (its images' layout transitions):
    /// the host issues them from [`Self::accesses`], [`GBuffer::earlier_accesses`] and
    /// [`GBuffer::read_accesses`] (`Barrier::between`).
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }

    /// What [`Self::record`] of `draws` into `target` reads and writes: the draw list and the
    /// host's streams (vertex shader), and every image of `target` in its attachment layout,
    /// overwritten whole (the transition in starts from `UNDEFINED`).
    pub fn accesses(&self, draws: &DrawList, target: &GBuffer) -> PassAccesses {
        let mut a = PassAccesses::default();
        a.add(Resource::DrawStreams, VERTEX_READ, VERTEX_READ, false);
        a.buffer(
            (draws.buffer(), "draw list"),
            VERTEX_READ,
            VERTEX_READ,
            false,
        );
        for (image, name, _) in target.named_images() {
            let (layout, access) = attachment(image);
            a.image((image, name), layout, true, access, access, true);
        }
        a
    }
}

impl GBuffer {
    /// What reads the G-buffer after [`GBufferPass::record`]: compute shaders' sampled reads
    /// (the masks), each image in its read layout (depth `DEPTH_STENCIL_READ_ONLY_OPTIMAL`,
    /// the others `SHADER_READ_ONLY_OPTIMAL`): where the pass's exit barrier leaves them.
    pub fn read_accesses(&self) -> PassAccesses {
        self.uses_in_read_layouts(Access::COMPUTE_SAMPLED_READ)
    }

    /// What may have used the images since the last [`GBufferPass::record`]: the masks'
    /// sampled reads and [`Self::record_readback`]'s copies (which return the images to
    /// their read layouts): what the pass's entry barrier waits for.
    pub fn earlier_accesses(&self) -> PassAccesses {
        self.uses_in_read_layouts(Access::COMPUTE_SAMPLED_READ.and(Access::TRANSFER_READ))
    }

    fn uses_in_read_layouts(&self, reads: Access) -> PassAccesses {
        let mut a = PassAccesses::default();
        for (image, name, layout) in self.named_images() {
            a.image((image, name), layout, false, reads, reads, false);
        }
        a
    }
}
