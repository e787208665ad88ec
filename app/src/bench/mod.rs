//! `motion-shadows bench`: the papers' measurements as presets. Each preset renders a sweep,
//! writes a CSV and PNG charts, and reports the key ratios, all measured in the same run on
//! the same device (timings across runs or machines are not comparable; ratios within a run
//! are).

mod measure;
mod presets;

pub use measure::{Measurement, measure};
pub use presets::{PRESETS, Preset, Ratio, Report, run_preset};

use std::path::PathBuf;

/// Sizes of a bench run: `quick` for CI and a first look, `full` for figures.
#[derive(Debug, Clone)]
pub struct Scale {
    pub quick: bool,
    /// Image (and shadow map) size.
    pub width: u32,
    pub height: u32,
    /// Repetitions per configuration; the fastest counts.
    pub runs: u32,
    pub out: PathBuf,
    /// The shadow estimator of the presets' temporal and coverage renders
    /// (`--shadow-estimator`; equal-quality sweeps both whatever it says).
    pub shadow_estimator: motion_shadows::technique::ShadowEstimator,
    /// The prism construction of the presets' temporal and coverage renders (`--prisms`).
    pub prisms: motion_shadows::technique::PrismConstruction,
    /// The receiver test of the presets' renders (`--receiver`).
    pub receiver: crate::render::ReceiverTest,
    /// The shadow-map filter of the presets' renders but the reference (`--shadow-filter`).
    pub shadow_filter: motion_shadows::technique::ShadowFilter,
}

impl Scale {
    pub fn new(quick: bool, out: PathBuf) -> Self {
        let (width, height, runs) = if quick { (256, 192, 2) } else { (1024, 768, 3) };
        Self {
            quick,
            width,
            height,
            runs,
            out,
            shadow_estimator: Default::default(),
            prisms: Default::default(),
            receiver: Default::default(),
            shadow_filter: Default::default(),
        }
    }

    /// The filter `method` renders with: `shadow_filter`, but never for the brute-force
    /// reference (a filtered reference would not converge to the truth).
    pub fn shadow_filter_for(
        &self,
        method: &crate::render::Method,
    ) -> motion_shadows::technique::ShadowFilter {
        match method {
            crate::render::Method::Reference { .. } => Default::default(),
            _ => self.shadow_filter,
        }
    }

    /// `full` for the paper-sized run, `quick` otherwise.
    pub fn pick<T>(&self, quick: T, full: T) -> T {
        if self.quick { quick } else { full }
    }
}
