//! The tests' "host engine": its own `ash::Entry`, instance, device, queue, command pool and
//! fence, so that the tests can check that `Context::from_raw` and the passes work inside
//! someone else's Vulkan setup, with what a test needs on top of the example engine's device
//! (`deferred::Gpu`, which it derefs to): a debug messenger that collects every validation
//! message (synchronization validation on), features turned off on request, and one command
//! buffer to record into. The only help it takes from the library is `DeviceRequirements`.

use ash::vk;
use motion_shadows::gpu::{DeviceFeatures, DeviceRequirements};
use motion_shadows_deferred_host::gpu::Gpu;
use std::ffi::{CStr, c_void};
use std::sync::{Arc, Mutex};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Every WARNING and ERROR the validation layer reported to the host's messenger.
pub type Messages = Arc<Mutex<Vec<String>>>;

/// The host's debug messenger. The boxed sink is registered as the callback's user data both
/// here and in the `VkInstanceCreateInfo` chain (which the layer also uses during
/// `vkDestroyInstance`), so it is freed only after the instance is gone.
struct Messenger {
    loader: ash::ext::debug_utils::Instance,
    handle: vk::DebugUtilsMessengerEXT,
}

pub struct Host {
    /// The instance, device and queue (destroyed by Host's Drop).
    gpu: Gpu,
    /// Validation messages (stays empty without validation).
    pub messages: Messages,
    pub device_name: String,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    messenger: Option<Messenger>,
    /// `Box<Messages>` handed to the layer as user data; freed in Drop after the instance.
    sink: *mut Messages,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data or null; `user` is our boxed sink, which
    // outlives the instance.
    let text = unsafe { data.as_ref() }
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    let line = format!("[host {severity:?}] {text}");
    eprintln!("vulkan validation: {line}");
    // SAFETY: `user` is the sink registered with this callback: a Box<Messages> freed only after
    // the instance (and so every messenger) is destroyed, and the layer calls back only while they
    // exist; only a shared reference is made, and the Mutex serializes writers.
    if let Some(sink) = unsafe { (user as *const Messages).as_ref() } {
        if let Ok(mut messages) = sink.lock() {
            messages.push(line);
        }
    }
    vk::FALSE
}

fn messenger_info(sink: *mut Messages) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(sink as *mut c_void)
}

impl Host {
    /// Creates the host's instance (with the Khronos validation layer, synchronization
    /// validation and a debug messenger when `validation`), picks a device and creates it
    /// with the features `DeviceRequirements::for_device` lists (the required ones, and the
    /// optional hostQueryReset and shaderStorageImageWriteWithoutFormat where the device has
    /// them).
    pub fn new(validation: bool) -> Result<Host, String> {
        Self::with_features(validation, |_| {})
    }

    /// [`Host::new`], with the features to enable changed by `edit` first (a test turns one
    /// off to see the library refuse the device).
    pub fn with_features(
        validation: bool,
        edit: impl FnOnce(&mut DeviceFeatures),
    ) -> Result<Host, String> {
        // SAFETY: loading the Vulkan loader runs its initialization; `entry` is kept in Host, so
        // the library stays loaded while the instance lives.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| format!("Vulkan loader: {e}"))?;
        if validation {
            // SAFETY: `entry` is a loaded entry, all that enumerating layers needs.
            let layers = unsafe { entry.enumerate_instance_layer_properties() }
                .map_err(|e| format!("vkEnumerateInstanceLayerProperties: {e}"))?;
            if !layers
                .iter()
                .any(|l| l.layer_name_as_c_str().ok() == Some(VALIDATION_LAYER))
            {
                return Err("VK_LAYER_KHRONOS_validation is not installed".into());
            }
        }
        let messages: Messages = Arc::new(Mutex::new(Vec::new()));
        let sink = Box::into_raw(Box::new(messages.clone()));
        // Until `Host` exists, each error path frees what was created so far.
        // SAFETY: `sink` is the Box made just above, freed by this closure only on the error paths
        // before Host owns it (each calls it once and returns), never after the instance that
        // reports through it is destroyed.
        let free_sink = || drop(unsafe { Box::from_raw(sink) });

        let app = vk::ApplicationInfo::default()
            .application_name(c"motion-shadows host")
            .engine_name(c"embed-host")
            .api_version(vk::API_VERSION_1_3);
        let layers = [VALIDATION_LAYER.as_ptr()];
        let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut creation_messenger = messenger_info(sink);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app);
        if validation {
            info = info
                .enabled_layer_names(&layers)
                .enabled_extension_names(&extensions)
                .push_next(&mut features)
                .push_next(&mut creation_messenger);
        }
        // SAFETY: `info` and what it chains (application info, layer and extension names,
        // validation features, the creation messenger pointing at the live sink) are locals alive
        // for the call.
        let instance = match unsafe { entry.create_instance(&info, None) } {
            Ok(i) => i,
            Err(e) => {
                free_sink();
                return Err(format!("vkCreateInstance: {e}"));
            }
        };
        // SAFETY: called only on error paths before Host exists: the instance has no device yet (or
        // the device failed), the messenger (if any) goes before its instance, and the sink after
        // the instance, once.
        let destroy_instance = |instance: &ash::Instance, messenger: Option<Messenger>| unsafe {
            if let Some(m) = messenger {
                m.loader.destroy_debug_utils_messenger(m.handle, None);
            }
            instance.destroy_instance(None);
            free_sink();
        };
        let messenger = if validation {
            let loader = ash::ext::debug_utils::Instance::new(&entry, &instance);
            // SAFETY: the instance has debug utils enabled (the validation branch), and the
            // messenger's sink stays allocated until after the instance is destroyed.
            match unsafe { loader.create_debug_utils_messenger(&messenger_info(sink), None) } {
                Ok(handle) => Some(Messenger { loader, handle }),
                Err(e) => {
                    destroy_instance(&instance, None);
                    return Err(format!("vkCreateDebugUtilsMessengerEXT: {e}"));
                }
            }
        } else {
            None
        };
        // The library's preference (`Context::headless`'s), so that a test that compares the
        // two renders on the same device.
        // SAFETY: the instance is live and made for Vulkan 1.3.
        let (physical, queue_family, mut requirements) =
            match unsafe { DeviceRequirements::choose_device(&instance) } {
                Ok(v) => v,
                Err(e) => {
                    destroy_instance(&instance, messenger);
                    return Err(e.to_string());
                }
            };
        // SAFETY: `physical` was enumerated from the live `instance`.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let device_name = (props.device_name_as_c_str())
            .map(|c| c.to_string_lossy().into_owned())
            .unwrap_or_default();

        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        // What the library asks for on this device: its required features, and the
        // optional ones the device has (shaderStorageImageWriteWithoutFormat for the
        // visibility-mask pass of deferred hosts, hostQueryReset for timestamps).
        edit(&mut requirements.features);
        let enabled = requirements.features;
        let extensions = requirements.extension_names();
        let device_info = requirements.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_extension_names(&extensions),
        );
        // SAFETY: `physical` belongs to `instance` and has every feature the requirements chain
        // (for_device checked it in pick_device); `device_info` and what it points at are locals
        // alive for the call.
        let device = match unsafe { instance.create_device(physical, &device_info, None) } {
            Ok(d) => d,
            Err(e) => {
                destroy_instance(&instance, messenger);
                return Err(format!("vkCreateDevice: {e}"));
            }
        };
        // SAFETY: the device was created just above with one queue of `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };

        let mut host = Host {
            gpu: Gpu {
                entry,
                instance,
                physical,
                device,
                queue_family,
                queue,
                enabled,
            },
            messages,
            device_name,
            pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            messenger,
            sink,
        };
        // From here on, Drop cleans up whatever was created.
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `queue_family` is the family the device was created with a queue of; the pool is
        // destroyed in Drop.
        host.pool = unsafe { host.gpu.device.create_command_pool(&pool_info, None) }
            .map_err(|e| format!("vkCreateCommandPool: {e}"))?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(host.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: `host.pool` was just made on this device; one primary buffer, freed with the
        // pool.
        host.cmd = unsafe { host.gpu.device.allocate_command_buffers(&alloc) }
            .map_err(|e| format!("vkAllocateCommandBuffers: {e}"))?[0];
        // SAFETY: creating an unsignalled fence on the live device has no precondition; it is
        // destroyed in Drop.
        host.fence = unsafe {
            host.gpu
                .device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .map_err(|e| format!("vkCreateFence: {e}"))?;
        Ok(host)
    }

    /// Records `f` into the host's own command buffer, submits it on the host's queue with
    /// the host's fence, and waits for it.
    pub fn record_and_wait(&self, f: impl FnOnce(vk::CommandBuffer)) -> Result<(), String> {
        self.record_and_submit(f)?;
        self.wait()
    }

    /// Records `f` into the host's own command buffer and submits it on the host's queue with
    /// the host's fence, without waiting: the frame is in flight until [`Self::wait`]. The
    /// previous submission must have been waited for.
    pub fn record_and_submit(&self, f: impl FnOnce(vk::CommandBuffer)) -> Result<(), String> {
        let d = &self.device;
        // SAFETY: the previous submission was waited for (this function's documented precondition,
        // which every caller keeps), so `cmd` and the fence are in no pending work; the pool allows
        // resetting one buffer (RESET_COMMAND_BUFFER).
        unsafe {
            d.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(|e| format!("vkResetCommandBuffer: {e}"))?;
            d.reset_fences(&[self.fence])
                .map_err(|e| format!("vkResetFences: {e}"))?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            d.begin_command_buffer(self.cmd, &begin)
                .map_err(|e| format!("vkBeginCommandBuffer: {e}"))?;
        }
        f(self.cmd);
        // SAFETY: `cmd` is still recording (`f` received only its handle), the fence was reset
        // above, and the queue is used by this thread only.
        unsafe {
            d.end_command_buffer(self.cmd)
                .map_err(|e| format!("vkEndCommandBuffer: {e}"))?;
            let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
            let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
            d.queue_submit2(self.queue, &submit, self.fence)
                .map_err(|e| format!("vkQueueSubmit2: {e}"))?;
        }
        Ok(())
    }

    /// Waits for the host's fence (the last submission).
    pub fn wait(&self) -> Result<(), String> {
        // SAFETY: the fence is the host's own, live until Drop.
        unsafe { self.device.wait_for_fences(&[self.fence], true, u64::MAX) }
            .map_err(|e| format!("vkWaitForFences: {e}"))
    }

    /// Destroys the host's device and instance and asserts that the validation layer heard
    /// nothing, also during the teardown (which reports objects left alive on them).
    pub fn assert_clean_teardown(self) {
        let messages = self.messages.clone();
        drop(self);
        let messages = messages.lock().map(|m| m.clone()).unwrap_or_default();
        assert!(
            messages.is_empty(),
            "the validation layer reported {} message(s) on the host's instance:\n{}",
            messages.len(),
            messages.join("\n")
        );
    }

    /// Everything the host's validation messenger collected so far.
    pub fn validation_messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: every library object made on this device was dropped before the host
        // (Context::from_raw's contract, which the tests keep), and waiting idle means nothing is
        // pending; children go before the device, the messenger before its instance, and the sink
        // after it, once.
        unsafe {
            let _ = self.device.device_wait_idle();
            // Null handles (a failed `new`) are ignored by the destroy calls.
            self.device.destroy_fence(self.fence, None);
            // Frees `cmd` with it.
            self.device.destroy_command_pool(self.pool, None);
            if let Some(m) = self.messenger.take() {
                m.loader.destroy_debug_utils_messenger(m.handle, None);
            }
            self.gpu.clone().destroy();
            // SAFETY: nothing refers to the sink once the instance is destroyed.
            drop(Box::from_raw(self.sink));
        }
    }
}

impl std::ops::Deref for Host {
    type Target = Gpu;

    fn deref(&self) -> &Gpu {
        &self.gpu
    }
}
