//! The Vulkan context: instance, device, one queue and a gpu-allocator.

use super::debug::{self, MessageSink, Messenger};
use super::device_select;
use super::requirements::{DeviceFeatures, describe};
use super::retire::{Doomed, Retirement};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

/// How to create a headless context.
#[derive(Debug, Clone, Default)]
pub struct ContextOptions {
    /// Turn on the Khronos validation layer with synchronization validation. Creation fails
    /// if the layer is not installed.
    pub validation: bool,
}

impl ContextOptions {
    /// Validation on when `MOTION_SHADOWS_VALIDATION=1` (the test script sets it).
    pub fn from_env() -> Self {
        Self {
            validation: std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1"),
        }
    }
}

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
    /// supported; a host says so in [`Context::from_raw`]): the visibility-mask pass needs it.
    pub storage_image_write_without_format: bool,
    /// hostQueryReset is enabled (a headless context enables it where supported; a host says
    /// so in [`Context::from_raw`]): without it [`super::TimestampQueries`] records nothing
    /// and says why.
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

/// Objects that must outlive every buffer and pipeline: freed last, in the right order
/// (retired objects, then the allocator, before the device; the device before the instance).
pub(crate) struct Shared {
    pub device: ash::Device,
    /// maxPushConstantsSize: pipeline layouts are checked against it.
    pub max_push_constants_size: u32,
    /// The context's own allocator, or the host's ([`Context::from_raw_with_allocator`]).
    pub allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    retirement: Retirement,
    owned: Option<Owned>,
}

impl Shared {
    /// Destroys `doomed` once no pending work can use it (see `retire.rs`).
    pub(crate) fn retire(&self, doomed: Doomed) {
        // SAFETY: objects made on this device, from this allocator, retired once (by their
        // Drop).
        unsafe {
            self.retirement
                .retire(doomed, &self.device, &self.allocator)
        };
    }

    /// Destroys what waits for frames up to `completed` (everything: `None`).
    ///
    /// # Safety
    /// Those frames' work has completed (`None`: no work is pending).
    pub(crate) unsafe fn collect(&self, completed: Option<u64>) -> usize {
        // SAFETY: the caller's contract.
        unsafe {
            self.retirement
                .collect(completed, &self.device, &self.allocator)
        }
    }

    pub(crate) fn retirement(&self) -> &Retirement {
        &self.retirement
    }
}

struct Owned {
    _entry: ash::Entry,
    instance: ash::Instance,
    messenger: Option<Messenger>,
    /// The sink of the messenger chained into VkInstanceCreateInfo, which the layer also uses
    /// during vkDestroyInstance: freed only after that.
    creation_sink: *mut MessageSink,
}

// SAFETY: the creation sink is only touched by the layer's callback (behind its mutex) and
// freed once, in Shared::drop.
unsafe impl Send for Owned {}
// SAFETY: shared references to Owned expose no method that touches the sink or the instance; only
// Shared::drop (which has &mut) destroys them, so sharing it between threads races on nothing.
unsafe impl Sync for Owned {}

impl Drop for Shared {
    fn drop(&mut self) {
        // SAFETY: every resource holding an Arc<Shared> is gone, and no work is pending (the
        // contracts of `from_raw` and of a headless context's drop, which waits): what waits
        // for its frame can go. The allocator must be dropped before the device is destroyed
        // (it frees its memory blocks then); a host's allocator stays with the host.
        unsafe {
            self.collect(None);
            ManuallyDrop::drop(&mut self.allocator);
        }
        if let Some(owned) = self.owned.take() {
            // SAFETY: `owned` holds the instance and device this context created (never a host's:
            // `owned` is None for from_raw). The allocator was dropped and retired objects
            // destroyed just above, so nothing made on the device is left; the messenger goes
            // before its instance, and the creation sink is freed after vkDestroyInstance, the last
            // call that may report through it, exactly once since `owned` was taken.
            unsafe {
                self.device.destroy_device(None);
                drop(owned.messenger);
                owned.instance.destroy_instance(None);
                drop(Box::from_raw(owned.creation_sink));
            }
        }
    }
}

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

fn device_info(
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
pub(crate) fn subgroup_vote_in_compute(subgroup: &vk::PhysicalDeviceSubgroupProperties) -> bool {
    subgroup
        .supported_stages
        .contains(vk::ShaderStageFlags::COMPUTE)
        && subgroup
            .supported_operations
            .contains(vk::SubgroupFeatureFlags::VOTE)
}

/// A gpu-allocator of the library's own on `device`.
fn new_allocator(
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
    /// Creates an instance and device of its own: a discrete GPU if one has every needed
    /// feature, else whatever does (lavapipe on a machine without a GPU).
    pub fn headless(options: &ContextOptions) -> Result<Self> {
        // SAFETY: loading the Vulkan loader runs its initialization code; `entry` keeps the library
        // loaded for as long as the instance lives (it is kept in Owned).
        let entry = unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))?;
        if options.validation && !debug::layer_available(&entry) {
            return Err(Error::ValidationLayerMissing);
        }
        let messages: MessageSink = Arc::new(Mutex::new(Vec::new()));
        let app = vk::ApplicationInfo::default()
            .application_name(c"motion-shadows")
            .api_version(vk::API_VERSION_1_3);
        let layers = [debug::VALIDATION_LAYER.as_ptr()];
        let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
        let mut validation_features = vk::ValidationFeaturesEXT::default()
            .enabled_validation_features(&debug::VALIDATION_FEATURES);
        // Reports problems in vkCreateInstance/vkDestroyInstance themselves.
        let creation_sink = Box::into_raw(Box::new(messages.clone()));
        let mut creation_messenger = debug::messenger_info(creation_sink);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app);
        if options.validation {
            info = info
                .enabled_layer_names(&layers)
                .enabled_extension_names(&extensions)
                .push_next(&mut validation_features)
                .push_next(&mut creation_messenger);
        }
        // SAFETY: `info` and everything it points at (application info, layer and extension names,
        // the chained validation features and creation messenger) are locals alive for the call;
        // the creation sink stays allocated until after vkDestroyInstance.
        let instance = unsafe { entry.create_instance(&info, None) };
        let instance = instance.inspect_err(|_| {
            // SAFETY: no instance, so no layer holds the creation sink any more.
            drop(unsafe { Box::from_raw(creation_sink) });
        });
        let instance = instance.map_err(|result| match result {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::NoDevice {
                detail: " (the loader found no driver)".into(),
            },
            result => Error::Vulkan {
                call: "vkCreateInstance",
                result,
            },
        })?;
        let messenger = if options.validation {
            match Messenger::new(&entry, &instance, messages.clone()) {
                Ok(m) => Some(m),
                Err(e) => {
                    // SAFETY: the messenger failed, so the instance just created has no child
                    // object; it is destroyed once, and the creation sink freed after it (the layer
                    // may report through it until then).
                    unsafe {
                        instance.destroy_instance(None);
                        drop(Box::from_raw(creation_sink));
                    }
                    return Err(e);
                }
            }
        } else {
            None
        };
        let chosen = match device_select::choose(&instance)
            .and_then(|c| device_select::create_device(&instance, &c).map(|d| (c, d)))
        {
            Ok(v) => v,
            Err(e) => {
                drop(messenger);
                // SAFETY: device creation failed, so the instance has no device; its messenger was
                // dropped just above, then the instance goes, then the sink it reported through.
                unsafe {
                    instance.destroy_instance(None);
                    drop(Box::from_raw(creation_sink));
                }
                return Err(e);
            }
        };
        let (chosen, (device, queue)) = chosen;
        let enabled = chosen.requirements.features;
        let owned = Owned {
            _entry: entry,
            instance,
            messenger,
            creation_sink,
        };
        let allocator = match new_allocator(&owned.instance, chosen.physical, &device) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the device was just created and nothing has been made on it yet (the
                // allocator failed); `owned` still destroys the instance after this returns.
                unsafe { device.destroy_device(None) };
                return Err(e);
            }
        };
        // SAFETY: the handles were just created by us, and `owned` destroys them.
        unsafe {
            Self::assemble(
                &owned.instance.clone(),
                chosen.physical,
                device,
                chosen.queue_family,
                queue,
                &enabled,
                allocator,
                Some(owned),
                messages,
            )
        }
    }

    /// Wraps a host engine's Vulkan objects. The library then never destroys them.
    ///
    /// `enabled` is what the host enabled when it created `device` (what was enabled cannot be
    /// queried from a `VkDevice`): the features it chained into `VkDeviceCreateInfo`, e.g.
    /// [`super::DeviceRequirements::features`] when it chained those. Refused
    /// ([`Error::FeaturesNotEnabled`], naming each) when a required feature is off there, or
    /// ([`Error::MissingFeatures`]) when it is on there but the device does not support it.
    /// Optional features: hostQueryReset (off: [`super::TimestampQueries`] records nothing
    /// and says so), shaderStorageImageWriteWithoutFormat (off:
    /// `technique::VisibilityMaskPass::new` fails).
    ///
    /// # Safety
    /// - `device` was created from `physical` of `instance` (Vulkan 1.3), with a queue of
    ///   `queue_family` supporting graphics and compute, and with every feature that is on in
    ///   `enabled` enabled ([`super::DeviceRequirements`] lists them).
    /// - `instance` and `device` outlive the returned context and every object made from it.
    /// - The library submits to `queue` only through [`super::OneShot`] (which the standalone
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
