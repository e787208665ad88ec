//! Buffers and images with their own memory, and the barriers and checks around them.

use super::*;

// ---------------------------------------------------------------------------------------
// Engine resources: buffers and images with their own memory (a real engine suballocates
// from a few large blocks; one allocation each keeps the example short).
// ---------------------------------------------------------------------------------------

pub(super) fn memory_type(
    props: &vk::PhysicalDeviceMemoryProperties,
    bits: u32,
    flags: vk::MemoryPropertyFlags,
) -> Result<u32> {
    (0..props.memory_type_count)
        .find(|&i| {
            bits & (1 << i) != 0
                && props.memory_types[i as usize]
                    .property_flags
                    .contains(flags)
        })
        .ok_or_else(|| format!("no memory type with {flags:?}").into())
}

/// A buffer in host-visible, coherent memory, mapped for its whole life. The engine's vertex,
/// index, uniform and readback buffers. With `SHADER_DEVICE_ADDRESS` usage its device address
/// is what the library's position and index streams point at.
pub struct HostBuffer {
    pub(super) device: ash::Device,
    pub buffer: vk::Buffer,
    pub(super) memory: vk::DeviceMemory,
    pub(super) mapped: *mut u8,
    pub size: u64,
}

impl HostBuffer {
    pub fn new(host: &Host, size: u64, usage: vk::BufferUsageFlags) -> Result<Self> {
        let device = &host.device;
        let mut buffer = HostBuffer {
            device: device.clone(),
            buffer: vk::Buffer::null(),
            memory: vk::DeviceMemory::null(),
            mapped: std::ptr::null_mut(),
            size: size.max(4),
        };
        // From here on, Drop frees whatever was created.
        let info = vk::BufferCreateInfo::default()
            .size(buffer.size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `info` is a local; a host-visible buffer of the requested size and usage.
        buffer.buffer = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `buffer.buffer` was just created on this device.
        let req = unsafe { device.get_buffer_memory_requirements(buffer.buffer) };
        // SAFETY: `host.physical` is a physical device of the host's live instance.
        let props = unsafe {
            host.instance
                .get_physical_device_memory_properties(host.physical)
        };
        let index = memory_type(
            &props,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        )?;
        // Buffers reached by device address need memory allocated for it.
        let mut flags =
            vk::MemoryAllocateFlagsInfo::default().flags(vk::MemoryAllocateFlags::DEVICE_ADDRESS);
        let mut alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(index);
        if usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS) {
            alloc = alloc.push_next(&mut flags);
        }
        // SAFETY: the memory type was chosen from the buffer's requirements' type bits, of its
        // size, with the device-address flag where the usage needs it.
        buffer.memory = unsafe { device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: the memory was allocated for this buffer's requirements and is bound once, at
        // offset 0.
        unsafe { device.bind_buffer_memory(buffer.buffer, buffer.memory, 0) }
            .vk("vkBindBufferMemory")?;
        // SAFETY: the memory is host-visible (chosen so) and not mapped yet; it stays mapped until
        // it is freed.
        buffer.mapped = unsafe {
            device.map_memory(
                buffer.memory,
                0,
                vk::WHOLE_SIZE,
                vk::MemoryMapFlags::empty(),
            )
        }
        .vk("vkMapMemory")? as *mut u8;
        Ok(buffer)
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Copy>(
        host: &Host,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut buffer = Self::new(host, std::mem::size_of_val(data) as u64, usage)?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    /// Copies `data` to byte `offset`. Only while no pending submission reads the bytes: the
    /// engine writes a frame slot's buffers after waiting for that slot's fence. Host-coherent
    /// memory written before `vkQueueSubmit` is visible to the submitted work without a
    /// barrier (the submission is a host memory dependency).
    pub fn write<T: Copy>(&mut self, offset: u64, data: &[T]) -> Result<()> {
        let bytes = std::mem::size_of_val(data) as u64;
        if offset + bytes > self.size {
            return Err(format!("writing {bytes} bytes at {offset} into {}", self.size).into());
        }
        // SAFETY: in bounds of the mapping; T is plain data.
        unsafe {
            std::ptr::copy_nonoverlapping(
                data.as_ptr() as *const u8,
                self.mapped.add(offset as usize),
                bytes as usize,
            )
        };
        Ok(())
    }

    /// Reads `count` values from the start, after the GPU's writes were made available to
    /// the host (a barrier to HOST_READ) and the submission's fence was waited on.
    pub fn read<T: Copy + Default>(&self, count: usize) -> Result<Vec<T>> {
        let bytes = count * std::mem::size_of::<T>();
        if bytes as u64 > self.size {
            return Err(format!("reading {bytes} bytes from {}", self.size).into());
        }
        let mut out = vec![T::default(); count];
        // SAFETY: in bounds of the mapping; T is plain data.
        unsafe { std::ptr::copy_nonoverlapping(self.mapped, out.as_mut_ptr() as *mut u8, bytes) };
        Ok(out)
    }

    /// The buffer's device address (it must have SHADER_DEVICE_ADDRESS usage).
    pub fn address(&self) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.buffer);
        // SAFETY: every buffer the engine asks the address of was made with SHADER_DEVICE_ADDRESS
        // usage and device-address memory (this method's documented precondition).
        unsafe { self.device.get_buffer_device_address(&info) }
    }
}

impl Drop for HostBuffer {
    fn drop(&mut self) {
        // Null handles (a failed `new`) are ignored by the destroy calls; freeing the memory
        // unmaps it.
        // SAFETY: the engine drops its buffers after waiting for the frames that use them; freeing
        // the memory unmaps it; null handles of a failed `new` are ignored.
        unsafe {
            self.device.destroy_buffer(self.buffer, None);
            self.device.free_memory(self.memory, None);
        }
    }
}

/// A 2D image in device-local memory with one view.
pub struct Image {
    pub(super) device: ash::Device,
    pub image: vk::Image,
    pub(super) memory: vk::DeviceMemory,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub aspect: vk::ImageAspectFlags,
}

impl Image {
    pub fn new(
        host: &Host,
        format: vk::Format,
        size: (u32, u32),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let device = &host.device;
        let mut image = Image {
            device: device.clone(),
            image: vk::Image::null(),
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
            format,
            aspect,
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: size.0,
                height: size.1,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: Engine::new checked that the device supports the engine's attachment formats for
        // these uses (its format checks), and the storage formats are those every device with the
        // library's features writes; `info` is a local.
        image.image = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: `image.image` was just created on this device.
        let req = unsafe { device.get_image_memory_requirements(image.image) };
        // SAFETY: `host.physical` is a physical device of the host's live instance.
        let props = unsafe {
            host.instance
                .get_physical_device_memory_properties(host.physical)
        };
        let index = memory_type(
            &props,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::DEVICE_LOCAL,
        )?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(index);
        // SAFETY: the memory type was chosen from the image's requirements, device-local, of its
        // size.
        image.memory = unsafe { device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: the memory was allocated for this image's requirements and is bound once, at
        // offset 0.
        unsafe { device.bind_image_memory(image.image, image.memory, 0) }
            .vk("vkBindImageMemory")?;
        let view = vk::ImageViewCreateInfo::default()
            .image(image.image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        // SAFETY: the image is bound to memory, and the view's format and aspect are the image's
        // own.
        image.view = unsafe { device.create_image_view(&view, None) }.vk("vkCreateImageView")?;
        Ok(image)
    }

    /// A synchronization2 layout transition of the whole image.
    pub fn barrier(
        &self,
        (old, src_stage, src_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
        (new, dst_stage, dst_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
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
        // SAFETY: the engine drops its images after waiting for the frames that use them; the view
        // goes before its image, the image before its memory.
        unsafe {
            self.device.destroy_image_view(self.view, None);
            self.device.destroy_image(self.image, None);
            self.device.free_memory(self.memory, None);
        }
    }
}

pub(super) fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
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

/// The bytes of a plain-data value (push constants, uniform buffers).
pub(super) fn bytes_of<T: Copy>(value: &T) -> &[u8] {
    // SAFETY: T is plain data (repr(C) structs of f32, u32, u64 and glam vectors).
    unsafe { std::slice::from_raw_parts(value as *const T as *const u8, std::mem::size_of::<T>()) }
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
