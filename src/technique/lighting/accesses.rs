//! What the lighting pass reads and writes, the one source of its entry barrier and of a
//! host's: its target's buffers (the header, radiance, counters and visibility, cleared by
//! transfer at the frame's start), the draw list and the host's streams, and a temporal map's
//! lookups; the target's readback and [`LightingImageOutput`] after it. The barriers between
//! the pass's own steps (the chunks' fills, raster and shading) and its closing barrier stay
//! its own.

use super::{LightingPass, LightingTarget, ShadowSource};
use crate::gpu::Access;
use crate::technique::accesses::{PassAccesses, Resource};
use crate::technique::declared_barriers::Barrier;
use crate::technique::draws::DrawList;
use crate::technique::image_output::LightingImageOutput;
use ash::vk;

/// The shading's reads of the radiance by [`LightingImageOutput`].
const COMPUTE_READ: Access = Access {
    stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};

impl LightingPass {
    /// The same pass without its entry barrier (the target's buffers cleared after their
    /// earlier uses): the host issues it, `Barrier::between` what used the target since
    /// (the previous frame's [`Self::accesses`], [`LightingTarget::readback_accesses`],
    /// [`LightingImageOutput::accesses`]) and this frame's [`Self::accesses`]. Its closing
    /// barrier (the radiance to compute and transfer reads) and those between its steps stay.
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }

    /// What a frame of [`Self::record`] (or [`Self::record_clear`] and its chunks) reads and
    /// writes: the target's header (written by transfer, read by every stage), radiance,
    /// counters and visibility (cleared by transfer; written by the raster's geometry and
    /// fragment shaders and the shading), the draw list and the host's streams, and with
    /// [`ShadowSource::Temporal`] the map's lookups by the shading. The ordinary shadow maps
    /// of the other sources are not declared (their pass records its own barriers).
    pub fn accesses(
        &self,
        draws: &DrawList,
        shadow: ShadowSource<'_>,
        target: &LightingTarget,
    ) -> PassAccesses {
        frame_uses(draws, shadow, target)
    }
}

/// [`LightingPass::accesses`].
fn frame_uses(draws: &DrawList, shadow: ShadowSource<'_>, target: &LightingTarget) -> PassAccesses {
    let mut a = match shadow {
        ShadowSource::Temporal(map) => map.lookup_accesses(vk::PipelineStageFlags2::COMPUTE_SHADER),
        _ => PassAccesses::default(),
    };
    let read = Access::ANY_SHADER_READ;
    a.add(Resource::DrawStreams, read, read, false);
    a.buffer((draws.buffer(), "draw list"), read, read, false);
    a.and(&target_uses(target))
}

/// The frame's uses of the target's own buffers.
fn target_uses(target: &LightingTarget) -> PassAccesses {
    let mut a = PassAccesses::default();
    let (w, read) = (Access::TRANSFER_WRITE, Access::ANY_SHADER_READ);
    a.buffer((&target.header, "lighting target header"), w, read, true);
    let raster = Access::GEOMETRY_RW.and(Access::FRAGMENT_RW);
    a.buffer((&target.radiance, "radiance"), w, Access::COMPUTE_RW, true);
    a.buffer(
        (&target.counters, "lighting counters"),
        w,
        raster.and(Access::COMPUTE_RW),
        true,
    );
    a.buffer(
        (&target.visibility, "visibility"),
        w,
        Access::COMPUTE_RW,
        true,
    );
    a
}

/// The pass's own entry barrier: after what may have used the target since its last frame
/// (that frame, its readback, a copy into a host image). The draw list and the map are only
/// read: they add nothing to it.
pub(super) fn entry_barrier(target: &LightingTarget) -> Option<Barrier> {
    let this = target_uses(target);
    let earlier = this
        .clone()
        .and(&target.readback_accesses())
        .and(&radiance_read(target));
    Barrier::between(&earlier, &this)
}

/// Declares a frame of the pass to the access check (from [`LightingPass::record`], after
/// the entry barrier).
pub(super) fn declare_frame(draws: &DrawList, shadow: ShadowSource<'_>, target: &LightingTarget) {
    frame_uses(draws, shadow, target).declare_run(target.header.access_check(), "lighting");
}

fn radiance_read(target: &LightingTarget) -> PassAccesses {
    let mut a = PassAccesses::default();
    a.buffer(
        (&target.radiance, "radiance"),
        COMPUTE_READ,
        COMPUTE_READ,
        false,
    );
    a
}

impl LightingTarget {
    /// What [`Self::record_readback`] reads and writes: the radiance and the counters by
    /// transfer, into the target's readback buffers.
    pub fn readback_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let (r, w) = (Access::TRANSFER_READ, Access::TRANSFER_WRITE);
        a.buffer((&self.radiance, "radiance"), r, r, false);
        a.buffer((&self.counters, "lighting counters"), r, r, false);
        a.buffer((self.readback(), "radiance readback"), w, w, true);
        a.buffer(
            (self.counters_readback(), "lighting counters readback"),
            w,
            w,
            true,
        );
        a
    }
}

impl LightingImageOutput {
    /// What [`Self::record`] of `target` into `image` reads and writes: the radiance (the
    /// compute shader's storage reads, after the lighting pass's closing barrier) and the
    /// host's image (storage writes, in `GENERAL`; its barriers are the host's).
    pub fn accesses(&self, target: &LightingTarget, image: vk::ImageView) -> PassAccesses {
        let mut a = radiance_read(target);
        let write = Access {
            stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_WRITE,
        };
        let image = Resource::ImageView {
            view: image,
            layout: vk::ImageLayout::GENERAL,
        };
        a.add(image, write, write, true);
        a
    }
}
