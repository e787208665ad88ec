//! What the library knows about the device: its limits, its driver's loop limit, the
//! features enabled on it, read once when the context is made.

use crate::gpu::requirements::DeviceFeatures;
use ash::vk;

/// What the library knows about the device it runs on.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    /// The device's name.
    pub name: String,
    /// Discrete, integrated, virtual or CPU.
    pub device_type: String,
    /// The driver's name and version.
    pub driver: String,
    /// maxStorageBufferRange.
    pub max_storage_buffer_range: u64,
    /// maxMemoryAllocationSize: the largest buffer the library makes.
    pub max_allocation_size: u64,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Valid bits of the queue's timestamps (0: no timestamps).
    pub timestamp_valid_bits: u32,
    /// Bits of sub-pixel precision the rasterizer snaps vertex positions to.
    pub sub_pixel_precision_bits: u32,
    /// maxPushConstantsSize: the most push-constant bytes a pipeline layout may have.
    pub max_push_constants_size: u32,
    /// shaderStorageImageWriteWithoutFormat is enabled (a headless context enables it where
    /// supported; a host says so in [`crate::gpu::Context::from_raw`]): the visibility-mask pass
    /// needs it.
    pub storage_image_write_without_format: bool,
    /// hostQueryReset is enabled (a headless context enables it where supported; a host says so in
    /// [`crate::gpu::Context::from_raw`]): without it [`crate::gpu::TimestampQueries`] records
    /// nothing and says why.
    pub host_query_reset: bool,
    /// Whether compute shaders have the subgroup vote operations (`subgroupAny`:
    /// `VkPhysicalDeviceSubgroupProperties` lists `VK_SUBGROUP_FEATURE_VOTE_BIT` for the
    /// compute stage): the visibility-mask pass needs them.
    pub subgroup_vote_in_compute: bool,
    /// Loop iterations a shader invocation may run in all before the driver leaves its loops
    /// (silently): 65,535 on lavapipe (llvmpipe's loop limiter, shared by every loop of an
    /// invocation, counted per SIMD group); `None` where the driver has no such limit.
    pub shader_loop_limit: Option<u32>,
    /// Optimal-tiling features of the attachment formats the ordinary shadow maps are drawn
    /// into (D32_SFLOAT, R32_UINT), in that order.
    pub attachment_format_features: [vk::FormatFeatureFlags; 2],
}

/// Invocations that share one loop counter on a loop-limited device (llvmpipe runs 8 lanes
/// per SIMD group).
const LOOP_LIMIT_LANES: u32 = 8;
/// Iterations left to a shader's own loops (outside the shadow lookups).
const LOOP_LIMIT_RESERVE: u32 = 256;

impl DeviceInfo {
    /// The most loop iterations one invocation's shadow lookups (`ms_loop_iterations`) may
    /// run and still be sure to finish on this device: its share of
    /// [`Self::shader_loop_limit`], less a reserve for the shader's other loops. 0 where the
    /// device has no limit.
    pub fn shader_loop_budget(&self) -> u32 {
        self.shader_loop_limit.map_or(0, |limit| {
            (limit / LOOP_LIMIT_LANES).saturating_sub(LOOP_LIMIT_RESERVE)
        })
    }
}

pub(super) fn device_info(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    family: u32,
    enabled: &DeviceFeatures,
) -> DeviceInfo {
    let mut p11 = vk::PhysicalDeviceMaintenance3Properties::default();
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut p2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut p11)
        .push_next(&mut driver)
        .push_next(&mut subgroup);
    // SAFETY: `instance` is a live instance and `pd` one of its physical devices (both outlive the
    // context: created here or the host's contract), and `p2`'s chain points at locals that outlive
    // the call.
    unsafe { instance.get_physical_device_properties2(pd, &mut p2) };
    let props = p2.properties;
    // SAFETY: `pd` is a physical device of the live `instance`.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let name = props
        .device_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    let driver_name = driver
        .driver_info_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    DeviceInfo {
        name,
        device_type: format!("{:?}", props.device_type),
        driver: driver_name,
        subgroup_vote_in_compute: subgroup_vote_in_compute(&subgroup),
        shader_loop_limit: (driver.driver_id == vk::DriverId::MESA_LLVMPIPE).then_some(65_535),
        max_storage_buffer_range: props.limits.max_storage_buffer_range as u64,
        max_allocation_size: p11.max_memory_allocation_size,
        timestamp_period_ns: props.limits.timestamp_period,
        timestamp_valid_bits: families
            .get(family as usize)
            .map_or(0, |f| f.timestamp_valid_bits),
        sub_pixel_precision_bits: props.limits.sub_pixel_precision_bits,
        max_push_constants_size: props.limits.max_push_constants_size,
        storage_image_write_without_format: enabled.storage_image_write_without_format(),
        host_query_reset: enabled.host_query_reset(),
        attachment_format_features: [vk::Format::D32_SFLOAT, vk::Format::R32_UINT].map(|f| {
            // SAFETY: `pd` is a physical device of the live `instance`; any format may be queried.
            unsafe { instance.get_physical_device_format_properties(pd, f) }.optimal_tiling_features
        }),
    }
}

/// Whether `subgroup` lists the vote operations for the compute stage.
fn subgroup_vote_in_compute(subgroup: &vk::PhysicalDeviceSubgroupProperties) -> bool {
    subgroup
        .supported_stages
        .contains(vk::ShaderStageFlags::COMPUTE)
        && subgroup
            .supported_operations
            .contains(vk::SubgroupFeatureFlags::VOTE)
}

#[cfg(test)]
mod subgroup_tests {
    use super::subgroup_vote_in_compute;
    use ash::vk;

    /// The vote operations count only where the compute stage has them.
    #[test]
    fn subgroup_vote_needs_the_operation_and_the_compute_stage() {
        let props = |stages, operations| vk::PhysicalDeviceSubgroupProperties {
            supported_stages: stages,
            supported_operations: operations,
            ..Default::default()
        };
        let vote = vk::SubgroupFeatureFlags::BASIC | vk::SubgroupFeatureFlags::VOTE;
        let compute = vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::FRAGMENT;
        assert!(subgroup_vote_in_compute(&props(compute, vote)));
        assert!(!subgroup_vote_in_compute(&props(
            vk::ShaderStageFlags::FRAGMENT,
            vote
        )));
        assert!(!subgroup_vote_in_compute(&props(
            compute,
            vk::SubgroupFeatureFlags::BASIC
        )));
    }
}
