//! Layer 3: the standalone renderer. It creates nothing but what a frame needs on a given
//! [`Context`], drives the passes, submits and waits, and re-runs the shadow pass when its
//! buffers were too small, so its output is always exact.
//!
//! One frame, in order: scene -> [`upload::flatten`] -> GPU buffers -> the method's shadow
//! pass (for the temporal method: collection and generation, counters read back, grown and
//! re-run if needed) -> lighting -> radiance read back -> [`RadianceImage`].

pub mod camera_motion;
pub mod deferred;
pub mod deferred_settings;
mod empty_map;
mod frame;
mod mask_walks;
mod methods;
mod passes;
pub mod range_bound;
pub mod range_ceiling;
mod receiver;
pub mod stats;
pub mod times;
pub mod turning_light;
pub mod upload;

use crate::error::{Error, Result};
use crate::output::RadianceImage;
use crate::scene::Scene;
pub use frame::forward_light;
use motion_shadows::gpu::{Context, OneShot, TimestampQueries};
use motion_shadows::technique::{
    DrawList, LightView, LightingTarget, LightingView, Lookup, MAX_SAMPLES_PER_CHUNK,
    PrismConstruction, Pruning, RangeStorage, ShadowEstimator, ShadowFilter, TemporalShadowMap,
};
pub use receiver::ReceiverTest;
pub use stats::{
    FrameStats, MAP_COPY_PASS, PassTime, counted_ms, equation_2_bytes, sorted_map_bytes,
};
use std::time::Instant;

/// Which shadow method renders the frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// The depth-time ranges shadow map (Hong & Oh 2018).
    Temporal,
    /// The temporal shadow map with the coverage map of the 2017 paper: pixels one triangle
    /// covers, nearest, all frame long keep only that triangle's range.
    Coverage,
    /// Time-dependent shadow maps (Akenine-Moller et al. 2007, as McGuire et al. 2010 run
    /// them): one depth map per time stratum, at a random time in it; sample k tests the map
    /// of its stratum.
    Tsm,
    /// Brute force: the scene at `slices` stratified times, each with an ordinary shadow map
    /// at that time and one jittered sample per pixel, averaged. The papers' ground truth.
    Reference { slices: u32 },
    /// One ordinary shadow map of the scene frozen at `time`, for every sample. Exact for
    /// static scenes; the baseline for checks.
    Plain { time: f32 },
    /// No shadow map: the lighting pass's samples ray traced on the CPU against the
    /// triangles at each sample's time (see [`crate::raytrace`]). The exact truth.
    Raytrace,
}

impl Method {
    pub fn name(&self) -> &'static str {
        match self {
            Method::Temporal => "temporal",
            Method::Coverage => "coverage",
            Method::Tsm => "tsm",
            Method::Reference { .. } => "reference",
            Method::Plain { .. } => "plain",
            Method::Raytrace => "raytrace",
        }
    }

    /// Samples each pixel averages: the slices of the reference, else the settings' spp.
    fn samples_per_pixel(&self, spp: u32) -> u32 {
        match self {
            Method::Reference { slices } => *slices,
            _ => spp,
        }
    }
}

pub const MAX_REFERENCE_SLICES: u32 = 100_000;
pub const MAX_SPP: u32 = 64;
pub const MAX_IMAGE_SIDE: u32 = 16384;

#[derive(Debug, Clone)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u32,
    /// Shadow map resolution; the image resolution when `None` (as in the papers).
    pub shadow_size: Option<(u32, u32)>,
    pub method: Method,
    /// Starting capacities of the fragment and range buffers; `None` picks a guess. Any
    /// value gives the same image: too small only costs a re-run.
    pub initial_node_capacity: Option<u32>,
    pub initial_range_capacity: Option<u32>,
    /// Samples per pixel one lighting geometry pass handles (1 = one pass per sample; for
    /// measurements). Any value gives the same image.
    pub max_samples_per_chunk: u32,
    /// How the temporal and coverage methods estimate the shadow term.
    pub shadow_estimator: ShadowEstimator,
    /// How every shadow-map method reads its maps around a receiver (the ray tracer has
    /// none).
    pub shadow_filter: ShadowFilter,
    /// How the temporal and coverage methods' collection pass builds the prisms.
    pub prisms: PrismConstruction,
    /// How receivers are tested against the maps: at their plane's depth at the texel centre
    /// without normal offset (`LightView::receiver_plane`), or offset along their normal.
    pub receiver: ReceiverTest,
    /// Keep static triangles in the temporal map's static layer (`LightView::static_layer`;
    /// off: in the lists, as the papers do).
    pub static_layer: bool,
    /// With `static_layer`: render the frame as an engine renders every frame after its
    /// first when it keeps the static layer (`LightView::keep_static_layer`): the layer is
    /// drawn in a shadow pass before the timed one (not timed, not counted), and the timed
    /// pass draws only what moves. The image is the same.
    pub keep_static_layer: bool,
    /// How the temporal map keeps the ranges its collection stores (`--range-storage`).
    pub range_storage: RangeStorage,
    /// Which ranges the sort of sorted ranges leaves out (`--pruning`).
    pub pruning: Pruning,
    /// How the temporal method's lighting reads its map (`--lookup`): the papers' depth lines,
    /// or each sample's shadow ray against the triangles its texel names
    /// ([`Lookup::Exact`]: the conservative collection, still triangles in the static name
    /// lists with the static layer; range storage and pruning do not apply).
    pub lookup: Lookup,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1024,
            height: 768,
            spp: 8,
            seed: 1,
            shadow_size: None,
            method: Method::Temporal,
            initial_node_capacity: None,
            initial_range_capacity: None,
            max_samples_per_chunk: MAX_SAMPLES_PER_CHUNK,
            shadow_estimator: ShadowEstimator::Sampled,
            shadow_filter: ShadowFilter::None,
            prisms: PrismConstruction::Exact,
            receiver: ReceiverTest::Auto,
            static_layer: true,
            keep_static_layer: false,
            range_storage: RangeStorage::Sorted,
            pruning: Pruning::StaticLayer,
            lookup: Lookup::DepthLine,
        }
    }
}

impl RenderSettings {
    /// Whether this frame's method tests receivers at their plane's depth.
    pub fn receiver_plane(&self) -> bool {
        self.receiver.uses_plane(&self.method)
    }

    pub fn shadow_size(&self) -> (u32, u32) {
        self.shadow_size.unwrap_or((self.width, self.height))
    }

    /// The method's name in file names, tables and the JSON: `temporal-exact` for the
    /// temporal map with the exact lookup (as the deferred frame names it).
    pub fn method_name(&self) -> &'static str {
        match (self.method, self.lookup) {
            (Method::Temporal, Lookup::Exact) => "temporal-exact",
            (method, _) => method.name(),
        }
    }

    /// `--lookup exact` applies to the temporal method only, with the exact construction and
    /// no shadow filter: the refusal, naming the option, where it does not.
    fn validate_lookup(&self) -> Result<()> {
        if self.lookup != Lookup::Exact {
            return Ok(());
        }
        let refuse = |why: String| Err(Error::InvalidArgument(format!("--lookup exact: {why}")));
        if self.method != Method::Temporal {
            return refuse(format!(
                "the exact lookup reads the temporal map (--method temporal); {} has no such \
                 lookup",
                self.method.name()
            ));
        }
        if self.prisms != PrismConstruction::Exact {
            return refuse(
                "the exact lookup's conservative collection needs the exact construction \
                 (--prisms exact), not the papers' prisms"
                    .to_owned(),
            );
        }
        if self.shadow_filter != ShadowFilter::None {
            return refuse(format!(
                "--shadow-filter {} does not apply: the exact lookup tests each sample's shadow \
                 ray, it has no texels to filter; use --shadow-filter none",
                stats::filter_name(self.shadow_filter)
            ));
        }
        Ok(())
    }

    pub fn validate(&self) -> Result<()> {
        let side_ok = |v: u32| (1..=MAX_IMAGE_SIDE).contains(&v);
        let (sw, sh) = self.shadow_size();
        if !side_ok(self.width) || !side_ok(self.height) {
            return Err(Error::InvalidArgument(format!(
                "image size {}x{}: each side must be 1..={MAX_IMAGE_SIDE}",
                self.width, self.height
            )));
        }
        if !side_ok(sw) || !side_ok(sh) {
            return Err(Error::InvalidArgument(format!(
                "shadow map size {sw}x{sh}: each side must be 1..={MAX_IMAGE_SIDE}"
            )));
        }
        if !(1..=MAX_SPP).contains(&self.spp) {
            return Err(Error::InvalidArgument(format!(
                "spp {}: must be 1..={MAX_SPP}",
                self.spp
            )));
        }
        match self.method {
            Method::Plain { time } if !(0.0..=1.0).contains(&time) => Err(Error::InvalidArgument(
                format!("plain shadow map time {time}: must be in [0, 1]"),
            )),
            Method::Reference { slices } if !(1..=MAX_REFERENCE_SLICES).contains(&slices) => {
                Err(Error::InvalidArgument(format!(
                    "reference slices {slices}: must be 1..={MAX_REFERENCE_SLICES}"
                )))
            }
            // The reference is the papers' ground truth, unfiltered wherever it is used
            // (`compare` and `bench` always render it so): a filtered one would not converge
            // to the truth, and would not be the reference the documentation describes.
            Method::Reference { .. } if self.shadow_filter != ShadowFilter::None => {
                Err(Error::InvalidArgument(format!(
                    "--shadow-filter {}: the brute-force reference stays unfiltered (it is the \
                     ground truth the filters are measured against); use --shadow-filter none \
                     with --method reference",
                    stats::filter_name(self.shadow_filter)
                )))
            }
            _ => self.validate_lookup(),
        }
    }
}

/// What every method's shadow step reads: the scene's draws and the light.
#[derive(Clone, Copy)]
struct FrameInputs<'a> {
    draws: &'a DrawList,
    light: &'a LightView,
}

/// A rendered frame.
pub struct RenderResult {
    pub image: RadianceImage,
    /// Per pixel, the share of its samples that see a moving triangle (the moving-object
    /// mask of comparisons).
    pub moving_coverage: Vec<f32>,
    pub stats: FrameStats,
    /// The temporal shadow map of the frame (for inspection), when the method built one.
    pub shadow_map: Option<TemporalShadowMap>,
}

/// The passes, each made by the first frame that needs it and reused across frames.
pub struct Renderer<'a> {
    ctx: &'a Context,
    passes: passes::Passes,
    /// Taken out while a submission records into it (the closure borrows the renderer).
    timestamps: Option<TimestampQueries>,
    /// Made by the first deferred frame.
    deferred: Option<deferred::DeferredPasses>,
}

impl<'a> Renderer<'a> {
    pub fn new(ctx: &'a Context) -> Result<Self> {
        Ok(Self {
            ctx,
            passes: passes::Passes::default(),
            timestamps: Some(TimestampQueries::new(ctx, 16)?),
            deferred: None,
        })
    }

    /// Renders `scene`. `progress` receives a line for each step that may take a while.
    /// [`Method::Raytrace`] is refused here: it runs on the CPU ([`crate::raytrace::render`];
    /// [`crate::frame::render`] picks the right one).
    ///
    /// The steps, each in `render/frame.rs`: upload the scene and set up the views
    /// (`prepare_frame`); the method's shadow pass (`shadow_pass`); the lighting pass, again
    /// with one sample per invocation if a device's loop limit cut it short (`shade`); the
    /// frame's refusals and warnings; its statistics.
    pub fn render(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        progress: &mut dyn FnMut(&str),
    ) -> Result<RenderResult> {
        if settings.method == Method::Raytrace {
            return Err(Error::InvalidArgument(
                "the ray tracer runs on the CPU: raytrace::render".to_owned(),
            ));
        }
        settings.validate()?;
        scene.validate()?;
        upload::check_moving_light_forward(scene, settings)?;
        camera_motion::check_moving_camera_forward(scene, settings)?;
        // A refused frame makes no pass; a frame's clock never counted making them.
        self.passes.make_for(self.ctx, settings.method)?;
        let start = Instant::now();
        let frame = self.prepare_frame(scene, settings, progress)?;
        let mut passes = Vec::new();
        let target = frame.lighting_target(self.ctx, settings)?;
        let outcome = self.shadow_pass(&frame, settings, &target, &mut passes, progress)?;
        let target = self.shade(&frame, settings, &outcome, target, &mut passes, progress)?;
        frame::check_target(self.ctx, &target)?;
        let image = RadianceImage::new(settings.width, settings.height, target.read_rgb()?)?;
        let moving_coverage = target.read_moving_coverage()?;
        let warnings = frame::warnings(self.ctx, scene, settings, &frame, &outcome)?;
        for w in &warnings {
            progress(&format!("warning: {w}"));
        }
        let stats = frame::stats(
            self.ctx,
            scene,
            settings,
            &frame,
            &outcome,
            &target,
            frame::Timing {
                passes,
                warnings,
                wall_ms: start.elapsed().as_secs_f64() * 1e3,
            },
        )?;
        Ok(RenderResult {
            image,
            moving_coverage,
            stats,
            shadow_map: outcome.into_temporal_map(),
        })
    }

    /// Records with `record` between timestamps, submits, waits, and appends the spans.
    /// Records and runs the lighting pass into `target`, then its readback.
    fn light(
        &mut self,
        draws: &DrawList,
        view: &LightingView,
        shadow: motion_shadows::technique::ShadowSource<'_>,
        target: &LightingTarget,
        passes: &mut Vec<PassTime>,
    ) -> Result<()> {
        // The image is copied out in the same submission, after the timed passes.
        self.run_timed(passes, |this, cmd, ts| {
            let device = this.ctx.device();
            // SAFETY: a OneShot command buffer of this context, recording, outside
            // rendering; the shadow source was recorded in an earlier submission.
            unsafe {
                this.passes.lighting(this.ctx)?.record(
                    device,
                    cmd,
                    draws,
                    view,
                    shadow,
                    target,
                    Some(ts),
                )
            }?;
            // SAFETY: the same command buffer, after the frame's passes.
            unsafe { target.record_readback(device, cmd) };
            Ok(())
        })
    }

    fn run_timed(
        &mut self,
        passes: &mut Vec<PassTime>,
        record: impl FnOnce(
            &mut Self,
            motion_shadows::ash::vk::CommandBuffer,
            &mut TimestampQueries,
        ) -> motion_shadows::Result<()>,
    ) -> Result<()> {
        let mut ts = match self.timestamps.take() {
            Some(ts) => ts,
            None => TimestampQueries::new(self.ctx, 16)?,
        };
        // SAFETY: `ts` is the renderer's own pool, and its last use was in an earlier OneShot,
        // which waited for its fence before returning: no command buffer with its marks is pending.
        unsafe { ts.clear() };
        let one_shot = OneShot::new(self.ctx)?;
        one_shot.run(|cmd| {
            // SAFETY: `cmd` is the OneShot's command buffer of this context, recording, and `ts`
            // lives until after `run` has waited for it.
            unsafe { ts.mark(cmd, "start") };
            record(self, cmd, &mut ts)
        })?;
        for (pass, gpu_ms) in ts.spans_ms()? {
            passes.push(PassTime { pass, gpu_ms });
        }
        self.timestamps = Some(ts);
        Ok(())
    }
}
