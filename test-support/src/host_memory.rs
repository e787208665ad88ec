//! Buffers and images of the tests' host (the probes' queries and results, a lighting
//! target), in memory from an allocator of its own on the host's device: what a host engine
//! writes for its own resources, here without a library context.

use ash::vk;
use bytemuck::Pod;
use motion_shadows::gpu_allocator::{MemoryLocation, vulkan as alloc};
use motion_shadows_deferred_host::gpu::Gpu;
use std::sync::{Arc, Mutex};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error + Send + Sync>>;

/// The host's device and an allocator on it (device addresses on: shaders read the buffers
/// by address).
#[derive(Clone)]
pub struct Memory {
    pub gpu: Gpu,
    pub allocator: Arc<Mutex<alloc::Allocator>>,
}

impl Memory {
    pub fn new(gpu: &Gpu) -> Result<Memory> {
        let (instance, device, physical_device) = (&gpu.instance, &gpu.device, gpu.physical);
        let (instance, device, buffer_device_address) = (instance.clone(), device.clone(), true);
        let (debug_settings, allocation_sizes) = Default::default();
        let desc = alloc::AllocatorCreateDesc {
            instance,
            device,
            physical_device,
            debug_settings,
            buffer_device_address,
            allocation_sizes,
        };
        let allocator = Arc::new(Mutex::new(alloc::Allocator::new(&desc)?));
        Ok(Memory {
            gpu: gpu.clone(),
            allocator,
        })
    }
}

/// A buffer or an image with its memory; dropped (after the frames that use it), the
/// handles go, then the memory. Null handles (what was not made) are ignored.
struct Bound {
    memory: Memory,
    allocation: Option<alloc::Allocation>,
    handles: (vk::Buffer, vk::Image, vk::ImageView),
}

impl Bound {
    fn allocate(&mut self, requirements: vk::MemoryRequirements) -> Result<&alloc::Allocation> {
        let host = self.handles.1 == vk::Image::null(); // buffers are mapped, images local
        let location = if host {
            MemoryLocation::CpuToGpu
        } else {
            MemoryLocation::GpuOnly
        };
        let scheme = alloc::AllocationScheme::GpuAllocatorManaged;
        let desc = alloc::AllocationCreateDesc {
            name: "engine",
            requirements,
            location,
            linear: host,
            allocation_scheme: scheme,
        };
        let mut allocator = self
            .memory
            .allocator
            .lock()
            .map_err(|_| "a poisoned allocator")?;
        Ok(self.allocation.insert(allocator.allocate(&desc)?))
    }
}

impl Drop for Bound {
    fn drop(&mut self) {
        let (device, (buffer, image, view)) = (&self.memory.gpu.device, self.handles);
        // SAFETY: the tests drop their buffers and images after the frames that use them;
        // the view goes before its image, both before their memory.
        unsafe {
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            device.destroy_buffer(buffer, None);
        }
        let allocation = self.allocation.take();
        if let (Some(allocation), Ok(mut allocator)) = (allocation, self.memory.allocator.lock()) {
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
        let mut bound = Bound {
            memory: memory.clone(),
            allocation: None,
            handles: <_>::default(),
        };
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage);
        let (d, by_address) = (
            &memory.gpu.device,
            vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        );
        // SAFETY: `info` is a local; the memory is allocated for the buffer's requirements
        // and bound once; the address is asked only with SHADER_DEVICE_ADDRESS usage, of an
        // allocator with device addresses on. On an error `bound` destroys what was made.
        let (buffer, address) = unsafe {
            let buffer = d.create_buffer(&info, None)?;
            bound.handles.0 = buffer;
            let allocation = bound.allocate(d.get_buffer_memory_requirements(buffer))?;
            d.bind_buffer_memory(buffer, allocation.memory(), allocation.offset())?;
            let info = vk::BufferDeviceAddressInfo::default().buffer(buffer);
            (
                buffer,
                usage
                    .contains(by_address)
                    .then(|| d.get_buffer_device_address(&info)),
            )
        };
        Ok(HostBuffer {
            buffer,
            address: address.unwrap_or(0),
            bound,
        })
    }

    fn mapped(&mut self) -> Result<&mut [u8]> {
        let allocation = self.bound.allocation.as_mut();
        Ok(allocation
            .and_then(|a| a.mapped_slice_mut())
            .ok_or("unmapped")?)
    }

    /// Copies `data` to the start, while no submission uses the buffer: written before
    /// `vkQueueSubmit`, coherent memory is visible to the submission without a barrier.
    pub fn write<T: Pod>(&mut self, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        self.mapped()?
            .get_mut(..bytes.len())
            .ok_or("past the end")?
            .copy_from_slice(bytes);
        Ok(())
    }

    /// Reads `count` values from the start, after a barrier to HOST_READ and the fence.
    pub fn read<T: Pod>(&mut self, count: usize) -> Result<Vec<T>> {
        let bytes = self
            .mapped()?
            .get(..count * size_of::<T>())
            .ok_or("past the end")?;
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
    range: vk::ImageSubresourceRange,
    _bound: Bound,
}

impl Image {
    /// Errors if the device cannot use `format` with `features` (what `usage` needs).
    pub fn new(
        memory: &Memory,
        format: vk::Format,
        usage: Usage,
        size: (u32, u32),
    ) -> Result<Self> {
        let ((usage, features), (width, height)) = (usage, size);
        let depth = format == vk::Format::D32_SFLOAT;
        let aspect = if depth {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let range = vk::ImageSubresourceRange::default().aspect_mask(aspect);
        let range = range.level_count(1).layer_count(1);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format);
        let info = info
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1);
        let info = info
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let view = vk::ImageViewCreateInfo::default().view_type(vk::ImageViewType::TYPE_2D);
        let view = view.format(format).subresource_range(range);
        let mut bound = Bound {
            memory: memory.clone(),
            allocation: None,
            handles: <_>::default(),
        };
        let gpu = &memory.gpu;
        // SAFETY: the physical device is the instance's and supports the format for `usage`
        // (checked first); `info` is a local; the memory is allocated for the image's
        // requirements and bound once; the view has the image's format and aspect. On an
        // error `bound` destroys what was made.
        unsafe {
            let properties = gpu
                .instance
                .get_physical_device_format_properties(gpu.physical, format);
            if !properties.optimal_tiling_features.contains(features) {
                return Err(format!("{format:?} cannot be {usage:?} on this device").into());
            }
            let image = gpu.device.create_image(&info, None)?;
            bound.handles.1 = image;
            let allocation = bound.allocate(gpu.device.get_image_memory_requirements(image))?;
            gpu.device
                .bind_image_memory(image, allocation.memory(), allocation.offset())?;
            bound.handles.2 = gpu.device.create_image_view(&view.image(image), None)?;
        }
        Ok(Image {
            image: bound.handles.1,
            view: bound.handles.2,
            range,
            _bound: bound,
        })
    }

    /// A layout transition of the whole image, with its memory dependency.
    pub fn barrier(&self, from: State, to: State) -> vk::ImageMemoryBarrier2<'static> {
        let barrier = vk::ImageMemoryBarrier2::default()
            .image(self.image)
            .old_layout(from.0);
        let barrier = barrier
            .src_stage_mask(from.1)
            .src_access_mask(from.2)
            .new_layout(to.0);
        let barrier = barrier.dst_stage_mask(to.1).dst_access_mask(to.2);
        barrier.subresource_range(self.range)
    }
}

/// An image's usage and the format features it needs.
pub type Usage = (vk::ImageUsageFlags, vk::FormatFeatureFlags);

/// Records one `vkCmdPipelineBarrier2` of `images` and `memory` into `cmd`.
pub fn pipeline_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: &[vk::ImageMemoryBarrier2],
    memory: &[vk::MemoryBarrier2],
) {
    let dependency = vk::DependencyInfo::default().image_memory_barriers(images);
    // SAFETY: every caller passes a command buffer it is recording, outside rendering, and
    // barriers of its own images; `dependency` lives through the call.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency.memory_barriers(memory)) };
}
