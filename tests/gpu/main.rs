//! GPU tests: every one runs on a real Vulkan device (lavapipe in CI) with the validation
//! layer and synchronization validation on, and fails if either is missing. These need only
//! the library's public API; the tests that use the app (its standalone renderer, scenes, ray
//! tracer, compare and bench) are in `app/tests/gpu/`.

use motion_shadows_test_support as support;

mod access_check;
mod analytic;
mod conservative_collection;
mod crossing_prism;
mod deferred_host;
mod device_setup;
mod engine_api;
mod engine_api_mask;
mod engine_tsm;
mod exact_lookup;
mod exact_prisms;
mod footprint_hull;
mod footprint_hull_ties;
mod gbuffer_declared;
mod host_memory;
mod layout;
mod lighting_declared;
mod map_bytes;
mod mask_ids;
mod minimal_host;
mod own_barriers;
mod pass_accesses;
mod prism;
mod pruning_model;
mod range_ceiling;
mod several_runs;
mod sorted_ranges;
mod static_layer;
mod validation;
