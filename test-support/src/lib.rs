//! What the tests of the workspace share, compiled once as a dev-dependency instead of being
//! included into each test crate: the library's tests (`tests/gpu/`) use it as `support`, the
//! app's tests (`app/tests/`) for the context, the RNG and the sampling model.
//!
//! Nothing here uses the app: the library's tests need only its public API.

pub mod coverage_oracle;
pub mod deferred_host;
pub mod gpu;
pub mod host;
pub mod host_memory;
pub mod prism_model;
pub mod rng;
pub mod sampling;
pub mod scene;
pub mod test_shader;
