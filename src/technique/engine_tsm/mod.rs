//! Time-dependent shadow maps (Akenine-Moller, Munkberg and Hasselgren 2007) as an engine
//! builds them, for the deferred frame: the baseline the temporal map's
//! [`super::VisibilityMaskPass`] is compared against, built to be as fast as is honest.
//!
//! For N maps at the times t_i = (i + 0.5) / N: start a D32 depth map from the static draws'
//! map (drawn once and kept across frames, like the temporal map's kept static layer), draw
//! the moving draws at t_i into it depth-only (`shadow_depth.vert`, as
//! [`super::PlainShadowPass`] draws), and test the host's G-buffer (the same
//! [`super::MaskInputs`] as the temporal mask) against it: each pixel's point moved to
//! `p + (t_i - time) * motion`, tested with the temporal map's own receiver test
//! (`ms_receiver_texel` in `glsl/motion_shadows.glsl`: normal offset, receiver-plane depth,
//! light bias) against the map's depth read through a sampled image, and counted lit or not.
//! The host's image ends as the lit fraction of the N times, which converges to the shutter's
//! lit fraction as N grows (error at most about 1/N plus a texel's worth of motion).
//!
//! The maps are drawn in batches of [`EngineTsmMap::layers`] (the layers of the working map,
//! an array image), and one compute dispatch (`glsl/tsm_mask.comp`) tests every pixel against
//! the batch's maps: the pixel's G-buffer point, normal and the light are read once per
//! batch, the output image read and written once per batch (the first batch writes its count
//! of lit maps, later ones add theirs, the last scales the sum by 1/N). On lavapipe that
//! per-pixel work, not the lookups, is most of a dispatch, so layers trade memory (4 bytes per
//! texel and layer) for time (measured in docs/src/deferred-frame.md).
//!
//! How each map starts from the static draws is [`TsmStart`]: an image copy of the static
//! map into the working map's layer ([`TsmStart::Copy`]), or a cleared layer and a second
//! lookup of the static map in the mask shader ([`TsmStart::SecondLookup`]). Both give the
//! same answers, bit for bit.
//!
//! The map's images are [`EngineTsmMap`] (`map.rs`); the pipelines and the recording are
//! [`EngineTsmPass`] (`pass.rs`), whose record runs the steps of `steps.rs` on the commands of
//! `commands.rs` with an [`EngineTsmBindings`] (`bindings.rs`); the refusals are in
//! `checks.rs`.

mod accesses;
mod bindings;
mod checks;
mod commands;
mod map;
mod pass;
mod steps;

use ash::vk;

pub use bindings::EngineTsmBindings;
pub use map::EngineTsmMap;
pub use pass::EngineTsmPass;

/// The most maps one [`EngineTsmPass::record`] draws (the papers compare up to 64; 1,024
/// leaves room for a reference, and keeps the count of lit maps exact in the R32 image).
pub const MAX_TSM_MAPS: u32 = 1024;
/// The most layers an [`EngineTsmMap`]'s working map may have (maps per dispatch).
pub const MAX_TSM_LAYERS: u32 = 64;

/// The maps' format: 32-bit float depth, as the ordinary shadow maps.
const MAP_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// How each of the N maps starts from the static draws' map.
///
/// Copying is the default: on lavapipe a copy costs less than a second lookup over a 1080p
/// G-buffer (docs/src/deferred-frame.md has the figures). On a GPU both are cheap and the
/// balance may differ: measure there.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TsmStart {
    /// Copy the static map into the working map's layer (a depth image copy per map), then
    /// draw the moving draws into it: one lookup per pixel and map.
    #[default]
    Copy,
    /// Clear the working map's layer (the render pass's load op), draw the moving draws into
    /// it, and look up both it and the static map per pixel (the nearer depth wins): no copy,
    /// two lookups.
    SecondLookup,
}
