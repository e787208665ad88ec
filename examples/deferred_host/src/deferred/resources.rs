//! Buffers and images in memory from the engine's gpu-allocator, which the library's context
//! allocates from too, and the barriers around them.

use super::*;
use motion_shadows::gpu_allocator::MemoryLocation;
use motion_shadows::gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use std::sync::{Arc, Mutex};

/// The engine's allocator, shared with the library (`Context::from_raw_with_allocator`).
pub type SharedAllocator = Arc<Mutex<Allocator>>;

/// An allocator on `gpu`'s device with device addresses on (the library reads the engine's
/// vertex and index buffers by address). Dropped after everything allocated from it.
pub fn new_allocator(gpu: &Gpu) -> Result<SharedAllocator> {
    Ok(Arc::new(Mutex::new(Allocator::new(&AllocatorCreateDesc {
        instance: gpu.instance.clone(),
        device: gpu.device.clone(),
        physical_device: gpu.physical,
        debug_settings: Default::default(),
        buffer_device_address: true,
        allocation_sizes: Default::default(),
    })?)))
}

/// A buffer or an image with its memory: dropped, the handles go, then the memory.
struct Bound {
    device: ash::Device,
    allocator: SharedAllocator,
    allocation: Option<Allocation>,
    buffer: vk::Buffer,
    image: vk::Image,
    view: vk::ImageView,
}

impl Bound {
    fn new(gpu: &Gpu, allocator: &SharedAllocator) -> Self {
        let (device, allocator) = (gpu.device.clone(), allocator.clone());
        let (buffer, image, view) = Default::default();
        Bound { device, allocator, allocation: None, buffer, image, view }
    }

    fn allocate(
        &mut self,
        requirements: vk::MemoryRequirements,
        host: bool,
    ) -> Result<&Allocation> {
        let location = if host { MemoryLocation::CpuToGpu } else { MemoryLocation::GpuOnly };
        let desc = AllocationCreateDesc {
            name: "engine",
            requirements,
            location,
            linear: host,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        };
        let mut allocator =
            self.allocator.lock().map_err(|_| "the allocator's lock is poisoned")?;
        Ok(self.allocation.insert(allocator.allocate(&desc)?))
    }
}

impl Drop for Bound {
    fn drop(&mut self) {
        // SAFETY: the engine drops its buffers and images after waiting for the frames that
        // use them; the view goes before its image, both before their memory; null handles
        // (what was not made) are ignored.
        unsafe {
            self.device.destroy_image_view(self.view, None);
            self.device.destroy_image(self.image, None);
            self.device.destroy_buffer(self.buffer, None);
        }
        if let (Some(allocation), Ok(mut allocator)) =
            (self.allocation.take(), self.allocator.lock())
        {
            // A free that fails leaks the block until the allocator goes: nothing to do here.
            let _ = allocator.free(allocation);
        }
    }
}

/// A buffer in host-visible, coherent memory, mapped for its whole life: the engine's
/// geometry, constants and readback. With `SHADER_DEVICE_ADDRESS` usage, its device address
/// is what the library's streams and the engine's shaders read it by.
pub struct HostBuffer {
    pub buffer: vk::Buffer,
    address: u64,
    bound: Bound,
}

impl HostBuffer {
    pub fn new(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut bound = Bound::new(gpu, allocator);
        let info = vk::BufferCreateInfo::default().size(size.max(4)).usage(usage);
        let d = &gpu.device;
        // SAFETY: `info` is a local; the memory is allocated for this buffer's requirements
        // and bound once; the address is asked only with SHADER_DEVICE_ADDRESS usage, of an
        // allocator with device addresses on. On an error `bound` destroys what was made.
        let address = unsafe {
            bound.buffer = d.create_buffer(&info, None)?;
            let buffer = bound.buffer;
            let memory = bound.allocate(d.get_buffer_memory_requirements(buffer), true)?;
            d.bind_buffer_memory(buffer, memory.memory(), memory.offset())?;
            let by_address = usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS);
            let address = vk::BufferDeviceAddressInfo::default().buffer(buffer);
            by_address.then(|| d.get_buffer_device_address(&address)).unwrap_or(0)
        };
        Ok(HostBuffer { buffer: bound.buffer, address, bound })
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Pod>(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut buffer = Self::new(gpu, allocator, std::mem::size_of_val(data) as u64, usage)?;
        buffer.write(data)?;
        Ok(buffer)
    }

    fn mapped(&mut self) -> Result<&mut [u8]> {
        let allocation = self.bound.allocation.as_mut();
        allocation.and_then(|a| a.mapped_slice_mut()).ok_or_else(|| "an unmapped buffer".into())
    }

    /// Copies `data` to the start, only while no pending submission uses the buffer (the
    /// engine writes a slot's buffers after its fence). Coherent memory written before
    /// `vkQueueSubmit` is visible to the submission without a barrier.
    pub fn write<T: Pod>(&mut self, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mapped = self.mapped()?.get_mut(..bytes.len()).ok_or("writing past a buffer's end")?;
        mapped.copy_from_slice(bytes);
        Ok(())
    }

    /// Reads `count` values from the start, once the GPU's writes were made visible to the
    /// host (a barrier to HOST_READ) and the submission's fence waited for.
    pub fn read<T: Pod>(&mut self, count: usize) -> Result<Vec<T>> {
        let bytes = count * std::mem::size_of::<T>();
        let mapped = self.mapped()?.get(..bytes).ok_or("reading past a buffer's end")?;
        Ok(bytemuck::pod_collect_to_vec(mapped))
    }

    /// The device address (0 without SHADER_DEVICE_ADDRESS usage).
    pub fn address(&self) -> u64 {
        self.address
    }
}

/// Layout, stages and accesses: one side of an image barrier.
pub type State = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// A 2D image in device-local memory with one view of all of it.
pub struct Image {
    pub image: vk::Image,
    pub view: vk::ImageView,
    aspect: vk::ImageAspectFlags,
    _bound: Bound,
}

impl Image {
    /// Errors if the device cannot use `format` with `usage`.
    pub fn new(
        gpu: &Gpu,
        allocator: &SharedAllocator,
        (format, usage): (vk::Format, vk::ImageUsageFlags),
        (width, height): (u32, u32),
    ) -> Result<Self> {
        use vk::{FormatFeatureFlags as F, ImageUsageFlags as U};
        let needs = [
            (U::SAMPLED, F::SAMPLED_IMAGE),
            (U::STORAGE, F::STORAGE_IMAGE),
            (U::COLOR_ATTACHMENT, F::COLOR_ATTACHMENT),
            (U::DEPTH_STENCIL_ATTACHMENT, F::DEPTH_STENCIL_ATTACHMENT),
            (U::TRANSFER_SRC, F::TRANSFER_SRC),
        ];
        let needed = needs
            .iter()
            .filter(|(u, _)| usage.contains(*u))
            .fold(F::empty(), |all, (_, f)| all | *f);
        let aspect = match format {
            vk::Format::D32_SFLOAT => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        let extent = vk::Extent3D { width, height, depth: 1 };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(extent)
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let mut bound = Bound::new(gpu, allocator);
        let d = &gpu.device;
        // SAFETY: the physical device is the instance's, and the device supports the format
        // for every use asked (checked first); `info` is a local; the memory is allocated for
        // the image's requirements and bound once; the view is of the image's own format and
        // aspect. On an error `bound` destroys what was made.
        unsafe {
            let properties =
                gpu.instance.get_physical_device_format_properties(gpu.physical, format);
            if !properties.optimal_tiling_features.contains(needed) {
                return Err(format!("{format:?} cannot be {usage:?} on this device").into());
            }
            let image = d.create_image(&info, None)?;
            bound.image = image;
            let memory = bound.allocate(d.get_image_memory_requirements(image), false)?;
            d.bind_image_memory(image, memory.memory(), memory.offset())?;
            let view = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format)
                .subresource_range(range(aspect));
            bound.view = d.create_image_view(&view, None)?;
        }
        Ok(Image { image: bound.image, view: bound.view, aspect, _bound: bound })
    }

    /// A layout transition of the whole image, with its memory dependency.
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
            .image(self.image)
            .subresource_range(range(self.aspect))
    }
}

fn range(aspect_mask: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange { aspect_mask, level_count: 1, layer_count: 1, ..Default::default() }
}

/// Records one `vkCmdPipelineBarrier2` of `images` and `memory`.
pub fn pipeline_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: &[vk::ImageMemoryBarrier2],
    memory: &[vk::MemoryBarrier2],
) {
    let dependency =
        vk::DependencyInfo::default().image_memory_barriers(images).memory_barriers(memory);
    // SAFETY: every caller passes a command buffer it is recording, outside rendering, and
    // barriers of its own images; `dependency` lives through the call.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}
