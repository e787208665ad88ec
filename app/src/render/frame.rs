//! The steps of [`Renderer::render`]'s frame, in order: the scene uploaded and the views set
//! up, the method's shadow pass, the lighting pass, the frame's refusals and warnings, and
//! its statistics.

use super::methods::RangeBounds;
use super::methods::ShadowOutcome;
use super::stats::{self, FrameStats, PassTime, equation_2_bytes, sorted_map_bytes};
use super::upload::{self, SceneGeometry};
use super::{FrameInputs, Method, RenderSettings, Renderer, empty_map};
use crate::error::Result;
use crate::scene::Scene;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    DrawList, LightView, LightingTarget, LightingView, RangeStorage, ShadowEstimator,
};

/// A frame's scene on the device and its views: what every later step reads.
pub(super) struct PreparedFrame {
    geometry: SceneGeometry,
    draws: DrawList,
    light: LightView,
    view: LightingView,
    /// Samples per pixel the method renders.
    spp: u32,
    /// The most samples one lighting chunk may hold.
    max_chunk: u32,
    /// Bounds on the ranges of the temporal map (`range_bound.rs`, `range_ceiling.rs`).
    range_bounds: RangeBounds,
}

impl PreparedFrame {
    fn inputs(&self) -> FrameInputs<'_> {
        FrameInputs {
            draws: &self.draws,
            light: &self.light,
        }
    }

    /// The lighting pass's target for this frame's size, samples and chunking.
    pub(super) fn lighting_target(
        &self,
        ctx: &Context,
        settings: &RenderSettings,
    ) -> Result<LightingTarget> {
        Ok(LightingTarget::new(
            ctx,
            settings.width,
            settings.height,
            self.spp,
            self.max_chunk,
        )?)
    }
}

/// The stochastic (forward) frame's light as `settings` set it up (receiver test, static
/// layer, lookup). Public for hosts of the same frame (the viewer).
pub fn forward_light(scene: &Scene, settings: &RenderSettings) -> LightView {
    let mut light = LightView {
        prisms: settings.prisms,
        static_layer: settings.static_layer,
        keep_static_layer: settings.static_layer && settings.keep_static_layer,
        lookup: settings.lookup,
        ..upload::light_view(scene, settings.shadow_size())
    };
    if settings.receiver_plane() {
        light.receiver_plane = true;
        light.normal_offset_texels = 0.0;
    }
    light
}

/// What the statistics take from the frame's run.
pub(super) struct Timing {
    pub(super) passes: Vec<PassTime>,
    pub(super) warnings: Vec<String>,
    pub(super) wall_ms: f64,
}

impl Renderer<'_> {
    /// Uploads `scene` (its draws recorded into a draw list) and sets up the light's and the
    /// camera's views as `settings` say.
    pub(super) fn prepare_frame(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        progress: &mut dyn FnMut(&str),
    ) -> Result<PreparedFrame> {
        let ctx = self.ctx;
        // The one place closed meshes around the light or camera are handled: the upload
        // draws them open (`effective_closed`), and the user is told.
        for exception in crate::scene::culling_exceptions(scene) {
            progress(&format!("note: {}", exception.note(scene)));
        }
        progress("uploading the scene");
        let geometry = SceneGeometry::upload(ctx, scene)?;
        let mut draws = DrawList::new(ctx, geometry.draws.len() as u32)?;
        self.run_timed(&mut Vec::new(), |this, cmd, _| {
            // SAFETY: a OneShot command buffer of this context, recording, outside rendering.
            unsafe { draws.record_update(this.ctx.device(), cmd, &geometry.draws) }
        })?;
        let light = upload::with_motion(scene, forward_light(scene, settings))?;
        let view = LightingView {
            camera: super::camera_motion::camera_view(scene, (settings.width, settings.height))?,
            seed: settings.seed,
            ambient: scene.ambient,
            estimator: settings.shadow_estimator,
            filter: settings.shadow_filter,
        };
        let max_chunk = match settings.method {
            // One slice per chunk: each slice has a shadow map of its own.
            Method::Reference { .. } => 1,
            _ => settings.max_samples_per_chunk,
        };
        let range_bounds = match settings.method {
            Method::Temporal | Method::Coverage => RangeBounds::of(
                scene,
                &light,
                settings.shadow_size(),
                settings.method == Method::Coverage,
                ctx.max_addressed_buffer_bytes(),
            ),
            _ => RangeBounds::default(),
        };
        Ok(PreparedFrame {
            geometry,
            draws,
            light,
            view,
            spp: settings.method.samples_per_pixel(settings.spp),
            max_chunk,
            range_bounds,
        })
    }

    /// The method's shadow pass (the reference renders its slices into `target` here).
    pub(super) fn shadow_pass(
        &mut self,
        frame: &PreparedFrame,
        settings: &RenderSettings,
        target: &LightingTarget,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<ShadowOutcome> {
        let inputs = frame.inputs();
        match settings.method {
            Method::Temporal | Method::Coverage => self.temporal_shadow(
                inputs,
                settings,
                settings.method == Method::Coverage,
                frame.range_bounds,
                passes,
                progress,
            ),
            Method::Tsm => self.time_dependent_shadow(inputs, settings, passes, progress),
            Method::Plain { time } => self.plain_shadow(inputs, settings, time, passes),
            Method::Reference { slices } => self.reference(
                inputs,
                &frame.view,
                settings,
                slices,
                target,
                passes,
                progress,
            ),
            Method::Raytrace => unreachable!("refused by Renderer::render"),
        }
    }

    /// The lighting pass over `outcome`'s shadows into `target`, or (the reference, which
    /// lit its slices already) its read-back. Where the device's loop limit cut a chunk's
    /// lookups short, the pass runs again with one sample per invocation: returns the
    /// target that holds the frame.
    pub(super) fn shade(
        &mut self,
        frame: &PreparedFrame,
        settings: &RenderSettings,
        outcome: &ShadowOutcome,
        target: LightingTarget,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<LightingTarget> {
        let Some(shadow) = outcome.source() else {
            self.run_timed(passes, |this, cmd, _| {
                // SAFETY: the same command buffer, after the frame's passes.
                unsafe { target.record_readback(this.ctx.device(), cmd) };
                Ok(())
            })?;
            return Ok(target);
        };
        progress(&format!(
            "lighting pass: {}x{} pixels, {} spp",
            settings.width, settings.height, settings.spp
        ));
        self.light(&frame.draws, &frame.view, shadow, &target, passes)?;
        let over = target.read_over_budget_pixels()?;
        if over == 0 || frame.max_chunk == 1 {
            return Ok(target);
        }
        // Each invocation shades one sample instead: its lookups then fit.
        progress(&format!(
            "lighting pass: {over} pixel(s) need more loop iterations than this device runs \
             per invocation; again, one sample per pass"
        ));
        let target = LightingTarget::new(self.ctx, settings.width, settings.height, frame.spp, 1)?;
        passes.retain(|p| !p.pass.starts_with("lighting"));
        self.light(&frame.draws, &frame.view, shadow, &target, passes)?;
        Ok(target)
    }
}

/// The frame's refusals: pixels whose lookups a loop limit still cut short, and triangles
/// the collection dropped for an invalid index.
pub(super) fn check_target(ctx: &Context, target: &LightingTarget) -> Result<()> {
    let over = target.read_over_budget_pixels()?;
    if over > 0 {
        let limit = ctx.info().shader_loop_limit.unwrap_or(0);
        return Err(motion_shadows::Error::LoopLimit {
            pixels: over,
            limit,
        }
        .into());
    }
    let invalid = target.read_invalid_triangles()?;
    if invalid > 0 {
        return Err(motion_shadows::Error::InvalidIndices { triangles: invalid }.into());
    }
    Ok(())
}

/// What the user should know about an image that rendered: a temporal map that received
/// nothing (the exact prisms' one inexact case, a plane through the spot light, is exact now).
pub(super) fn warnings(
    ctx: &Context,
    scene: &Scene,
    settings: &RenderSettings,
    frame: &PreparedFrame,
    outcome: &ShadowOutcome,
) -> Result<Vec<String>> {
    let mut warnings = Vec::new();
    let temporal = matches!(outcome, ShadowOutcome::Temporal { .. });
    if temporal
        && outcome.counters()?.node_count == 0
        && frame.geometry.triangle_count > 0
        && !outcome.static_layer_drawn(ctx, &frame.light)?
    {
        warnings.push(empty_map::empty_map_warning(
            scene,
            &frame.light,
            settings.shadow_size(),
            settings.prisms,
        ));
    }
    Ok(warnings)
}

/// The frame's statistics (the `--json` summary's fields).
pub(super) fn stats(
    ctx: &Context,
    scene: &Scene,
    settings: &RenderSettings,
    frame: &PreparedFrame,
    outcome: &ShadowOutcome,
    target: &LightingTarget,
    timing: Timing,
) -> Result<FrameStats> {
    let counts = outcome.counters()?;
    let shadow_size = settings.shadow_size();
    let shadow_pixels = shadow_size.0 as u64 * shadow_size.1 as u64;
    let (fragments, ranges) = (counts.node_count as u64, counts.range_count as u64);
    let fragments_stored = if counts.ranges_direct != 0 {
        0
    } else {
        fragments
    };
    let temporal = matches!(outcome, ShadowOutcome::Temporal { .. });
    // The collection stored the ranges and the map sorted them.
    let sorted =
        temporal && counts.ranges_direct != 0 && settings.range_storage == RangeStorage::Sorted;
    let eq2 = |ranges: u64| match (temporal, sorted) {
        (false, _) => 0,
        (true, false) => equation_2_bytes(fragments_stored, ranges, shadow_pixels),
        (true, true) => sorted_map_bytes(ranges, shadow_pixels),
    };
    let Timing {
        passes,
        warnings,
        wall_ms,
    } = timing;
    Ok(FrameStats {
        scene: scene.name.clone(),
        method: settings.method_name().to_owned(),
        shadow_estimator: match settings.shadow_estimator {
            ShadowEstimator::Sampled => "sampled",
            ShadowEstimator::Analytic => "analytic",
        }
        .to_owned(),
        shadow_filter: stats::filter_name(settings.shadow_filter).to_owned(),
        prisms: stats::prisms_name(settings.prisms).to_owned(),
        range_storage: if sorted { "sorted" } else { "lists" }.to_owned(),
        pruning: if sorted {
            stats::pruning_name(settings.pruning)
        } else {
            "none"
        }
        .to_owned(),
        lookup: stats::lookup_name(settings.method, settings.lookup).to_owned(),
        receiver_plane: settings.receiver_plane(),
        width: settings.width,
        height: settings.height,
        shadow_width: shadow_size.0,
        shadow_height: shadow_size.1,
        spp: frame.spp,
        seed: settings.seed,
        triangles: frame.geometry.triangle_count,
        fragments,
        fragments_stored,
        ranges,
        ranges_without_coverage: counts.ranges_without_coverage as u64,
        shadow_map_bytes_eq2: if sorted {
            sorted_map_bytes(counts.sorted_count as u64, shadow_pixels)
        } else {
            eq2(ranges)
        },
        shadow_map_bytes_eq2_unpruned: eq2(ranges),
        ranges_pruned: if sorted {
            ranges - counts.sorted_count as u64
        } else {
            0
        },
        shadow_map_bytes_transient: if sorted {
            sorted_map_bytes(ranges, shadow_pixels)
        } else {
            0
        },
        static_layer_bytes: outcome.static_layer_bytes(&frame.light, shadow_pixels),
        static_layer_kept: outcome.static_layer_kept(&frame.light),
        light_moves: scene.light.moves(),
        camera_moves: scene.camera.moves(),
        shadow_map_bytes_eq2_without_coverage: eq2(counts.ranges_without_coverage as u64),
        coverage_map_bytes: outcome.coverage_bytes(),
        shadow_map_bytes_allocated: outcome.allocated_bytes(),
        shadow_pass_attempts: outcome.attempts(),
        ranges_at_most: frame.range_bounds.at_most(),
        longest_fragment_list: counts.longest_list,
        samples_per_chunk: target.samples_per_chunk(),
        shadow_pass_ms: stats::counted_ms(&passes, |p| !stats::is_lighting_pass(p)),
        lighting_pass_ms: stats::counted_ms(&passes, stats::is_lighting_pass),
        frame_ms: stats::counted_ms(&passes, |_| true),
        runs: 1,
        passes,
        warnings,
        wall_ms,
        device: format!("{} ({})", ctx.info().name, ctx.info().driver),
    })
}
