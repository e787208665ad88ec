//! The engine's Vulkan device: its own instance and device, made with what the library asks
//! for (`DeviceRequirements::choose_device` picks the device and lists what to enable).

use crate::deferred::{Error, Result};
use ash::vk;
use motion_shadows::{DeviceFeatures, DeviceRequirements};

/// The handles the engine runs on. Plain handles: whoever made them destroys them
/// ([`Gpu::destroy`] for [`Gpu::new`]'s).
#[derive(Clone)]
pub struct Gpu {
    /// Keeps the Vulkan loader loaded while the instance lives.
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    /// A family with graphics and compute; `queue` is its first queue.
    pub queue_family: u32,
    pub queue: vk::Queue,
    /// The features the device was created with (what `Context::from_raw` is told).
    pub enabled: DeviceFeatures,
}

impl Gpu {
    /// A Vulkan 1.3 instance (with the Khronos validation layer when `validation`: it prints
    /// what it finds) and a device with the features the library needs.
    pub fn new(validation: bool) -> Result<Gpu> {
        // SAFETY: loading the loader runs its initialization; `entry` is kept in Gpu.
        let entry = unsafe { ash::Entry::load() }?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let mut info = vk::InstanceCreateInfo::default().application_info(&app);
        if validation {
            info = info.enabled_layer_names(&layers);
        }
        // SAFETY: `info` and what it points at are locals alive for the call.
        let instance = unsafe { entry.create_instance(&info, None) }?;
        // SAFETY: the instance is live and made for Vulkan 1.3; on an error, nothing else
        // was made on it, so it is destroyed at once.
        let device = unsafe {
            DeviceRequirements::choose_device(&instance)
                .map_err(Error::from)
                .and_then(|chosen| Self::create_device(&instance, chosen))
                .inspect_err(|_| instance.destroy_instance(None))
        }?;
        let (physical, queue_family, device, enabled) = device;
        // SAFETY: the device was made with one queue of `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        Ok(Gpu {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue,
            enabled,
        })
    }

    /// # Safety
    /// `physical` is a device of `instance` with every feature `requirements` lists.
    unsafe fn create_device(
        instance: &ash::Instance,
        (physical, queue_family, mut requirements): (vk::PhysicalDevice, u32, DeviceRequirements),
    ) -> Result<(vk::PhysicalDevice, u32, ash::Device, DeviceFeatures)> {
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let extensions = requirements.extension_names();
        let info = requirements.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_extension_names(&extensions),
        );
        // SAFETY: the caller's contract; `info` and its chain are locals alive for the call.
        let device = unsafe { instance.create_device(physical, &info, None) }?;
        Ok((physical, queue_family, device, requirements.features))
    }

    /// Destroys the device and the instance.
    ///
    /// # Safety
    /// Everything made on the device (the engine, the library's context and objects, their
    /// allocator) is gone, and nothing else destroys these handles.
    pub unsafe fn destroy(self) {
        // SAFETY: the caller's contract: nothing made on the device is left.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}
