//! The Vulkan context: instance, device, one queue and a gpu-allocator. Made headless
//! (`headless.rs`) or around a host's handles (`host.rs`); what it knows about the device is
//! `device_info.rs`, what its objects hold on to `shared.rs`.

mod device_info;
mod headless;
mod host;
mod shared;

pub use device_info::DeviceInfo;
pub use headless::ContextOptions;
pub(crate) use shared::Shared;

use super::debug::MessageSink;
use super::requirements::DeviceFeatures;
use super::retire::Retirement;
use crate::error::{Error, Result, VkContext};
use ash::vk;
use device_info::device_info;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use shared::Owned;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

/// A device, a queue and an allocator. Either created headless ([`Context::headless`]) or
/// wrapped around a host engine's handles ([`Context::from_raw`]).
pub struct Context {
    pub(crate) shared: Arc<Shared>,
    /// For format queries (the caller keeps it alive: `from_raw`'s contract).
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    /// Held while a [`super::OneShot`] allocates, records, submits and waits, or frees: the
    /// command pool and the queue need external synchronization, and the context may be
    /// shared between threads.
    /// The command pool, made by the first OneShot (a host that records only into its own
    /// command buffers gets none).
    one_shot: Mutex<vk::CommandPool>,
    queue: vk::Queue,
    queue_family: u32,
    info: DeviceInfo,
    messages: MessageSink,
}

/// A gpu-allocator of the library's own on `device`.
pub(crate) fn new_allocator(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    device: &ash::Device,
) -> Result<Arc<Mutex<Allocator>>> {
    let allocator = Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device: physical,
        debug_settings: Default::default(),
        buffer_device_address: true,
        allocation_sizes: Default::default(),
    })
    .map_err(|source| Error::Allocation {
        what: "the allocator".into(),
        source,
    })?;
    Ok(Arc::new(Mutex::new(allocator)))
}

impl Context {
    #[allow(clippy::too_many_arguments)]
    unsafe fn assemble(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: ash::Device,
        queue_family: u32,
        queue: vk::Queue,
        enabled: &DeviceFeatures,
        allocator: Arc<Mutex<Allocator>>,
        owned: Option<Owned>,
        messages: MessageSink,
    ) -> Result<Self> {
        let info = device_info(instance, physical, queue_family, enabled);
        let host = owned.is_none();
        let shared = Arc::new(Shared {
            device,
            max_push_constants_size: info.max_push_constants_size,
            allocator: ManuallyDrop::new(allocator),
            retirement: Retirement::new(host),
            access_check: Default::default(),
            owned,
        });
        Ok(Self {
            shared,
            instance: instance.clone(),
            physical,
            one_shot: Mutex::new(vk::CommandPool::null()),
            queue,
            queue_family,
            info,
            messages,
        })
    }

    /// The debug check of declared accesses ([`super::AccessCheck`]): off until enabled;
    /// a host that records the passes' barriers itself reports them here.
    pub fn access_check(&self) -> &super::AccessCheck {
        &self.shared.access_check
    }

    /// The device.
    pub fn device(&self) -> &ash::Device {
        &self.shared.device
    }
    /// The physical device.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical
    }
    /// The queue [`super::OneShot`] submits to.
    pub fn queue(&self) -> vk::Queue {
        self.queue
    }
    /// The queue's family.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }
    /// What the library knows about the device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }
    /// The command pool of [`super::OneShot`] (made now if this is the first), locked: the
    /// pool and the queue need external synchronization.
    pub(crate) fn one_shot_lock(&self) -> Result<std::sync::MutexGuard<'_, vk::CommandPool>> {
        let mut pool = self.one_shot.lock().unwrap_or_else(|e| e.into_inner());
        if *pool == vk::CommandPool::null() {
            let info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(self.queue_family)
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
            // SAFETY: `self.queue_family` is the family the device was created with a queue of, and
            // the pool is made once under the lock; it is destroyed in Context::drop.
            *pool = unsafe { self.shared.device.create_command_pool(&info, None) }
                .vk("vkCreateCommandPool")?;
        }
        Ok(pool)
    }

    /// Whether a 2D optimal-tiling image of `format` with `usage` and `layers` layers of
    /// `width` x `height` can be made on this device.
    pub(crate) fn image_supported(
        &self,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        (width, height, layers): (u32, u32, u32),
    ) -> bool {
        // SAFETY: `physical` is of `instance`, which outlives the context.
        let properties = unsafe {
            self.instance.get_physical_device_image_format_properties(
                self.physical,
                format,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                usage,
                vk::ImageCreateFlags::empty(),
            )
        };
        properties.is_ok_and(|p| {
            width > 0
                && height > 0
                && layers > 0
                && width <= p.max_extent.width
                && height <= p.max_extent.height
                && layers <= p.max_array_layers
        })
    }

    /// Optimal-tiling features of any format.
    pub(crate) fn format_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        // SAFETY: as above.
        unsafe {
            self.instance
                .get_physical_device_format_properties(self.physical, format)
        }
        .optimal_tiling_features
    }

    /// Tells the context that the host now records frame `frame` (numbers that never
    /// decrease; a smaller one is taken as the largest so far). Every object of this context
    /// dropped from now on, whose handles that frame's commands may use, waits until
    /// [`Self::collect`] is told that `frame` completed. A host's context
    /// ([`Self::from_raw`]) always retires dropped objects this way, frame 0 until the first
    /// call; a headless one only after the first call (before it, its objects go at once
    /// when no [`super::OneShot`] runs: that is the only work it submits, and it waits).
    pub fn begin_frame(&self, frame: u64) {
        self.shared.retirement().begin_frame(frame);
    }

    /// Destroys every object dropped while the host recorded frames up to `completed` (see
    /// [`Self::begin_frame`]); returns how many. Call it once `completed`'s fence has
    /// signalled: on one queue that frame and every earlier one have completed.
    ///
    /// # Safety
    /// Every submission recorded while the host recorded frames `<= completed` (and before
    /// its first [`Self::begin_frame`]) has completed execution.
    pub unsafe fn collect(&self, completed: u64) -> usize {
        // SAFETY: the caller's contract.
        unsafe { self.shared.collect(Some(completed)) }
    }

    /// The latest frame [`Self::collect`] was told completed (None before the first call).
    pub(crate) fn completed_frame(&self) -> Option<u64> {
        self.shared.retirement().completed()
    }

    /// Objects dropped whose frame has not been collected yet ([`Self::collect`]).
    pub fn retired_objects(&self) -> usize {
        self.shared.retirement().waiting()
    }

    /// Every warning and error the validation layer reported so far: empty without the layer,
    /// and always empty for a [`Context::from_raw`] context (the host's own messenger gets them).
    pub fn validation_messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    /// Optimal-tiling features of `format`, for the formats the library draws into
    /// ([`DeviceInfo::attachment_format_features`]); empty for any other.
    pub fn optimal_tiling_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        match format {
            vk::Format::D32_SFLOAT => self.info.attachment_format_features[0],
            vk::Format::R32_UINT => self.info.attachment_format_features[1],
            _ => vk::FormatFeatureFlags::empty(),
        }
    }

    /// The largest buffer the shaders reach through its device address (the fragment and
    /// range buffers), in bytes: one allocation.
    pub fn max_addressed_buffer_bytes(&self) -> u64 {
        self.info.max_allocation_size
    }

    /// Memory for a buffer or image (`linear`: a buffer or linear image) from the context's
    /// allocator; `what` names it in the error.
    pub(crate) fn allocate(
        &self,
        name: &str,
        what: impl FnOnce() -> String,
        requirements: vk::MemoryRequirements,
        location: gpu_allocator::MemoryLocation,
        linear: bool,
    ) -> Result<gpu_allocator::vulkan::Allocation> {
        self.shared
            .allocator
            .lock()
            .map_err(|_| Error::InvalidArgument("allocator mutex poisoned".into()))?
            .allocate(&gpu_allocator::vulkan::AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: gpu_allocator::vulkan::AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|source| Error::Allocation {
                what: what(),
                source,
            })
    }

    /// The largest storage buffer a shader can address through a descriptor, in bytes.
    pub fn max_buffer_bytes(&self) -> u64 {
        self.info
            .max_storage_buffer_range
            .min(self.info.max_allocation_size)
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: for a headless context, the device is ours and waiting idle first means no
        // command buffer of the pool is pending; a host's device is not waited for, but the pool is
        // used only by OneShot, which waits for its own submission before it returns, so no pending
        // work uses it. `&mut self` means no OneShot holds the lock.
        unsafe {
            // A host's device is the host's to synchronize: never stall it from here.
            if self.shared.owned.is_some() {
                let _ = self.shared.device.device_wait_idle();
            }
            let pool = *self.one_shot.get_mut().unwrap_or_else(|e| e.into_inner());
            if pool != vk::CommandPool::null() {
                self.shared.device.destroy_command_pool(pool, None);
            }
        }
    }
}
