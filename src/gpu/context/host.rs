//! A context around a host engine's instance, device and queue, which the library never
//! destroys: the features the host enabled checked first.

use super::Context;
use super::new_allocator;
use crate::error::{Error, Result};
use crate::gpu::requirements::{DeviceFeatures, describe};
use ash::vk;
use gpu_allocator::vulkan::Allocator;
use std::sync::{Arc, Mutex};

impl Context {
    /// Wraps a host engine's Vulkan objects. The library then never destroys them.
    ///
    /// `enabled` is what the host enabled when it created `device` (what was enabled cannot be
    /// queried from a `VkDevice`): the features it chained into `VkDeviceCreateInfo`, e.g.
    /// [`crate::gpu::DeviceRequirements::features`] when it chained those. Refused
    /// ([`Error::FeaturesNotEnabled`], naming each) when a required feature is off there, or
    /// ([`Error::MissingFeatures`]) when it is on there but the device does not support it.
    /// Optional features: hostQueryReset (off: [`crate::gpu::TimestampQueries`] records nothing
    /// and says so), shaderStorageImageWriteWithoutFormat (off:
    /// `technique::VisibilityMaskPass::new` fails).
    ///
    /// # Safety
    /// - `device` was created from `physical` of `instance` (Vulkan 1.3), with a queue of
    ///   `queue_family` supporting graphics and compute, and with every feature that is on in
    ///   `enabled` enabled ([`crate::gpu::DeviceRequirements`] lists them).
    /// - `instance` and `device` outlive the returned context and every object made from it.
    /// - The library submits to `queue` only through [`crate::gpu::OneShot`] (which the standalone
    ///   renderer and `TemporalShadowMap::download` use); passes only record into command
    ///   buffers the host gives them. The host does not use `queue` from another thread
    ///   while a `OneShot` of this context runs (Vulkan's external synchronization of
    ///   queues: the context serializes its own OneShots, not the host's submissions).
    /// - No work using the context's objects is pending when the context and the last of
    ///   its objects are gone (the context does not wait on a host's device). Objects
    ///   dropped before that wait for the host's fences: see [`Self::begin_frame`] and
    ///   [`Self::collect`].
    ///
    /// The context makes its memory with a gpu-allocator of its own on `device`; to count
    /// it in the host's budget, give the host's with [`Self::from_raw_with_allocator`].
    pub unsafe fn from_raw(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: ash::Device,
        queue_family: u32,
        queue: vk::Queue,
        enabled: &DeviceFeatures,
    ) -> Result<Self> {
        let allocator = new_allocator(instance, physical, &device)?;
        // SAFETY: the caller's contract.
        unsafe {
            Self::from_raw_with_allocator(
                instance,
                physical,
                device,
                queue_family,
                queue,
                enabled,
                allocator,
            )
        }
    }

    /// [`Self::from_raw`], with the host's gpu-allocator: every buffer and image the library
    /// makes is an allocation of the host's, named after what it holds (e.g. `"nodes"`,
    /// `"ranges"`), so the host's `Allocator::generate_report` counts it in the host's
    /// budget. The library frees each allocation into the same allocator once no pending
    /// frame can use it ([`Self::collect`]).
    ///
    /// # Safety
    /// As [`Self::from_raw`]; and `allocator` was made for `device` with
    /// `buffer_device_address` on (the library's buffers are reached by address).
    pub unsafe fn from_raw_with_allocator(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: ash::Device,
        queue_family: u32,
        queue: vk::Queue,
        enabled: &DeviceFeatures,
        allocator: Arc<Mutex<Allocator>>,
    ) -> Result<Self> {
        let not_enabled = enabled.missing_required();
        if !not_enabled.is_empty() {
            return Err(Error::FeaturesNotEnabled {
                detail: describe(&not_enabled),
                missing: not_enabled,
            });
        }
        // A host cannot have enabled what the device does not support.
        // SAFETY: the caller's contract (`physical` of `instance`, Vulkan 1.3).
        let supported = unsafe { DeviceFeatures::supported(instance, physical) };
        let missing = supported.missing_required();
        if !missing.is_empty() {
            return Err(Error::MissingFeatures(format!(
                "the host's device lacks {}",
                describe(&missing)
            )));
        }
        // SAFETY: the caller's contract of from_raw (the handles are live and related, `enabled` is
        // what was enabled), checked for the required features just above; `owned` is None, so the
        // context never destroys the host's handles.
        unsafe {
            Self::assemble(
                instance,
                physical,
                device,
                queue_family,
                queue,
                enabled,
                allocator,
                None,
                Arc::new(Mutex::new(Vec::new())),
            )
        }
    }
}
