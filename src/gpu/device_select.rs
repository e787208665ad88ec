//! Choosing a physical device and checking that it has every feature the technique uses.

use super::requirements::DeviceRequirements;
use crate::error::{Error, Result};
use ash::vk;

pub(crate) struct Chosen {
    pub physical: vk::PhysicalDevice,
    pub queue_family: u32,
    pub kind: vk::PhysicalDeviceType,
    /// What to enable on it.
    pub requirements: DeviceRequirements,
}

fn graphics_compute_family(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<u32> {
    // SAFETY: `pd` was enumerated from the live `instance`.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    families
        .iter()
        .position(|q| {
            q.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .map(|i| i as u32)
}

fn preference(kind: vk::PhysicalDeviceType) -> u32 {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// Picks a discrete GPU if one is suitable, else integrated, virtual, then CPU (lavapipe).
pub(crate) fn choose(instance: &ash::Instance) -> Result<Chosen> {
    // SAFETY: `instance` is a live instance; enumerating its physical devices has no other
    // precondition.
    let devices = unsafe { instance.enumerate_physical_devices() }.map_err(|result| {
        if result == vk::Result::ERROR_INITIALIZATION_FAILED {
            Error::NoDevice {
                detail: String::new(),
            }
        } else {
            Error::Vulkan {
                call: "vkEnumeratePhysicalDevices",
                result,
            }
        }
    })?;
    if devices.is_empty() {
        return Err(Error::NoDevice {
            detail: String::new(),
        });
    }
    let mut rejected = Vec::new();
    let mut candidates = Vec::new();
    for pd in devices {
        // SAFETY: `pd` was enumerated from `instance`.
        let requirements = match unsafe { DeviceRequirements::for_device(instance, pd) } {
            Ok(r) => r,
            Err(Error::MissingFeatures(why)) => {
                rejected.push(why);
                continue;
            }
            Err(e) => return Err(e),
        };
        // SAFETY: `pd` was enumerated from the live `instance`.
        let props = unsafe { instance.get_physical_device_properties(pd) };
        let Some(queue_family) = graphics_compute_family(instance, pd) else {
            let name = props
                .device_name_as_c_str()
                .unwrap_or(c"?")
                .to_string_lossy();
            rejected.push(format!("{name}: no graphics+compute queue"));
            continue;
        };
        candidates.push(Chosen {
            physical: pd,
            queue_family,
            kind: props.device_type,
            requirements,
        });
    }
    candidates.sort_by_key(|c| preference(c.kind));
    candidates
        .into_iter()
        .next()
        .ok_or_else(|| Error::MissingFeatures(rejected.join("; ")))
}

/// Creates the device with what `chosen.requirements` lists (the required features and the
/// optional ones the device has).
pub(crate) fn create_device(
    instance: &ash::Instance,
    chosen: &Chosen,
) -> Result<(ash::Device, vk::Queue)> {
    let priorities = [1.0f32];
    let queue_info = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(chosen.queue_family)
        .queue_priorities(&priorities)];
    let mut requirements = chosen.requirements.clone();
    let extensions = requirements.extension_names();
    let info = requirements.chain(
        vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&extensions),
    );
    // SAFETY: `chosen.physical` belongs to `instance` and has every feature `info` chains (choose()
    // checked them); `info` and the queue priorities, extension names and feature structs it points
    // at are locals alive for the call.
    let device =
        unsafe { instance.create_device(chosen.physical, &info, None) }.map_err(|result| {
            Error::Vulkan {
                call: "vkCreateDevice",
                result,
            }
        })?;
    // SAFETY: the device was created just above with one queue of `chosen.queue_family` (index 0
    // exists).
    let queue = unsafe { device.get_device_queue(chosen.queue_family, 0) };
    Ok((device, queue))
}
