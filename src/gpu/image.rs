//! Device-local 2D array images that free their memory, handle and views when dropped: the
//! attachments of depth-tested passes.

use super::context::{Context, Shared};
use super::retire::{Doomed, Handle};
use crate::error::{Result, VkContext};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::Allocation;
use std::sync::Arc;

/// A 2D array image with one view per layer (for rendering into a layer).
pub struct Image {
    shared: Arc<Shared>,
    raw: vk::Image,
    allocation: Option<Allocation>,
    layer_views: Vec<vk::ImageView>,
    format: vk::Format,
    aspect: vk::ImageAspectFlags,
    width: u32,
    height: u32,
    layers: u32,
}

impl Image {
    /// `layers` layers of `width` x `height` texels of `format` (a depth format gets the depth
    /// aspect, any other the colour aspect), for `usage`.
    pub fn new(
        ctx: &Context,
        name: &str,
        (width, height, layers): (u32, u32, u32),
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        let aspect = match format {
            vk::Format::D32_SFLOAT | vk::Format::D16_UNORM | vk::Format::X8_D24_UNORM_PACK32 => {
                vk::ImageAspectFlags::DEPTH
            }
            _ => vk::ImageAspectFlags::COLOR,
        };
        if !ctx.image_supported(format, usage, (width, height, layers)) {
            return Err(crate::Error::InvalidArgument(format!(
                "{name}: the device cannot make a {width}x{height}x{layers} {format:?} image for {usage:?}"
            )));
        }
        let device = &ctx.shared.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(layers)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: the format, usage, size and layer count were checked against
        // vkGetPhysicalDeviceImageFormatProperties above (image_supported); `info` is a local alive
        // for the call.
        let raw = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut image = Self {
            shared: ctx.shared.clone(),
            raw,
            allocation: None,
            layer_views: Vec::new(),
            format,
            aspect,
            width,
            height,
            layers,
        };
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let what = || format!("{name} ({width}x{height}x{layers} {format:?})");
        let allocation = ctx.allocate(name, what, requirements, MemoryLocation::GpuOnly, false)?;
        // SAFETY: the allocation was made for `raw`'s requirements (GPU-only, optimal tiling:
        // linear false, so the allocator keeps it off linear resources' granularity pages), and the
        // image is bound once; if binding fails, `image` (holding the allocation) is dropped and
        // frees both.
        let bound =
            unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) };
        image.allocation = Some(allocation);
        bound.vk("vkBindImageMemory")?;
        for layer in 0..layers {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format)
                .subresource_range(image.layers_range(layer, 1));
            let view =
                // SAFETY: the image is bound to memory (checked just above), of this format, and
                // `layer` < the image's layer count, so the view's subresource range lies within
                // it.
                unsafe { device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
            image.layer_views.push(view);
        }
        Ok(image)
    }

    /// Bytes of its memory allocation.
    pub fn allocated_bytes(&self) -> u64 {
        self.allocation.as_ref().map_or(0, |a| a.size())
    }

    /// The image handle.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }
    /// A 2D view of `layer`.
    pub fn layer_view(&self, layer: u32) -> vk::ImageView {
        self.layer_views[layer as usize]
    }
    /// Its format.
    pub fn format(&self) -> vk::Format {
        self.format
    }
    /// Depth or colour.
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        self.aspect
    }
    /// Texels along x and y, and layers.
    pub fn size(&self) -> (u32, u32, u32) {
        (self.width, self.height, self.layers)
    }
    /// Layers `first..first + count` of the only mip level.
    pub fn layers_range(&self, first: u32, count: u32) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: first,
            layer_count: count,
        }
    }

    /// Records a copy of every layer, tightly packed layer after layer, to `buffer` at
    /// `offset`. The image must be in `TRANSFER_SRC_OPTIMAL`; the caller puts the barriers
    /// around it.
    ///
    /// # Safety
    /// `cmd` is recording, outside rendering; `buffer` was made with transfer-destination
    /// usage and holds `offset` + width x height x layers texels.
    pub unsafe fn record_copy_to_buffer(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        buffer: vk::Buffer,
        offset: u64,
    ) {
        let region = [vk::BufferImageCopy {
            buffer_offset: offset,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: self.aspect,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: self.layers,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.width,
                height: self.height,
                depth: 1,
            },
        }];
        // SAFETY: the caller's contract: `cmd` is recording outside rendering, the image is in
        // TRANSFER_SRC_OPTIMAL, and `buffer` has transfer-destination usage and room for `offset` +
        // every layer's texels, which is exactly what the region copies.
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                self.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                &region,
            )
        };
    }
}

impl Drop for Image {
    /// Retires the image and its views: destroyed once no pending frame can use them.
    fn drop(&mut self) {
        let mut handles: Vec<Handle> = self.layer_views.drain(..).map(Handle::ImageView).collect();
        handles.push(Handle::Image(self.raw));
        self.shared.retire(Doomed {
            handles,
            allocation: self.allocation.take(),
            name: "image".into(),
        });
    }
}
