//! The engine's frame (`render --frame deferred`): a G-buffer drawn at one shutter time (the
//! camera time T; engines draw their current frame at shutter close, T = 1), then per pixel
//! the share of the shutter its point sees the light, multiplied into Lambert shading on the
//! host side. What differs between the methods is only that share:
//!  - temporal: the temporal map and the mask pass (exact lit fraction, receivers moving as
//!    the G-buffer's motion says, or standing still with `moving_receivers` off);
//!  - TSM-N: N depth maps at the strata's centres, each looked up with the receiver where it
//!    is at that map's time, averaged ([`motion_shadows::technique::EngineTsmPass`]);
//!  - plain: one depth map at mid-shutter (TSM-1);
//!  - raytrace: the truth, on the CPU ([`crate::raytrace::deferred::render_truth`]): the exact lit fraction
//!    of each pixel's moving point, from its own camera rays.
//!
//! Timed as an engine runs its frames after the first: the static layer (temporal) or the
//! static depth map (TSM) is drawn before the timed passes and kept; the timed passes are the
//! shadow pass and the mask.

use super::methods::RangeBounds;
use super::stats::PassTime;
use super::{FrameInputs, ReceiverTest, RenderSettings, Renderer, upload};
use crate::error::{Error, Result};
use crate::output::RadianceImage;
use crate::scene::Scene;
use glam::DVec3;
use motion_shadows::ash::vk;
use motion_shadows::gpu::{Access, Buffer, BufferUsage, Image, image_barrier, memory_barrier};
use motion_shadows::technique::{
    DrawList, EngineTsmMap, EngineTsmPass, GBuffer, GBufferCamera, GBufferContents, GBufferPass,
    LightView, Lookup, MaskInputs, TemporalShadowMap, TsmStart, VisibilityMaskPass,
};
use std::time::Instant;

pub use super::deferred_settings::{
    DeferredMethod, DeferredResult, DeferredSettings, MAX_DEFERRED_TSM_MAPS,
};

/// Bytes of the depth maps a deferred TSM-`maps` frame at `shadow_size` allocates: the static
/// map and the working map's layers (maps are drawn [`TSM_LAYERS_PER_BATCH`] at a time), 4 a
/// texel each. Known before the frame, so that a sweep can refuse what cannot fit.
pub fn deferred_tsm_bytes((width, height): (u32, u32), maps: u32) -> u64 {
    (1 + u64::from(TSM_LAYERS_PER_BATCH.min(maps)))
        .saturating_mul(4 * u64::from(width))
        .saturating_mul(u64::from(height))
}

impl Renderer<'_> {
    /// Renders the deferred frame of `scene` on the device. [`DeferredMethod::Raytrace`] is
    /// refused here: the truth is traced on the CPU, without a device
    /// ([`crate::frame::render_deferred`] picks the right one).
    pub fn render_deferred(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        deferred: &DeferredSettings,
        progress: &mut dyn FnMut(&str),
    ) -> Result<DeferredResult> {
        let start = Instant::now();
        settings.validate()?;
        deferred.validate()?;
        scene.validate()?;
        let size = (settings.width, settings.height);
        if deferred.method == DeferredMethod::Raytrace {
            return Err(Error::InvalidArgument(
                "the deferred truth is traced on the CPU: raytrace::deferred::render_truth"
                    .to_owned(),
            ));
        }
        upload::check_moving_light_deferred(scene, deferred)?;
        let ctx = self.ctx;
        progress("uploading the scene");
        let geometry = upload::SceneGeometry::upload(ctx, scene)?;
        let mut draws = DrawList::new(ctx, geometry.draws.len() as u32)?;
        self.run_timed(&mut Vec::new(), |this, cmd, _| {
            // SAFETY: a OneShot command buffer of this context, recording, outside rendering.
            unsafe { draws.record_update(this.ctx.device(), cmd, &geometry.draws) }
        })?;
        let light = upload::with_motion(scene, deferred_light(scene, settings, deferred))?;
        // The G-buffer is a snapshot at the camera time, the camera's pose included (a moving
        // camera's; a still one's as it is).
        let camera = upload::camera_view_of(&scene.camera.at(deferred.camera_time), size);
        let view_proj = camera.proj * camera.view;
        let gbuffer = GBuffer::new(ctx, settings.width, settings.height)?;
        self.deferred_passes()?;
        progress(&format!(
            "G-buffer at t = {}: {}x{} pixels",
            deferred.camera_time, settings.width, settings.height
        ));
        self.run_timed(&mut Vec::new(), |this, cmd, _| {
            let camera = GBufferCamera {
                view_proj,
                eye: camera.position,
            };
            let pass = &this.deferred_passes_made().gbuffer;
            // SAFETY: a OneShot command buffer of this context, recording, outside
            // rendering; the draw list was uploaded in an earlier submission.
            unsafe {
                pass.record(
                    this.ctx.device(),
                    cmd,
                    &draws,
                    &camera,
                    deferred.camera_time,
                    &gbuffer,
                )
            };
            Ok(())
        })?;

        let mask = MaskTarget::new(ctx, size)?;
        let mut inputs = gbuffer.mask_inputs(
            mask.image.layer_view(0),
            view_proj.inverse(),
            deferred.camera_time,
            deferred.moving_receivers,
        );
        inputs.plane_test_where_still = still_pixels_plane(settings, deferred);
        let frame = FrameInputs {
            draws: &draws,
            light: &light,
        };
        let mut passes = Vec::new();
        let shadow = settings.shadow_size();
        let shadow_bytes = match deferred.method {
            DeferredMethod::Temporal => {
                // The map is built (grown until it fits) with the static layer kept, then
                // the timed frame: the shadow pass again, and the mask.
                let bound = RangeBounds::of(
                    scene,
                    &light,
                    shadow,
                    false,
                    self.ctx.max_addressed_buffer_bytes(),
                );
                let outcome =
                    self.temporal_shadow(frame, settings, false, bound, &mut Vec::new(), progress)?;
                let map = outcome
                    .into_temporal_map()
                    .expect("the temporal shadow step makes a temporal map");
                progress("timed frame: shadow pass and mask");
                self.deferred_temporal_frame(frame, &map, &inputs, &mask, &gbuffer, &mut passes)?;
                map.allocated_bytes()
            }
            DeferredMethod::Tsm { maps } => self.deferred_tsm_frame(
                frame,
                shadow,
                maps,
                &inputs,
                &mask,
                &gbuffer,
                &mut passes,
                progress,
            )?,
            DeferredMethod::Plain => self.deferred_tsm_frame(
                frame,
                shadow,
                1,
                &inputs,
                &mask,
                &gbuffer,
                &mut passes,
                progress,
            )?,
            DeferredMethod::Raytrace => unreachable!("refused above"),
        };
        let contents = gbuffer.read()?;
        let lit = mask.read(size)?;
        // Shaded with the light where it is at the camera time (a moving light's, as the
        // deferred truth does).
        let shading_light = upload::light_at(scene, shadow, deferred.camera_time)?;
        let (image, hit, facing) =
            shade(scene, &shading_light, &contents, view_proj.inverse(), &lit)?;
        let lit = lit
            .iter()
            .zip(&hit)
            .map(|(&l, &h)| if h { l } else { 1.0 })
            .collect();
        Ok(DeferredResult {
            image,
            lit,
            hit,
            triangle: contents.ids,
            facing,
            method: deferred.name(),
            shadow_and_mask_ms: passes.iter().map(|p| p.gpu_ms).sum(),
            shadow_bytes,
            passes,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// The deferred frame's passes, made on first use (most renders never need them).
    pub(super) fn deferred_passes(&mut self) -> Result<&DeferredPasses> {
        if self.deferred.is_none() {
            self.deferred = Some(DeferredPasses {
                gbuffer: GBufferPass::new(self.ctx)?,
                mask: VisibilityMaskPass::new(self.ctx)?,
                tsm: EngineTsmPass::new(self.ctx)?,
            });
        }
        Ok(self.deferred_passes_made())
    }

    fn deferred_passes_made(&self) -> &DeferredPasses {
        self.deferred
            .as_ref()
            .expect("deferred_passes() made them before this submission")
    }

    fn deferred_temporal_frame(
        &mut self,
        frame: FrameInputs<'_>,
        map: &TemporalShadowMap,
        inputs: &MaskInputs,
        mask: &MaskTarget,
        gbuffer: &GBuffer,
        passes: &mut Vec<PassTime>,
    ) -> Result<()> {
        let ctx = self.ctx;
        let mut bindings = self.deferred_passes()?.mask.bindings(ctx, inputs.size)?;
        self.run_timed(passes, |this, cmd, ts| {
            let device = this.ctx.device();
            let FrameInputs { draws, light } = frame;
            mask.record_to_storage(device, cmd);
            // SAFETY: `cmd` is the OneShot's command buffer of this context, recording, on its
            // graphics and compute queue (timestamps are marked only where supported), and `ts` is
            // kept by the renderer past the OneShot's wait.
            unsafe { ts.mark(cmd, "setup") };
            // SAFETY: a OneShot command buffer of this context, recording, outside
            // rendering; the map fits (built above); the G-buffer was drawn in an earlier
            // submission and left in its read layouts; the mask image is in GENERAL.
            unsafe {
                this.passes
                    .collection(this.ctx)?
                    .record(device, cmd, draws, light, map, None)?;
                ts.mark(cmd, "collection");
                this.passes.generation(this.ctx)?.record(device, cmd, map);
                ts.mark(cmd, "generation");
                let mask_pass = &this.deferred_passes_made().mask;
                mask_pass.record(device, cmd, &mut bindings, inputs, map)?;
                ts.mark(cmd, "mask");
                map.record_counter_readback(device, cmd);
            }
            mask.record_readback(device, cmd);
            // SAFETY: the same command buffer; the mask pass read the G-buffer before.
            unsafe { gbuffer.record_readback(device, cmd) };
            Ok(())
        })?;
        passes.retain(|p| p.pass != "setup");
        map.check_complete(&map.read_counters()?)?;
        let over = bindings.read_over_budget_pixels()?;
        if over > 0 {
            let limit = self.ctx.info().shader_loop_limit.unwrap_or(0);
            return Err(loop_limit_error(over, limit, map.recorded_lookup()));
        }
        Ok(())
    }

    /// TSM-`maps`: a warm-up frame draws the static map (kept, as the temporal map's
    /// static layer is), then the timed frame: per batch of maps, copies of the static map,
    /// the moving draws, and the mask's lookups. Returns the bytes of its depth maps.
    #[allow(clippy::too_many_arguments)]
    fn deferred_tsm_frame(
        &mut self,
        frame: FrameInputs<'_>,
        shadow_size: (u32, u32),
        maps: u32,
        inputs: &MaskInputs,
        mask: &MaskTarget,
        gbuffer: &GBuffer,
        passes: &mut Vec<PassTime>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<u64> {
        let ctx = self.ctx;
        let light = frame.light;
        let (width, height) = shadow_size;
        let tsm_map = EngineTsmMap::new(
            ctx,
            width,
            height,
            TSM_LAYERS_PER_BATCH.min(maps),
            TsmStart::Copy,
        )?;
        let mut bindings = self.deferred_passes()?.tsm.bindings()?;
        for timed in [false, true] {
            progress(&if timed {
                format!("timed frame: {maps} time-dependent shadow maps and their lookups")
            } else {
                "time-dependent shadow maps: the static map, drawn before the timed frame".into()
            });
            let mut spans = Vec::new();
            self.run_timed(&mut spans, |this, cmd, ts| {
                let device = this.ctx.device();
                mask.record_to_storage(device, cmd);
                // SAFETY: as above: the OneShot's recording command buffer; `ts` outlives its
                // execution, which run_timed waits for.
                unsafe { ts.mark(cmd, "setup") };
                let tsm = &this.deferred_passes_made().tsm;
                // SAFETY: a OneShot command buffer of this context, recording, outside
                // rendering; the G-buffer was drawn in an earlier submission and left in its
                // read layouts; the mask image is R32_SFLOAT, storage, in GENERAL; the draw
                // list was updated in an earlier submission.
                unsafe {
                    tsm.record(
                        device,
                        cmd,
                        &mut bindings,
                        inputs,
                        frame.draws,
                        light,
                        &tsm_map,
                        maps,
                    )?
                };
                // SAFETY: after the mask pass in the same OneShot command buffer; `ts` outlives it
                // (run_timed waits).
                unsafe { ts.mark(cmd, "tsm maps + mask") };
                mask.record_readback(device, cmd);
                // SAFETY: the same command buffer; the mask pass read the G-buffer before.
                unsafe { gbuffer.record_readback(device, cmd) };
                Ok(())
            })?;
            // Submitted (and waited for): the timed frame may keep the static map.
            tsm_map.static_map_submitted();
            if timed {
                passes.extend(spans.into_iter().filter(|p| p.pass != "setup"));
            }
        }
        Ok(tsm_map.bytes())
    }
}

/// Whether receivers are tested at their plane's depth. `Auto`: only where they stand
/// still and the map holds triangle ids (temporal). A moving receiver's G-buffer normal is
/// its normal at the camera time: where its surface turns during the shutter, that plane
/// is off the surface at the other times by up to a texel's distance times the change of
/// slope, and its own surface's neighbouring triangles shadow it in speckles (measured on
/// cubes-toward-light's turning cubes); the normal offset keeps clear of them.
fn deferred_receiver_plane(settings: &RenderSettings, deferred: &DeferredSettings) -> bool {
    match settings.receiver {
        ReceiverTest::Auto => {
            deferred.method == DeferredMethod::Temporal && !deferred.moving_receivers
        }
        other => other.uses_plane(&settings.method),
    }
}

/// Whether, in a mask of moving receivers, the pixels that do not move take the
/// standing receivers' plane test (`Auto`, temporal: the G-buffer holds ids), while the
/// moving ones keep the light's normal offset. Why per pixel: with the offset on every
/// pixel as soon as anything moves, still ground lost its contact shadows (against an
/// independent path tracer, 1.5-2.5x the error of `--static-receivers` on still
/// receivers). Public for hosts of the same frame (the viewer).
pub fn still_pixels_plane(settings: &RenderSettings, deferred: &DeferredSettings) -> bool {
    settings.receiver == ReceiverTest::Auto
        && deferred.method == DeferredMethod::Temporal
        && deferred.moving_receivers
}

/// The deferred frame's light as the settings set it up (receiver test, static layer
/// kept). Public for hosts of the same frame (the viewer).
pub fn deferred_light(
    scene: &Scene,
    settings: &RenderSettings,
    deferred: &DeferredSettings,
) -> LightView {
    let mut light = LightView {
        prisms: settings.prisms,
        static_layer: settings.static_layer,
        keep_static_layer: settings.static_layer,
        lookup: deferred.lookup,
        ..upload::light_view(scene, settings.shadow_size())
    };
    if deferred_receiver_plane(settings, deferred) {
        light.receiver_plane = true;
        light.normal_offset_texels = 0.0;
    }
    light
}

/// The passes only deferred frames use.
pub(super) struct DeferredPasses {
    pub(super) gbuffer: GBufferPass,
    pub(super) mask: VisibilityMaskPass,
    pub(super) tsm: EngineTsmPass,
}

/// TSM maps drawn per batch (the working map's layers: 16 MiB each at 2048x2048).
const TSM_LAYERS_PER_BATCH: u32 = 8;

/// The mask image (R32_SFLOAT, storage) and its readback buffer.
struct MaskTarget {
    image: Image,
    readback: Buffer,
}

impl MaskTarget {
    fn new(ctx: &motion_shadows::gpu::Context, (width, height): (u32, u32)) -> Result<Self> {
        Ok(Self {
            image: Image::new(
                ctx,
                "deferred mask",
                (width, height, 1),
                vk::Format::R32_SFLOAT,
                vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
            readback: Buffer::new(
                ctx,
                "deferred mask readback",
                4 * width as u64 * height as u64,
                BufferUsage::Readback,
            )?,
        })
    }

    /// Moves the image to GENERAL for the mask's storage writes (contents discarded).
    fn record_to_storage(&self, device: &motion_shadows::ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: only called inside a OneShot's recording command buffer, outside rendering; the
        // image is this mask's, its earlier transfer reads (the last readback) are the source
        // scope, and UNDEFINED discards contents the mask pass overwrites whole.
        unsafe {
            image_barrier(
                device,
                cmd,
                self.image.raw(),
                self.image.layers_range(0, 1),
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::TRANSFER_READ,
                Access::COMPUTE_RW,
            )
        };
    }

    /// Copies the mask (written by the compute pass before) into the readback buffer.
    fn record_readback(&self, device: &motion_shadows::ash::Device, cmd: vk::CommandBuffer) {
        let range = self.image.layers_range(0, 1);
        let layouts = (
            vk::ImageLayout::GENERAL,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        );
        // SAFETY: only called after the mask pass in the same OneShot command buffer, outside
        // rendering; the mask image is in GENERAL (record_to_storage put it there) and moves to
        // TRANSFER_SRC_OPTIMAL for the copy.
        unsafe {
            image_barrier(
                device,
                cmd,
                self.image.raw(),
                range,
                layouts,
                Access::COMPUTE_RW,
                Access::TRANSFER_READ,
            )
        };
        // SAFETY: recording outside rendering; the buffer holds the image.
        unsafe {
            self.image
                .record_copy_to_buffer(device, cmd, self.readback.raw(), 0)
        };
        // SAFETY: the same command buffer, outside rendering; host reads are a valid destination
        // once the OneShot's fence signals, which run waits for.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
    }

    fn read(&self, (width, height): (u32, u32)) -> Result<Vec<f32>> {
        Ok(self.readback.read(width as usize * height as usize)?)
    }
}

/// The light at `p` (unit normal `n`, on the side the camera sees) but for shadows, per unit
/// albedo: `E cos / (pi d^2)` (d = 1 for a directional light), the lighting pass's term
/// ([`crate::raytrace::shade`]); `None` where the normal faces away from the light or `p`
/// lies outside a spot's cone.
pub fn direct_factor(light: &LightView, p: DVec3, n: DVec3) -> Option<f64> {
    let gpu = light.gpu();
    let spot = gpu.position.w > 0.5;
    let direction = gpu.direction.truncate().as_dvec3();
    let to_light = if spot {
        gpu.position.truncate().as_dvec3() - p
    } else {
        -direction
    };
    let dist2 = if spot { to_light.length_squared() } else { 1.0 };
    let l = to_light.normalize();
    let cos_theta = n.dot(l);
    let in_cone = !spot || (-l).dot(direction) >= f64::from(gpu.direction.w);
    (cos_theta > 0.0 && in_cone)
        .then(|| f64::from(gpu.emission.x) * cos_theta / (std::f64::consts::PI * dist2))
}

/// Lambert shading of the G-buffer with the lit shares `lit`: ambient plus the direct term
/// ([`direct_factor`]) times the lit share. Returns the image, which pixels hold a surface and
/// which of those the light reaches but for shadows.
fn shade(
    scene: &Scene,
    light: &LightView,
    g: &GBufferContents,
    inv_view_proj: glam::Mat4,
    lit: &[f32],
) -> Result<(RadianceImage, Vec<bool>, Vec<bool>)> {
    let ambient = f64::from(scene.ambient);
    let inv = inv_view_proj.as_dmat4();
    let (w, h) = (g.width as usize, g.height as usize);
    let mut rgb = vec![0.0f32; 3 * w * h];
    let mut hit = vec![false; w * h];
    let mut facing = vec![false; w * h];
    for i in 0..w * h {
        if g.depth[i] >= 1.0 {
            continue;
        }
        hit[i] = true;
        let (x, y) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
        let ndc = glam::DVec4::new(
            x / w as f64 * 2.0 - 1.0,
            y / h as f64 * 2.0 - 1.0,
            f64::from(g.depth[i]),
            1.0,
        );
        let p = inv * ndc;
        let p = p.truncate() / p.w;
        let albedo = g.albedo[i].as_dvec3();
        let direct = direct_factor(light, p, g.normal[i].as_dvec3());
        facing[i] = direct.is_some();
        let radiance = albedo * (ambient + direct.unwrap_or(0.0) * f64::from(lit[i]));
        rgb[3 * i..3 * i + 3].copy_from_slice(&radiance.as_vec3().to_array());
    }
    Ok((RadianceImage::new(g.width, g.height, rgb)?, hit, facing))
}

/// The refusal of a mask whose `pixels` walked past the device's loop `limit`, reading a map
/// built for `lookup`. (The forward frame's refusal suggests its own options: a shadow
/// filter, the estimator.)
pub fn loop_limit_error(pixels: u32, limit: u32, lookup: Lookup) -> Error {
    let fewer_ranges = match lookup {
        Lookup::DepthLine => "store fewer ranges per texel (--pruning cover)",
        // Its lists name every triangle near a texel and are not pruned.
        Lookup::Exact => {
            "read the map's depth lines instead (--lookup depth: fewer ranges per texel)"
        }
    };
    Error::MaskLoopLimit {
        pixels,
        limit,
        fewer_ranges,
    }
}
