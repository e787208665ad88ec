//! The frame loop: submitting frames in flight, retiring them, and each frame's shadow draws.

use super::*;

impl<'h> Engine<'h> {
    /// Renders frames `frames` of `world` with `FRAMES_IN_FLIGHT` frames in flight: frame f
    /// records into slot f % FRAMES_IN_FLIGHT after waiting for that slot's previous frame, so
    /// the CPU prepares one frame while the GPU runs the earlier ones.
    ///
    /// The library reserves each frame's room from the meshes' descriptions (their CPU
    /// geometry here), so no frame's shadow overflows; one that did (a bound too small) or
    /// whose mask the device's loop limit cut short is an error once its fence signalled.
    /// Returns the frames `keep(frame)` asked for, in order.
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
                let _ = unsafe { (self.gpu.device).wait_for_fences(&[slot.fence], true, u64::MAX) };
            }
        }
    }

    /// Waits for the slot's frame (if any), checks its shadows, and reads it back if kept.
    pub(super) fn retire(
        &mut self,
        world: &World,
        slot: usize,
        keep: &dyn Fn(u32) -> bool,
    ) -> Result<Option<FrameOutput>> {
        let Some(frame) = self.slots[slot].pending.take() else {
            return Ok(None);
        };
        let s = &mut self.slots[slot];
        // SAFETY: the slot's fence was submitted with its pending frame.
        unsafe { (self.gpu.device).wait_for_fences(&[s.fence], true, u64::MAX) }
            .vk("vkWaitForFences")?;
        // SAFETY: this slot's submission has completed, and with it every earlier one on
        // the queue: what was dropped while recording them can go.
        unsafe { self.ctx.collect(s.submission) };
        for (light, (_, shadow)) in self.shadows.iter_mut().enumerate() {
            shadow
                .finish_frame(&self.ctx, s.submission)
                .map_err(|e| format!("frame {frame}, light {light}: {e}"))?;
        }
        if !keep(frame) || world.lights.is_empty() {
            return Ok(None);
        }
        let pixels = (self.settings.width * self.settings.height) as usize;
        let counters = (self.shadows.iter())
            .map(|(_, shadow)| {
                let c = shadow.map(s.submission).read_counters()?;
                Ok(MapCounts {
                    node_count: c.node_count,
                    range_count: c.range_count,
                    range_capacity: c.range_capacity,
                    ranges_direct: c.ranges_direct,
                })
            })
            .collect::<Result<_>>()?;
        let masks = (s.mask_readback.iter_mut())
            .map(|b| b.read(pixels))
            .collect::<Result<_>>()?;
        Ok(Some(FrameOutput {
            frame,
            slot,
            counters,
            radiance: s.radiance_readback.read(pixels)?,
            masks,
            static_layer_drawn: s.static_layer_drawn.clone(),
        }))
    }

    /// Writes the slot's per-frame buffers, records frame `frame` into its command buffer and
    /// submits it with its fence. The slot must be idle (retired).
    pub(super) fn submit(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        // Library objects dropped from here on (a light's old shadow) wait for this frame.
        self.submissions += 1;
        self.ctx.begin_frame(self.submissions);
        self.slots[slot].submission = self.submissions;
        // A light that moved between frames gets a new shadow (its maps follow the light).
        for (at, light) in world.lights.iter().enumerate() {
            if self
                .shadows
                .get(at)
                .is_none_or(|(made_for, _)| made_for != light)
            {
                let shadow = LightShadow::new(&self.ctx, self.shadow_settings(light))?;
                self.shadows.truncate(at);
                self.shadows.push((*light, shadow));
            }
        }
        let gpu = self.gpu;
        let device = &gpu.device;
        let f = frame as f64;
        let size = (self.settings.width, self.settings.height);
        let view_proj = world.camera.view_proj(size.0 as f32 / size.1 as f32);
        let cpu = cpu_positions(world, f);
        let meshes = self.shadow_meshes(world, slot, f, &cpu);
        let recorder = Recorder {
            device,
            ctx: &self.ctx,
            settings: &self.settings,
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
            info: UVec4::new(size.0, size.1, world.lights.len() as u32, 0),
            shading: Vec4::new(world.ambient, 0.0, 0.0, 0.0),
            lights: Default::default(),
        };
        for (c, light) in constants.lights.iter_mut().zip(&world.lights) {
            // position.w: 1 for a spot light, 0 for a directional one (no position);
            // direction.w: the spot's cosine of its cone half angle.
            let (position, direction, cos_cone, emission) = match *light {
                Light::Spot {
                    position,
                    direction,
                    cone_half_angle_deg,
                    intensity,
                    ..
                } => {
                    let cos_cone = cone_half_angle_deg.to_radians().cos();
                    (position.extend(1.0), direction, cos_cone, intensity)
                }
                Light::Directional {
                    direction,
                    irradiance,
                    ..
                } => (Vec4::ZERO, direction, -1.0, irradiance),
            };
            *c = LightConstants {
                position,
                direction: direction.normalize().extend(cos_cone),
                emission: Vec4::new(emission, 0.0, 0.0, 0.0),
            };
        }
        s.frame_constants
            .write(0, std::slice::from_ref(&constants))?;
        for ((mesh, m), (prev, cur)) in world.meshes.iter().zip(&recorder.geometry.meshes).zip(&cpu)
        {
            if let (Motion::Deformed(deform), Some(cur)) = (&mesh.motion, cur) {
                // Last frame's positions next to this frame's: what the engine keeps for its
                // motion vectors, and the shutter's two ends for the shadow pass.
                let normals = deform(f);
                if prev.len() != m.vertex_count as usize || cur.len() != prev.len() {
                    return Err(
                        format!("{}: the deformation changed the vertex count", mesh.name).into(),
                    );
                }
                let packed: Vec<[f32; 12]> = (prev.iter().zip(cur).zip(&normals))
                    .map(|((p, c), v)| {
                        let [i, j, k] = v.normal;
                        [p.x, p.y, p.z, 1.0, c.x, c.y, c.z, 1.0, i, j, k, 0.0]
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
        let shadows = (self.shadows.iter_mut()).map(|(_, shadow)| shadow);
        let recorded = recorder.record(s, world, f, self.submissions, &meshes, shadows, &constants);
        // SAFETY: the recorder received only the handle; the command buffer is still recording.
        unsafe { device.end_command_buffer(s.cmd) }.vk("vkEndCommandBuffer")?;
        recorded?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(s.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the command buffer was ended and the fence reset above; the host's queue is used
        // by this thread only, and every object the frame uses belongs to the slot or the engine,
        // kept until its fence has signalled.
        unsafe { device.queue_submit2(gpu.queue, &submit, s.fence) }.vk("vkQueueSubmit2")?;
        s.pending = Some(frame);
        Ok(())
    }

    /// The frame's meshes for the shadow pass, each described once: the engine's buffers by
    /// device address, with last frame's and this frame's transforms (rigid meshes) or
    /// positions (deformed ones), and the CPU copy the library reserves the room from.
    pub(super) fn shadow_meshes<'c>(
        &self,
        world: &'c World,
        slot: usize,
        f: f64,
        cpu: &'c [CpuPositions],
    ) -> Vec<ShadowMesh<'c>> {
        let g = &self.geometry;
        let (statics, deformed) = (
            g.static_vertices.address(),
            self.slots[slot].deformed.address(),
        );
        let stream = PositionStream::from_device_address;
        let mut meshes = Vec::new();
        for ((mesh, m), (prev, cur)) in world.meshes.iter().zip(&g.meshes).zip(cpu) {
            // The streams' contract (every unsafe below): the engine's buffers were made with
            // STORAGE_BUFFER and SHADER_DEVICE_ADDRESS usage on the context's device; each
            // mesh's vertices and indices lie inside them (offsets from the upload, 16-bit
            // indices padded to a whole word); the static buffers never change and the
            // deformed one is this slot's, written only when the slot is idle, before the
            // submission (visible to it without a barrier).
            // SAFETY: the streams' contract, for this mesh's indices.
            let index =
                unsafe { IndexStream::from_device_address(g.indices.address() + m.index_offset) };
            let indices = match &mesh.indices {
                MeshIndices::U16(_) => Indices::U16(index),
                MeshIndices::U32(_) => Indices::U32(index),
            };
            let n = m.vertex_count;
            let (described, geometry) = match &mesh.motion {
                Motion::Rigid(transform) => {
                    let (t0, t1) = (transform(f - 1.0).as_mat4(), transform(f).as_mat4());
                    // SAFETY: the streams' contract, for this rigid mesh's static vertices.
                    let at = unsafe { stream(statics + m.vertex_offset, 24) };
                    if t0 == t1 {
                        let still = ShadowMesh::still(at, n).transform(t1);
                        (still, CpuGeometry::still(prev))
                    } else {
                        let moving = ShadowMesh::moving(at, at, n).transforms(t0, t1);
                        (moving, CpuGeometry::moving(prev, prev))
                    }
                }
                Motion::Deformed(_) => {
                    let base = deformed + m.vertex_offset;
                    // SAFETY: the streams' contract, for this deformed mesh's two position
                    // sets in the slot's buffer.
                    let (open, close) = unsafe {
                        (
                            stream(base, DEFORMED_STRIDE),
                            stream(base + 16, DEFORMED_STRIDE),
                        )
                    };
                    let moving = ShadowMesh::moving(open, close, n);
                    (
                        moving,
                        CpuGeometry::moving(prev, cur.as_deref().unwrap_or(prev)),
                    )
                }
            };
            let geometry = match &mesh.indices {
                MeshIndices::U16(i) => geometry.indices_u16(i),
                MeshIndices::U32(i) => geometry.indices_u32(i),
            };
            let described = described
                .indexed(indices, mesh.triangle_count())
                .first_triangle_id(m.first_triangle_id)
                .cpu(geometry);
            meshes.push(if mesh.closed {
                described.closed()
            } else {
                described
            });
        }
        meshes
    }
}

/// Per mesh, the CPU positions the room is reserved from: object space for a rigid mesh;
/// last frame's and this frame's world positions for a deformed one.
pub(super) type CpuPositions = (Vec<Vec3>, Option<Vec<Vec3>>);

pub(super) fn cpu_positions(world: &World, f: f64) -> Vec<CpuPositions> {
    let positions = |vertices: &[Vertex]| vertices.iter().map(|v| Vec3::from(v.position)).collect();
    (world.meshes.iter())
        .map(|mesh| match &mesh.motion {
            Motion::Rigid(_) => (positions(&mesh.vertices), None),
            Motion::Deformed(deform) => (positions(&deform(f - 1.0)), Some(positions(&deform(f)))),
        })
        .collect()
}
