//! The frame loop: frames in flight (each slot waits only for its own last frame), the
//! map's room reserved before each frame, acquire, record, submit, present, and the results
//! of a completed frame read back (counters, over-budget pixels, GPU times, a screenshot).
//! A resize or an out-of-date surface makes the swapchain and the size's images again.

use super::allocations::AllocationCounter;
use super::device::{Messages, ViewDevice};
use super::frame_slot::{FrameSlot, SizedTargets, screenshot_buffer};
use super::frame_slot::{Pending, SplitSide};
use super::method::ViewMethod;
use super::overlay::{OVERLAY_HEIGHT, OVERLAY_WIDTH, Overlay};
use super::record::{FrameView, Passes, Present, SplitFrame, record_frame};
use super::room::{Side, prepare_side};
use super::shade::ShadePass;
use super::swapchain::{Acquired, Swapchain};
use crate::scene::Scene;
use anyhow::Context as _;
use ash::vk;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    CameraView, CollectionPass, EngineTsmPass, GBufferPass, GenerationPass, LightView,
    LightingImageOutput, LightingPass, LightingView, VisibilityMaskPass,
};

mod results;

/// Frames recorded while earlier ones still run.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// The viewer's settings that no key changes.
#[derive(Debug, Clone, Copy)]
pub struct FrameSettings {
    pub camera_time: f32,
    pub moving_receivers: bool,
    pub exposure: f32,
    pub shadow_size: (u32, u32),
}

/// What one frame shows.
pub struct FrameRequest<'a> {
    /// The window's size (not zero).
    pub window: (u32, u32),
    pub camera: &'a dyn Fn((u32, u32)) -> CameraView,
    pub method: ViewMethod,
    /// The method's light ([`ViewMethod::light`]) and the still pixels' plane test.
    pub light: LightView,
    pub plane_test_where_still: bool,
    pub overlay: Option<&'a [String]>,
    /// Keep a copy of exactly what is presented ([`FrameLoop::take_screenshot`] once the
    /// frame completed).
    pub screenshot: bool,
    /// The stochastic frame (the temporal map's, `light` its forward light) with these
    /// samples per pixel, instead of the deferred frame.
    pub stochastic: Option<(LightingView, u32)>,
    /// The split view (the deferred frame only): the right half shows this method's frame.
    pub split: Option<SplitRequest>,
}

/// The split view's right-hand method, its light and still pixels' plane test
/// ([`ViewMethod::light`]).
pub struct SplitRequest {
    pub method: ViewMethod,
    pub light: LightView,
    pub plane_test_where_still: bool,
}

/// A presented frame read back: RGB, 3 bytes a pixel, rows from the top.
pub struct Screenshot {
    pub size: (u32, u32),
    pub rgb: Vec<u8>,
}

/// What the completed frames measured.
#[derive(Debug, Default, Clone)]
pub struct FrameStats {
    /// Frames whose results were read back.
    pub completed: u64,
    /// GPU milliseconds per pass, summed over the completed frames after the first.
    pub pass_ms: Vec<(String, f64)>,
    pub timed_frames: u64,
    /// The last completed frame's GPU milliseconds per pass.
    pub last_pass_ms: Vec<(String, f64)>,
    /// The last temporal frame's stored ranges.
    pub last_ranges: u32,
    /// Frames whose map ran out of room (grown after): their shadows missed casters.
    pub incomplete_frames: u64,
    /// Bytes of the shadow maps (all slots: the temporal maps, TSM's once made).
    pub map_bytes: u64,
    pub swapchains_made: u64,
}

pub enum Drawn {
    Presented,
    /// Nothing drawn: the surface was out of date (the swapchain was made again).
    Skipped,
    /// Nothing drawn: the surface has no area (a minimized window); the swapchain is made
    /// when it has one again.
    NoArea,
}

pub struct FrameLoop {
    slots: Vec<FrameSlot>,
    passes: Passes,
    /// Made on the first frame of a TSM method.
    tsm_pass: Option<EngineTsmPass>,
    /// Made on the first stochastic frame.
    lighting: Option<(LightingPass, LightingImageOutput)>,
    scene: Scene,
    /// Incremented by each [`Self::set_scene`]: slots rewrite their geometry when behind.
    scene_version: u64,
    settings: FrameSettings,
    overlay: Overlay,
    /// The number the next frame gets.
    frame: u64,
    stale_swapchain: bool,
    screenshot: Option<Screenshot>,
    stats: FrameStats,
    ctx: Context,
    swapchain: Option<Swapchain>,
    pool: vk::CommandPool,
    /// Declared last: destroyed after everything made on it.
    gpu: ViewDevice,
}

impl FrameLoop {
    /// The loop's objects, the swapchain for `window`, and each slot's map reserved for
    /// `method` lit by `light` (the first method's) before the first frame.
    pub fn new(
        gpu: ViewDevice,
        scene: Scene,
        method: ViewMethod,
        light: &LightView,
        settings: FrameSettings,
        window: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        let ctx = gpu.context()?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `gpu.device` is alive and `queue_family` is one of its queues' families; the
        // pool is destroyed before the device (Drop, or below on error).
        let pool = counter
            .counted(unsafe { gpu.device.create_command_pool(&pool_info, None) })
            .context("vkCreateCommandPool")?;
        // Until the loop exists, an error must free the pool itself.
        let parts = (|| -> anyhow::Result<_> {
            let passes = Passes {
                gbuffer: counter.counted(GBufferPass::new(&ctx)?),
                collection: counter.counted(CollectionPass::new(&ctx)?),
                generation: counter.counted(GenerationPass::new(&ctx)?),
                mask: counter.counted(VisibilityMaskPass::new(&ctx)?),
                shade: counter.counted(ShadePass::new(&ctx, &scene)?),
            };
            let mut slots = Vec::new();
            for _ in 0..FRAMES_IN_FLIGHT {
                slots.push(FrameSlot::new(
                    &ctx,
                    pool,
                    &scene,
                    settings.shadow_size,
                    counter,
                )?);
            }
            Ok((passes, slots))
        })();
        let (passes, slots) = match parts {
            Ok(parts) => parts,
            Err(e) => {
                // SAFETY: the pool is this device's and nothing was submitted from it; the
                // slots made from it were dropped with the closure's error.
                unsafe { gpu.device.destroy_command_pool(pool, None) };
                return Err(e);
            }
        };
        let mut this = Self {
            slots,
            passes,
            tsm_pass: None,
            lighting: None,
            scene,
            scene_version: 0,
            settings,
            overlay: Overlay::default(),
            frame: 0,
            stale_swapchain: false,
            screenshot: None,
            stats: FrameStats::default(),
            ctx,
            swapchain: None,
            pool,
            gpu,
        };
        // Where the window starts without area, the first frame with one makes it.
        this.make_swapchain(window, counter)?;
        // Each slot's map is reserved before its first frame, so that the frames after the
        // first allocate nothing (TSM's maps are made on the first frame that shows it).
        if !matches!(method, ViewMethod::Tsm { .. }) {
            for slot in &mut this.slots {
                let triangles = u64::from(slot.geometry.triangle_count);
                let side = Side {
                    method,
                    light,
                    map: &mut slot.map,
                    tsm: &mut slot.tsm,
                    switched: false,
                };
                prepare_side(&this.ctx, side, None, &this.scene, triangles, counter)?;
                slot.last_method = Some(method);
            }
        }
        Ok(this)
    }

    pub fn device_name(&self) -> &str {
        &self.gpu.device_name
    }

    /// The validation layer's messages, also those still to come at the teardown.
    pub fn messages(&self) -> Messages {
        self.gpu.base.messages.clone()
    }

    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The size of the images presented now.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.swapchain.as_ref().map(Swapchain::size)
    }

    /// The window changed size: the next frame makes the swapchain again first.
    pub fn mark_resized(&mut self) {
        self.stale_swapchain = true;
    }

    /// The scene posed anew (the animation's time, the shutter): each slot rewrites its
    /// vertices before its next frame.
    pub fn set_scene(
        &mut self,
        scene: Scene,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<()> {
        if self.passes.shade.set_scene(&self.ctx, &scene)? {
            counter.during_event(|c| c.note(1));
        }
        self.scene = scene;
        self.scene_version += 1;
        Ok(())
    }

    pub fn take_screenshot(&mut self) -> Option<Screenshot> {
        self.screenshot.take()
    }

    /// Makes the swapchain for `window` and the slots' images of its size; false (the old
    /// one kept, still stale) where the surface has no area.
    fn make_swapchain(
        &mut self,
        window: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<bool> {
        // Nothing may use the old swapchain's images or semaphores any more.
        // SAFETY: the device is alive; no other thread uses its queue (the viewer is one
        // thread).
        unsafe { self.gpu.device.device_wait_idle() }.map_err(device_error)?;
        self.finish_all(counter)?;
        let old_handle = self
            .swapchain
            .as_ref()
            .map_or(vk::SwapchainKHR::null(), |s| s.handle);
        let made = Swapchain::new(&self.gpu, window, old_handle);
        let Some(made) = made.transpose() else {
            self.stale_swapchain = true;
            return Ok(false);
        };
        // Retired by the new one (or by the failed attempt): destroyed either way.
        self.swapchain = None;
        let swapchain = counter.counted(made?);
        let size = swapchain.size();
        self.swapchain = Some(swapchain);
        self.stats.swapchains_made += 1;
        self.stale_swapchain = false;
        // Every slot's images of the new size now (the device is idle), not at each slot's
        // first frame after it.
        for slot in &mut self.slots {
            if slot.targets.as_ref().map(|t| t.size) != Some(size) {
                slot.targets = None;
                slot.targets = Some(SizedTargets::new(
                    &self.ctx,
                    size,
                    &self.passes.mask,
                    &self.passes.shade,
                    counter,
                )?);
            }
        }
        Ok(true)
    }

    /// Draws and presents one frame.
    pub fn draw(
        &mut self,
        request: &FrameRequest<'_>,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Drawn> {
        if self.stale_swapchain
            && !counter.during_event(|c| self.make_swapchain(request.window, c))?
        {
            return Ok(Drawn::NoArea);
        }
        let index = self.frame as usize % FRAMES_IN_FLIGHT;
        let device = self.gpu.device.clone();
        let fence = self.slots[index].fence;
        // SAFETY: the fence is the slot's, of this device, alive while the slot is.
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.map_err(device_error)?;
        self.finish(index, counter)?;
        let acquired = self
            .swapchain
            .as_ref()
            .context("the viewer has no swapchain")?
            .acquire(self.slots[index].acquired)?;
        let (image, suboptimal) = match acquired {
            Acquired::Image(image, suboptimal) => (image, suboptimal),
            Acquired::OutOfDate => {
                let made = counter.during_event(|c| self.make_swapchain(request.window, c))?;
                return Ok(if made { Drawn::Skipped } else { Drawn::NoArea });
            }
        };
        let Some(swapchain) = self.swapchain.as_ref() else {
            anyhow::bail!("the viewer has no swapchain");
        };
        let size = swapchain.size();
        let swap_image = swapchain.images[image as usize];
        let rendered = swapchain.rendered[image as usize];
        let shows_tsm = |m: ViewMethod| matches!(m, ViewMethod::Tsm { .. });
        if self.tsm_pass.is_none()
            && (shows_tsm(request.method)
                || request.split.as_ref().is_some_and(|s| shows_tsm(s.method)))
        {
            let ctx = &self.ctx;
            self.tsm_pass =
                Some(counter.during_event(|c| EngineTsmPass::new(ctx).map(|p| c.counted(p)))?);
        }
        let ctx = &self.ctx;
        let slot = &mut self.slots[index];
        if slot.targets.as_ref().map(|t| t.size) != Some(size) {
            anyhow::bail!("the frame slot's images are not of the swapchain's size");
        }
        if request.screenshot {
            let buffer =
                counter.during_event(|c| screenshot_buffer(ctx, size).map(|b| c.counted(b)))?;
            slot.screenshot = Some((buffer, size));
        }
        slot.update_geometry(ctx, &self.scene, self.scene_version, counter)?;
        if let Some((_, spp)) = request.stochastic {
            if matches!(request.method, ViewMethod::Tsm { .. }) {
                anyhow::bail!("the viewer's stochastic frame is the temporal map's, not TSM's");
            }
            if self.lighting.is_none() {
                self.lighting = Some(counter.during_event(|c| -> anyhow::Result<_> {
                    c.note(2);
                    Ok((LightingPass::new(ctx)?, LightingImageOutput::new(ctx)?))
                })?);
            }
            let Some((_, output)) = self.lighting.as_ref() else {
                anyhow::bail!("the lighting pass was not made");
            };
            counter.during_event(|c| slot.lighting_targets(ctx, output, size, spp, c))?;
        }
        let triangles = u64::from(slot.geometry.triangle_count);
        let method_switched = slot.last_method != Some(request.method);
        let tsm_maps = prepare_side(
            ctx,
            Side {
                method: request.method,
                light: &request.light,
                map: &mut slot.map,
                tsm: &mut slot.tsm,
                switched: method_switched,
            },
            self.tsm_pass.as_ref(),
            &self.scene,
            triangles,
            counter,
        )?;
        slot.last_method = Some(request.method);
        let split_maps = match &request.split {
            Some(split) => {
                if request.stochastic.is_some() {
                    anyhow::bail!(
                        "the split view shows the deferred frame, not the stochastic one"
                    );
                }
                let shadow = self.settings.shadow_size;
                let side = match &mut slot.split {
                    Some(side) => side,
                    empty => {
                        empty.insert(counter.during_event(|c| SplitSide::new(ctx, shadow, c))?)
                    }
                };
                let switched = side.last_method != Some(split.method);
                let maps = prepare_side(
                    ctx,
                    Side {
                        method: split.method,
                        light: &split.light,
                        map: &mut side.map,
                        tsm: &mut side.tsm,
                        switched,
                    },
                    self.tsm_pass.as_ref(),
                    &self.scene,
                    triangles,
                    counter,
                )?;
                side.last_method = Some(split.method);
                Some((split, maps))
            }
            None => None,
        };
        let overlay = match request.overlay {
            Some(lines) => {
                slot.overlay.write(self.overlay.compose(lines))?;
                Some((
                    slot.overlay.device_address(),
                    (OVERLAY_WIDTH, OVERLAY_HEIGHT),
                ))
            }
            None => None,
        };
        self.ctx.begin_frame(self.frame);
        let camera = (request.camera)(size);
        let view = FrameView {
            light: &request.light,
            view_proj: camera.proj * camera.view,
            eye: camera.position,
            camera_time: self.settings.camera_time,
            moving_receivers: self.settings.moving_receivers,
            plane_test_where_still: request.plane_test_where_still,
            exposure: self.settings.exposure,
            overlay,
            tsm: tsm_maps.and_then(|maps| self.tsm_pass.as_ref().map(|pass| (pass, maps))),
            split: split_maps.map(|(split, maps)| SplitFrame {
                light: &split.light,
                plane_test_where_still: split.plane_test_where_still,
                tsm: maps.and_then(|maps| self.tsm_pass.as_ref().map(|pass| (pass, maps))),
            }),
            stochastic: match (&request.stochastic, &self.lighting) {
                (Some((lighting_view, _)), Some((pass, output))) => Some((
                    pass,
                    output,
                    // The camera of the presented size (the request's may predate a resize).
                    LightingView {
                        camera,
                        ..*lighting_view
                    },
                )),
                _ => None,
            },
        };
        let present = Present {
            image: swap_image,
            screenshot: slot.screenshot.as_ref().map(|(b, _)| b.raw()),
        };
        // SAFETY: the slot's last frame completed (its fence was waited for above), so its
        // command buffer, fence, timestamps and descriptor sets are not in use; the buffer is
        // from a pool made with RESET_COMMAND_BUFFER, and is recording when `record_frame`
        // runs. `record_frame`'s contract: the slot's targets are of the swapchain image's
        // size (checked above), `swap_image` was acquired with `slot.acquired`, which the
        // submission waits for at the transfer stage, and the map's room was reserved above
        // (temporal) or grows after a frame that overflowed (exact). The submission's
        // semaphores and fence are this device's; `rendered` is the image's own, unsignalled
        // (its last present, which waited on it, was before this image's acquire).
        unsafe {
            slot.timestamps.clear();
            device
                .reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(device_error)?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(slot.cmd, &begin)
                .map_err(device_error)?;
            record_frame(&device, &self.passes, slot, &view, &present)?;
            device.end_command_buffer(slot.cmd).map_err(device_error)?;
            let waits = [vk::SemaphoreSubmitInfo::default()
                .semaphore(slot.acquired)
                .stage_mask(vk::PipelineStageFlags2::TRANSFER)];
            let signals = [vk::SemaphoreSubmitInfo::default()
                .semaphore(rendered)
                .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
            let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(slot.cmd)];
            let submit = [vk::SubmitInfo2::default()
                .wait_semaphore_infos(&waits)
                .command_buffer_infos(&cmds)
                .signal_semaphore_infos(&signals)];
            device.reset_fences(&[slot.fence]).map_err(device_error)?;
            device
                .queue_submit2(self.gpu.queue, &submit, slot.fence)
                .map_err(device_error)?;
        }
        let split_tsm = slot.split.as_ref().and_then(|s| s.tsm.as_ref());
        for tsm in slot.tsm.iter().chain(split_tsm) {
            // The static map it may have drawn is now kept for the side's next TSM frame.
            tsm.map.static_map_submitted();
        }
        slot.pending = Some(Pending {
            frame: self.frame,
            method: request.method,
            stochastic: request.stochastic.is_some(),
            split: request.split.as_ref().map(|s| s.method),
        });
        self.frame += 1;
        if !swapchain.present(self.gpu.queue, image)? || suboptimal {
            self.stale_swapchain = true;
        }
        Ok(Drawn::Presented)
    }
}

/// A Vulkan error of a submission or wait, with a clear word for a lost device.
fn device_error(result: vk::Result) -> anyhow::Error {
    match result {
        vk::Result::ERROR_DEVICE_LOST => anyhow::anyhow!(
            "the Vulkan device was lost (the driver reset it or it hung): the viewer cannot go on"
        ),
        other => anyhow::anyhow!("Vulkan: {other}"),
    }
}

impl Drop for FrameLoop {
    fn drop(&mut self) {
        // SAFETY: after the wait no submission is pending (or the device is lost and runs
        // none), so every frame the context retired objects for has completed.
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            self.ctx.collect(u64::MAX);
        }
        // The library's objects go before the context, the swapchain and the pool before the
        // device (fields drop in order after this).
        self.slots.clear();
        self.tsm_pass = None;
        // SAFETY: the device is idle (above) and the slots, whose command buffers came from
        // the pool, are gone; the pool is this device's and destroyed once.
        unsafe { self.gpu.device.destroy_command_pool(self.pool, None) };
    }
}
