//! Layout transitions derived from declared accesses: between two declared uses of one of
//! the library's own images ([`Resource::Image`]) in different layouts, or before a use that
//! overwrites the image whole, an image barrier carries both the layout change and the
//! image's memory dependency, so [`super::Barrier::between`] puts it there rather than in
//! the global memory barrier.

use super::accesses::{AccessData, Resource, ResourceUse};
use ash::vk;

/// One image's layout transition between two declared uses: `before` waits for the earlier
/// use's last accesses in layout `old` (UNDEFINED when the later use discards the contents),
/// `after` holds the later use's first, in layout `new`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageTransition {
    /// The image.
    pub image: vk::Image,
    /// Its name (as its allocation's).
    pub name: &'static str,
    /// Its aspect (depth or colour).
    pub aspect: vk::ImageAspectFlags,
    /// How many layers (all of them, of its only mip level).
    pub layers: u32,
    /// The layout it leaves.
    pub old: vk::ImageLayout,
    /// The layout it enters.
    pub new: vk::ImageLayout,
    /// Source stages and accesses.
    pub before: AccessData,
    /// Destination stages and accesses.
    pub after: AccessData,
}

impl ImageTransition {
    /// The transition `later` needs after `earlier`, both uses of one library image: None
    /// when they are not such uses, or when the layout stays and the later use keeps the
    /// contents (a memory barrier then orders them, if either writes).
    pub(crate) fn between(earlier: &ResourceUse, later: &ResourceUse) -> Option<Self> {
        let Resource::Image {
            image, layout: old, ..
        } = earlier.resource
        else {
            return None;
        };
        let Resource::Image {
            image: later_image,
            name,
            aspect,
            layers,
            layout: new,
            discards,
        } = later.resource
        else {
            return None;
        };
        if image != later_image || (old == new && !discards) {
            return None;
        }
        Some(Self {
            image,
            name,
            aspect,
            layers,
            old: if discards {
                vk::ImageLayout::UNDEFINED
            } else {
                old
            },
            new,
            before: earlier.last,
            after: later.first,
        })
    }

    /// The Vulkan barrier (one queue family, every layer of the only mip level).
    pub fn barrier(&self) -> vk::ImageMemoryBarrier2<'static> {
        vk::ImageMemoryBarrier2::default()
            .src_stage_mask(self.before.stages)
            .src_access_mask(self.before.access)
            .dst_stage_mask(self.after.stages)
            .dst_access_mask(self.after.access)
            .old_layout(self.old)
            .new_layout(self.new)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(self.image)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: self.aspect,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: 0,
                layer_count: self.layers,
            })
    }
}
