//! Lighting pass (paper 3.3, McGuire et al. 2010): stochastic rasterization from the camera
//! into a sample-level visibility buffer, then shading and the shadow test per sample.
//!
//! Why a visibility buffer and not MSAA: lavapipe offers at most 4 samples per pixel, and the
//! papers use 8 to 20. Keeping the nearest (distance, triangle) per sample with a 64-bit
//! atomicMin lets one geometry pass serve as many samples as fit in a storage buffer, and
//! shading runs once per visible sample instead of once per covering fragment.

use super::collection::draw_each;
use super::declared_barriers::record_own;
use super::draws::DrawList;
use super::gpu_types::{COUNT_INVALID, CameraParams, FIXED_TIME, GpuCameraEnd, ShadowMode};
use super::plain_shadow::PlainShadowMap;
use super::push_constants::{LightingRasterPush, PushBlock, RasterCamera, RasterPush, ShadePush};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use super::view::{LightingView, Lookup, ShadowEstimator, ShadowFilter};
use crate::error::{Error, Result};
use crate::gpu::{
    Access, ComputeVariants, Context, Pipeline, TimestampQueries, attachmentless_pipeline,
    begin_attachmentless, memory_barrier,
};
use ash::vk;
use std::sync::Arc;

mod accesses;
mod target;
pub use target::LightingTarget;

// The most samples one geometry pass handles (bounded further by the device's buffer limit).
pub use super::gpu_constants::MAX_SAMPLES_PER_CHUNK;

/// What the lighting pass tests shadows against.
#[derive(Clone, Copy)]
pub enum ShadowSource<'a> {
    /// The depth-time ranges of a temporal shadow map (and its coverage map, if its
    /// collection pass was recorded with one).
    Temporal(&'a TemporalShadowMap),
    /// Layer 0 of an ordinary shadow map with ids ([`super::DepthFormat::DepthAndId`]), for
    /// every sample.
    Plain(&'a PlainShadowMap),
    /// Time-dependent shadow maps: one depth-only layer per time stratum (as many layers as
    /// samples per pixel); a sample tests the layer of its stratum.
    TimeDependent(&'a PlainShadowMap),
    /// No shadows; the map only gives the light (its shadow data is not read).
    Unshadowed(&'a PlainShadowMap),
}

impl ShadowSource<'_> {
    /// Whether it is a temporal map whose last recorded collection built it for the exact
    /// lookup ([`Lookup::Exact`]): the pass then tests each sample's shadow ray against the
    /// triangles its texel names (`ms_visible_exact`) instead of the depth lines.
    fn reads_exact_lookup(&self) -> bool {
        matches!(self, Self::Temporal(map) if map.recorded_lookup() == Lookup::Exact)
    }

    /// Whether the source's last recording was for a moving light (its header then holds
    /// the pose at t = 1).
    fn recorded_for_moving_light(&self) -> bool {
        match self {
            Self::Temporal(map) => map.recorded_for_moving_light(),
            Self::Plain(map) | Self::TimeDependent(map) | Self::Unshadowed(map) => {
                map.recorded_for_moving_light()
            }
        }
    }

    fn mode_and_header(&self) -> (ShadowMode, u64) {
        match self {
            Self::Temporal(map) => (ShadowMode::Temporal, map.header_address()),
            Self::Plain(map) => (ShadowMode::Plain, map.header_address()),
            Self::TimeDependent(map) => (ShadowMode::Tsm, map.header_address()),
            Self::Unshadowed(map) => (ShadowMode::None, map.header_address()),
        }
    }
}

/// The papers' lighting pass. Immutable after creation: one serves every frame in flight.
pub struct LightingPass {
    raster: Pipeline,
    /// The raster for a moving camera (`lighting_camera_moves.geom`): a still camera's keeps
    /// none of its code.
    raster_camera_moves: Pipeline,
    /// The shading pipelines, one per [`ShadeVariant`] and chunk size, made on first use.
    resolve: ComputeVariants,
    /// The most loop iterations one pixel's shadow lookups may report before the pass
    /// counts it as possibly cut short (0: the device has no loop limit, nothing counted).
    loop_budget: u32,
    /// Whether [`Self::record_clear`] records its entry barrier (off:
    /// [`Self::with_host_barriers`]).
    outer_barriers: bool,
}

/// What one shading pipeline is specialized for (`resolve.comp`'s specialization
/// constants): the shadow test, and for the tests that have them the estimator and the
/// filter. Fixed per pipeline rather than read per pixel, so that the shading runs no path of
/// another variant (a CPU device runs every side of a branch its lanes might take).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ShadeVariant {
    mode: ShadowMode,
    analytic: bool,
    filter: ShadowFilter,
    /// Temporal: the exact lookup's test (`SHADE_EXACT`).
    exact: bool,
    /// The source was recorded for a moving light (`SHADE_LIGHT_MOVES`).
    light_moves: bool,
    /// The camera moves during the shutter (`SHADE_CAMERA_MOVES`).
    camera_moves: bool,
}

impl ShadeVariant {
    /// The variant that renders `mode` with `estimator` and `filter` (choices a test does
    /// not have are dropped, so that they do not make pipelines that differ for nothing).
    fn of(
        mode: ShadowMode,
        estimator: ShadowEstimator,
        filter: ShadowFilter,
        exact: bool,
        light_moves: bool,
        camera_moves: bool,
    ) -> Self {
        Self {
            light_moves,
            camera_moves,
            exact: mode == ShadowMode::Temporal && exact,
            mode,
            analytic: mode == ShadowMode::Temporal && estimator == ShadowEstimator::Analytic,
            filter: if mode == ShadowMode::None {
                ShadowFilter::None
            } else {
                filter
            },
        }
    }

    /// The values of `resolve.comp`'s specialization constants for a chunk of `samples`
    /// samples per pixel on a device with `loop_budget`.
    fn constants(self, loop_budget: u32, samples: u32) -> [u32; 8] {
        let filter = match self.filter {
            ShadowFilter::None => 0,
            ShadowFilter::Bilinear => 1,
            ShadowFilter::Footprint => 2,
        };
        [
            self.mode as u32,
            self.analytic as u32,
            filter,
            loop_budget,
            samples,
            self.exact as u32,
            self.light_moves as u32,
            self.camera_moves as u32,
        ]
    }
}

impl LightingPass {
    /// Creates the raster pipeline (vertex, geometry, fragment shader). The shading's compute
    /// pipelines (one per shadow test, estimator, filter and chunk size) are made when a
    /// record first needs them.
    pub fn new(ctx: &Context) -> Result<Self> {
        let raster = |name, geometry| {
            attachmentless_pipeline(
                ctx,
                RasterPush::BYTES,
                &[
                    (
                        vk::ShaderStageFlags::VERTEX,
                        "scene.vert",
                        shaders::SCENE_VERT,
                    ),
                    (vk::ShaderStageFlags::GEOMETRY, name, geometry),
                    (
                        vk::ShaderStageFlags::FRAGMENT,
                        "lighting.frag",
                        shaders::LIGHTING_FRAG,
                    ),
                ],
            )
        };
        Ok(Self {
            raster: raster("lighting.geom", shaders::LIGHTING_GEOM)?,
            raster_camera_moves: raster(
                "lighting_camera_moves.geom",
                shaders::LIGHTING_CAMERA_MOVES_GEOM,
            )?,
            resolve: ComputeVariants::new(
                ctx,
                ShadePush::BYTES,
                "resolve.comp",
                shaders::RESOLVE_COMP,
            )?,
            loop_budget: ctx.info().shader_loop_budget(),
            outer_barriers: true,
        })
    }

    /// The shading pipeline for `shadow` seen as `view` says, for chunks of `samples`.
    fn shading(
        &self,
        shadow: ShadowSource<'_>,
        view: &LightingView,
        samples: u32,
    ) -> Result<Arc<Pipeline>> {
        if shadow.reads_exact_lookup() && view.filter != ShadowFilter::None {
            return Err(Error::InvalidArgument(format!(
                "the exact lookup (a temporal map built with Lookup::Exact) tests each sample's shadow ray, it has no texels to filter: ShadowFilter::{:?} does not apply, use ShadowFilter::None",
                view.filter
            )));
        }
        if let ShadowSource::Temporal(map) = shadow {
            if map.recorded_for_moving_light() && view.estimator == ShadowEstimator::Analytic {
                return Err(Error::InvalidArgument(
                    "ShadowEstimator::Analytic takes a still receiver's lit share of the shutter, \
                     which a moving light (LightView::end) does not leave still: use \
                     ShadowEstimator::Sampled"
                        .to_owned(),
                ));
            }
        }
        if view.camera.is_moving() {
            check_moving_camera(view)?;
        }
        let (mode, _) = shadow.mode_and_header();
        let variant = ShadeVariant::of(
            mode,
            view.estimator,
            view.filter,
            shadow.reads_exact_lookup(),
            shadow.recorded_for_moving_light(),
            view.camera.is_moving(),
        );
        self.resolve
            .get(&variant.constants(self.loop_budget, samples))
    }

    /// Records the whole lighting pass for the target's samples per pixel (as many chunks as
    /// the target needs), leaving the averaged radiance in `target.radiance`. With
    /// `timestamps`, marks "lighting raster" and "lighting shade" after each chunk's halves.
    ///
    /// A temporal map whose last recorded collection built it for the exact lookup
    /// ([`Lookup::Exact`]) is read with it: each sample's shadow ray at the sample's time
    /// against the triangles its texel names (`ms_visible_exact`; with
    /// [`ShadowEstimator::Analytic`], a receiver on a still triangle takes its exact lit share
    /// of the shutter, `ms_lit_fraction_exact`).
    ///
    /// Errors (nothing recorded) when a shading pipeline this frame needs cannot be made
    /// (each variant is made on first use), or when `shadow` is read with the exact lookup
    /// and `view.filter` is not [`ShadowFilter::None`] (the exact test has no texels to
    /// filter).
    ///
    /// # Safety
    /// - As [`super::CollectionPass::record`] for `cmd` and `draws`.
    /// - The shadow source was recorded earlier in `cmd` (or a command buffer submitted
    ///   before it on the same queue); its passes' closing barriers make it visible here.
    /// - `target` is not in use by a command buffer running at the same time.
    ///
    /// Synchronization: waits for earlier compute and transfer uses of the target (the entry
    /// barrier, derived from [`Self::accesses`], [`LightingTarget::readback_accesses`] and
    /// [`super::LightingImageOutput::accesses`]; the host's with [`Self::with_host_barriers`]);
    /// leaves the radiance written by the compute stage and visible to compute and transfer
    /// reads. `record` declares the frame to the access check (`record_clear` and
    /// `record_samples` called apart do not).
    /// State changed: the bound graphics and compute pipelines, push constants, viewport,
    /// scissor.
    #[allow(clippy::too_many_arguments)]
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        view: &LightingView,
        shadow: ShadowSource<'_>,
        target: &LightingTarget,
        mut timestamps: Option<&mut TimestampQueries>,
    ) -> Result<()> {
        // Every chunk is full but maybe the last: both pipelines are made before anything
        // is recorded.
        let full = target.samples_per_chunk.min(target.spp);
        self.shading(shadow, view, full)?;
        if target.spp % full != 0 {
            self.shading(shadow, view, target.spp % full)?;
        }
        // SAFETY: this function's contract is record_clear's (it says "As Self::record").
        unsafe { self.record_clear(device, cmd, view, target) };
        accesses::declare_frame(draws, shadow, target);
        let mut first = 0;
        while first < target.spp {
            let count = target.samples_per_chunk.min(target.spp - first);
            let samples = Samples {
                first,
                count,
                fixed_time: None,
            };
            // SAFETY: record_clear of this frame was recorded just above, as record_samples
            // requires, and the rest of its contract is this function's.
            unsafe {
                self.record_samples(
                    device,
                    cmd,
                    draws,
                    view,
                    shadow,
                    target,
                    samples,
                    timestamps.as_deref_mut(),
                )
            }?;
            first += count;
        }
        Ok(())
    }

    /// Writes the target's header for `view` and zeroes its radiance and counters, before a
    /// frame's first [`Self::record_samples`].
    ///
    /// # Safety
    /// As [`Self::record`].
    pub unsafe fn record_clear(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        view: &LightingView,
        target: &LightingTarget,
    ) {
        let header = CameraParams {
            visibility: target.visibility.device_address(),
            radiance: target.radiance.device_address(),
            counters: target.counters.device_address(),
            camera_end: match view.camera.end {
                Some(_) => target.header.device_address() + CAMERA_END_OFFSET,
                None => 0,
            },
            ..CameraParams::new(view, (target.width, target.height), target.spp)
        };
        let moving_header = view.camera.gpu_end().map(|end| MovingCameraHeader {
            camera: header,
            end,
        });
        if self.outer_barriers {
            let entry = accesses::entry_barrier(target);
            let check = target.header.access_check();
            // SAFETY: `cmd` is recording outside any render pass on a graphics and compute
            // queue (CollectionPass::record's contract, taken by record), so every stage
            // named is supported.
            unsafe { record_own(device, cmd, check, "lighting entry", entry.as_ref()) };
        }
        // SAFETY: the header gets one CameraParams (its size) and the fills cover the target's own
        // radiance and counter buffers (WHOLE_SIZE), outside rendering, after their earlier readers
        // (the barrier above); no other command buffer uses the target meanwhile (the contract).
        unsafe {
            match moving_header {
                Some(moving) => target.header.record_write(device, cmd, &[moving]),
                None => target.header.record_write(device, cmd, &[header]),
            }
            device.cmd_fill_buffer(cmd, target.radiance.raw(), 0, vk::WHOLE_SIZE, 0);
            device.cmd_fill_buffer(cmd, target.counters.raw(), 0, vk::WHOLE_SIZE, 0);
        }
        // SAFETY: the same command buffer, outside rendering; stages its queue supports.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::TRANSFER_WRITE,
                Access::ANY_SHADER_READ
                    .and(Access::COMPUTE_RW)
                    .and(Access::GEOMETRY_RW),
            )
        };
    }

    /// Renders one chunk of samples (at most the target's samples per chunk) and adds their
    /// share (1/spp each) to the target's radiance, seen from `view` (the frame's
    /// [`Self::record_clear`] view: the raster pushes its camera rather than reading the
    /// header). The chunk starting at sample 0 counts the triangles dropped for an invalid
    /// index.
    ///
    /// Errors (nothing recorded) when the chunk's shading pipeline cannot be made.
    ///
    /// # Safety
    /// As [`Self::record`], after [`Self::record_clear`] of the same frame.
    #[allow(clippy::too_many_arguments)]
    pub unsafe fn record_samples(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        view: &LightingView,
        shadow: ShadowSource<'_>,
        target: &LightingTarget,
        samples: Samples,
        mut timestamps: Option<&mut TimestampQueries>,
    ) -> Result<()> {
        let (_, map) = shadow.mode_and_header();
        let count = samples.count.clamp(1, target.samples_per_chunk);
        let resolve = self.shading(shadow, view, count)?;
        let fixed_time = if samples.fixed_time.is_some() {
            FIXED_TIME
        } else {
            0
        };
        let time = samples.fixed_time.unwrap_or(0.0);
        let shade = ShadePush {
            draws: draws.address(),
            shadow: map,
            target: target.header.device_address(),
            draw_count: draws.draw_count(),
            first_sample: samples.first,
            time,
            flags: fixed_time,
        };
        // The previous chunk's resolve read the visibility buffer.
        // SAFETY: outside any render pass (the contract), on a queue with compute and transfer.
        unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_WRITE) };
        // SAFETY: a WHOLE_SIZE fill of the target's own visibility buffer, outside rendering, after
        // the previous chunk's resolve (the barrier above).
        unsafe {
            device.cmd_fill_buffer(cmd, target.visibility.raw(), 0, vk::WHOLE_SIZE, u32::MAX)
        };
        // SAFETY: outside rendering; transfer, fragment and compute are on the contract's graphics
        // and compute queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::TRANSFER_WRITE,
                Access::FRAGMENT_RW.and(Access::COMPUTE_RW),
            )
        };
        // SAFETY: outside rendering, and the target's size is the extent the raster pipeline's
        // dynamic viewport takes.
        unsafe { begin_attachmentless(device, cmd, target.width, target.height) };
        let raster_pipeline = if view.camera.is_moving() {
            &self.raster_camera_moves
        } else {
            &self.raster
        };
        // SAFETY: rendering has begun; the raster pipeline is this pass's, alive as long as `self`.
        unsafe { raster_pipeline.bind(device, cmd) };
        let raster = RasterPush {
            pass: LightingRasterPush {
                visibility: target.visibility.device_address(),
                target: target.header.device_address(),
                first_sample: samples.first,
                sample_count: count,
                time,
                flags: fixed_time | if samples.first == 0 { COUNT_INVALID } else { 0 },
                ..LightingRasterPush::default()
            },
            camera: RasterCamera::new(&CameraParams::new(
                view,
                (target.width, target.height),
                target.spp,
            )),
            padding: 0,
        };
        // The camera stays pushed while each draw pushes its LightingRasterPush over the first
        // bytes.
        // SAFETY: the raster pipeline's layout was made with RasterPush's size (its push range),
        // and it is bound just above.
        unsafe { raster_pipeline.push(device, cmd, &raster) };
        draw_each(device, cmd, raster_pipeline, draws, raster.pass);
        // SAFETY: the rendering began above and every draw is recorded into it.
        unsafe { device.cmd_end_rendering(cmd) };
        if let Some(ts) = timestamps.as_deref_mut() {
            // SAFETY: outside rendering, on the context's device; `mark` records nothing where
            // timestamps are unsupported, and a dropped TimestampQueries retires its pool until the
            // frames that may use it complete, so the pool outlives `cmd`.
            unsafe { ts.mark(cmd, "lighting raster") };
        }
        // SAFETY: outside rendering; fragment, geometry and compute stages are on this queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::FRAGMENT_RW.and(Access::GEOMETRY_RW),
                Access::COMPUTE_RW,
            )
        };
        // SAFETY: the resolve pipeline was made (or fetched) by `shading` for this frame and is
        // owned by `self`, alive as long as it; a compute bind outside rendering.
        unsafe { resolve.bind(device, cmd) };
        // SAFETY: the resolve pipeline's push range is the size of `shade`, the struct every
        // shading variant was made with.
        unsafe { resolve.push(device, cmd, &shade) };
        // SAFETY: the resolve pipeline is bound with its constants; 8x8 groups cover the target,
        // and the shader returns for invocations past its edges.
        unsafe { device.cmd_dispatch(cmd, target.width.div_ceil(8), target.height.div_ceil(8), 1) };
        if let Some(ts) = timestamps {
            // SAFETY: as the mark above: outside rendering, the pool retired rather than destroyed
            // while frames may use it.
            unsafe { ts.mark(cmd, "lighting shade") };
        }
        // SAFETY: outside rendering; compute and transfer stages are on this queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::COMPUTE_RW,
                Access::COMPUTE_RW.and(Access::TRANSFER_READ),
            )
        };
        Ok(())
    }
}

/// Where a moving camera's [`GpuCameraEnd`] sits in a lighting target's header: right after
/// its [`CameraParams`].
const CAMERA_END_OFFSET: u64 = std::mem::size_of::<CameraParams>() as u64;

/// A lighting target's header for a moving camera: a still camera's header writes only the
/// [`CameraParams`], as it always did.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MovingCameraHeader {
    camera: CameraParams,
    end: GpuCameraEnd,
}

/// Refuses the settings whose shading takes the camera as still (named, with what to use).
fn check_moving_camera(view: &LightingView) -> Result<()> {
    if view.estimator == ShadowEstimator::Analytic {
        return Err(Error::InvalidArgument(
            "ShadowEstimator::Analytic takes a still receiver's lit share of the shutter at \
             one point of a pixel, which a moving camera (CameraView::end) does not keep on one \
             point: use ShadowEstimator::Sampled"
                .to_owned(),
        ));
    }
    if view.filter == ShadowFilter::Footprint {
        return Err(Error::InvalidArgument(
            "ShadowFilter::Footprint measures the pixel's footprint from the camera at t = 0, \
             which a moving camera (CameraView::end) leaves: use ShadowFilter::None or \
             ShadowFilter::Bilinear"
                .to_owned(),
        ));
    }
    Ok(())
}

/// Which samples [`LightingPass::record_samples`] renders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Samples {
    /// Index of the first sample.
    pub first: u32,
    /// Samples in the chunk.
    pub count: u32,
    /// Every sample at this time instead of its own stratified time (reference slices).
    pub fixed_time: Option<f32>,
}
