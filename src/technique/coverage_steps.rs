//! The coverage map's passes 2 and 3 as declarations of their steps, whose pairs give every
//! barrier [`super::CoveragePass`] records (`Barrier::between`): the coverage and cover-depth
//! buffers as earlier frames left them (read by lookups in any stage, written by an earlier
//! frame's caps and reset), cleared by transfer, marked by the caps and the reset (fragment
//! shaders), and read after (the generation's compute shaders, lookups in any stage). The
//! nearest map the caps read is ordered after the collection's fragment writes through the
//! chain of the first two barriers (the first waits for fragment writes, the second makes
//! what it ordered visible to fragment shaders).

use super::accesses::PassAccesses;
use super::coverage::CoverageMap;
use super::declared_barriers::{Barrier, record_within};
use crate::gpu::Access;
use ash::vk;

/// One step, as the barriers between the steps see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// What may have used the buffers since the last clear: lookups of any stage, an earlier
    /// frame's caps and reset.
    Earlier,
    /// The clears, by transfer.
    Fill,
    /// The caps' and then the reset's marks (fragment shaders).
    Marks,
    /// What reads the marks after: the generation (compute) and lookups of any stage.
    Later,
}

impl Step {
    fn uses(self, coverage: &CoverageMap) -> PassAccesses {
        let (first, last, writes) = match self {
            Step::Earlier => {
                let a = Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW);
                (a, a, true)
            }
            Step::Fill => (Access::TRANSFER_WRITE, Access::TRANSFER_WRITE, true),
            Step::Marks => (Access::FRAGMENT_RW, Access::FRAGMENT_RW, true),
            Step::Later => {
                let a = Access::COMPUTE_RW.and(Access::ANY_SHADER_READ);
                (a, a, true)
            }
        };
        let mut a = PassAccesses::default();
        a.buffer((&coverage.coverage, "coverage map"), first, last, writes);
        a.buffer((&coverage.cover_depth, "cover depth"), first, last, writes);
        a
    }
}

/// Records the barrier `later` needs after `earlier`, if any.
///
/// # Safety
/// `cmd` is recording, outside rendering, on a graphics and compute queue.
pub(super) unsafe fn step_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    coverage: &CoverageMap,
    (earlier, later): (Step, Step),
) {
    if let Some(b) = Barrier::between(&earlier.uses(coverage), &later.uses(coverage)) {
        // SAFETY: the caller's contract.
        unsafe { record_within(device, cmd, &b) };
    }
}
