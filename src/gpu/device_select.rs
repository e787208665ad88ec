//! Choosing a physical device and checking that it has every feature the technique uses.

use crate::error::{Error, Result};
use ash::vk;

/// The device features the passes need, with why, so that a missing one is named clearly.
const REQUIRED: &[(&str, &str)] = &[
    ("geometryShader", "prism and convex-hull generation"),
    (
        "fragmentStoresAndAtomics",
        "per-pixel linked lists written from fragment shaders",
    ),
    ("shaderInt64", "64-bit depth|id visibility samples"),
    (
        "shaderBufferInt64Atomics",
        "64-bit atomicMin on the visibility buffer",
    ),
    ("dynamicRendering", "attachment-less render passes"),
    ("synchronization2", "pipeline barriers"),
    ("hostQueryReset", "timestamp queries"),
    (
        "bufferDeviceAddress",
        "fragment and range buffers larger than one storage-buffer descriptor",
    ),
];

pub(crate) struct Chosen {
    pub physical: vk::PhysicalDevice,
    pub queue_family: u32,
    pub kind: vk::PhysicalDeviceType,
}

/// The required features a device lacks, named with what they are for. `have` follows
/// [`REQUIRED`].
fn name_missing(have: [vk::Bool32; REQUIRED.len()]) -> Vec<String> {
    REQUIRED
        .iter()
        .zip(have)
        .filter(|(_, ok)| *ok == vk::FALSE)
        .map(|((name, why), _)| format!("{name} ({why})"))
        .collect()
}

pub(crate) fn missing_features(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Vec<String> {
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut f2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut f12)
        .push_next(&mut f13);
    unsafe { instance.get_physical_device_features2(pd, &mut f2) };
    let f = f2.features;
    let have = [
        f.geometry_shader,
        f.fragment_stores_and_atomics,
        f.shader_int64,
        f12.shader_buffer_int64_atomics,
        f13.dynamic_rendering,
        f13.synchronization2,
        f12.host_query_reset,
        f12.buffer_device_address,
    ];
    name_missing(have)
}

fn graphics_compute_family(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<u32> {
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
        let props = unsafe { instance.get_physical_device_properties(pd) };
        let name = props
            .device_name_as_c_str()
            .unwrap_or(c"?")
            .to_string_lossy()
            .into_owned();
        if props.api_version < vk::API_VERSION_1_3 {
            rejected.push(format!(
                "{name}: Vulkan {}.{} < 1.3",
                vk::api_version_major(props.api_version),
                vk::api_version_minor(props.api_version)
            ));
            continue;
        }
        let missing = missing_features(instance, pd);
        if !missing.is_empty() {
            rejected.push(format!("{name}: lacks {}", missing.join(", ")));
            continue;
        }
        let Some(queue_family) = graphics_compute_family(instance, pd) else {
            rejected.push(format!("{name}: no graphics+compute queue"));
            continue;
        };
        candidates.push(Chosen {
            physical: pd,
            queue_family,
            kind: props.device_type,
        });
    }
    candidates.sort_by_key(|c| preference(c.kind));
    candidates
        .into_iter()
        .next()
        .ok_or_else(|| Error::MissingFeatures(rejected.join("; ")))
}

/// Whether the device supports an optional feature: `shaderStorageImageWriteWithoutFormat`
/// (the visibility-mask pass writes any single-channel output format with one pipeline).
pub(crate) fn supports_storage_write_without_format(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
) -> bool {
    let f = unsafe { instance.get_physical_device_features(pd) };
    f.shader_storage_image_write_without_format == vk::TRUE
}

/// Enables exactly the features checked above, and the optional ones the device has.
pub(crate) fn create_device(
    instance: &ash::Instance,
    chosen: &Chosen,
) -> Result<(ash::Device, vk::Queue)> {
    let priorities = [1.0f32];
    let queue_info = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(chosen.queue_family)
        .queue_priorities(&priorities)];
    let features = vk::PhysicalDeviceFeatures::default()
        .geometry_shader(true)
        .fragment_stores_and_atomics(true)
        .shader_int64(true)
        .shader_storage_image_write_without_format(supports_storage_write_without_format(
            instance,
            chosen.physical,
        ));
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
        .shader_buffer_int64_atomics(true)
        .host_query_reset(true)
        .buffer_device_address(true);
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true);
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_info)
        .enabled_features(&features)
        .push_next(&mut f12)
        .push_next(&mut f13);
    let device =
        unsafe { instance.create_device(chosen.physical, &info, None) }.map_err(|result| {
            Error::Vulkan {
                call: "vkCreateDevice",
                result,
            }
        })?;
    let queue = unsafe { device.get_device_queue(chosen.queue_family, 0) };
    Ok((device, queue))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_feature_is_named_with_its_purpose() {
        let mut have = [vk::TRUE; REQUIRED.len()];
        assert!(name_missing(have).is_empty());
        have[0] = vk::FALSE;
        have[3] = vk::FALSE;
        let missing = name_missing(have);
        assert_eq!(missing.len(), 2);
        assert!(missing[0].starts_with("geometryShader ("), "{missing:?}");
        assert!(
            missing[1].starts_with("shaderBufferInt64Atomics ("),
            "{missing:?}"
        );
    }
}
