//! A context of the library's own: it loads Vulkan, makes the instance (with the validation
//! layer when asked), picks a device and creates it, undoing each step if a later one fails.

use super::shared::Owned;
use super::{Context, new_allocator};
use crate::error::{Error, Result};
use crate::gpu::debug::{self, MessageSink, Messenger};
use crate::gpu::device_select;
use ash::vk;
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
}
