//! What to install when the library cannot find Vulkan: the command line's advice (the
//! library's errors say what is missing, not how a given distribution provides it).

use motion_shadows::Error;

/// The install advice for `error`, if it is one a package fixes.
pub fn for_error(error: &Error) -> Option<&'static str> {
    match error {
        Error::Loader(_) => Some(
            "install the Vulkan loader and a driver (Debian: `apt-get install libvulkan1 mesa-vulkan-drivers`, or run scripts/setup.sh)",
        ),
        Error::NoDevice { .. } => Some(
            "for a CPU device install lavapipe (Debian: `apt-get install mesa-vulkan-drivers`, or run scripts/setup.sh); check VK_DRIVER_FILES / VK_ICD_FILENAMES if set",
        ),
        Error::ValidationLayerMissing => {
            Some("install it (Debian: `apt-get install vulkan-validationlayers`)")
        }
        _ => None,
    }
}

/// The advice for the first library error in `error`'s chain, if any.
pub fn for_chain(error: &anyhow::Error) -> Option<&'static str> {
    error
        .chain()
        .find_map(|cause| cause.downcast_ref::<Error>())
        .and_then(for_error)
}
