//! The frame loop: frames in flight submitted, retired after their fences, read back.

use super::*;

impl Engine<'_> {
    /// Renders frames `frames` of `world` with `FRAMES_IN_FLIGHT` frames in flight: frame f
    /// records into slot f % FRAMES_IN_FLIGHT once that slot's last frame is retired. A frame
    /// whose shadow was incomplete (room exceeded, the mask cut short by the device's loop
    /// limit) is an error after its fence. Returns the frames `keep(frame)` asks for.
    pub fn render(&mut self, world: &World, frames: Range<u32>, keep: Keep) -> Result<Frames> {
        let lights = self.slots[0].masks.len();
        if world.meshes.len() != self.meshes.len() || world.lights.len() != lights {
            return Err("not the meshes and lights the engine was made for".into());
        }
        let mut kept = Vec::new();
        for frame in frames {
            kept.extend(self.retire(frame as usize % FRAMES_IN_FLIGHT, keep)?);
            self.submit(world, frame as usize % FRAMES_IN_FLIGHT, frame)?;
        }
        // What is still in flight, oldest first.
        let mut pending: Vec<_> = self.slots.iter().map(|s| s.pending).enumerate().collect();
        pending.sort_by_key(|(_, frame)| *frame);
        for (slot, _) in pending {
            kept.extend(self.retire(slot, keep)?);
        }
        Ok(kept)
    }

    /// Waits for the slot's frame (if any), checks its shadows, and reads it back if kept.
    fn retire(&mut self, slot: usize, keep: Keep) -> Result<Option<FrameOutput>> {
        let s = &mut self.slots[slot];
        let Some(frame) = s.pending.take() else {
            return Ok(None);
        };
        // SAFETY: the fence was submitted with the slot's frame; once it signalled, that
        // submission and every earlier one completed: what the library dropped may go.
        unsafe {
            self.gpu
                .device
                .wait_for_fences(&[s.fence], true, u64::MAX)?;
            self.ctx.collect(s.submission);
        }
        for (light, shadow) in self.shadows.iter_mut().enumerate() {
            let finished = shadow.finish_frame(&self.ctx, s.submission);
            finished.map_err(|e| format!("frame {frame}, light {light}: {e}"))?;
        }
        if !keep(frame) {
            return Ok(None);
        }
        let pixels = (self.settings.width * self.settings.height) as usize;
        let values: Vec<f32> = s.output.read(pixels * (4 + s.masks.len()))?;
        let (radiance, masks) = values.split_at(4 * pixels);
        let radiance = bytemuck::cast_slice(radiance).to_vec();
        let masks = masks.chunks_exact(pixels).map(<[f32]>::to_vec).collect();
        let static_layer_drawn = s.layer_drawn.clone();
        let output = FrameOutput {
            frame,
            slot,
            radiance,
            masks,
            static_layer_drawn,
        };
        Ok(Some(output))
    }

    /// Writes the idle slot's constants, records frame `frame` and submits it.
    fn submit(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        // Library objects dropped from here on (a moved light's old shadow) wait for this frame.
        self.submissions += 1;
        self.ctx.begin_frame(self.submissions);
        self.slots[slot].submission = self.submissions;
        for (shadow, light) in self.shadows.iter_mut().zip(&world.lights) {
            shadow.set_light(&self.ctx, *light)?;
        }
        let (width, height) = (self.settings.width, self.settings.height);
        let view_proj = world.camera.view_proj(width as f32 / height as f32);
        let info = UVec4::new(width, height, world.lights.len() as u32, 0);
        let (eye, ambient) = (world.camera.eye.extend(1.0), Vec4::splat(world.ambient));
        let inv_view_proj = view_proj.inverse();
        // The slot is idle (retired), so the CPU may overwrite what its last frame read.
        let constants = FrameConstants {
            view_proj,
            inv_view_proj,
            eye,
            info,
            ambient,
        };
        self.slots[slot].constants.write(&[constants])?;
        let (cmd, fence, gpu) = (self.slots[slot].cmd, self.slots[slot].fence, self.gpu);
        let begin = vk::CommandBufferBeginInfo::default();
        let begin = begin.flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the slot is idle (retired, or never submitted): its command buffer and fence
        // are in no pending work, and its pool lets a buffer be reset; the buffer is ended
        // whether recording succeeded or not; the queue is used by this thread only; what the
        // frame uses is the slot's or the engine's, kept until its fence.
        unsafe {
            gpu.device.reset_fences(&[fence])?;
            gpu.device.begin_command_buffer(cmd, &begin)?;
            let recorded = self.record(world, slot, frame);
            gpu.device.end_command_buffer(cmd)?;
            recorded?;
            gpu.device.queue_submit2(gpu.queue, &submit, fence)?;
        }
        self.slots[slot].pending = Some(frame);
        Ok(())
    }
}
