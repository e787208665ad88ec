//! The host's barriers between two of its frame's passes, derived from what each declares:
//! the library's passes declare the host's images by view ([`Resource::ImageView`]), and a
//! view names no image for a layout transition, so every host had to map views back to its
//! images and write the transitions itself (and could silently leave one out). Here the host
//! names its images once ([`HostImage`]) and declares its own passes the same way
//! ([`PassAccesses::host_images`]).

use crate::technique::{AccessData, PassAccesses, Resource, ResourceUse};
use ash::vk;

/// One of the host's images: the view its passes (and the library's) are declared with, and
/// the image and subresources a layout transition of it covers.
#[derive(Debug, Clone, Copy)]
pub struct HostImage {
    /// The image.
    pub image: vk::Image,
    /// The view its declared uses name.
    pub view: vk::ImageView,
    /// What a transition covers (the view's subresources).
    pub range: vk::ImageSubresourceRange,
}

impl PassAccesses {
    /// A host pass's uses of `views`, each in `layout` with `access` first and last (written
    /// if `writes`): a host declares its own passes (a G-buffer's draws, a shading) with it
    /// to derive [`HostBarrier`]s between them and the library's.
    pub fn host_images(
        views: &[vk::ImageView],
        layout: vk::ImageLayout,
        access: AccessData,
        writes: bool,
    ) -> Self {
        let uses = views.iter().map(|&view| ResourceUse {
            resource: Resource::ImageView { view, layout },
            first: access,
            last: access,
            writes,
        });
        Self {
            uses: uses.collect(),
        }
    }
}

/// The barrier a host records between two passes of its own or the library's: one memory
/// dependency from every last access of the earlier pass to every first access of the later
/// one, and a layout transition of each [`HostImage`] the later pass uses in a layout the
/// earlier one did not leave it in (from `UNDEFINED`, contents discarded, when the earlier
/// pass does not name it: the first use of a frame slot's images).
#[derive(Debug, Clone, Default)]
pub struct HostBarrier {
    /// The global memory dependency.
    pub memory: vk::MemoryBarrier2<'static>,
    /// The host images' transitions.
    pub images: Vec<vk::ImageMemoryBarrier2<'static>>,
}

impl HostBarrier {
    /// From `before`'s last accesses to `after`'s first, with the transitions of `images`
    /// into the layouts `after` declares.
    pub fn between(before: &PassAccesses, after: &PassAccesses, images: &[HostImage]) -> Self {
        let (from, to) = (before.last(), after.first());
        let memory = memory(from, to);
        let layout_in = |uses: &PassAccesses, at: vk::ImageView| {
            uses.uses.iter().find_map(|u| match u.resource {
                Resource::ImageView { view, layout } if view == at => Some((layout, u.last)),
                _ => None,
            })
        };
        let transition = |u: &ResourceUse| {
            let Resource::ImageView { view, layout } = u.resource else {
                return None;
            };
            let image = images.iter().find(|i| i.view == view)?;
            let (old, src) = layout_in(before, view).unwrap_or((vk::ImageLayout::UNDEFINED, from));
            (old != layout).then(|| {
                let barrier = vk::ImageMemoryBarrier2::default().image(image.image);
                let barrier = barrier.subresource_range(image.range).old_layout(old);
                let barrier = barrier
                    .src_stage_mask(src.stages)
                    .src_access_mask(src.access);
                let barrier = barrier.new_layout(layout).dst_stage_mask(u.first.stages);
                barrier.dst_access_mask(u.first.access)
            })
        };
        let images = after.uses.iter().filter_map(transition).collect();
        Self { memory, images }
    }

    /// A memory dependency alone: `from` made available and visible to `to` (a host pass's
    /// output read back by the CPU, say).
    pub fn memory(from: AccessData, to: AccessData) -> Self {
        let (memory, images) = (memory(from, to), Vec::new());
        Self { memory, images }
    }

    /// Records the barrier (one `vkCmdPipelineBarrier2`) into `cmd`.
    ///
    /// # Safety
    /// `cmd` is recording, outside a render pass, on `device`'s queue with these stages; each
    /// image is alive and, where its transition starts from a layout, in that layout.
    pub unsafe fn record(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let memory = [self.memory];
        let dependency = vk::DependencyInfo::default().memory_barriers(&memory);
        let dependency = dependency.image_memory_barriers(&self.images);
        // SAFETY: the caller's contract.
        unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
    }
}

fn memory(from: AccessData, to: AccessData) -> vk::MemoryBarrier2<'static> {
    let barrier = vk::MemoryBarrier2::default().src_stage_mask(from.stages);
    let barrier = barrier.src_access_mask(from.access);
    barrier.dst_stage_mask(to.stages).dst_access_mask(to.access)
}
