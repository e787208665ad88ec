//! GPU tests: every one runs on a real Vulkan device (lavapipe in CI) with the validation
//! layer and synchronization validation on, and fails if either is missing. These use the
//! app (its standalone renderer, scenes, ray tracer, compare and bench) as the library's
//! client or as an independent reference; the tests that need only the library's public API
//! are in the library's `tests/gpu/`.

mod support;

mod analytic_estimator;
mod baselines;
mod bench;
mod character;
mod coverage;
mod deferred_exact;
mod deferred_frame;
mod deferred_host;
mod deferred_long_paths;
mod embedding;
mod errors;
mod exact_lookup_lighting;
mod exact_shadow;
mod filtered_lookup;
mod generation;
mod host_geometry;
mod lighting;
mod loop_limit;
mod moving_camera;
mod moving_camera_deferred;
mod moving_light;
mod moving_light_deferred_tsm;
mod moving_light_deferred_turn;
mod moving_light_exact;
mod range_bound;
mod range_storage;
mod raytrace;
mod receiver_plane;
mod static_layer;
mod through_light;
mod visibility;
