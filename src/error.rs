//! The library's one error type. Every fallible public function returns [`Result`].

use ash::vk;

/// Everything that can go wrong in the library, with enough figures to act on it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The Vulkan loader (`libvulkan.so.1`) could not be opened.
    #[error(
        "cannot load the Vulkan loader: {0}. Install it (Debian: `apt-get install libvulkan1 mesa-vulkan-drivers`, or run scripts/setup.sh)"
    )]
    Loader(String),

    /// No Vulkan device is visible at all.
    #[error(
        "no Vulkan device found{detail}. For a CPU device install lavapipe (Debian: `apt-get install mesa-vulkan-drivers`, or run scripts/setup.sh); check VK_DRIVER_FILES / VK_ICD_FILENAMES if set"
    )]
    NoDevice { detail: String },

    /// Devices exist, but none has what the technique needs.
    #[error("no suitable Vulkan device: {0}")]
    MissingFeatures(String),

    /// The Khronos validation layer was requested but is not installed.
    #[error(
        "the Vulkan validation layer VK_LAYER_KHRONOS_validation is not installed (Debian: `apt-get install vulkan-validationlayers`)"
    )]
    ValidationLayerMissing,

    /// A Vulkan call failed.
    #[error("Vulkan error in {call}: {result}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },

    /// gpu-allocator could not allocate or free memory.
    #[error("GPU memory allocation for {what} failed: {source}")]
    Allocation {
        what: String,
        #[source]
        source: gpu_allocator::AllocationError,
    },

    /// A buffer the technique needs is larger than the device can address.
    #[error(
        "{what} needs {needed_bytes} bytes ({count} elements of {element_bytes} bytes), but this device can address at most {limit_bytes} bytes in one buffer (maxStorageBufferRange for descriptors, maxMemoryAllocationSize for buffers reached by address); reduce the resolution or the scene"
    )]
    DeviceLimit {
        what: &'static str,
        count: u64,
        element_bytes: u64,
        needed_bytes: u64,
        limit_bytes: u64,
    },

    /// Some shadow-map pixels hold more prism fragments than the generation pass can pair.
    #[error(
        "{pixels} shadow-map pixel(s) hold more than {limit} prism fragments (longest list: {longest}{more}); the generation pass pairs at most {limit} per pixel. The scene has too many moving surfaces behind one another as seen from the light"
    )]
    FragmentListTooLong {
        pixels: u32,
        longest: u32,
        /// " or more" when the count was cut short.
        more: &'static str,
        limit: u32,
    },

    /// A caller-supplied value is out of range.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Attaches the name of the failing Vulkan call to a `vk::Result`.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}
