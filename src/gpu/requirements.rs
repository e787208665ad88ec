//! What a device must have enabled for the library: the feature structs and extensions a host
//! chains into its `VkDeviceCreateInfo` ([`DeviceRequirements`]), and the check of what a host
//! says it enabled ([`DeviceFeatures::missing_required`], used by `Context::from_raw`).

use crate::error::{Error, Result};
use ash::vk;
use std::ffi::{CStr, c_char};

/// Device features, in the structs a host chains into `VkDeviceCreateInfo`: Vulkan 1.0's
/// `VkPhysicalDeviceFeatures` and the Vulkan 1.2 and 1.3 feature structs (the library needs
/// nothing from 1.1's). Used both ways: what the library asks for
/// ([`DeviceRequirements::features`]) and what a host enabled (`Context::from_raw`).
///
/// The `p_next` fields are ignored (and cleared when [`DeviceRequirements::chain`] links the
/// structs).
#[derive(Debug, Clone, Copy, Default)]
pub struct DeviceFeatures {
    /// `VkPhysicalDeviceFeatures` (`pEnabledFeatures`, or `VkPhysicalDeviceFeatures2::features`).
    pub core: vk::PhysicalDeviceFeatures,
    /// `VkPhysicalDeviceVulkan12Features`.
    pub vulkan12: vk::PhysicalDeviceVulkan12Features<'static>,
    /// `VkPhysicalDeviceVulkan13Features`.
    pub vulkan13: vk::PhysicalDeviceVulkan13Features<'static>,
}

/// One feature the library uses: its Vulkan name, what it is for, and where it lives in
/// [`DeviceFeatures`].
struct Feature {
    name: &'static str,
    purpose: &'static str,
    get: fn(&DeviceFeatures) -> vk::Bool32,
    enable: Enable,
}

/// Turns one feature on in a host's feature structs.
type Enable = fn(
    &mut vk::PhysicalDeviceFeatures,
    &mut vk::PhysicalDeviceVulkan12Features<'_>,
    &mut vk::PhysicalDeviceVulkan13Features<'_>,
);

macro_rules! feature {
    ($name:literal, $purpose:literal, core . $field:ident) => {
        Feature {
            name: $name,
            purpose: $purpose,
            get: |f| f.core.$field,
            enable: |core, _, _| core.$field = vk::TRUE,
        }
    };
    ($name:literal, $purpose:literal, vulkan12 . $field:ident) => {
        Feature {
            name: $name,
            purpose: $purpose,
            get: |f| f.vulkan12.$field,
            enable: |_, vulkan12, _| vulkan12.$field = vk::TRUE,
        }
    };
    ($name:literal, $purpose:literal, vulkan13 . $field:ident) => {
        Feature {
            name: $name,
            purpose: $purpose,
            get: |f| f.vulkan13.$field,
            enable: |_, _, vulkan13| vulkan13.$field = vk::TRUE,
        }
    };
}

/// The features every pass may use. A device created without one of them is refused.
const REQUIRED: &[Feature] = &[
    feature!(
        "geometryShader",
        "prism and convex-hull generation",
        core.geometry_shader
    ),
    feature!(
        "fragmentStoresAndAtomics",
        "per-pixel linked lists written from fragment shaders",
        core.fragment_stores_and_atomics
    ),
    feature!(
        "shaderInt64",
        "64-bit depth|id visibility samples",
        core.shader_int64
    ),
    feature!(
        "shaderBufferInt64Atomics",
        "64-bit atomicMin on the visibility buffer",
        vulkan12.shader_buffer_int64_atomics
    ),
    feature!(
        "bufferDeviceAddress",
        "fragment and range buffers larger than one storage-buffer descriptor",
        vulkan12.buffer_device_address
    ),
    feature!(
        "dynamicRendering",
        "attachment-less render passes",
        vulkan13.dynamic_rendering
    ),
    feature!(
        "synchronization2",
        "pipeline barriers",
        vulkan13.synchronization2
    ),
];

/// Features that unlock one thing each; enabled where the device has them.
const OPTIONAL: &[Feature] = &[
    feature!(
        "hostQueryReset",
        "timestamps (gpu::TimestampQueries); without it timing is off",
        vulkan12.host_query_reset
    ),
    feature!(
        "shaderStorageImageWriteWithoutFormat",
        "the visibility-mask pass (technique::VisibilityMaskPass)",
        core.shader_storage_image_write_without_format
    ),
];

/// Device extensions the library needs: none (everything it uses is core Vulkan 1.3).
const EXTENSIONS: &[&CStr] = &[];

impl DeviceFeatures {
    /// Every feature the library requires, and nothing else.
    pub fn required() -> Self {
        let mut features = Self::default();
        for feature in REQUIRED {
            let DeviceFeatures {
                core,
                vulkan12,
                vulkan13,
            } = &mut features;
            (feature.enable)(core, vulkan12, vulkan13);
        }
        features
    }

    /// The features `physical` supports (as `vkGetPhysicalDeviceFeatures2` reports them).
    ///
    /// # Safety
    /// `physical` is a physical device of `instance`, which supports Vulkan 1.2 or later.
    pub unsafe fn supported(instance: &ash::Instance, physical: vk::PhysicalDevice) -> Self {
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut f12)
            .push_next(&mut f13);
        // SAFETY: the caller's contract.
        unsafe { instance.get_physical_device_features2(physical, &mut f2) };
        let core = f2.features;
        f12.p_next = std::ptr::null_mut();
        f13.p_next = std::ptr::null_mut();
        Self {
            core,
            vulkan12: f12,
            vulkan13: f13,
        }
    }

    /// The Vulkan names of the required features that are off here, in a fixed order.
    pub fn missing_required(&self) -> Vec<&'static str> {
        REQUIRED
            .iter()
            .filter(|f| (f.get)(self) == vk::FALSE)
            .map(|f| f.name)
            .collect()
    }

    /// Whether hostQueryReset is on (timestamps need it).
    pub fn host_query_reset(&self) -> bool {
        self.vulkan12.host_query_reset == vk::TRUE
    }

    /// Whether shaderStorageImageWriteWithoutFormat is on (the visibility-mask pass needs it).
    pub fn storage_image_write_without_format(&self) -> bool {
        self.core.shader_storage_image_write_without_format == vk::TRUE
    }

    /// Turns on, in the host's own feature structs, every feature that is on here (a host
    /// that enables features of its own merges the library's into them this way). Features
    /// already on stay on; the chain pointers are left alone.
    pub fn enable_in(
        &self,
        core: &mut vk::PhysicalDeviceFeatures,
        vulkan12: &mut vk::PhysicalDeviceVulkan12Features<'_>,
        vulkan13: &mut vk::PhysicalDeviceVulkan13Features<'_>,
    ) {
        for feature in REQUIRED.iter().chain(OPTIONAL) {
            if (feature.get)(self) == vk::TRUE {
                (feature.enable)(core, vulkan12, vulkan13);
            }
        }
    }
}

/// `name (purpose)` for each named feature, for error messages.
pub(crate) fn describe(names: &[&'static str]) -> String {
    names
        .iter()
        .map(
            |name| match REQUIRED.iter().chain(OPTIONAL).find(|f| f.name == *name) {
                Some(f) => format!("{} ({})", f.name, f.purpose),
                None => (*name).to_owned(),
            },
        )
        .collect::<Vec<_>>()
        .join(", ")
}

/// What a host chains into its `VkDeviceCreateInfo` for the library: the Vulkan version, the
/// feature structs and the device extensions. Made for one physical device by
/// [`DeviceRequirements::for_device`] (the required features, and the optional ones the device
/// has), or without one by [`DeviceRequirements::minimum`].
///
/// ```no_run
/// # use motion_shadows::ash::{self, vk};
/// # use motion_shadows::gpu::DeviceRequirements;
/// # fn f(instance: &ash::Instance, physical: vk::PhysicalDevice, family: u32)
/// #     -> motion_shadows::Result<()> {
/// // SAFETY: `physical` belongs to `instance`.
/// let mut requirements = unsafe { DeviceRequirements::for_device(instance, physical) }?;
/// let enabled = requirements.features; // what `Context::from_raw` is told
/// let extensions = requirements.extension_names();
/// let priorities = [1.0];
/// let queues = [vk::DeviceQueueCreateInfo::default()
///     .queue_family_index(family)
///     .queue_priorities(&priorities)];
/// let info = requirements.chain(
///     vk::DeviceCreateInfo::default()
///         .queue_create_infos(&queues)
///         .enabled_extension_names(&extensions),
/// );
/// let device = unsafe { instance.create_device(physical, &info, None) };
/// # Ok(()) }
/// ```
///
/// A host with feature structs of its own merges the library's into them with
/// [`DeviceFeatures::enable_in`] instead of [`Self::chain`].
#[derive(Debug, Clone)]
pub struct DeviceRequirements {
    /// The features to enable: every required one, and the optional ones the device has
    /// (hostQueryReset for timestamps, shaderStorageImageWriteWithoutFormat for the
    /// visibility-mask pass).
    pub features: DeviceFeatures,
    /// Device extensions to enable: none today (everything the library uses is core in
    /// Vulkan 1.3); a host enables these so that a later version's additions reach it.
    pub extensions: Vec<&'static CStr>,
    /// The Vulkan version the instance and device must support (`VkApplicationInfo::apiVersion`).
    pub api_version: u32,
}

impl DeviceRequirements {
    /// The required features only (no optional ones: no timestamps, no mask pass), for any
    /// device.
    pub fn minimum() -> Self {
        Self {
            features: DeviceFeatures::required(),
            extensions: EXTENSIONS.to_vec(),
            api_version: vk::API_VERSION_1_3,
        }
    }

    /// What to enable on `physical`: the required features and every optional one it
    /// supports. Errors ([`Error::MissingFeatures`]) naming each required feature the device
    /// lacks, or its Vulkan version if older than 1.3.
    ///
    /// # Safety
    /// `physical` is a physical device of `instance`.
    pub unsafe fn for_device(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
    ) -> Result<Self> {
        // SAFETY: the caller's contract.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let name = props
            .device_name_as_c_str()
            .unwrap_or(c"?")
            .to_string_lossy()
            .into_owned();
        if props.api_version < vk::API_VERSION_1_3 {
            return Err(Error::MissingFeatures(format!(
                "{name}: Vulkan {}.{} < 1.3",
                vk::api_version_major(props.api_version),
                vk::api_version_minor(props.api_version)
            )));
        }
        // SAFETY: the caller's contract, and the device has Vulkan 1.3.
        let supported = unsafe { DeviceFeatures::supported(instance, physical) };
        let missing = supported.missing_required();
        if !missing.is_empty() {
            return Err(Error::MissingFeatures(format!(
                "{name}: lacks {}",
                describe(&missing)
            )));
        }
        let mut requirements = Self::minimum();
        for feature in OPTIONAL {
            if (feature.get)(&supported) == vk::TRUE {
                let f = &mut requirements.features;
                (feature.enable)(&mut f.core, &mut f.vulkan12, &mut f.vulkan13);
            }
        }
        Ok(requirements)
    }

    /// The physical device the library's own contexts pick ([`crate::Context::headless`]),
    /// for a host that creates its device itself: the first of discrete, integrated, virtual
    /// and CPU devices that [`Self::for_device`] accepts and that has a queue family with
    /// graphics and compute. Returns the device, that queue family and what to enable on it.
    /// Errors ([`Error::MissingFeatures`]) with each rejected device's reason.
    ///
    /// # Safety
    /// `instance` is live and was created for Vulkan 1.3 ([`Self::api_version`]).
    pub unsafe fn choose_device(
        instance: &ash::Instance,
    ) -> Result<(vk::PhysicalDevice, u32, Self)> {
        let chosen = super::device_select::choose(instance)?;
        Ok((chosen.physical, chosen.queue_family, chosen.requirements))
    }

    /// [`Self::extensions`] as the pointers `enabled_extension_names` takes (valid as long
    /// as the program runs).
    pub fn extension_names(&self) -> Vec<*const c_char> {
        self.extensions.iter().map(|e| e.as_ptr()).collect()
    }

    /// `info` with the features linked in: `pEnabledFeatures` and the Vulkan 1.2 and 1.3
    /// feature structs pushed onto its chain. `info` must not set `pEnabledFeatures` or chain
    /// a `VkPhysicalDeviceFeatures2` or 1.2/1.3 feature struct of its own (merge with
    /// [`DeviceFeatures::enable_in`] then). Extensions are not set: pass
    /// [`Self::extension_names`] to `enabled_extension_names`.
    pub fn chain<'a>(&'a mut self, info: vk::DeviceCreateInfo<'a>) -> vk::DeviceCreateInfo<'a> {
        let f = &mut self.features;
        f.vulkan12.p_next = std::ptr::null_mut();
        f.vulkan13.p_next = std::ptr::null_mut();
        info.enabled_features(&f.core)
            .push_next(&mut f.vulkan12)
            .push_next(&mut f.vulkan13)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_required_set_names_nothing_missing_and_each_feature_by_name() {
        assert!(DeviceFeatures::required().missing_required().is_empty());
        assert_eq!(
            DeviceFeatures::default().missing_required(),
            [
                "geometryShader",
                "fragmentStoresAndAtomics",
                "shaderInt64",
                "shaderBufferInt64Atomics",
                "bufferDeviceAddress",
                "dynamicRendering",
                "synchronization2"
            ]
        );
        let mut f = DeviceFeatures::required();
        f.vulkan12.buffer_device_address = vk::FALSE;
        f.core.geometry_shader = vk::FALSE;
        assert_eq!(
            f.missing_required(),
            ["geometryShader", "bufferDeviceAddress"]
        );
        let text = describe(&f.missing_required());
        assert!(text.starts_with("geometryShader (prism"), "{text}");
        // Optional features are never required.
        assert!(!DeviceFeatures::required().host_query_reset());
        assert!(!DeviceFeatures::required().storage_image_write_without_format());
    }

    #[test]
    fn enable_in_merges_into_the_hosts_structs() {
        let mut core = vk::PhysicalDeviceFeatures::default().sampler_anisotropy(true);
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default().descriptor_indexing(true);
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut ours = DeviceFeatures::required();
        ours.vulkan12.host_query_reset = vk::TRUE;
        ours.enable_in(&mut core, &mut v12, &mut v13);
        let merged = DeviceFeatures {
            core,
            vulkan12: v12,
            vulkan13: v13,
        };
        assert!(merged.missing_required().is_empty());
        assert!(merged.host_query_reset());
        assert_eq!(
            merged.core.sampler_anisotropy,
            vk::TRUE,
            "the host's own stay on"
        );
        assert_eq!(merged.vulkan12.descriptor_indexing, vk::TRUE);
        assert!(!merged.storage_image_write_without_format());
    }

    #[test]
    fn chain_links_both_structs() {
        let mut r = DeviceRequirements::minimum();
        let info = r.chain(vk::DeviceCreateInfo::default());
        assert!(!info.p_enabled_features.is_null());
        let first = info.p_next as *const vk::BaseInStructure<'_>;
        // SAFETY: the chain points into `r`, alive here.
        let (a, b) = unsafe { ((*first).s_type, (*(*first).p_next).s_type) };
        assert_eq!(
            [a, b],
            [
                vk::StructureType::PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
                vk::StructureType::PHYSICAL_DEVICE_VULKAN_1_2_FEATURES
            ]
        );
    }
}
