//! The viewer's own Vulkan instance and device, made the way an engine makes them: the
//! window system's surface extensions on the instance, the swapchain extension on the device,
//! and the features the library asks for chained in ([`DeviceRequirements`]); the library then
//! wraps the device ([`Context::from_raw`]). With validation, the Khronos layer and its
//! synchronization validation report to the viewer's own messenger.

use anyhow::{Context as _, anyhow, bail};
use ash::vk;
use motion_shadows::gpu::{Context, DeviceFeatures, DeviceRequirements};
use std::ffi::{CStr, c_char, c_void};
use std::sync::{Arc, Mutex};
use winit::raw_window_handle::{RawDisplayHandle, RawWindowHandle};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Every warning and error the validation layer reported.
pub type Messages = Arc<Mutex<Vec<String>>>;

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes callback data that is valid for this call, or null.
    let text = unsafe { data.as_ref() }
        // SAFETY: `p_message` of the layer's data is null or a NUL-terminated string valid
        // for this call (the borrow ends before it returns).
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    let line = format!("[{severity:?}] {text}");
    eprintln!("vulkan validation: {line}");
    // SAFETY: `user` is the `Box<Messages>` both messengers were made with (`messenger_info`):
    // freed only in `ViewInstance`'s Drop after the instance (and so every messenger that
    // calls this) is destroyed; shared access only, through the mutex.
    if let Some(sink) = unsafe { (user as *const Messages).as_ref() }
        && let Ok(mut messages) = sink.lock()
    {
        messages.push(line);
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

/// The instance, its messenger and the window's surface; destroyed after the device.
pub struct ViewInstance {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub surface_loader: ash::khr::surface::Instance,
    pub surface: vk::SurfaceKHR,
    pub messages: Messages,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// `Box<Messages>` handed to the layer; freed in Drop after the instance.
    sink: *mut Messages,
}

impl ViewInstance {
    /// An instance for `display` (with the validation layer when `validation`) and a surface
    /// on `window`.
    pub fn new(
        display: RawDisplayHandle,
        window: RawWindowHandle,
        validation: bool,
    ) -> anyhow::Result<Self> {
        // SAFETY: loads the system's libvulkan.so.1 (its initialisers run; the loader is
        // trusted as every Vulkan program trusts it); `entry` keeps it loaded while used.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| anyhow!("the Vulkan loader (libvulkan.so.1) could not be loaded: {e}"))?;
        if validation {
            // SAFETY: `entry` holds a loaded Vulkan loader; the call has no other precondition.
            let layers = unsafe { entry.enumerate_instance_layer_properties() }?;
            if !layers
                .iter()
                .any(|l| l.layer_name_as_c_str().ok() == Some(VALIDATION_LAYER))
            {
                bail!(
                    "MOTION_SHADOWS_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not \
                     installed"
                );
            }
        }
        let surface_extensions = ash_window::enumerate_required_extensions(display)
            .context("the window system's Vulkan surface extensions")?;
        let mut extensions: Vec<*const c_char> = surface_extensions.to_vec();
        if validation {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        let messages: Messages = Arc::new(Mutex::new(Vec::new()));
        let sink = Box::into_raw(Box::new(messages.clone()));
        let app = vk::ApplicationInfo::default()
            .application_name(c"motion-shadows view")
            .engine_name(c"motion-shadows")
            .api_version(vk::API_VERSION_1_3);
        let layers = [VALIDATION_LAYER.as_ptr()];
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut creation_messenger = messenger_info(sink);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_extension_names(&extensions);
        if validation {
            info = info
                .enabled_layer_names(&layers)
                .push_next(&mut features)
                .push_next(&mut creation_messenger);
        }
        // SAFETY: `info` and everything it points to (application info, names, the pNext
        // chain with the validation features and the messenger's info) live on this stack
        // until the call returns; the layer and extensions were found or are the window
        // system's; the messenger's `user` is `sink`, alive until Drop.
        let instance = match unsafe { entry.create_instance(&info, None) } {
            Ok(instance) => instance,
            Err(e) => {
                // SAFETY: `sink` came from `Box::into_raw` above and no instance exists that
                // could call back with it; it is freed once, here (Drop never runs).
                drop(unsafe { Box::from_raw(sink) });
                bail!("vkCreateInstance with the window system's surface extensions: {e}");
            }
        };
        let surface_loader = ash::khr::surface::Instance::new(&entry, &instance);
        // From here on, Drop frees what exists (null handles are ignored).
        let mut this = Self {
            entry,
            instance,
            surface_loader,
            surface: vk::SurfaceKHR::null(),
            messages,
            messenger: None,
            sink,
        };
        if validation {
            let loader = ash::ext::debug_utils::Instance::new(&this.entry, &this.instance);
            // SAFETY: `loader` is of the live instance, made with the debug-utils extension
            // (enabled when `validation`); `sink` outlives the messenger (destroyed first in
            // Drop).
            let handle =
                unsafe { loader.create_debug_utils_messenger(&messenger_info(sink), None) }
                    .context("vkCreateDebugUtilsMessengerEXT")?;
            this.messenger = Some((loader, handle));
        }
        // SAFETY: the handles are the live window's, of the display the instance's surface
        // extensions were enumerated for; the surface is destroyed (Drop) before the window
        // goes (the viewer's GPU state is declared, and so dropped, before its window).
        this.surface = unsafe {
            ash_window::create_surface(&this.entry, &this.instance, display, window, None)
        }
        .context("creating the window's Vulkan surface")?;
        Ok(this)
    }
}

impl Drop for ViewInstance {
    fn drop(&mut self) {
        // SAFETY: every child of the instance is gone: the device, if one was made (the
        // `ViewDevice` that owns this instance destroys it before dropping its `base`), and
        // the swapchain made on the surface (dropped with the frame loop, before the
        // device). The surface may be null (ignored). The sink came from `Box::into_raw` in
        // `new` and is freed once, here, after the instance and its messengers, the only
        // ones that use it.
        unsafe {
            self.surface_loader.destroy_surface(self.surface, None);
            if let Some((loader, handle)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(handle, None);
            }
            self.instance.destroy_instance(None);
            drop(Box::from_raw(self.sink));
        }
    }
}

/// The device (one queue that draws, computes and presents) on a [`ViewInstance`].
pub struct ViewDevice {
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    pub queue: vk::Queue,
    pub device_name: String,
    pub enabled: DeviceFeatures,
    /// Declared last: dropped after the device (Drop) is destroyed.
    pub base: ViewInstance,
}

impl ViewDevice {
    /// The first device (discrete GPUs first, CPU devices last) with the library's features
    /// and a queue family that draws, computes and presents to the surface.
    pub fn new(base: ViewInstance) -> anyhow::Result<Self> {
        let (physical, queue_family, device_name) = pick_device(&base)?;
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        // SAFETY: `physical` was enumerated from the instance.
        let mut requirements = unsafe { DeviceRequirements::for_device(&base.instance, physical) }?;
        let enabled = requirements.features;
        let mut extensions = requirements.extension_names();
        extensions.push(ash::khr::swapchain::NAME.as_ptr());
        let info = requirements.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_extension_names(&extensions),
        );
        // SAFETY: `physical` is the instance's; `info`'s queue family is one of its families
        // (`pick_device`), its chained features and the library's extensions are those it
        // supports (`DeviceRequirements::for_device`; a missing swapchain extension fails the
        // call with EXTENSION_NOT_PRESENT); everything `info` points to lives until the call
        // returns.
        let device = unsafe { base.instance.create_device(physical, &info, None) }
            .context("vkCreateDevice with the swapchain extension")?;
        // SAFETY: the device was made with one queue of `queue_family`, index 0.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        Ok(Self {
            physical,
            device,
            queue_family,
            queue,
            device_name,
            enabled,
            base,
        })
    }

    /// The library's context on this device.
    pub fn context(&self) -> anyhow::Result<Context> {
        // SAFETY: the device was made from `physical` with `queue_family` (graphics and
        // compute) and the features `enabled` says; it outlives the context (the viewer drops
        // the context and its objects first, after waiting for the device).
        Ok(unsafe {
            Context::from_raw(
                &self.base.instance,
                self.physical,
                self.device.clone(),
                self.queue_family,
                self.queue,
                &self.enabled,
            )
        }?)
    }
}

impl Drop for ViewDevice {
    fn drop(&mut self) {
        // SAFETY: every object made on the device is gone: the frame loop owns this device
        // and drops its own objects, the library's context and the swapchain first (its
        // field order; where its start failed, its locals go before its argument); the wait leaves no work pending (or the device is lost and runs
        // none). The instance (`base`) is dropped after this.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_device(None);
        }
    }
}

fn pick_device(base: &ViewInstance) -> anyhow::Result<(vk::PhysicalDevice, u32, String)> {
    let instance = &base.instance;
    // SAFETY: `instance` is alive (borrowed from `base`).
    let devices =
        unsafe { instance.enumerate_physical_devices() }.context("vkEnumeratePhysicalDevices")?;
    let rank = |t: vk::PhysicalDeviceType| match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    };
    let mut best: Option<(u32, vk::PhysicalDevice, u32, String)> = None;
    for physical in devices {
        // SAFETY: enumerated from `instance`.
        if unsafe { DeviceRequirements::for_device(instance, physical) }.is_err() {
            continue;
        }
        // SAFETY: `physical` was enumerated from `instance`.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        // SAFETY: `physical` and `base.surface` belong to the instance the surface loader was
        // made from; `family` is below the count just queried.
        let presents = |family: u32| unsafe {
            base.surface_loader
                .get_physical_device_surface_support(physical, family, base.surface)
                .unwrap_or(false)
        };
        let Some(family) = (0..families.len() as u32).find(|&f| {
            families[f as usize]
                .queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
                && presents(f)
        }) else {
            continue;
        };
        let name = props
            .device_name_as_c_str()
            .map(|c| c.to_string_lossy().into_owned())
            .unwrap_or_default();
        let r = rank(props.device_type);
        if best.as_ref().is_none_or(|b| r < b.0) {
            best = Some((r, physical, family, name));
        }
    }
    best.map(|(_, physical, family, name)| (physical, family, name))
        .ok_or_else(|| {
            anyhow!(
                "no Vulkan 1.3 device with the features motion-shadows needs can present to \
                 this window (is lavapipe, mesa-vulkan-drivers, installed?)"
            )
        })
}
