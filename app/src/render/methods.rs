//! The shadow side of each method: what the renderer records before (or, for the reference,
//! instead of) the lighting pass.

use super::times::{REFERENCE_SALT, TSM_SALT, stratified_times};
use super::{FrameInputs, MAP_COPY_PASS, PassTime, RenderSettings, Renderer};
use crate::error::{Error, Result};
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    Counters, CoverageMap, DepthFormat, LightView, LightingTarget, LightingView,
    MAX_COVERAGE_TRIANGLES, NO_TRIANGLE, PlainShadowMap, Samples, ShadowSource, TemporalShadowMap,
};

/// Reference slices recorded per submission: bounds the command buffer, paces progress.
const SLICES_PER_SUBMISSION: u32 = 32;

/// What the scene says, before any pass, about the ranges a temporal frame stores (and the
/// exact lookup's static names): the room its first attempt gets.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RangeBounds {
    ranges: RangeRoom,
    /// At most this many static names (`range_ceiling::RoomAtMost`), where bounded.
    static_names: Option<u64>,
}

/// The ranges' part of [`RangeBounds`].
#[derive(Debug, Clone, Copy)]
enum RangeRoom {
    /// At most this many (`motion_shadows::technique::RangeCeiling`), and the device holds
    /// two buffers of them (the lists and the sorted copy): one attempt.
    AtMost(u64),
    /// No upper bound that fits (`at_most`: the bound, None with the papers' prisms): room
    /// for at least `at_least` (`range_bound.rs`; 0 with the coverage map), grown and run
    /// again until nothing overflowed.
    AtLeast { at_least: u64, at_most: Option<u64> },
}

impl Default for RangeRoom {
    fn default() -> Self {
        Self::AtLeast {
            at_least: 0,
            at_most: None,
        }
    }
}

impl RangeBounds {
    /// The lower bound (about 1 s per million moving triangles) is counted only where the
    /// upper bound is not used: when it is unknown or more than `device_bytes` can address.
    pub(super) fn of(
        scene: &crate::scene::Scene,
        light: &motion_shadows::technique::LightView,
        size: (u32, u32),
        with_coverage: bool,
        device_bytes: u64,
    ) -> Self {
        let room = super::range_ceiling::room_at_most(
            scene,
            light,
            size,
            light.uses_static_layer(with_coverage),
        );
        let at_most = room.map(|room| room.ranges);
        let range_bytes = std::mem::size_of::<motion_shadows::technique::Range>() as u64;
        let ranges = match at_most {
            Some(most) if most.saturating_mul(2 * range_bytes) <= device_bytes => {
                RangeRoom::AtMost(most)
            }
            _ => RangeRoom::AtLeast {
                // The coverage map stores fewer ranges than the pairs the lower bound counts.
                at_least: if with_coverage {
                    0
                } else {
                    super::range_bound::ranges_at_least(scene, light, size)
                },
                at_most,
            },
        };
        Self {
            ranges,
            static_names: room.map(|room| room.static_names),
        }
    }

    /// The upper bound on the ranges, where one is known (the JSON's `ranges_at_most`).
    pub(super) fn at_most(&self) -> Option<u64> {
        match self.ranges {
            RangeRoom::AtMost(most) => Some(most),
            RangeRoom::AtLeast { at_most, .. } => at_most,
        }
    }
}

pub(super) enum ShadowOutcome {
    Temporal {
        map: Box<TemporalShadowMap>,
        coverage: Option<Box<CoverageMap>>,
        attempts: u32,
    },
    Plain(PlainShadowMap),
    TimeDependent(PlainShadowMap),
    /// The reference lit the image itself, slice by slice.
    Lit,
}

impl ShadowOutcome {
    /// What the lighting pass tests against (`None` when the image is already lit).
    pub(super) fn source(&self) -> Option<ShadowSource<'_>> {
        match self {
            Self::Temporal { map, .. } => Some(ShadowSource::Temporal(map)),
            Self::Plain(map) => Some(ShadowSource::Plain(map)),
            Self::TimeDependent(maps) => Some(ShadowSource::TimeDependent(maps)),
            Self::Lit => None,
        }
    }

    pub(super) fn counters(&self) -> Result<Counters> {
        match self {
            Self::Temporal { map, .. } => Ok(map.read_counters()?),
            _ => Ok(Counters::default()),
        }
    }

    pub(super) fn allocated_bytes(&self) -> u64 {
        match self {
            Self::Temporal { map, coverage, .. } => {
                map.allocated_bytes() + coverage.as_ref().map_or(0, |c| c.allocated_bytes())
            }
            Self::Plain(map) | Self::TimeDependent(map) => map.bytes(),
            Self::Lit => 0,
        }
    }

    pub(super) fn coverage_bytes(&self) -> u64 {
        match self {
            Self::Temporal {
                coverage: Some(c), ..
            } => c.allocated_bytes(),
            _ => 0,
        }
    }

    /// The temporal map, if the frame kept static triangles in its static layer.
    fn static_layer_map(&self, light: &LightView) -> Option<&TemporalShadowMap> {
        match self {
            Self::Temporal { map, coverage, .. }
                if map.uses_static_layer(light, coverage.as_deref()) =>
            {
                Some(map)
            }
            _ => None,
        }
    }

    /// Whether any static triangle reached the temporal map's static layer (a download of
    /// the layer: ask only when no fragment reached the lists).
    pub(super) fn static_layer_drawn(&self, ctx: &Context, light: &LightView) -> Result<bool> {
        match self.static_layer_map(light) {
            Some(map) => {
                let layer = map.download_static_layer(ctx)?;
                Ok(layer.iter().any(|&k| k as u32 != NO_TRIANGLE))
            }
            None => Ok(false),
        }
    }

    /// Bytes of the static layer, if the frame used one (8 per texel).
    pub(super) fn static_layer_bytes(&self, light: &LightView, pixels: u64) -> u64 {
        self.static_layer_map(light).map_or(0, |_| 8 * pixels)
    }

    /// Whether the timed shadow pass kept a static layer drawn before it.
    pub(super) fn static_layer_kept(&self, light: &LightView) -> bool {
        light.keep_static_layer && self.static_layer_map(light).is_some()
    }

    pub(super) fn attempts(&self) -> u32 {
        match self {
            Self::Temporal { attempts, .. } => *attempts,
            _ => 1,
        }
    }

    pub(super) fn into_temporal_map(self) -> Option<TemporalShadowMap> {
        match self {
            Self::Temporal { map, .. } => Some(*map),
            _ => None,
        }
    }
}

/// Bytes of a fragment (node) of the temporal map's lists.
const NODE_BYTES: u64 = 16;

/// `count` elements of `what` as the map counts them (u32), or the device-limit refusal with
/// the real count (the map would refuse a count saturated to u32::MAX, printing that).
fn counted(
    count: u64,
    what: &'static str,
    element_bytes: u64,
    ctx: &motion_shadows::gpu::Context,
) -> Result<u32> {
    u32::try_from(count)
        .ok()
        .filter(|&n| n < u32::MAX)
        .ok_or_else(|| {
            motion_shadows::Error::DeviceLimit {
                what,
                count,
                element_bytes,
                needed_bytes: count.saturating_mul(element_bytes),
                limit_bytes: ctx.max_addressed_buffer_bytes(),
            }
            .into()
        })
}

/// [`counted`] for the range buffer.
/// `names` static names as a count the map takes (8 bytes each).
fn counted_names(names: u64, ctx: &motion_shadows::gpu::Context) -> Result<u32> {
    counted(names, "the static name lists", 8, ctx)
}

fn counted_ranges(ranges: u64, ctx: &motion_shadows::gpu::Context) -> Result<u32> {
    let range_bytes = std::mem::size_of::<motion_shadows::technique::Range>() as u64;
    counted(ranges, "the range buffer", range_bytes, ctx)
}

impl Renderer<'_> {
    /// Collection and generation (with the coverage passes between them when `with_coverage`).
    /// The first attempt has room for the upper bound where the device can hold it
    /// ([`RangeRoom::AtMost`]), so it never overflows; otherwise for the lower bound (a map
    /// that cannot hold that is refused before any pass runs), grown and re-run until nothing
    /// overflowed.
    pub(super) fn temporal_shadow(
        &mut self,
        inputs: FrameInputs<'_>,
        settings: &RenderSettings,
        with_coverage: bool,
        bounds: RangeBounds,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<ShadowOutcome> {
        let (width, height) = settings.shadow_size();
        let pixels = width * height;
        let ranges = match bounds.ranges {
            RangeRoom::AtMost(most) => {
                progress(&format!(
                    "shadow pass: the scene's triangles store at most {most} ranges: room for \
                     them, so one attempt"
                ));
                counted_ranges(most, self.ctx)?.max(1)
            }
            RangeRoom::AtLeast { at_least, at_most } => {
                if let Some(most) = at_most {
                    progress(&format!(
                        "shadow pass: the scene's triangles store at most {most} ranges, more \
                         than the device holds twice: room for fewer, grown if they overflow"
                    ));
                }
                if at_least > u64::from(pixels) {
                    progress(&format!(
                        "shadow pass: the moving triangles cover at least {at_least} (texel, \
                         triangle) pairs of the map during the shutter, a range each: room \
                         for them from the first attempt"
                    ));
                }
                counted_ranges(at_least, self.ctx)?.max(pixels)
            }
        };
        // The exact construction with the static layer stores no node (its collection writes
        // the ranges): a node buffer would be memory for nothing.
        let stores_nodes = !inputs.light.collects_ranges(with_coverage);
        let mut map = TemporalShadowMap::with_storage(
            self.ctx,
            width,
            height,
            match (settings.initial_node_capacity, stores_nodes) {
                (Some(nodes), _) => nodes,
                // A range pairs two fragments.
                (None, true) => counted(
                    2 * u64::from(ranges),
                    "the fragment (node) buffer",
                    NODE_BYTES,
                    self.ctx,
                )?,
                (None, false) => 1,
            },
            settings.initial_range_capacity.unwrap_or(ranges),
            settings.range_storage,
        )?
        .with_pruning(settings.pruning);
        if inputs.light.lookup == motion_shadows::technique::Lookup::Exact {
            map.reserve_triangle_records(self.ctx, inputs.draws.id_end())?;
            // Room for every static name the scene may store (none where the still draws
            // are not in the static layer), so that the first attempt does not overflow.
            if let Some(names) = bounds.static_names.filter(|&names| names > 0) {
                map.reserve_static_names(self.ctx, counted_names(names, self.ctx)?)?;
            }
        }
        // The cover rule's pipelines compiled here, not in the timed pass.
        self.passes
            .generation(self.ctx)?
            .prepare(settings.pruning)?;
        let coverage = if with_coverage {
            if inputs.draws.id_end() >= MAX_COVERAGE_TRIANGLES as u64 {
                return Err(Error::InvalidArgument(format!(
                    "the coverage map handles fewer than {MAX_COVERAGE_TRIANGLES} triangles, the scene has {}",
                    inputs.draws.triangle_count()
                )));
            }
            Some(Box::new(CoverageMap::new(self.ctx, width, height)?))
        } else {
            None
        };
        // Only the buffers this frame's path uses (its node buffer where it stores fragments).
        map.prepare_for(self.ctx, inputs.light, coverage.as_deref())?;
        let mut attempts = 0;
        loop {
            attempts += 1;
            // Only where the frame has a static layer (not with the coverage map), and again
            // after the map grew (new buffers).
            if inputs.light.keep_static_layer
                && map.uses_static_layer(inputs.light, coverage.as_deref())
                && map.static_layer_builds() == 0
            {
                // The frame before: draws the static layer that the timed pass keeps.
                progress("shadow pass: the static layer, drawn before the timed frame");
                self.run_timed(&mut Vec::new(), |this, cmd, _| {
                    let FrameInputs { draws, light } = inputs;
                    // SAFETY: as below; the timed pass clears the lists again.
                    unsafe {
                        this.passes.collection(this.ctx)?.record(
                            this.ctx.device(),
                            cmd,
                            draws,
                            light,
                            &map,
                            coverage.as_deref(),
                        )
                    }
                })?;
                // Submitted (and waited for): the timed pass may keep the layer.
                map.static_layer_submitted();
            }
            progress(&format!(
                "shadow pass (attempt {attempts}): {} triangles, room for {} fragments and {} ranges",
                inputs.draws.triangle_count(),
                map.node_capacity(),
                map.range_capacity()
            ));
            self.run_timed(passes, |this, cmd, ts| {
                let device = this.ctx.device();
                let FrameInputs { draws, light } = inputs;
                // SAFETY: a OneShot command buffer of this context, recording, outside
                // rendering; the draw list was uploaded in an earlier submission.
                unsafe {
                    this.passes.collection(this.ctx)?.record(
                        device,
                        cmd,
                        draws,
                        light,
                        &map,
                        coverage.as_deref(),
                    )?;
                    ts.mark(cmd, "collection");
                    if let Some(cover) = &coverage {
                        this.passes
                            .coverage(this.ctx)?
                            .record(device, cmd, draws, light, &map, cover);
                        ts.mark(cmd, "coverage");
                    }
                    this.passes.generation(this.ctx)?.record(device, cmd, &map);
                }
                // SAFETY: the OneShot's recording command buffer after the frame's passes; `ts`
                // outlives its execution (run_timed waits for the OneShot).
                unsafe { ts.mark(cmd, "generation") };
                // SAFETY: the same command buffer, after the frame's passes.
                unsafe { map.record_counter_readback(device, cmd) };
                Ok(())
            })?;
            map.static_layer_submitted();
            let counts = map.read_counters()?;
            if !map.needs_more_room(&counts) {
                map.check_complete(&counts)?;
                return Ok(ShadowOutcome::Temporal {
                    map: Box::new(map),
                    coverage,
                    attempts,
                });
            }
            // The timings of an overflowed attempt do not describe a frame.
            passes.clear();
            progress(&format!(
                "shadow pass needed {} fragments and {} ranges; growing the buffers and re-running",
                counts.node_count, counts.range_count
            ));
            map.grow_to_fit(self.ctx, &counts)?;
        }
    }

    /// One depth-only map per time stratum, each at a random time inside its stratum: as many
    /// draws of the scene as samples per pixel.
    pub(super) fn time_dependent_shadow(
        &mut self,
        inputs: FrameInputs<'_>,
        settings: &RenderSettings,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<ShadowOutcome> {
        let layers = settings.spp;
        progress(&format!("time-dependent shadow maps: {layers} maps"));
        let times = stratified_times(layers, settings.seed, TSM_SALT);
        let maps = self.ordinary_maps(inputs, settings, DepthFormat::DepthOnly, &times, passes)?;
        Ok(ShadowOutcome::TimeDependent(maps))
    }

    pub(super) fn plain_shadow(
        &mut self,
        inputs: FrameInputs<'_>,
        settings: &RenderSettings,
        time: f32,
        passes: &mut Vec<PassTime>,
    ) -> Result<ShadowOutcome> {
        let map = self.ordinary_maps(inputs, settings, DepthFormat::DepthAndId, &[time], passes)?;
        Ok(ShadowOutcome::Plain(map))
    }

    /// One ordinary map per time of `times`, in one timed submission (labelled by format).
    fn ordinary_maps(
        &mut self,
        inputs: FrameInputs<'_>,
        settings: &RenderSettings,
        format: DepthFormat,
        times: &[f32],
        passes: &mut Vec<PassTime>,
    ) -> Result<PlainShadowMap> {
        let (width, height) = settings.shadow_size();
        let layers = times.len() as u32;
        let maps = PlainShadowMap::new(self.ctx, width, height, layers, format)?;
        let label = match format {
            DepthFormat::DepthOnly => "tsm shadow maps",
            DepthFormat::DepthAndId => "plain shadow map",
        };
        self.run_timed(passes, |this, cmd, ts| {
            let device = this.ctx.device();
            // SAFETY: as in `temporal_shadow`.
            unsafe {
                this.passes.plain(this.ctx)?.record_render(
                    device,
                    cmd,
                    inputs.draws,
                    inputs.light,
                    &maps,
                    times,
                )
            };
            // SAFETY: the OneShot's recording command buffer after the maps' rendering; `ts`
            // outlives its execution (run_timed waits).
            unsafe { ts.mark(cmd, label) };
            // SAFETY: the same command buffer, after the maps' rendering.
            unsafe {
                this.passes
                    .plain(this.ctx)?
                    .record_copy_out(device, cmd, &maps)
            };
            // SAFETY: the same command buffer after the copy; `ts` outlives its execution.
            unsafe { ts.mark(cmd, MAP_COPY_PASS) };
            Ok(())
        })?;
        Ok(maps)
    }

    /// Brute force: per slice, an ordinary shadow map at the slice's time and one sample per
    /// pixel at that time (jittered in the pixel), added with weight 1/slices.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn reference(
        &mut self,
        inputs: FrameInputs<'_>,
        view: &LightingView,
        settings: &RenderSettings,
        slices: u32,
        target: &LightingTarget,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<ShadowOutcome> {
        let (width, height) = settings.shadow_size();
        let map = PlainShadowMap::new(self.ctx, width, height, 1, DepthFormat::DepthAndId)?;
        let times = stratified_times(slices, settings.seed, REFERENCE_SALT);
        let mut first = 0;
        while first < slices {
            let last = (first + SLICES_PER_SUBMISSION).min(slices);
            progress(&format!("reference: slices {first}..{last} of {slices}"));
            self.run_timed(passes, |this, cmd, ts| {
                let device = this.ctx.device();
                let FrameInputs { draws, light } = inputs;
                // SAFETY: as in `temporal_shadow`; every slice's map is recorded before the
                // slice's samples in the same command buffer.
                unsafe {
                    if first == 0 {
                        this.passes
                            .lighting(this.ctx)?
                            .record_clear(device, cmd, view, target);
                    }
                    for slice in first..last {
                        let t = times[slice as usize];
                        this.passes
                            .plain(this.ctx)?
                            .record(device, cmd, draws, light, &map, &[t]);
                        let samples = Samples {
                            first: slice,
                            count: 1,
                            fixed_time: Some(t),
                        };
                        this.passes.lighting(this.ctx)?.record_samples(
                            device,
                            cmd,
                            draws,
                            view,
                            ShadowSource::Plain(&map),
                            target,
                            samples,
                            None,
                        )?;
                    }
                }
                // SAFETY: the OneShot's recording command buffer after the reference slices; `ts`
                // outlives its execution.
                unsafe { ts.mark(cmd, "reference slices") };
                Ok(())
            })?;
            first = last;
        }
        Ok(ShadowOutcome::Lit)
    }
}
