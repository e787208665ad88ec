#![allow(dead_code)]
pub mod coverage_oracle;
pub mod gpu;
// The deferred host's device (`examples/deferred_host/`), shared with the example.
#[path = "../../examples/deferred_host/host.rs"]
pub mod host;
pub mod prism_model;
pub mod rng;
pub mod sampling;
pub mod scene;
pub mod test_shader;
