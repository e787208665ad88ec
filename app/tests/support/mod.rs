//! The app's GPU tests' helpers: the library's (`tests/support/`: the validated context, the
//! CPU sampling model; the deferred host's device from `examples/deferred_host/`) and their
//! own (scenes through the standalone renderer, host geometry frames).
#![allow(dead_code)]
#[path = "../../../tests/support/gpu.rs"]
pub mod device;
pub mod frame;
pub mod gpu;
#[path = "../../../examples/deferred_host/host.rs"]
pub mod host;
pub mod ray_traced;
#[path = "../../../tests/support/rng.rs"]
pub mod rng;
#[path = "../../../tests/support/sampling.rs"]
pub mod sampling;
