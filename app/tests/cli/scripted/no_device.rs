//! Without a Vulkan driver: a clear error saying what is missing.

use super::*;

/// With no Vulkan driver the binary fails with a message that says what is missing and how
/// to install lavapipe.
#[test]
fn no_device_gives_a_clear_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["render", "--width", "8", "--height", "8", "--spp", "1"])
        .env("VK_DRIVER_FILES", "/nonexistent/no_icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/no_icd.json")
        .env("MOTION_SHADOWS_VALIDATION", "0")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("run the binary");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success(),
        "must fail without a driver; stderr: {stderr}"
    );
    assert!(stderr.contains("no Vulkan device"), "stderr: {stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers"), "stderr: {stderr}");
}
