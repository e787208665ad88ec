//! The frame loop: frames in flight (each slot waits only for its own last frame), the
//! map's room reserved before each frame, acquire, record, submit, present, and the results
//! of a completed frame read back (counters, over-budget pixels, GPU times, a screenshot).
//! A resize or an out-of-date surface makes the swapchain and the size's images again.

use super::allocations::AllocationCounter;
use super::device::ViewDevice;
use super::frame_slot::{FrameSlot, SizedTargets, screenshot_buffer};
use super::record::{FrameView, Passes, Present, record_frame};
use super::shade::ShadePass;
use super::swapchain::{Acquired, Swapchain};
use crate::render::upload::{SceneGeometry, camera_view};
use crate::scene::Scene;
use anyhow::Context as _;
use ash::vk;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    CollectionPass, GBufferPass, GenerationPass, HostDraw, LightView, TemporalShadowMap,
    VisibilityMaskPass,
};

/// Frames recorded while earlier ones still run.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// The viewer's fixed frame settings.
#[derive(Debug, Clone, Copy)]
pub struct FrameSettings {
    pub camera_time: f32,
    pub moving_receivers: bool,
    pub plane_test_where_still: bool,
    pub exposure: f32,
    pub shadow_size: (u32, u32),
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
    /// Frames whose map ran out of room (grown after): their shadows missed casters.
    pub incomplete_frames: u64,
    /// Bytes of the maps (all slots).
    pub map_bytes: u64,
    pub swapchains_made: u64,
}

pub enum Drawn {
    Presented,
    /// Nothing drawn: the surface was out of date (the swapchain was made again).
    Skipped,
}

pub struct FrameLoop {
    slots: Vec<FrameSlot>,
    passes: Passes,
    geometry: SceneGeometry,
    light: LightView,
    scene: Scene,
    settings: FrameSettings,
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
    pub fn new(
        gpu: ViewDevice,
        scene: Scene,
        light: LightView,
        settings: FrameSettings,
        window: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        let ctx = gpu.context()?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
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
            let geometry = counter.counted(SceneGeometry::upload(&ctx, &scene)?);
            let mut slots = Vec::new();
            for _ in 0..FRAMES_IN_FLIGHT {
                slots.push(FrameSlot::new(
                    &ctx,
                    pool,
                    geometry.draws.len() as u32,
                    settings.shadow_size,
                    counter,
                )?);
            }
            Ok((passes, geometry, slots))
        })();
        let (passes, geometry, slots) = match parts {
            Ok(parts) => parts,
            Err(e) => {
                unsafe { gpu.device.destroy_command_pool(pool, None) };
                return Err(e);
            }
        };
        let mut this = Self {
            slots,
            passes,
            geometry,
            light,
            scene,
            settings,
            frame: 0,
            stale_swapchain: false,
            screenshot: None,
            stats: FrameStats::default(),
            ctx,
            swapchain: None,
            pool,
            gpu,
        };
        this.make_swapchain(window, counter)?;
        // Each slot's map is reserved before its first frame, so that the frames after the
        // first allocate nothing.
        for slot in &mut this.slots {
            reserve_map(&this.ctx, &mut slot.map, &this.light, &this.scene, counter)?;
        }
        Ok(this)
    }

    pub fn device_name(&self) -> &str {
        &self.gpu.device_name
    }

    /// The validation layer's messages, also those still to come at the teardown.
    pub fn messages(&self) -> super::device::Messages {
        self.gpu.base.messages.clone()
    }

    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    /// The size of the images presented now.
    pub fn size(&self) -> Option<(u32, u32)> {
        self.swapchain.as_ref().map(Swapchain::size)
    }

    /// The window changed size: the next frame makes the swapchain again first.
    pub fn mark_resized(&mut self) {
        self.stale_swapchain = true;
    }

    pub fn take_screenshot(&mut self) -> Option<Screenshot> {
        self.screenshot.take()
    }

    fn make_swapchain(
        &mut self,
        window: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<()> {
        // Nothing may use the old swapchain's images or semaphores any more.
        unsafe { self.gpu.device.device_wait_idle() }.context("vkDeviceWaitIdle")?;
        self.finish_all()?;
        let old = self.swapchain.take();
        let made = Swapchain::new(
            &self.gpu,
            window,
            old.as_ref().map_or(vk::SwapchainKHR::null(), |s| s.handle),
        );
        drop(old);
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
        Ok(())
    }

    /// Draws and presents one frame at the window's size `window` (not zero: a minimized
    /// window draws nothing); with `screenshot`, keeps a copy of exactly what is presented
    /// ([`Self::take_screenshot`] once the frame completed: [`Self::finish_all`]).
    pub fn draw(
        &mut self,
        window: (u32, u32),
        screenshot: bool,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Drawn> {
        if self.stale_swapchain {
            counter.during_event(|c| self.make_swapchain(window, c))?;
        }
        let index = self.frame as usize % FRAMES_IN_FLIGHT;
        let device = self.gpu.device.clone();
        let fence = self.slots[index].fence;
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }
            .context("waiting for a frame in flight")?;
        self.finish(index)?;
        let acquired = self
            .swapchain
            .as_ref()
            .context("the viewer has no swapchain")?
            .acquire(self.slots[index].acquired)?;
        let image = match acquired {
            Acquired::Image(image) => image,
            Acquired::OutOfDate => {
                counter.during_event(|c| self.make_swapchain(window, c))?;
                return Ok(Drawn::Skipped);
            }
        };
        let Some(swapchain) = self.swapchain.as_ref() else {
            anyhow::bail!("the viewer has no swapchain");
        };
        let size = swapchain.size();
        let swap_image = swapchain.images[image as usize];
        let rendered = swapchain.rendered[image as usize];
        let slot = &mut self.slots[index];
        if slot.targets.as_ref().map(|t| t.size) != Some(size) {
            anyhow::bail!("the frame slot's images are not of the swapchain's size");
        }
        if screenshot {
            let buffer = counter.during_event(|c| {
                screenshot_buffer(&self.ctx, size).map(|b| c.counted(b))
            })?;
            slot.screenshot = Some((buffer, size));
        }
        // Reserved before every frame: what it can store may change (an animation).
        reserve_map(&self.ctx, &mut slot.map, &self.light, &self.scene, counter)?;
        self.ctx.begin_frame(self.frame);
        let camera = camera_view(&self.scene, size);
        let view = FrameView {
            draws: &self.geometry.draws,
            light: &self.light,
            view_proj: camera.proj * camera.view,
            eye: camera.position,
            camera_time: self.settings.camera_time,
            moving_receivers: self.settings.moving_receivers,
            plane_test_where_still: self.settings.plane_test_where_still,
            exposure: self.settings.exposure,
        };
        let present = Present {
            image: swap_image,
            screenshot: slot.screenshot.as_ref().map(|(b, _)| b.raw()),
        };
        unsafe {
            slot.timestamps.clear();
            device
                .reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty())
                .context("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(slot.cmd, &begin)
                .context("vkBeginCommandBuffer")?;
            record_frame(&device, &self.passes, slot, &view, &present)?;
            device
                .end_command_buffer(slot.cmd)
                .context("vkEndCommandBuffer")?;
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
            device
                .reset_fences(&[slot.fence])
                .context("vkResetFences")?;
            device
                .queue_submit2(self.gpu.queue, &submit, slot.fence)
                .context("vkQueueSubmit2")?;
        }
        slot.pending = Some(self.frame);
        self.frame += 1;
        if !swapchain.present(self.gpu.queue, image)? {
            self.stale_swapchain = true;
        }
        Ok(Drawn::Presented)
    }

    /// Waits for every frame in flight and reads its results.
    pub fn finish_all(&mut self) -> anyhow::Result<()> {
        for index in 0..self.slots.len() {
            let fence = self.slots[index].fence;
            unsafe { self.gpu.device.wait_for_fences(&[fence], true, u64::MAX) }
                .context("waiting for a frame in flight")?;
            self.finish(index)?;
        }
        Ok(())
    }

    /// Reads the results of slot `index`'s completed frame, if not read yet.
    fn finish(&mut self, index: usize) -> anyhow::Result<()> {
        let slot = &mut self.slots[index];
        let Some(frame) = slot.pending.take() else {
            return Ok(());
        };
        // SAFETY: the slot's fence signalled; on one queue every earlier frame completed.
        unsafe { self.ctx.collect(frame) };
        let counts = slot.map.read_counters()?;
        if slot.map.needs_more_room(&counts) {
            // Only where the room could not be reserved (reserve_for has no bound).
            self.stats.incomplete_frames += 1;
            slot.map.grow_to_fit(&self.ctx, &counts)?;
        } else {
            slot.map.check_complete(&counts)?;
        }
        if let Some(targets) = &slot.targets {
            let over = targets.mask_bindings.read_over_budget_pixels()?;
            if over > 0 {
                let limit = self.ctx.info().shader_loop_limit.unwrap_or(0);
                return Err(crate::render::deferred::loop_limit_error(
                    over,
                    limit,
                    slot.map.recorded_lookup(),
                )
                .into());
            }
        }
        if frame > 0 {
            self.stats.timed_frames += 1;
            for (pass, ms) in slot.timestamps.spans_ms()? {
                match self.stats.pass_ms.iter_mut().find(|(p, _)| *p == pass) {
                    Some((_, sum)) => *sum += ms,
                    None => self.stats.pass_ms.push((pass, ms)),
                }
            }
        }
        self.stats.completed += 1;
        self.stats.map_bytes = self.slots.iter().map(|s| s.map.allocated_bytes()).sum();
        let slot = &mut self.slots[index];
        if let Some((buffer, size)) = slot.screenshot.take() {
            let format = self
                .swapchain
                .as_ref()
                .map_or(vk::Format::UNDEFINED, |s| s.format);
            let bgra: Vec<u8> = buffer.read(4 * size.0 as usize * size.1 as usize)?;
            let rgb = bgra
                .chunks_exact(4)
                .flat_map(|p| match format {
                    vk::Format::B8G8R8A8_UNORM => [p[2], p[1], p[0]],
                    _ => [p[0], p[1], p[2]],
                })
                .collect();
            self.screenshot = Some(Screenshot { size, rgb });
        }
        Ok(())
    }
}

/// Reserves room in `map` for all that a frame of `scene` lit by `light` can store, from the
/// host's positions ([`TemporalShadowMap::reserve_for`]): such a frame never overflows and
/// is never grown and drawn again. Counts the map's growth as an allocation.
fn reserve_map(
    ctx: &Context,
    map: &mut TemporalShadowMap,
    light: &LightView,
    scene: &Scene,
    counter: &mut AllocationCounter,
) -> anyhow::Result<()> {
    let host_draws: Vec<HostDraw> = scene
        .meshes
        .iter()
        .filter(|m| m.t0.len() >= 3)
        .map(|m| HostDraw::new(&m.t0, &m.t1, None))
        .collect();
    let before = map.allocated_bytes();
    map.reserve_for(ctx, light, None, &host_draws)?;
    if map.allocated_bytes() != before {
        counter.note(1);
    }
    Ok(())
}

impl Drop for FrameLoop {
    fn drop(&mut self) {
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            // SAFETY: the device is idle.
            self.ctx.collect(u64::MAX);
        }
        // The library's objects go before the context, the swapchain and the pool before the
        // device (fields drop in order after this).
        self.slots.clear();
        unsafe { self.gpu.device.destroy_command_pool(self.pool, None) };
    }
}
