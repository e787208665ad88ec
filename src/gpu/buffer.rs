//! Buffers that free their memory and handle exactly once, when dropped.

use super::context::{Context, Shared};
use super::retire::{Doomed, Handle};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::Allocation;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// What a buffer is for; decides usage flags and where its memory lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BufferUsage {
    /// Read and written by shaders, filled/copied by transfers; device-local.
    Storage,
    /// Read by shaders, written by the host every frame.
    Uniform,
    /// Shader-readable data written once by the host (scene geometry).
    HostToDevice,
    /// Destination of copies that the host reads back.
    Readback,
    /// Small results that shaders write (by address: rare counters) and the host reads,
    /// without a copy; host-visible.
    DeviceToHost,
}

impl BufferUsage {
    fn flags(self) -> vk::BufferUsageFlags {
        let transfer = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        match self {
            // Device-local storage may be reached through its address (fragment and range
            // buffers beyond one descriptor's range) or hold indirect dispatch arguments.
            Self::Storage => {
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | transfer
            }
            // Geometry the shaders read by address, which a host may also bind as vertex and
            // index buffers for its own passes.
            Self::HostToDevice => {
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
                    | vk::BufferUsageFlags::VERTEX_BUFFER
                    | vk::BufferUsageFlags::INDEX_BUFFER
                    | transfer
            }
            Self::Uniform => vk::BufferUsageFlags::UNIFORM_BUFFER,
            Self::Readback => vk::BufferUsageFlags::TRANSFER_DST,
            Self::DeviceToHost => {
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
                    | vk::BufferUsageFlags::TRANSFER_DST
            }
        }
    }
    fn location(self) -> MemoryLocation {
        match self {
            Self::Storage => MemoryLocation::GpuOnly,
            Self::Uniform | Self::HostToDevice => MemoryLocation::CpuToGpu,
            Self::Readback | Self::DeviceToHost => MemoryLocation::GpuToCpu,
        }
    }
}

/// Source of [`Buffer::uid`]s.
static NEXT_UID: AtomicU64 = AtomicU64::new(1);

/// A `VkBuffer` with its own allocation.
pub struct Buffer {
    uid: u64,
    shared: Arc<Shared>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    name: String,
    /// Made with SHADER_DEVICE_ADDRESS usage.
    address_usage: bool,
}

impl Buffer {
    /// Creates a buffer of `size` bytes (at least 4, so that empty inputs stay valid).
    pub fn new(ctx: &Context, name: &str, size: u64, usage: BufferUsage) -> Result<Self> {
        let size = size.max(4);
        let device = &ctx.shared.device;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage.flags())
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `size` is at least 4 and the usage flags are those of a BufferUsage, which the
        // device supports (bufferDeviceAddress is a required feature).
        let raw = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let what = || format!("{name} ({size} bytes)");
        let allocation = match ctx.allocate(name, what, requirements, usage.location(), true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer was just created and nothing has bound or used it, so it is
                // destroyed once, here.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        let bound =
            // SAFETY: the allocation was made for `raw`'s own memory requirements (size and
            // alignment, linear), so it is bound at an offset the allocator aligned, within the
            // memory block; it is bound once.
            unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) };
        let buffer = Self {
            uid: NEXT_UID.fetch_add(1, Ordering::Relaxed),
            shared: ctx.shared.clone(),
            raw,
            allocation: Some(allocation),
            size,
            name: name.to_owned(),
            address_usage: usage
                .flags()
                .contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS),
        };
        bound.vk("vkBindBufferMemory")?;
        Ok(buffer)
    }

    /// A host-visible buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &Context,
        name: &str,
        usage: BufferUsage,
        data: &[T],
    ) -> Result<Self> {
        let bytes = std::mem::size_of_val(data);
        let mut buffer = Self::new(ctx, name, bytes as u64, usage)?;
        buffer.write(data)?;
        Ok(buffer)
    }

    /// The buffer handle.
    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }

    /// Unique for the process's lifetime, unlike the handle: a driver may give a new buffer
    /// the handle value of a freed one.
    pub fn uid(&self) -> u64 {
        self.uid
    }
    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }
    /// The name it was created with (also its allocation's name in the allocator).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Whether the buffer was made with `ctx` (its device): a safe function that records a
    /// buffer into a command buffer of a context checks it first.
    pub fn is_of(&self, ctx: &Context) -> bool {
        Arc::ptr_eq(&self.shared, &ctx.shared)
    }
    /// Bytes of its memory allocation (at least [`Self::size`]: the device's requirements
    /// may round it up).
    pub fn allocated_bytes(&self) -> u64 {
        self.allocation.as_ref().map_or(0, |a| a.size())
    }

    /// Writes `data` at the start of a host-visible buffer.
    pub fn write<T: bytemuck::Pod>(&mut self, data: &[T]) -> Result<()> {
        let bytes = std::mem::size_of_val(data);
        let name = self.name.clone();
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::InvalidArgument(format!("{name} is not host-visible")))?;
        if bytes > slice.len() {
            return Err(Error::InvalidArgument(format!(
                "{name}: writing {bytes} bytes into {} bytes",
                slice.len()
            )));
        }
        slice[..bytes].copy_from_slice(bytemuck::cast_slice(data));
        Ok(())
    }

    /// Reads `count` elements from the start of a host-visible buffer. Any bytes are a valid
    /// `T` (`Pod`); for the GPU's values, the caller must have waited for the GPU and made its
    /// writes available to the host.
    ///
    /// A type some bytes are not a value of does not compile (before `Pod`, this was
    /// undefined behaviour from safe code):
    ///
    /// ```compile_fail,E0277
    /// # fn f(buffer: &motion_shadows::gpu::Buffer) {
    /// let flags = buffer.read::<bool>(4);
    /// # }
    /// ```
    pub fn read<T: bytemuck::Pod>(&self, count: usize) -> Result<Vec<T>> {
        let bytes = count * std::mem::size_of::<T>();
        let slice = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or_else(|| Error::InvalidArgument(format!("{} is not host-visible", self.name)))?;
        if bytes > slice.len() {
            return Err(Error::InvalidArgument(format!(
                "{}: reading {bytes} bytes from {} bytes",
                self.name,
                slice.len()
            )));
        }
        let mut out = vec![T::zeroed(); count];
        bytemuck::cast_slice_mut::<T, u8>(&mut out).copy_from_slice(&slice[..bytes]);
        Ok(out)
    }

    /// The buffer's device address, for shaders that reach it through a buffer reference
    /// ([`BufferUsage::Storage`], [`BufferUsage::HostToDevice`] and
    /// [`BufferUsage::DeviceToHost`] buffers have one; 0 for the others).
    pub fn device_address(&self) -> u64 {
        if self.address_usage {
            let info = vk::BufferDeviceAddressInfo::default().buffer(self.raw);
            // SAFETY: `address_usage` is set only for buffers created with SHADER_DEVICE_ADDRESS
            // usage and bound to memory (new), and the bufferDeviceAddress feature is required of
            // every context.
            unsafe { self.shared.device.get_buffer_device_address(&info) }
        } else {
            0
        }
    }

    /// Records writes of `data` at the start of the buffer (`vkCmdUpdateBuffer`, in pieces
    /// of at most 65,536 bytes). The caller puts the barriers around it.
    ///
    /// # Safety
    /// `cmd` is a command buffer of the buffer's device, recording, outside a render pass;
    /// `data`'s size is a multiple of 4 and fits the buffer, which was made with
    /// transfer-destination usage and outlives the execution of `cmd`.
    pub unsafe fn record_write<T: bytemuck::Pod>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        data: &[T],
    ) {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        debug_assert!(bytes.len() % 4 == 0 && bytes.len() as u64 <= self.size);
        for (i, piece) in bytes.chunks(65536).enumerate() {
            // SAFETY: the caller's contract: `cmd` is recording outside a render pass and the
            // buffer has transfer-destination usage; each piece is at most 65,536 bytes at a
            // 4-byte-aligned offset, within the buffer since `data` fits it (debug-asserted here,
            // the caller's promise).
            unsafe { device.cmd_update_buffer(cmd, self.raw, i as u64 * 65536, piece) };
        }
    }

    /// The debug check of declared accesses of the buffer's context.
    pub(crate) fn access_check(&self) -> &super::AccessCheck {
        &self.shared.access_check
    }

    /// The whole buffer as a descriptor range.
    pub fn descriptor(&self) -> vk::DescriptorBufferInfo {
        vk::DescriptorBufferInfo {
            buffer: self.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }
    }
}

impl Drop for Buffer {
    /// Retires the buffer: destroyed once no pending frame can use it (see
    /// [`Context::begin_frame`]).
    fn drop(&mut self) {
        self.shared.access_check.forget(self.raw);
        self.shared.retire(Doomed {
            handles: vec![Handle::Buffer(self.raw)],
            allocation: self.allocation.take(),
            name: std::mem::take(&mut self.name),
        });
    }
}
