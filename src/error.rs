//! The library's one error type. Every fallible public function returns [`Result`].

use ash::vk;

/// Everything that can go wrong in the library, with enough figures to act on it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The Vulkan loader (`libvulkan.so.1`) could not be opened.
    #[error("cannot load the Vulkan loader (libvulkan.so.1 / vulkan-1.dll): {0}")]
    Loader(String),

    /// No Vulkan device is visible at all.
    #[error("no Vulkan device found{detail}; a GPU driver or lavapipe (a CPU device) provides one")]
    NoDevice {
        /// What the loader said, if anything.
        detail: String,
    },

    /// Devices exist, but none has what the technique needs.
    #[error("no suitable Vulkan device: {0}")]
    MissingFeatures(String),

    /// A host's device (`Context::from_raw`) was created without features the library
    /// requires.
    #[error(
        "the device was created without {detail}; enable them when creating it (gpu::DeviceRequirements lists what to chain into VkDeviceCreateInfo)"
    )]
    FeaturesNotEnabled {
        /// The Vulkan names of the features that are off (`geometryShader`, ...).
        missing: Vec<&'static str>,
        /// Each with what the library uses it for.
        detail: String,
    },

    /// The Khronos validation layer was requested but is not installed.
    #[error("the Vulkan validation layer VK_LAYER_KHRONOS_validation is not installed")]
    ValidationLayerMissing,

    /// A Vulkan call failed.
    #[error("Vulkan error in {call}: {result}")]
    Vulkan {
        /// The Vulkan function.
        call: &'static str,
        /// What it returned.
        result: vk::Result,
    },

    /// gpu-allocator could not allocate or free memory.
    #[error("GPU memory allocation for {what} failed: {source}")]
    Allocation {
        /// The buffer (name and size).
        what: String,
        /// gpu-allocator's error.
        #[source]
        source: gpu_allocator::AllocationError,
    },

    /// A buffer the technique needs is larger than the device can address.
    #[error(
        "{what} needs {needed_bytes} bytes ({count} elements of {element_bytes} bytes), but this device can address at most {limit_bytes} bytes in one buffer (maxMemoryAllocationSize: every buffer is reached by address); reduce the resolution or the scene"
    )]
    DeviceLimit {
        /// The buffer.
        what: &'static str,
        /// Elements it needs.
        count: u64,
        /// Bytes per element.
        element_bytes: u64,
        /// Bytes it needs.
        needed_bytes: u64,
        /// Bytes the device allows.
        limit_bytes: u64,
    },

    /// Some shadow-map pixels hold more prism fragments than the generation pass can pair.
    #[error(
        "{pixels} shadow-map pixel(s) hold more than {limit} prism fragments (longest list: {longest}{more}); the generation pass pairs at most {limit} per pixel. Too many surfaces lie behind one another (or overlap) along one ray from the light: reduce the depth complexity the light sees there, or the shadow-map resolution"
    )]
    FragmentListTooLong {
        /// Pixels whose lists were too long.
        pixels: u32,
        /// The longest list (counted up to 8 times the limit).
        longest: u32,
        /// " or more" when the count was cut short.
        more: &'static str,
        /// [`crate::technique::MAX_LIST_NODES`].
        limit: u32,
    },

    /// Some triangles were not drawn because an index pointed past their draw's vertex count.
    #[error(
        "{triangles} triangle(s) have an index at or past their draw's vertex count and were not drawn; check the index buffers and vertex counts of the draws"
    )]
    InvalidIndices {
        /// Triangles dropped.
        triangles: u32,
    },

    /// On a device that leaves shader loops after a fixed number of iterations (lavapipe),
    /// the shadow lookups of some pixels needed more than their share even at one sample
    /// per invocation, so their shading may have been cut short.
    #[error(
        "{pixels} pixel(s) need more shader loop iterations for their shadow lookups than this device runs ({limit} per invocation, lavapipe's loop limiter): their shading could be wrong. Read fewer texels per lookup (no shadow filter), use the sampled estimator, or a device without the limit"
    )]
    LoopLimit {
        /// Pixels over the budget.
        pixels: u32,
        /// The device's limit.
        limit: u32,
    },

    /// A frame produced 2^32 fragments or more: the 32-bit fragment counter wrapped, so its
    /// figures cannot size the buffers.
    #[error(
        "the frame produced 2^32 prism fragments or more (the fragment counter wrapped); reduce the shadow-map resolution or the scene"
    )]
    FragmentCountOverflow,

    /// The debug check of declared accesses ([`crate::gpu::AccessCheck`]) found a pass
    /// whose declared use of a buffer came after a conflicting one (a write on either side)
    /// with no reported barrier ordering the two.
    #[error(
        "no barrier orders {resource}'s use by {next} after its use by {previous}: record the barrier the passes' declared accesses give (technique::Barrier::between) and report it (gpu::AccessCheck::report_barrier)"
    )]
    MissingBarrier {
        /// The buffer (as the declarations name it, e.g. `"ranges"`).
        resource: String,
        /// The earlier use: the pass and its last access (stages: accesses).
        previous: String,
        /// The later use: the pass and its first access.
        next: String,
    },

    /// A frame stored more ranges than the room reserved for it from its meshes' CPU
    /// geometry and bounds: a [`crate::MeshBound`] did not hold its mesh's GPU positions (or,
    /// for a moving light, whose room is not bounded, the map was too small). The
    /// ranges past the room were dropped, so the frame's shadow is incomplete; the map has
    /// been grown to what the frame needed.
    #[error(
        "frame {frame} stored {stored} shadow ranges, more than the {reserved} it had room for: a mesh's bound (MeshBound) does not hold its GPU positions, or the room could not be bounded (a moving light); the frame's shadow is incomplete, the map was grown to fit"
    )]
    RoomExceeded {
        /// The frame.
        frame: u64,
        /// Ranges the frame stored (counted past the room too).
        stored: u32,
        /// Ranges reserved.
        reserved: u32,
    },

    /// The visibility mask of a frame ([`crate::LightShadow::finish_frame`]) has pixels whose
    /// lookups ran past the device's loop budget (lavapipe's loop limiter): their values may
    /// have been cut short, so the mask cannot be trusted at those pixels. The map and its
    /// shadow are complete; what ran too long is one texel's list (a shadow that comes and
    /// goes very often in the shutter) or a receiver's path longer than the follow-up rounds
    /// cover.
    #[error(
        "frame {frame}: {pixels} mask pixel(s) need more loop iterations than this device runs (lavapipe's loop limiter): their visibility-mask values may be cut short. Use a coarser map, shorter motion, or a device without the limit"
    )]
    MaskCutShort {
        /// The frame.
        frame: u64,
        /// Pixels counted past the budget.
        pixels: u32,
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
