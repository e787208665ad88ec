//! What a deferred frame is asked for and what it gives back: the method, its settings and
//! their checks, and the frame's result.

use super::stats::PassTime;
use crate::error::{Error, Result};
use crate::output::RadianceImage;
use motion_shadows::technique::Lookup;

/// The largest N of `--method tsm` in a deferred frame.
pub const MAX_DEFERRED_TSM_MAPS: u32 = 1024;

/// How a deferred frame finds each pixel's lit share of the shutter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeferredMethod {
    Temporal,
    /// `maps` depth maps at the centres of equal time strata.
    Tsm {
        maps: u32,
    },
    /// One depth map at mid-shutter.
    Plain,
    /// The exact truth on the CPU.
    Raytrace,
}

impl DeferredMethod {
    pub fn name(&self) -> String {
        match self {
            Self::Temporal => "temporal".to_owned(),
            Self::Tsm { maps } => format!("tsm-{maps}"),
            Self::Plain => "plain".to_owned(),
            Self::Raytrace => "raytrace".to_owned(),
        }
    }
}

impl DeferredSettings {
    /// The method's name, `temporal-exact` for the temporal map with the exact lookup.
    pub fn name(&self) -> String {
        match (self.method, self.lookup) {
            (DeferredMethod::Temporal, Lookup::Exact) => "temporal-exact".to_owned(),
            (method, _) => method.name(),
        }
    }
}

/// What a deferred frame adds to [`RenderSettings`] (whose size, shadow size, receiver test
/// and static-layer choice it uses; spp and seed do not apply).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeferredSettings {
    pub method: DeferredMethod,
    /// The shutter time the G-buffer shows, in [0, 1].
    pub camera_time: f32,
    /// Receivers move as the G-buffer's motion image says (off: each stands still where the
    /// G-buffer shows it, as the mask did before receivers could move).
    pub moving_receivers: bool,
    /// The temporal mask's lookup: the papers' depth lines, or the exact test against the
    /// triangles the map names (`Lookup::Exact`). Read by the temporal method only.
    pub lookup: Lookup,
}

impl Default for DeferredSettings {
    fn default() -> Self {
        Self {
            method: DeferredMethod::Temporal,
            camera_time: 1.0,
            moving_receivers: true,
            lookup: Lookup::DepthLine,
        }
    }
}

impl DeferredSettings {
    pub fn validate(&self) -> Result<()> {
        if !(0.0..=1.0).contains(&self.camera_time) {
            return Err(Error::InvalidArgument(format!(
                "camera time {}: must be in [0, 1]",
                self.camera_time
            )));
        }
        if self.lookup == Lookup::Exact && self.method != DeferredMethod::Temporal {
            return Err(Error::InvalidArgument(format!(
                "the exact lookup is the temporal map's: {} has no such lookup",
                self.method.name()
            )));
        }
        if let DeferredMethod::Tsm { maps } = self.method
            && !(1..=MAX_DEFERRED_TSM_MAPS).contains(&maps)
        {
            return Err(Error::InvalidArgument(format!(
                "TSM maps {maps}: must be 1..={MAX_DEFERRED_TSM_MAPS}"
            )));
        }
        Ok(())
    }
}

/// A deferred frame.
pub struct DeferredResult {
    pub image: RadianceImage,
    /// Per pixel: the lit share of the shutter (1 where no surface is seen).
    pub lit: Vec<f32>,
    /// Per pixel: whether a surface is seen.
    pub hit: Vec<bool>,
    /// Per pixel: the triangle seen (its global id), `u32::MAX` for none: the G-buffer's id
    /// image, or the truth's camera ray's hit. Where a method's and the truth's differ (at
    /// silhouettes, rasterization and the ray may see different faces) their lit shares
    /// belong to different points.
    pub triangle: Vec<u32>,
    /// Per pixel: whether the light reaches the surface at the camera time but for shadows
    /// (it faces the light, inside a spot's cone): where the lit share multiplies the light,
    /// and where comparisons measure it.
    pub facing: Vec<bool>,
    pub method: String,
    /// GPU milliseconds of the timed passes (shadow pass and mask); CPU milliseconds for
    /// the ray tracer.
    pub passes: Vec<PassTime>,
    /// Sum of `passes`: the shadow side of the frame (shadow pass plus mask).
    pub shadow_and_mask_ms: f64,
    /// Bytes of GPU memory the frame's shadow maps occupy: the temporal map's buffers (with
    /// its triangle records, for the exact lookup), or TSM's depth maps (the static map and
    /// the working layers, [`deferred_tsm_bytes`](super::deferred::deferred_tsm_bytes)); 0 for the ray tracer.
    pub shadow_bytes: u64,
    pub wall_ms: f64,
}
