//! One measured render: the renderer's figures, the frame's GPU time, repeated so the first
//! (cold) run's shader compilation and cache misses do not count.

use crate::error::Result;
use crate::output::RadianceImage;
use crate::render::{FrameStats, RenderSettings, Renderer, counted_ms};
use crate::scene::Scene;

/// A render's figures, from its fastest of `runs` repetitions (GPU time per pass summed).
pub struct Measurement {
    pub stats: FrameStats,
    pub image: RadianceImage,
    pub moving_coverage: Vec<f32>,
}

impl Measurement {
    /// GPU milliseconds of the passes whose names `keep` accepts.
    pub fn gpu_ms_where(&self, keep: impl Fn(&str) -> bool) -> f64 {
        counted_ms(&self.stats.passes, keep)
    }

    /// GPU milliseconds of the whole frame (the render's `frame_ms`).
    pub fn frame_ms(&self) -> f64 {
        self.stats.frame_ms
    }

    /// GPU milliseconds of the shadow side: everything before the lighting pass.
    pub fn shadow_ms(&self) -> f64 {
        self.stats.shadow_pass_ms
    }

    pub fn lighting_ms(&self) -> f64 {
        self.stats.lighting_pass_ms
    }

    /// Shadow-map bytes as the papers count them: equation (2) for the temporal methods (plus
    /// the static layer, where the frame had one), the maps themselves for the others.
    pub fn shadow_bytes(&self) -> u64 {
        if self.stats.shadow_map_bytes_eq2 > 0 {
            self.stats.shadow_map_bytes_eq2 + self.stats.static_layer_bytes
        } else {
            self.stats.shadow_map_bytes_allocated
        }
    }
}

/// Renders `runs` times (at least once) and keeps the fastest frame.
pub fn measure(
    renderer: &mut Renderer<'_>,
    scene: &Scene,
    settings: &RenderSettings,
    runs: u32,
) -> Result<Measurement> {
    let mut best: Option<Measurement> = None;
    for _ in 0..runs.max(1) {
        let result = crate::frame::render(Some(&mut *renderer), scene, settings, &mut |_| {})?;
        let m = Measurement {
            stats: result.stats,
            image: result.image,
            moving_coverage: result.moving_coverage,
        };
        if best.as_ref().is_none_or(|b| m.frame_ms() < b.frame_ms()) {
            best = Some(m);
        }
    }
    Ok(best.expect("at least one run"))
}
