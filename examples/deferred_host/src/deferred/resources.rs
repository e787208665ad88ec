//! Buffers and images in memory from the engine's allocator (gpu-allocator, which the
//! library's context allocates from too), and the barriers around them.

use super::*;
use motion_shadows::gpu_allocator::MemoryLocation;
use motion_shadows::gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use std::sync::{Arc, Mutex};

/// The engine's allocator, shared with the library (`Context::from_raw_with_allocator`).
pub type SharedAllocator = Arc<Mutex<Allocator>>;

/// An allocator on `gpu`'s device, with device addresses on (the library reads the
/// engine's vertex buffers by address). Dropped before the device.
pub fn new_allocator(gpu: &Gpu) -> Result<SharedAllocator> {
    Ok(Arc::new(Mutex::new(Allocator::new(
        &AllocatorCreateDesc {
            instance: gpu.instance.clone(),
            device: gpu.device.clone(),
            physical_device: gpu.physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        },
    )?)))
}

fn allocate(
    allocator: &SharedAllocator,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> Result<Allocation> {
    let mut allocator = allocator
        .lock()
        .map_err(|_| "the allocator's lock is poisoned")?;
    Ok(allocator.allocate(&AllocationCreateDesc {
        name: "engine",
        requirements,
        location,
        linear,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    })?)
}

fn free(allocator: &SharedAllocator, allocation: Option<Allocation>) {
    if let (Some(allocation), Ok(mut allocator)) = (allocation, allocator.lock()) {
        // A free that fails leaks the block until the allocator goes; nothing to do here.
        let _ = allocator.free(allocation);
    }
}

/// A buffer in host-visible, coherent memory, mapped for its whole life: the engine's vertex,
/// index, uniform and readback buffers. With `SHADER_DEVICE_ADDRESS` usage its device address
/// is what the library's position and index streams point at.
pub struct HostBuffer {
    device: ash::Device,
    allocator: SharedAllocator,
    pub buffer: vk::Buffer,
    allocation: Option<Allocation>,
    pub size: u64,
}

impl HostBuffer {
    pub fn new(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let size = size.max(4);
        let info = vk::BufferCreateInfo::default().size(size).usage(usage);
        // SAFETY: `info` is a local; a buffer of the requested size and usage.
        let buffer = unsafe { gpu.device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        let mut out = HostBuffer {
            device: gpu.device.clone(),
            allocator: allocator.clone(),
            buffer,
            allocation: None,
            size,
        };
        // SAFETY: the buffer was just made on this device (Drop destroys it on an error).
        let requirements = unsafe { gpu.device.get_buffer_memory_requirements(buffer) };
        let allocation = allocate(allocator, requirements, MemoryLocation::CpuToGpu, true)?;
        // SAFETY: the allocation was made for this buffer's requirements; bound once.
        unsafe {
            (gpu.device).bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
        }
        .vk("vkBindBufferMemory")?;
        out.allocation = Some(allocation);
        Ok(out)
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Pod>(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut buffer = Self::new(gpu, allocator, std::mem::size_of_val(data) as u64, usage)?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    fn mapped(&mut self) -> Result<&mut [u8]> {
        (self.allocation.as_mut())
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| "a host buffer that is not mapped".into())
    }

    /// Copies `data` to byte `offset`. Only while no pending submission reads the bytes: the
    /// engine writes a frame slot's buffers after waiting for that slot's fence. Host-coherent
    /// memory written before `vkQueueSubmit` is visible to the submitted work without a
    /// barrier (the submission is a host memory dependency).
    pub fn write<T: Pod>(&mut self, offset: u64, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let at = offset as usize..offset as usize + bytes.len();
        let size = self.size;
        (self.mapped()?.get_mut(at))
            .ok_or_else(|| format!("writing {} bytes at {offset} into {size}", bytes.len()))?
            .copy_from_slice(bytes);
        Ok(())
    }

    /// Reads `count` values from the start, after the GPU's writes were made available to
    /// the host (a barrier to HOST_READ) and the submission's fence was waited on.
    pub fn read<T: Pod>(&mut self, count: usize) -> Result<Vec<T>> {
        let bytes = count * std::mem::size_of::<T>();
        let size = self.size;
        let mapped = (self.mapped()?.get(..bytes))
            .ok_or_else(|| format!("reading {bytes} bytes from {size}"))?;
        Ok(bytemuck::pod_collect_to_vec(mapped))
    }

    /// The buffer's device address (it must have SHADER_DEVICE_ADDRESS usage).
    pub fn address(&self) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.buffer);
        // SAFETY: every buffer the engine asks the address of was made with SHADER_DEVICE_ADDRESS
        // usage, in memory of an allocator with device addresses on.
        unsafe { self.device.get_buffer_device_address(&info) }
    }
}

impl Drop for HostBuffer {
    fn drop(&mut self) {
        // SAFETY: the engine drops its buffers after waiting for the frames that use them.
        unsafe { self.device.destroy_buffer(self.buffer, None) };
        free(&self.allocator, self.allocation.take());
    }
}

/// A 2D image in device-local memory with one view.
pub struct Image {
    device: ash::Device,
    allocator: SharedAllocator,
    pub image: vk::Image,
    allocation: Option<Allocation>,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub aspect: vk::ImageAspectFlags,
}

impl Image {
    pub fn new(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        (format, usage): (vk::Format, vk::ImageUsageFlags),
        (width, height): (u32, u32),
    ) -> Result<Self> {
        let aspect = if format == DEPTH_FORMAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        // SAFETY: Engine::new checked the device supports the attachment formats for these
        // uses, and R32 storage formats are written by every device; `info` is a local.
        let image = unsafe { gpu.device.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut out = Image {
            device: gpu.device.clone(),
            allocator: allocator.clone(),
            image,
            allocation: None,
            view: vk::ImageView::null(),
            format,
            aspect,
        };
        // SAFETY: the image was just made on this device (Drop destroys it on an error).
        let requirements = unsafe { gpu.device.get_image_memory_requirements(image) };
        let allocation = allocate(allocator, requirements, MemoryLocation::GpuOnly, false)?;
        let view = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        // SAFETY: the allocation was made for this image's requirements and is bound once; the
        // view's format and aspect are the image's own.
        unsafe {
            (gpu.device)
                .bind_image_memory(image, allocation.memory(), allocation.offset())
                .vk("vkBindImageMemory")?;
            out.allocation = Some(allocation);
            out.view = gpu
                .device
                .create_image_view(&view, None)
                .vk("vkCreateImageView")?;
        }
        Ok(out)
    }

    /// A synchronization2 layout transition of the whole image.
    pub fn barrier(
        &self,
        (old, src_stage, src_access): State,
        (new, dst_stage, dst_access): State,
    ) -> vk::ImageMemoryBarrier2<'static> {
        vk::ImageMemoryBarrier2::default()
            .src_stage_mask(src_stage)
            .src_access_mask(src_access)
            .dst_stage_mask(dst_stage)
            .dst_access_mask(dst_access)
            .old_layout(old)
            .new_layout(new)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(self.image)
            .subresource_range(range(self.aspect))
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the engine drops its images after waiting for the frames that use them; the
        // view goes before its image (null ones of a failed `new` are ignored).
        unsafe {
            self.device.destroy_image_view(self.view, None);
            self.device.destroy_image(self.image, None);
        }
        free(&self.allocator, self.allocation.take());
    }
}

pub(super) fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        level_count: 1,
        layer_count: 1,
        ..Default::default()
    }
}

pub fn pipeline_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: &[vk::ImageMemoryBarrier2],
    memory: &[vk::MemoryBarrier2],
) {
    let dependency = vk::DependencyInfo::default()
        .image_memory_barriers(images)
        .memory_barriers(memory);
    // SAFETY: every caller passes its slot's command buffer, recording outside any rendering, and
    // barriers of its own images and buffers; `dependency` lives through the call.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// Attaches the Vulkan call to an error code.
pub(super) trait VkCheck<T> {
    fn vk(self, call: &str) -> Result<T>;
}

impl<T> VkCheck<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &str) -> Result<T> {
        self.map_err(|e| format!("{call}: {e}").into())
    }
}
