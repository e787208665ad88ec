//! Barriers derived from declared accesses: the one rule that turns "the earlier declared
//! use, then this declared use" into a global memory barrier. The passes record their own
//! entry and exit barriers with it, and a host with a render graph gets the same barriers
//! from the same declarations, so the two cannot drift.

use super::accesses::{AccessData, PassAccesses, Resource};
use super::image_transitions::ImageTransition;
use crate::gpu::{Access, AccessCheck, TrackedUse};
use ash::vk;

/// The barrier between two declared uses: a global memory barrier (`before` waits for the
/// earlier pass's last accesses, `after` holds the later pass's first; both empty when only
/// images need ordering) and the layout transitions of the library's images.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Barrier {
    /// Source stages and accesses.
    pub before: AccessData,
    /// Destination stages and accesses.
    pub after: AccessData,
    /// The library's images that change layout (or are overwritten whole) between the two
    /// uses, each with its own memory dependency (not in `before`/`after`).
    pub images: Vec<ImageTransition>,
}

impl Resource {
    /// Whether two declared resources are one: buffers by handle, images by view (the
    /// layout is each pass's own), the draw streams always.
    pub fn same_as(&self, other: &Resource) -> bool {
        match (self, other) {
            (Resource::Buffer { buffer: a, .. }, Resource::Buffer { buffer: b, .. }) => a == b,
            (Resource::DrawStreams, Resource::DrawStreams) => true,
            (Resource::ImageView { view: a, .. }, Resource::ImageView { view: b, .. }) => a == b,
            (Resource::Image { image: a, .. }, Resource::Image { image: b, .. }) => a == b,
            _ => false,
        }
    }
}

impl Barrier {
    /// The barrier `later` needs after `earlier`: for every resource both use where either
    /// writes, `earlier`'s last access joins the source and `later`'s first the
    /// destination; a library image ([`Resource::Image`]) that changes layout, or that
    /// `later` overwrites whole, gets its own transition instead. None when they share
    /// nothing that conflicts (reads after reads in one layout). The host's images
    /// ([`Resource::ImageView`]) are in the memory barrier; their layout transitions are the
    /// host's (the layouts are in the declarations).
    pub fn between(earlier: &PassAccesses, later: &PassAccesses) -> Option<Barrier> {
        let mut found: Option<(Access, Access)> = None;
        let mut images = Vec::new();
        for e in &earlier.uses {
            for l in later
                .uses
                .iter()
                .filter(|l| l.resource.same_as(&e.resource))
            {
                if let Some(transition) = ImageTransition::between(e, l) {
                    images.push(transition);
                } else if e.writes || l.writes {
                    let (before, after) = found.unwrap_or((Access::NONE, Access::NONE));
                    found = Some((before.and(e.last.into()), after.and(l.first.into())));
                }
            }
        }
        if found.is_none() && images.is_empty() {
            return None;
        }
        let (before, after) = found.unwrap_or((Access::NONE, Access::NONE));
        Some(Barrier {
            before: before.into(),
            after: after.into(),
            images,
        })
    }

    /// Records the barrier into `cmd` (one `vkCmdPipelineBarrier2`: the memory barrier, if
    /// any, and the image transitions) and reports its memory barrier to `check` (labelled
    /// `by`; the check follows buffers, synchronization validation sees the images).
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` in the recording state, outside a render pass,
    /// on a queue that supports the stages named; each transition's image is alive until
    /// `cmd` completes and is in its `old` layout when the barrier executes (the earlier
    /// declared use's, which holds when the declared passes ran in that order).
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        check: &AccessCheck,
        by: &str,
    ) {
        // SAFETY: the caller's contract.
        unsafe { record_within(device, cmd, self) };
        if Access::from(self.before) != Access::NONE {
            check.report_barrier(by, self.before.into(), self.after.into());
        }
    }
}

/// Records `barrier` without reporting it to the access check: a barrier between a pass's
/// own steps (the check follows what passes and hosts order between passes).
///
/// # Safety
/// As [`Barrier::record`].
pub(crate) unsafe fn record_within(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    barrier: &Barrier,
) {
    let global = Access::from(barrier.before) != Access::NONE;
    let memory = [vk::MemoryBarrier2::default()
        .src_stage_mask(barrier.before.stages)
        .src_access_mask(barrier.before.access)
        .dst_stage_mask(barrier.after.stages)
        .dst_access_mask(barrier.after.access)];
    let images: Vec<_> = barrier
        .images
        .iter()
        .map(ImageTransition::barrier)
        .collect();
    let dependency = vk::DependencyInfo::default()
        .memory_barriers(if global { &memory } else { &[] })
        .image_memory_barriers(&images);
    // SAFETY: the caller's contract: `cmd` is recording outside a render pass on a queue with
    // these stages; each image is alive and in its `old` layout.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
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
    barrier: Option<&Barrier>,
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

    fn image(layout: vk::ImageLayout, discards: bool) -> Resource {
        Resource::Image {
            image: vk::Image::from_raw(9),
            name: "i",
            aspect: vk::ImageAspectFlags::COLOR,
            layers: 2,
            layout,
            discards,
        }
    }

    /// A library image changing layout gets its own transition (from the earlier layout, or
    /// UNDEFINED when the later use overwrites it whole), out of the memory barrier; one
    /// read twice in one layout needs nothing; written and read in one layout, the memory
    /// barrier orders it.
    #[test]
    fn a_library_image_changing_layout_gets_a_transition_of_its_own() {
        use vk::ImageLayout as L;
        let sampled = Access::COMPUTE_SAMPLED_READ;
        let attachment = Access::COLOR_ATTACHMENT_WRITE;
        let drawn = pass(&[(
            image(L::COLOR_ATTACHMENT_OPTIMAL, true),
            attachment,
            attachment,
            true,
        )]);
        let read = pass(&[(
            image(L::SHADER_READ_ONLY_OPTIMAL, false),
            sampled,
            sampled,
            false,
        )]);
        let exit = Barrier::between(&drawn, &read).expect("a transition");
        assert_eq!(Access::from(exit.before), Access::NONE);
        assert_eq!(exit.images.len(), 1);
        let t = exit.images[0];
        assert_eq!(
            (t.old, t.new),
            (L::COLOR_ATTACHMENT_OPTIMAL, L::SHADER_READ_ONLY_OPTIMAL)
        );
        assert_eq!((t.before, t.after), (attachment.into(), sampled.into()));
        assert_eq!((t.layers, t.aspect), (2, vk::ImageAspectFlags::COLOR));
        let entry = Barrier::between(&read, &drawn).expect("a transition");
        let t = entry.images[0];
        assert_eq!((t.old, t.new), (L::UNDEFINED, L::COLOR_ATTACHMENT_OPTIMAL));
        assert_eq!((t.before, t.after), (sampled.into(), attachment.into()));
        assert_eq!(Barrier::between(&read, &read), None);
        let general = |writes| {
            let a = if writes { Access::COMPUTE_RW } else { sampled };
            pass(&[(image(L::GENERAL, false), a, a, writes)])
        };
        let same_layout = Barrier::between(&general(true), &general(false)).expect("a barrier");
        assert!(same_layout.images.is_empty());
        assert_eq!(Access::from(same_layout.before), Access::COMPUTE_RW);
    }
}
