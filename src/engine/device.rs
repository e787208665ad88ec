//! A host's own device made with what the library asks for: the queue, the extensions and the
//! feature chain every host writes the same way, and the features to hand `Context::from_raw`
//! (which must be the ones the device was made with); and the gpu-allocator a host shares
//! with the library, with the one setting the library depends on.

use crate::error::{Result, VkContext};
use crate::gpu::{Context, DeviceFeatures, DeviceRequirements};
use ash::vk;
use gpu_allocator::vulkan::Allocator;
use std::sync::{Arc, Mutex};

impl Context {
    /// A gpu-allocator on `device` as the library needs one (device addresses on: the
    /// library's buffers are read by address), for a host that makes its own memory from it
    /// too and hands it to [`Context::from_raw_with_allocator`].
    pub fn new_allocator(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: &ash::Device,
    ) -> Result<Arc<Mutex<Allocator>>> {
        crate::gpu::new_allocator(instance, physical, device)
    }
}

impl DeviceRequirements {
    /// Creates a device on `physical` with one queue of `family` and these requirements'
    /// extensions and features (those of [`Self::choose_device`] or [`Self::for_device`]).
    /// Returns the device, its queue, and the features it was made with, for
    /// `Context::from_raw`. The device is the caller's to destroy.
    ///
    /// # Safety
    /// `physical` is a physical device of the live `instance`, which was made for Vulkan 1.3,
    /// and supports every feature these requirements enable (as `for_device` checked).
    pub unsafe fn create_device(
        mut self,
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        family: u32,
    ) -> Result<(ash::Device, vk::Queue, DeviceFeatures)> {
        let priorities = [1.0f32];
        let queue = vk::DeviceQueueCreateInfo::default().queue_family_index(family);
        let queues = [queue.queue_priorities(&priorities)];
        let extensions = self.extension_names();
        let enabled = self.features;
        let info = vk::DeviceCreateInfo::default().queue_create_infos(&queues);
        let info = self.chain(info.enabled_extension_names(&extensions));
        // SAFETY: the caller's contract; `info` and what it points at are locals.
        let device =
            unsafe { instance.create_device(physical, &info, None) }.vk("vkCreateDevice")?;
        // SAFETY: the device was just made with one queue of `family`.
        let queue = unsafe { device.get_device_queue(family, 0) };
        Ok((device, queue, enabled))
    }
}
