//! The ordinary shadow maps' steps as declarations, whose pairs give every barrier
//! [`super::PlainShadowPass`] records (`Barrier::between`, the attachments' layout
//! transitions included): the header written by transfer and read by shaders, the
//! attachments drawn (their contents discarded) and copied out, and the planes' buffers the
//! copy writes and the lookups read.

use super::accesses::PassAccesses;
use super::declared_barriers::{Barrier, record_within};
use super::plain_shadow::PlainShadowMap;
use crate::gpu::Access;
use ash::vk;

/// One step of the pass, as the barriers between the steps see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// The header written by transfer.
    HeaderWrite,
    /// The header read by shaders of any stage (the map's draws and its lookups).
    HeaderReads,
    /// The attachments drawn, cleared first (their contents discarded).
    Draw,
    /// The attachments copied into the planes' buffers.
    CopyOut,
    /// The planes' buffers read by shaders of any stage (the lookups).
    PlanesRead,
}

impl Step {
    fn uses(self, map: &PlainShadowMap) -> PassAccesses {
        let mut a = PassAccesses::default();
        let (read, write) = (Access::ANY_SHADER_READ, Access::TRANSFER_WRITE);
        let header = (&map.header, "ordinary shadow map header");
        match self {
            Step::HeaderWrite => a.buffer(header, write, write, true),
            Step::HeaderReads => a.buffer(header, read, read, false),
            Step::Draw => {
                for (image, name) in map.named_attachments() {
                    let (layout, access) = super::plain_shadow::attachment_state(image);
                    a.image((image, name), layout, true, access, access, true);
                }
            }
            Step::CopyOut => {
                for (image, name) in map.named_attachments() {
                    let (layout, r) =
                        (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, Access::TRANSFER_READ);
                    a.image((image, name), layout, false, r, r, false);
                }
                for plane in map.named_planes() {
                    a.buffer(plane, write, write, true);
                }
            }
            Step::PlanesRead => {
                for plane in map.named_planes() {
                    a.buffer(plane, read, read, false);
                }
            }
        }
        a
    }
}

/// Records the barrier the steps `later` need after the steps `earlier` (each side's
/// declarations joined), if any.
///
/// # Safety
/// `cmd` is recording, outside rendering, on a graphics and compute queue; the map's
/// attachments are in `earlier`'s layouts (or `later` discards them), in no other hands.
pub(super) unsafe fn step_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &PlainShadowMap,
    earlier: &[Step],
    later: &[Step],
) {
    let join = |steps: &[Step]| {
        steps
            .iter()
            .fold(PassAccesses::default(), |a, s| a.and(&s.uses(map)))
    };
    if let Some(b) = Barrier::between(&join(earlier), &join(later)) {
        // SAFETY: the caller's contract.
        unsafe { record_within(device, cmd, &b) };
    }
}
