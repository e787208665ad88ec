//! A completed frame's results, read back once its slot's fence signalled: the maps'
//! counters (an overflow counted and grown; missing ranges or pixels past the loop limit an
//! error), the GPU times per pass, the maps' memory, a screenshot.

use super::{FrameLoop, FrameStats, Screenshot, device_error};
use crate::view::allocations::AllocationCounter;
use crate::view::frame_slot::{FrameSlot, Pending};
use crate::view::method::ViewMethod;
use ash::vk;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{Counters, MaskBindings, TemporalShadowMap};

impl FrameLoop {
    /// Waits for every frame in flight and reads its results.
    pub fn finish_all(&mut self, counter: &mut AllocationCounter) -> anyhow::Result<()> {
        for index in 0..self.slots.len() {
            let fence = self.slots[index].fence;
            // SAFETY: the fence is the slot's, of this device, alive while the slot is.
            unsafe { self.gpu.device.wait_for_fences(&[fence], true, u64::MAX) }
                .map_err(device_error)?;
            self.finish(index, counter)?;
        }
        Ok(())
    }

    /// Reads the results of slot `index`'s completed frame, if not read yet.
    pub(super) fn finish(
        &mut self,
        index: usize,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<()> {
        let slot = &mut self.slots[index];
        let Some(Pending {
            frame,
            method,
            stochastic,
            split,
        }) = slot.pending.take()
        else {
            return Ok(());
        };
        // SAFETY: the slot's fence signalled; on one queue every earlier frame completed.
        unsafe { self.ctx.collect(frame) };
        if !matches!(method, ViewMethod::Tsm { .. }) {
            let mask = slot
                .targets
                .as_ref()
                .filter(|_| !stochastic)
                .map(|t| &t.mask_bindings);
            let counts =
                check_temporal_frame(&self.ctx, &mut slot.map, mask, &mut self.stats, counter)?;
            self.stats.last_ranges = counts.range_count;
        }
        if let (Some(side), Some(ViewMethod::Temporal | ViewMethod::TemporalExact)) =
            (slot.split.as_mut(), split)
        {
            let mask = slot.targets.as_ref().map(|t| &t.split_mask_bindings);
            check_temporal_frame(&self.ctx, &mut side.map, mask, &mut self.stats, counter)?;
        }
        if let Some(lighting) = slot.lighting.as_ref().filter(|_| stochastic) {
            let over = lighting.target.read_over_budget_pixels()?;
            if over > 0 {
                anyhow::bail!(
                    "the stochastic frame's shadow lookups ran past the device's loop limit \
                     at {over} pixels (lavapipe): its shadows may be wrong there; use the \
                     deferred frame (F) or the depth lookup"
                );
            }
        }
        let spans = slot.timestamps.spans_ms()?;
        if frame > 0 {
            self.stats.timed_frames += 1;
            for (pass, ms) in &spans {
                match self.stats.pass_ms.iter_mut().find(|(p, _)| p == pass) {
                    Some((_, sum)) => *sum += ms,
                    None => self.stats.pass_ms.push((pass.clone(), *ms)),
                }
            }
        }
        self.stats.last_pass_ms = spans;
        self.stats.completed += 1;
        self.stats.map_bytes = self.slots.iter().map(FrameSlot::map_bytes).sum();
        let slot = &mut self.slots[index];
        if let Some((buffer, size)) = slot.screenshot.take() {
            let format = self
                .swapchain
                .as_ref()
                .map_or(vk::Format::UNDEFINED, |s| s.format);
            let pixels: Vec<u8> = buffer.read(4 * size.0 as usize * size.1 as usize)?;
            let rgb = pixels
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

/// Reads a completed temporal frame's counters from `map` (and its mask's pixels past the
/// loop limit from `mask`): a frame that overflowed (the room reserved was short: a bug of
/// the bound) is counted as incomplete and the map grown; a frame with missing ranges or
/// pixels past the loop limit is an error.
fn check_temporal_frame(
    ctx: &Context,
    map: &mut TemporalShadowMap,
    mask: Option<&MaskBindings>,
    stats: &mut FrameStats,
    counter: &mut AllocationCounter,
) -> anyhow::Result<Counters> {
    let counts = map.read_counters()?;
    if map.needs_more_room(&counts) {
        stats.incomplete_frames += 1;
        map.grow_to_fit(ctx, &counts)?;
        counter.note(1);
    } else {
        map.check_complete(&counts)?;
    }
    if let Some(mask) = mask {
        let over = mask.read_over_budget_pixels()?;
        if over > 0 {
            let limit = ctx.info().shader_loop_limit.unwrap_or(0);
            return Err(crate::render::deferred::loop_limit_error(
                over,
                limit,
                map.recorded_lookup(),
            )
            .into());
        }
    }
    Ok(counts)
}
