//! The engine's own Vulkan instance and device, made with what the library asks for
//! (`DeviceRequirements::choose_device` picks the device and says what to enable).

use crate::deferred::Result;
use ash::vk;
use motion_shadows::{DeviceFeatures, DeviceRequirements};

/// The handles the engine runs on: plain handles, destroyed by whoever made them
/// ([`Gpu::destroy`] for [`Gpu::new`]'s). `queue` is the first of `queue_family` (graphics
/// and compute); `enabled`, the features the device was made with (`Context::from_raw`'s).
#[derive(Clone)]
pub struct Gpu {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    pub queue: vk::Queue,
    pub enabled: DeviceFeatures,
}

impl Gpu {
    /// A Vulkan 1.3 instance (with the Khronos validation layer when `validation`) and a
    /// device with the features the library needs.
    pub fn new(validation: bool) -> Result<Gpu> {
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let layers = if validation { &layers[..] } else { &[] };
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        let info = info.enabled_layer_names(layers);
        // SAFETY: loading the loader runs its initialization, and `entry` is kept in the Gpu
        // while the instance lives; `info` and what it points at are locals.
        let (entry, instance) = unsafe {
            let entry = ash::Entry::load()?;
            let instance = entry.create_instance(&info, None)?;
            (entry, instance)
        };
        // SAFETY: the instance is live and made for Vulkan 1.3; the device is the one chosen
        // on it, with what its requirements enable. On an error nothing else was made on the
        // instance, so it goes at once.
        let (physical, queue_family, (device, queue, enabled)) = unsafe {
            let made = DeviceRequirements::choose_device(&instance);
            let made = made.and_then(|(p, f, r)| Ok((p, f, r.create_device(&instance, p, f)?)));
            made.inspect_err(|_| instance.destroy_instance(None))?
        };
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
