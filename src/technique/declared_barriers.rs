//! Barriers derived from declared accesses: the one rule that turns "the earlier declared
//! use, then this declared use" into a global memory barrier. The passes record their own
//! entry and exit barriers with it, and a host with a render graph gets the same barriers
//! from the same declarations, so the two cannot drift.

use super::accesses::{AccessData, PassAccesses, Resource};
use crate::gpu::{Access, AccessCheck, TrackedUse, memory_barrier};
use ash::vk;

/// A global memory barrier between two declared uses: `before` waits for the earlier
/// pass's last accesses, `after` holds the later pass's first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Barrier {
    /// Source stages and accesses.
    pub before: AccessData,
    /// Destination stages and accesses.
    pub after: AccessData,
}

impl Resource {
    /// Whether two declared resources are one: buffers by handle, images by view (the
    /// layout is each pass's own), the draw streams always.
    pub fn same_as(&self, other: &Resource) -> bool {
        match (self, other) {
            (Resource::Buffer { buffer: a, .. }, Resource::Buffer { buffer: b, .. }) => a == b,
            (Resource::DrawStreams, Resource::DrawStreams) => true,
            (Resource::ImageView { view: a, .. }, Resource::ImageView { view: b, .. }) => a == b,
            _ => false,
        }
    }
}

impl Barrier {
    /// The barrier `later` needs after `earlier`: for every resource both use where either
    /// writes, `earlier`'s last access joins the source and `later`'s first the
    /// destination. None when they share nothing that conflicts (reads after reads).
    /// Images changing layout need an image barrier of the host's on top (the layouts are
    /// in [`Resource::ImageView`]).
    pub fn between(earlier: &PassAccesses, later: &PassAccesses) -> Option<Barrier> {
        let mut found: Option<(Access, Access)> = None;
        for e in &earlier.uses {
            for l in later
                .uses
                .iter()
                .filter(|l| l.resource.same_as(&e.resource) && (e.writes || l.writes))
            {
                let (before, after) = found.unwrap_or((Access::NONE, Access::NONE));
                found = Some((before.and(e.last.into()), after.and(l.first.into())));
            }
        }
        found.map(|(before, after)| Barrier {
            before: before.into(),
            after: after.into(),
        })
    }

    /// Records the barrier into `cmd` and reports it to `check` (labelled `by`).
    ///
    /// # Safety
    /// As [`memory_barrier`]: `cmd` is a command buffer of `device` in the recording state,
    /// outside a render pass, on a queue that supports the stages named.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        check: &AccessCheck,
        by: &str,
    ) {
        // SAFETY: the caller's contract.
        unsafe { memory_barrier(device, cmd, self.before.into(), self.after.into()) };
        check.report_barrier(by, self.before.into(), self.after.into());
    }
}

/// Records `barrier` (if any) as a pass's own entry or exit barrier, reported as `by`.
///
/// # Safety
/// As [`Barrier::record`].
pub(crate) unsafe fn record_own(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    check: &AccessCheck,
    by: &str,
    barrier: Option<Barrier>,
) {
    if let Some(b) = barrier {
        // SAFETY: the caller's contract.
        unsafe { b.record(device, cmd, check, by) };
    }
}

impl PassAccesses {
    /// Both passes' uses as one (a resource used by both: its accesses joined): what may
    /// come before (or after) a pass when several passes may.
    pub fn and(mut self, other: &PassAccesses) -> Self {
        for u in &other.uses {
            match self
                .uses
                .iter_mut()
                .find(|s| s.resource.same_as(&u.resource))
            {
                Some(s) => {
                    let join = |a: AccessData, b: AccessData| -> AccessData {
                        Access::from(a).and(b.into()).into()
                    };
                    s.first = join(s.first, u.first);
                    s.last = join(s.last, u.last);
                    s.writes |= u.writes;
                }
                None => self.uses.push(*u),
            }
        }
        self
    }

    /// Declares to `check` that a pass (named `pass`) runs now with these uses: the
    /// library's passes call it from their record functions; a host calls it for its own
    /// shaders that read the map ([`super::TemporalShadowMap::lookup_accesses`]). The
    /// library's buffers are checked; the host's images and draw streams are not tracked.
    pub fn declare_run(&self, check: &AccessCheck, pass: &str) {
        if !check.is_enabled() {
            return;
        }
        let uses: Vec<TrackedUse> = self
            .uses
            .iter()
            .filter_map(|u| match u.resource {
                Resource::Buffer { buffer, name } => Some(TrackedUse {
                    buffer,
                    name,
                    first: u.first.into(),
                    last: u.last.into(),
                    writes: u.writes,
                }),
                _ => None,
            })
            .collect();
        check.pass_runs(pass, &uses);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::accesses::ResourceUse;
    use ash::vk::Handle;

    fn buffer(n: u64) -> Resource {
        Resource::Buffer {
            buffer: vk::Buffer::from_raw(n),
            name: "b",
        }
    }

    fn pass(uses: &[(Resource, Access, Access, bool)]) -> PassAccesses {
        PassAccesses {
            uses: uses
                .iter()
                .map(|&(resource, first, last, writes)| ResourceUse {
                    resource,
                    first: first.into(),
                    last: last.into(),
                    writes,
                })
                .collect(),
        }
    }

    #[test]
    fn the_barrier_joins_only_the_resources_that_conflict() {
        let read = Access::ANY_SHADER_READ;
        let earlier = pass(&[
            (buffer(1), Access::TRANSFER_WRITE, Access::FRAGMENT_RW, true),
            (buffer(2), read, read, false),
            (
                buffer(3),
                Access::TRANSFER_READ,
                Access::TRANSFER_READ,
                false,
            ),
        ]);
        let later = pass(&[
            (buffer(1), Access::COMPUTE_RW, Access::COMPUTE_RW, true),
            // Read after read: nothing to order.
            (
                buffer(2),
                Access::INDIRECT_READ,
                Access::INDIRECT_READ,
                false,
            ),
            // Write after read: the read's stages, before the write.
            (
                buffer(3),
                Access::TRANSFER_WRITE,
                Access::TRANSFER_WRITE,
                true,
            ),
            (buffer(4), Access::HOST_READ, Access::HOST_READ, false),
        ]);
        let b = Barrier::between(&earlier, &later).expect("conflicts");
        let before: Access = b.before.into();
        let after: Access = b.after.into();
        assert_eq!(before, Access::FRAGMENT_RW.and(Access::TRANSFER_READ));
        assert_eq!(after, Access::COMPUTE_RW.and(Access::TRANSFER_WRITE));
        assert_eq!(
            Barrier::between(&earlier, &pass(&[(buffer(2), read, read, false)])),
            None
        );
    }
}
