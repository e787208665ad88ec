//! The app's GPU tests' helpers: the workspace's (`test-support/`: the validated context, the
//! CPU sampling model, the deferred host's device) and their own (scenes through the standalone
//! renderer, host geometry frames).
#![allow(dead_code)]
pub mod frame;
pub mod gpu;
pub mod ray_traced;
pub use motion_shadows_test_support::gpu as device;
pub use motion_shadows_test_support::{deferred_host, host, host_memory, rng, sampling};
