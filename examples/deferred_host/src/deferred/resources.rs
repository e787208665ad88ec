//! Buffers and images in memory from the engine's gpu-allocator, which the library's
//! context allocates from too.

use super::*;
use motion_shadows::gpu_allocator::{MemoryLocation, vulkan as alloc};
use std::sync::{Arc, Mutex};

/// The engine's device and its allocator (with device addresses on: the library reads the
/// engine's buffers by address), shared with the library (`Context::from_raw_with_allocator`).
#[derive(Clone)]
pub struct Memory {
    pub gpu: Gpu,
    pub allocator: Arc<Mutex<alloc::Allocator>>,
}

impl Memory {
    pub fn new(gpu: &Gpu) -> Result<Memory> {
        let (instance, device, physical_device) =
            (gpu.instance.clone(), gpu.device.clone(), gpu.physical);
        let (debug_settings, allocation_sizes) = Default::default();
        let desc = alloc::AllocatorCreateDesc {
            instance,
            device,
            physical_device,
            debug_settings,
            buffer_device_address: true,
            allocation_sizes,
        };
        Ok(Memory {
            gpu: gpu.clone(),
            allocator: Arc::new(Mutex::new(alloc::Allocator::new(&desc)?)),
        })
    }
}

/// A buffer or an image with its memory; dropped (after the frames that use it), the
/// handles go, then the memory. Null handles (what was not made) are ignored.
#[derive(Default)]
struct Bound {
    memory: Option<Memory>,
    allocation: Option<alloc::Allocation>,
    buffer: vk::Buffer,
    image: vk::Image,
    view: vk::ImageView,
}

impl Bound {
    fn new(memory: &Memory) -> Self {
        let (buffer, image, view) = Default::default();
        Bound { memory: Some(memory.clone()), allocation: None, buffer, image, view }
    }

    fn allocate(
        &mut self,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
    ) -> Result<&alloc::Allocation> {
        let linear = location == MemoryLocation::CpuToGpu;
        let allocation_scheme = alloc::AllocationScheme::GpuAllocatorManaged;
        let desc = alloc::AllocationCreateDesc {
            name: "engine",
            requirements,
            location,
            linear,
            allocation_scheme,
        };
        let memory = self.memory.as_ref().ok_or("no allocator")?;
        let allocation =
            memory.allocator.lock().map_err(|_| "a poisoned allocator")?.allocate(&desc)?;
        Ok(self.allocation.insert(allocation))
    }
}

impl Drop for Bound {
    fn drop(&mut self) {
        let Some(memory) = &self.memory else { return };
        let device = &memory.gpu.device;
        // SAFETY: the engine drops its buffers and images after the frames that use them;
        // the view goes before its image, both before their memory.
        unsafe {
            device.destroy_image_view(self.view, None);
            device.destroy_image(self.image, None);
            device.destroy_buffer(self.buffer, None);
        }
        if let (Some(allocation), Ok(mut allocator)) =
            (self.allocation.take(), memory.allocator.lock())
        {
            let _ = allocator.free(allocation); // a failed free leaks until the allocator goes
        }
    }
}

/// A buffer in host-visible, coherent memory, mapped for its whole life. With
/// `SHADER_DEVICE_ADDRESS` usage, shaders and the library's streams read it by address.
pub struct HostBuffer {
    pub buffer: vk::Buffer,
    address: u64,
    bound: Bound,
}

impl HostBuffer {
    pub fn new(memory: &Memory, size: u64, usage: vk::BufferUsageFlags) -> Result<Self> {
        let (mut bound, d) = (Bound::new(memory), &memory.gpu.device);
        let info = vk::BufferCreateInfo::default().size(size.max(4)).usage(usage);
        let by_address = usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS);
        // SAFETY: `info` is a local; the memory is allocated for the buffer's requirements
        // and bound once; the address is asked only with SHADER_DEVICE_ADDRESS usage, of an
        // allocator with device addresses on. On an error `bound` destroys what was made.
        let address = unsafe {
            let buffer = d.create_buffer(&info, None)?;
            bound.buffer = buffer;
            let allocation = bound
                .allocate(d.get_buffer_memory_requirements(buffer), MemoryLocation::CpuToGpu)?;
            d.bind_buffer_memory(buffer, allocation.memory(), allocation.offset())?;
            let info = vk::BufferDeviceAddressInfo::default().buffer(buffer);
            by_address.then(|| d.get_buffer_device_address(&info)).unwrap_or(0)
        };
        Ok(HostBuffer { buffer: bound.buffer, address, bound })
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Pod>(
        memory: &Memory,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut buffer = Self::new(memory, size_of_val(data) as u64, usage)?;
        buffer.write(data)?;
        Ok(buffer)
    }

    fn mapped(&mut self) -> Result<&mut [u8]> {
        Ok(self
            .bound
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or("an unmapped buffer")?)
    }

    /// Copies `data` to the start, while no submission uses the buffer: written before
    /// `vkQueueSubmit`, coherent memory is visible to the submission without a barrier.
    pub fn write<T: Pod>(&mut self, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        self.mapped()?.get_mut(..bytes.len()).ok_or("writing past the end")?.copy_from_slice(bytes);
        Ok(())
    }

    /// Reads `count` values from the start, after a barrier to HOST_READ and the fence.
    pub fn read<T: Pod>(&mut self, count: usize) -> Result<Vec<T>> {
        let bytes = self.mapped()?.get(..count * size_of::<T>()).ok_or("reading past the end")?;
        Ok(bytemuck::pod_collect_to_vec(bytes))
    }

    /// The device address (0 without SHADER_DEVICE_ADDRESS usage).
    pub fn address(&self) -> u64 {
        self.address
    }
}

/// Layout, stages and accesses: one side of an image barrier.
pub type State = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// A 2D image in device-local memory with a view of all of it.
pub struct Image {
    pub image: vk::Image,
    pub view: vk::ImageView,
    aspect: vk::ImageAspectFlags,
    _bound: Bound,
}

impl Image {
    /// Errors if the device cannot use `format` for `usage`.
    pub fn new(
        memory: &Memory,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        (width, height): (u32, u32),
    ) -> Result<Self> {
        use vk::{FormatFeatureFlags as F, ImageUsageFlags as U};
        let uses = [
            (U::SAMPLED, F::SAMPLED_IMAGE),
            (U::STORAGE, F::STORAGE_IMAGE),
            (U::TRANSFER_SRC, F::TRANSFER_SRC),
        ];
        let uses = [
            (U::COLOR_ATTACHMENT, F::COLOR_ATTACHMENT),
            (U::DEPTH_STENCIL_ATTACHMENT, F::DEPTH_STENCIL_ATTACHMENT),
        ]
        .into_iter()
        .chain(uses);
        let needed =
            uses.filter(|(u, _)| usage.contains(*u)).fold(F::empty(), |all, (_, f)| all | f);
        let depth = format == vk::Format::D32_SFLOAT;
        let aspect = if depth { vk::ImageAspectFlags::DEPTH } else { vk::ImageAspectFlags::COLOR };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .mip_levels(1)
            .array_layers(1);
        let info = info
            .extent(vk::Extent3D { width, height, depth: 1 })
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let (mut bound, gpu) = (Bound::new(memory), &memory.gpu);
        // SAFETY: the physical device is the instance's, and supports the format for every use
        // asked (checked first); `info` is a local; the memory is allocated for the image's
        // requirements and bound once; the view has the image's format and aspect. On an
        // error `bound` destroys what was made.
        unsafe {
            let properties =
                gpu.instance.get_physical_device_format_properties(gpu.physical, format);
            if !properties.optimal_tiling_features.contains(needed) {
                return Err(format!("{format:?} cannot be {usage:?} on this device").into());
            }
            let image = gpu.device.create_image(&info, None)?;
            bound.image = image;
            let allocation = bound.allocate(
                gpu.device.get_image_memory_requirements(image),
                MemoryLocation::GpuOnly,
            )?;
            gpu.device.bind_image_memory(image, allocation.memory(), allocation.offset())?;
            let view = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format);
            bound.view =
                gpu.device.create_image_view(&view.subresource_range(range(aspect)), None)?;
        }
        Ok(Image { image: bound.image, view: bound.view, aspect, _bound: bound })
    }

    /// A layout transition of the whole image, with its memory dependency.
    pub fn barrier(
        &self,
        (old, src_stage, src_access): State,
        (new, dst_stage, dst_access): State,
    ) -> vk::ImageMemoryBarrier2<'static> {
        let barrier = vk::ImageMemoryBarrier2::default()
            .src_stage_mask(src_stage)
            .src_access_mask(src_access)
            .old_layout(old);
        let barrier = barrier.dst_stage_mask(dst_stage).dst_access_mask(dst_access).new_layout(new);
        barrier.image(self.image).subresource_range(range(self.aspect))
    }
}

fn range(aspect_mask: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange { aspect_mask, level_count: 1, layer_count: 1, ..Default::default() }
}

/// Records one `vkCmdPipelineBarrier2` of `images` and `memory` into `cmd`.
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
