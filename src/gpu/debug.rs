//! The Khronos validation layer, with synchronization validation, and a sink that keeps
//! every warning and error it reports so tests can assert that there were none.

use crate::error::{Result, VkContext};
use ash::vk;
use std::ffi::{CStr, c_void};
use std::sync::{Arc, Mutex};

pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

pub(crate) type MessageSink = Arc<Mutex<Vec<String>>>;

pub(crate) struct Messenger {
    loader: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    sink: *mut MessageSink,
}

// SAFETY: the raw sink pointer is only dereferenced by the callback (which locks the mutex)
// and freed in Drop after the messenger is destroyed.
unsafe impl Send for Messenger {}
// SAFETY: as Send: the sink pointer is read only by the callback, through a shared reference to a
// Mutex, and freed once in Drop, which needs &mut; the loader and handle are plain data.
unsafe impl Sync for Messenger {}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data; `user` is the sink we registered.
    let text = unsafe {
        data.as_ref()
            .and_then(|d| d.message_as_c_str())
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let line = format!("[{severity:?}] {text}");
    eprintln!("vulkan validation: {line}");
    // SAFETY: `user` is the pointer messenger_info registered: a Box<MessageSink> that stays
    // allocated until the messenger (or, for the creation sink, the instance) is destroyed, and the
    // layer calls back only while that object exists. Only a shared reference is made, and the
    // Mutex serializes writers.
    if let Some(sink) = unsafe { (user as *const MessageSink).as_ref() } {
        if let Ok(mut messages) = sink.lock() {
            messages.push(line);
        }
    }
    vk::FALSE
}

/// Chained into VkInstanceCreateInfo so that synchronization validation is on.
pub(crate) const VALIDATION_FEATURES: [vk::ValidationFeatureEnableEXT; 1] =
    [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];

pub(crate) fn messenger_info(
    sink: *mut MessageSink,
) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE
                | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(sink as *mut c_void)
}

impl Messenger {
    pub(crate) fn new(
        entry: &ash::Entry,
        instance: &ash::Instance,
        sink: MessageSink,
    ) -> Result<Self> {
        let loader = ash::ext::debug_utils::Instance::new(entry, instance);
        let sink = Box::into_raw(Box::new(sink));
        let info = messenger_info(sink);
        // SAFETY: `info` points at the sink, boxed just above and freed only in Drop or on the
        // error arm below, so it outlives the messenger; `instance` is live and has debug utils
        // enabled (the validation case only).
        match unsafe { loader.create_debug_utils_messenger(&info, None) }
            .vk("vkCreateDebugUtilsMessengerEXT")
        {
            Ok(messenger) => Ok(Self {
                loader,
                messenger,
                sink,
            }),
            Err(e) => {
                // SAFETY: not registered anywhere, so we own it again.
                drop(unsafe { Box::from_raw(sink) });
                Err(e)
            }
        }
    }
}

impl Drop for Messenger {
    fn drop(&mut self) {
        // SAFETY: the messenger was created by this loader and is destroyed once; the sink is freed
        // after it, when no callback can reach it any more.
        unsafe {
            self.loader
                .destroy_debug_utils_messenger(self.messenger, None);
            drop(Box::from_raw(self.sink));
        }
    }
}

pub(crate) fn layer_available(entry: &ash::Entry) -> bool {
    // SAFETY: enumerating the instance layers has no precondition beyond a loaded entry, which
    // `entry` is.
    unsafe { entry.enumerate_instance_layer_properties() }
        .unwrap_or_default()
        .iter()
        .any(|l| l.layer_name_as_c_str().ok() == Some(VALIDATION_LAYER))
}
