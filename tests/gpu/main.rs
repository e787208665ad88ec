//! GPU tests: every one runs on a real Vulkan device (lavapipe in CI) with the validation
//! layer and synchronization validation on, and fails if either is missing.

#[path = "../support/mod.rs"]
mod support;

mod analytic;
mod analytic_estimator;
mod baselines;
mod bench;
mod character;
mod coverage;
mod crossing_prism;
mod deferred_host;
mod device_setup;
mod embedding;
mod engine_tsm;
mod errors;
mod exact_prisms;
mod filtered_lookup;
mod generation;
mod host_geometry;
mod layout;
mod lighting;
mod loop_limit;
mod prism;
mod receiver_plane;
mod several_runs;
mod static_layer;
mod validation;
mod visibility;
