//! What every GPU test needs: a validated context on a real Vulkan device (lavapipe in CI).
//! The library's tests use it as `support::gpu`; the app's GPU tests (`app/tests/gpu`) as
//! `support::device`, with their scene builders on top.

use motion_shadows::gpu::{Context, ContextOptions};

/// A context with the validation layer and synchronization validation on. No device, or no
/// layer, is a test failure: the suite never skips.
pub fn context() -> Context {
    match Context::headless(&ContextOptions { validation: true }) {
        Ok(ctx) => ctx,
        Err(e) => panic!("GPU tests need a Vulkan device and the validation layer: {e}"),
    }
}

pub fn assert_no_validation_messages(ctx: &Context) {
    let messages = ctx.validation_messages();
    assert!(
        messages.is_empty(),
        "the validation layer reported {} message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}
