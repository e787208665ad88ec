//! The frame loop: submitting frames in flight, retiring them, and each frame's shadow draws.

use super::*;

impl<'h> Engine<'h> {
    /// Renders frames `frames` of `world` with two frames in flight: frame f records into slot
    /// f % 2 after waiting for that slot's previous frame (two frames earlier), so the CPU
    /// prepares one frame while the GPU runs the other.
    ///
    /// Shadow-map overflow, the engine way: each frame copies its maps' counters out; when a
    /// slot's fence has signalled, the counters say whether its maps had room. If not, the
    /// maps grow to fit (`grow_to_fit`, safe then: nothing pending uses them) and the next
    /// frame in that slot has room. A frame whose shadows were incomplete is re-rendered only
    /// if `keep(frame)` says it is kept (written to disk, compared); a real-time engine would
    /// have shown it and moved on. Returns the kept frames, in order.
    pub fn render(
        &mut self,
        world: &World,
        frames: std::ops::Range<u32>,
        keep: &dyn Fn(u32) -> bool,
    ) -> Result<Vec<FrameOutput>> {
        let mut kept = Vec::new();
        let result = (|| -> Result<()> {
            for frame in frames {
                let slot = frame as usize % FRAMES_IN_FLIGHT;
                if let Some(output) = self.retire(world, slot, keep)? {
                    kept.push(output);
                }
                self.slots[slot].attempts = 0;
                self.submit(world, slot, frame)?;
            }
            // Retire what is still in flight, oldest first.
            let mut pending: Vec<(u32, usize)> = (0..FRAMES_IN_FLIGHT)
                .filter_map(|s| self.slots[s].pending.map(|f| (f, s)))
                .collect();
            pending.sort();
            for (_, slot) in pending {
                if let Some(output) = self.retire(world, slot, keep)? {
                    kept.push(output);
                }
            }
            Ok(())
        })();
        if result.is_err() {
            // Leave nothing pending behind an error (the engine may be dropped next).
            self.wait_all();
        }
        result.map(|()| kept)
    }

    pub(super) fn wait_all(&mut self) {
        for slot in &mut self.slots {
            if slot.pending.take().is_some() {
                // SAFETY: the fence belongs to this slot and was submitted with its frame
                // (`pending`).
                let _ = unsafe {
                    self.host
                        .device
                        .wait_for_fences(&[slot.fence], true, u64::MAX)
                };
            }
        }
    }

    /// Waits for the slot's frame (if any), grows its overflowing maps, re-renders it if it is
    /// kept and was incomplete, and reads it back if kept.
    pub(super) fn retire(
        &mut self,
        world: &World,
        slot: usize,
        keep: &dyn Fn(u32) -> bool,
    ) -> Result<Option<FrameOutput>> {
        let Some(frame) = self.slots[slot].pending else {
            return Ok(None);
        };
        let device = &self.host.device;
        loop {
            // SAFETY: the slot's fence was submitted with its pending frame.
            unsafe { device.wait_for_fences(&[self.slots[slot].fence], true, u64::MAX) }
                .vk("vkWaitForFences")?;
            self.slots[slot].pending = None;
            // SAFETY: this slot's submission has completed, and with it every earlier one on
            // the queue: what was dropped while recording them can go.
            unsafe { self.ctx.collect(self.slots[slot].submission) };
            let (s, ctx) = (&mut self.slots[slot], &self.ctx);
            let mut complete = true;
            for map in &mut s.maps {
                let counts = map.read_counters()?;
                if map.needs_more_room(&counts) {
                    // Nothing pending uses this slot's maps now (its fence has signalled).
                    // `grow_to_fit` makes room for exactly these counts; the scene changes a
                    // little every frame, so ask for a quarter more than this frame needed,
                    // or the next frame in this slot would likely overflow again.
                    let headroom = Counters {
                        node_count: counts.node_count.saturating_add(counts.node_count / 4),
                        range_count: counts.range_count.saturating_add(counts.range_count / 4),
                        ..counts
                    };
                    map.grow_to_fit(ctx, &headroom)?;
                    complete = false;
                } else {
                    // Errors that growing cannot fix: invalid indices, or a texel with more
                    // fragments than the generation pass can pair.
                    map.check_complete(&counts)?;
                }
            }
            // As the mask pass asks: a device that leaves long loops may have cut some
            // pixels' lookups short; their mask values cannot be trusted.
            for (light, bindings) in s.mask_bindings.iter().enumerate() {
                let over = bindings.read_over_budget_pixels()?;
                if complete && over > 0 {
                    return Err(format!(
                        "frame {frame}, light {light}: {over} mask pixel(s) need more loop \
                         iterations than this device runs"
                    )
                    .into());
                }
            }
            if !keep(frame) {
                return Ok(None);
            }
            if complete {
                break;
            }
            if s.attempts >= 3 {
                return Err(format!(
                    "frame {frame}: the shadow maps still overflow after growing twice"
                )
                .into());
            }
            // Kept and incomplete: render it again in the same slot, with the grown maps.
            self.submit(world, slot, frame)?;
        }
        let s = &self.slots[slot];
        let pixels = (self.settings.width * self.settings.height) as usize;
        let counters = s
            .maps
            .iter()
            .map(|m| m.read_counters())
            .collect::<motion_shadows::Result<_>>()?;
        let masks = s
            .mask_readback
            .iter()
            .map(|b| read_mask(b, self.mask_format, pixels))
            .collect::<Result<_>>()?;
        Ok(Some(FrameOutput {
            frame,
            slot,
            attempts: s.attempts,
            counters,
            radiance: s.radiance_readback.read(pixels)?,
            masks,
        }))
    }

    /// Writes the slot's per-frame buffers, records frame `frame` into its command buffer and
    /// submits it with its fence. The slot must be idle (retired).
    pub(super) fn submit(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        // Library objects dropped from here on (a map that grows) wait for this submission.
        self.submissions += 1;
        self.ctx.begin_frame(self.submissions);
        self.slots[slot].submission = self.submissions;
        let host = self.host;
        let device = &host.device;
        let f = frame as f64;
        let size = (self.settings.width, self.settings.height);
        let view_proj = world.camera.view_proj(size.0 as f32 / size.1 as f32);
        let lights: Vec<LightView> = world
            .lights
            .iter()
            .map(|l| LightView {
                keep_static_layer: self.settings.keep_static_layer,
                ..l.view(self.settings.shadow_size)
            })
            .collect();
        let draws = self.shadow_draws(world, slot, f)?;
        let recorder = Recorder {
            device,
            settings: &self.settings,
            passes: &self.passes,
            pipelines: &self.pipelines,
            geometry: &self.geometry,
        };
        let s = &mut self.slots[slot];
        // The uniform buffer and the deformed vertices are this slot's: its last frame has
        // completed, so the CPU may overwrite them.
        let mut constants = FrameConstants {
            view_proj,
            inv_view_proj: view_proj.inverse(),
            eye: world.camera.eye.extend(1.0),
            info: UVec4::new(size.0, size.1, lights.len() as u32, 0),
            shading: Vec4::new(world.ambient, 0.0, 0.0, 0.0),
            lights: Default::default(),
        };
        for (c, l) in constants.lights.iter_mut().zip(&lights) {
            let (w, cos_cone, emission) = match l.kind {
                LightKind::Spot {
                    cos_cone,
                    intensity,
                } => (1.0, cos_cone, intensity),
                LightKind::Directional { irradiance } => (0.0, -1.0, irradiance),
            };
            *c = LightConstants {
                position: l.position.extend(w),
                direction: l.direction.extend(cos_cone),
                emission: Vec4::new(emission, 0.0, 0.0, 0.0),
            };
        }
        s.frame_constants
            .write(0, std::slice::from_ref(&constants))?;
        for (mesh, m) in world.meshes.iter().zip(&recorder.geometry.meshes) {
            if let Motion::Deformed(deform) = &mesh.motion {
                // Last frame's positions next to this frame's: what the engine keeps for its
                // motion vectors, and the shutter's two ends for the shadow pass.
                let (prev, cur) = (deform(f - 1.0), deform(f));
                if prev.len() != m.vertex_count as usize || cur.len() != prev.len() {
                    return Err(
                        format!("{}: the deformation changed the vertex count", mesh.name).into(),
                    );
                }
                let packed: Vec<[f32; 12]> = prev
                    .iter()
                    .zip(&cur)
                    .map(|(p, c)| {
                        let [a, b, d] = p.position;
                        let [e, g, h] = c.position;
                        let [i, j, k] = c.normal;
                        [a, b, d, 1.0, e, g, h, 1.0, i, j, k, 0.0]
                    })
                    .collect();
                s.deformed.write(m.vertex_offset, &packed)?;
            }
        }
        // SAFETY: the slot is idle (the caller retired it: its fence signalled), so its command
        // buffer and fence are in no pending work; the pool allows resetting one buffer.
        unsafe {
            device.reset_fences(&[s.fence]).vk("vkResetFences")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(s.cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        let recorded = recorder.record(s, world, f, &draws, &lights, &constants);
        // SAFETY: the recorder received only the handle; the command buffer is still recording.
        unsafe { device.end_command_buffer(s.cmd) }.vk("vkEndCommandBuffer")?;
        recorded?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(s.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the command buffer was ended and the fence reset above; the host's queue is used
        // by this thread only, and every object the frame uses belongs to the slot or the engine,
        // kept until its fence has signalled.
        unsafe { device.queue_submit2(host.queue, &submit, s.fence) }.vk("vkQueueSubmit2")?;
        // The maps' static layers drawn by this frame may be kept by the slot's next one.
        for map in &s.maps {
            map.static_layer_submitted();
        }
        s.pending = Some(frame);
        s.attempts += 1;
        Ok(())
    }

    /// The frame's draws for the shadow pass: the engine's buffers by device address, with
    /// last frame's and this frame's transforms (rigid meshes) or positions (deformed ones).
    pub(super) fn shadow_draws(&self, world: &World, slot: usize, f: f64) -> Result<Vec<Draw>> {
        let g = &self.geometry;
        let (statics, deformed) = (
            g.static_vertices.address(),
            self.slots[slot].deformed.address(),
        );
        let index_base = g.indices.address();
        let mut draws = Vec::new();
        for (mesh, m) in world.meshes.iter().zip(&g.meshes) {
            let at = IndexStream::from_device_address;
            // The streams' contract (every unsafe below): the engine's buffers were made with
            // STORAGE_BUFFER and SHADER_DEVICE_ADDRESS usage on the context's device; each mesh's
            // vertices and indices lie inside them (offsets from the upload, the 16-bit indices
            // padded to a whole word); the static buffers never change and the deformed one is this
            // slot's, written only when the slot is idle; host writes before the submission are
            // visible to it without a barrier.
            let indices = match m.index_type {
                // SAFETY: the streams' contract, as stated above, for this mesh's 16-bit indices.
                vk::IndexType::UINT16 => Indices::U16(unsafe { at(index_base + m.index_offset) }),
                // SAFETY: the streams' contract, as stated above, for this mesh's 32-bit indices.
                _ => Indices::U32(unsafe { at(index_base + m.index_offset) }),
            };
            let mut draw = match &mesh.motion {
                Motion::Rigid(transform) => {
                    // SAFETY: the streams' contract, as stated above, for this rigid mesh's static
                    // vertices.
                    let stream = unsafe {
                        PositionStream::from_device_address(statics + m.vertex_offset, 24)
                    };
                    let mut draw = Draw::new(
                        stream,
                        stream,
                        m.vertex_count,
                        indices,
                        mesh.triangle_count(),
                        m.first_triangle_id,
                    );
                    draw.transform_t0 = transform(f - 1.0).as_mat4();
                    draw.transform_t1 = transform(f).as_mat4();
                    draw
                }
                Motion::Deformed(_) => {
                    let base = deformed + m.vertex_offset;
                    // SAFETY: the streams' contract, as stated above, for this deformed mesh's two
                    // position sets in the slot's buffer.
                    let (prev, cur) = unsafe {
                        (
                            PositionStream::from_device_address(base, DEFORMED_STRIDE),
                            PositionStream::from_device_address(base + 16, DEFORMED_STRIDE),
                        )
                    };
                    Draw::new(
                        prev,
                        cur,
                        m.vertex_count,
                        indices,
                        mesh.triangle_count(),
                        m.first_triangle_id,
                    )
                }
            };
            // `albedo` is for the library's own lighting pass; this engine shades itself.
            draw.closed = mesh.closed;
            draws.push(draw);
        }
        Ok(draws)
    }
}
