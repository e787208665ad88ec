//! One frame's commands: the G-buffer, each light's shadow and mask (the library's), the
//! shading, and the engine's barriers between them, from the declared accesses.

use super::*;

impl Engine<'_> {
    /// Records frame `frame` into its slot's command buffer (recording, outside rendering).
    pub(super) fn record(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        let submission = self.submissions;
        let Engine {
            gpu,
            settings,
            pipelines: p,
            geometry,
            slots,
            shadows,
            ctx,
            ..
        } = self;
        let ((vertices, indices, meshes), device, s) = (&*geometry, &gpu.device, &mut slots[slot]);
        let (cmd, width, height, f) = (s.cmd, settings.width, settings.height, f64::from(frame));
        // Last frame's and this frame's transforms: the shutter's two ends.
        let at = |m: &Mesh, f: f64| (m.transform)(f).as_mat4();
        let transforms: Vec<_> = world
            .meshes
            .iter()
            .map(|m| (at(m, f - 1.0), at(m, f)))
            .collect();

        // 1. The G-buffer at t = 1. Its images' last contents were read by the slot's last
        //    frame's compute passes: wait for those, discard the contents.
        let after_reads: State = (L::UNDEFINED, S::COMPUTE_SHADER, A::NONE);
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        let depth = (L::ATTACHMENT_OPTIMAL, tests, depth_rw);
        let color = (
            L::ATTACHMENT_OPTIMAL,
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_WRITE,
        );
        let written = |i| if i == 0 { depth } else { color };
        let to_attachments = |(i, g): (usize, &Image)| g.barrier(after_reads, written(i));
        let barriers: Vec<_> = s.gbuffer.iter().enumerate().map(to_attachments).collect();
        pipeline_barrier(device, cmd, &barriers, &[]);
        // Cleared to zero, the ids to "no triangle", the depth to the far plane.
        let far = vk::ClearDepthStencilValue {
            depth: 1.0,
            stencil: 0,
        };
        let none = vk::ClearColorValue {
            uint32: [u32::MAX; 4],
        };
        let clears = [vk::ClearValue { depth_stencil: far }, Default::default()];
        let clears = [
            clears[0],
            clears[1],
            clears[1],
            clears[1],
            vk::ClearValue { color: none },
        ];
        let attachment = |(image, clear): (&Image, _)| {
            let info = vk::RenderingAttachmentInfo::default().image_view(image.view);
            let info = info.load_op(vk::AttachmentLoadOp::CLEAR).clear_value(clear);
            info.store_op(vk::AttachmentStoreOp::STORE)
                .image_layout(L::ATTACHMENT_OPTIMAL)
        };
        let attachments: Vec<_> = s.gbuffer.iter().zip(clears).map(attachment).collect();
        let area = vk::Rect2D {
            offset: Default::default(),
            extent: vk::Extent2D { width, height },
        };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1);
        let info = info
            .color_attachments(&attachments[1..])
            .depth_attachment(&attachments[0]);
        let (w, h) = (width as f32, height as f32);
        let viewport = vk::Viewport {
            width: w,
            height: h,
            max_depth: 1.0,
            ..Default::default()
        };
        let rows = |m: Mat4| [m.row(0), m.row(1), m.row(2)];
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let addresses = [s.constants.address(), vertices.address()];
        // SAFETY: the barrier above moved the attachments (the slot's, of the render area's
        // size) to the layout `info` names; the pipeline was made for their formats; each
        // mesh's indices lie in the index buffer at its offset, its vertices from its base;
        // the push constants are DrawConstants, the layout's range.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.gbuffer);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            for ((mesh, m), (t0, t1)) in world.meshes.iter().zip(meshes).zip(&transforms) {
                let (model, previous_model) = (rows(*t1), rows(*t0));
                let (albedo, first_id) = (mesh.albedo, m.first_triangle_id);
                let push = DrawConstants {
                    addresses,
                    model,
                    previous_model,
                    albedo,
                    first_id,
                };
                device.cmd_push_constants(cmd, p.layouts[0], stages, 0, bytemuck::bytes_of(&push));
                let index_type = match mesh.indices {
                    MeshIndices::U16(_) => vk::IndexType::UINT16,
                    MeshIndices::U32(_) => vk::IndexType::UINT32,
                };
                device.cmd_bind_index_buffer(cmd, indices.buffer, m.index_offset, index_type);
                let base = (m.vertex_offset / size_of::<Vertex>() as u64) as i32;
                device.cmd_draw_indexed(cmd, mesh.indices.count() as u32, 1, 0, base, 0);
            }
            device.cmd_end_rendering(cmd);
        }

        // 2. Per light, the library's shadow of the meshes, each described once: the draw and
        //    the room reserved come from the same description.
        let mut described = Vec::new();
        for ((mesh, m), &(t0, t1)) in world.meshes.iter().zip(meshes).zip(&transforms) {
            // SAFETY: the streams' contract: the engine's vertex and index buffers were made
            // with STORAGE_BUFFER and SHADER_DEVICE_ADDRESS usage on the context's device,
            // written before the first submission and never again, and outlive every frame;
            // each mesh's vertices (24-byte stride) and indices (4-byte aligned runs, padded
            // to a whole word) lie inside them at its offsets.
            let (at, index) = unsafe {
                let at =
                    PositionStream::from_device_address(vertices.address() + m.vertex_offset, 24);
                (
                    at,
                    IndexStream::from_device_address(indices.address() + m.index_offset),
                )
            };
            let (n, cpu) = (m.positions.len() as u32, &m.positions[..]);
            let (shape, cpu) = match t0 == t1 {
                true => (
                    ShadowMesh::still(at, n).transform(t1),
                    CpuGeometry::still(cpu),
                ),
                false => {
                    let shape = ShadowMesh::moving(at, at, n).transforms(t0, t1);
                    (shape, CpuGeometry::moving(cpu, cpu))
                }
            };
            let (index, cpu) = match &mesh.indices {
                MeshIndices::U16(i) => (Indices::U16(index), cpu.indices_u16(i)),
                MeshIndices::U32(i) => (Indices::U32(index), cpu.indices_u32(i)),
            };
            let shape = shape
                .indexed(index, (mesh.indices.count() / 3) as u32)
                .cpu(cpu);
            let shape = shape.first_triangle_id(m.first_triangle_id);
            described.push(if mesh.closed { shape.closed() } else { shape });
        }
        // The masks' inputs: the G-buffer; moving receivers need the ids too (a turning face's
        // own triangle would shadow it, and the mask refuses to run without them).
        let (view, read) = (|i: usize| s.gbuffer[i].view, L::READ_ONLY_OPTIMAL);
        let inv_view_proj = world.camera.view_proj(w / h).inverse();
        let encoding = NormalEncoding::Signed;
        let normals = NormalImage {
            view: view(1),
            layout: read,
            encoding,
        };
        let motion = MotionImage {
            view: view(3),
            layout: read,
        };
        let ids = TriangleIdImage {
            view: view(4),
            layout: read,
        };
        let mask_inputs = |mask: &Image| {
            let inputs = MaskInputs::new(view(0), read, mask.view, (width, height), inv_view_proj);
            let inputs = inputs.with_normals(normals).with_ids(ids);
            if settings.receivers_move {
                inputs.with_motion(motion, 1.0)
            } else {
                inputs
            }
        };
        let inputs: Vec<_> = s.masks.iter().map(mask_inputs).collect();
        // The shading's own uses: depth, normal, albedo and masks sampled by compute.
        let sampled = AccessData {
            stages: S::COMPUTE_SHADER,
            access: A::SHADER_SAMPLED_READ,
        };
        let reads = s.gbuffer[..3].iter().map(|i| (i, read));
        let reads = reads.chain(s.masks.iter().map(|i| (i, L::GENERAL)));
        let read_use = |(i, layout): (&Image, _)| {
            let resource = Resource::ImageView {
                view: i.view,
                layout,
            };
            ResourceUse {
                resource,
                first: sampled,
                last: sampled,
                writes: false,
            }
        };
        let shading = PassAccesses {
            uses: reads.map(read_use).collect(),
        };
        // Each image the masks and the shading use, from where it is (G-buffer written, masks
        // discarded) into its declared layout, before its declared first accesses.
        let mask_uses = |all: PassAccesses, i: &MaskInputs| all.and(&i.image_accesses());
        let declared = inputs.iter().fold(shading.clone(), mask_uses);
        let now = |view| match s.gbuffer.iter().position(|i| i.view == view) {
            Some(i) => Some((&s.gbuffer[i], written(i))),
            None => Some((s.masks.iter().find(|i| i.view == view)?, after_reads)),
        };
        let barrier = |u: &ResourceUse| match u.resource {
            Resource::ImageView { view, layout } => {
                let (image, from) = now(view)?;
                Some(image.barrier(from, (layout, u.first.stages, u.first.access)))
            }
            _ => None,
        };
        let barriers: Vec<_> = declared.uses.iter().filter_map(barrier).collect();
        pipeline_barrier(device, cmd, &barriers, &[]);
        let mut frames = Vec::new();
        for ((_, shadow), inputs) in shadows.iter_mut().zip(&inputs) {
            let (meshes, inputs) = (&described, Some(inputs));
            // SAFETY: recording outside rendering on the context's graphics+compute queue,
            // after the shadow's earlier frames (one queue, submitted in order); the streams'
            // contract is kept above; the mask's views have the usages its inputs ask and are
            // in the layouts they name (the barrier just recorded).
            frames.push(unsafe { shadow.record_frame(ctx, cmd, submission, meshes, inputs) }?);
        }
        s.layer_drawn = frames.iter().map(|f| f.static_layer_drawn).collect();

        // 3. The shading (each light read from its map's header), after the masks' declared
        //    last accesses; the generation's closing barrier made the maps readable.
        let masks = frames.iter().flat_map(|f| f.mask.as_ref());
        let written = masks
            .fold(PassAccesses::default(), |all, m| all.and(m))
            .last();
        let reads = frames
            .iter()
            .fold(shading, |all, f| all.and(&f.lookups))
            .first();
        let memory = |(src_stage, src_access), (dst_stage, dst_access)| {
            let barrier = vk::MemoryBarrier2::default().src_stage_mask(src_stage);
            let barrier = barrier
                .src_access_mask(src_access)
                .dst_stage_mask(dst_stage);
            [barrier.dst_access_mask(dst_access)]
        };
        let to_shading = memory(
            (written.stages, written.access),
            (reads.stages, reads.access),
        );
        pipeline_barrier(device, cmd, &[], &to_shading);
        let (output, pixels) = (s.output.address(), u64::from(width) * u64::from(height));
        let maps = [frames[0].map_header, frames[frames.len() - 1].map_header];
        let push = [
            s.constants.address(),
            output,
            output + 16 * pixels,
            maps[0],
            maps[1],
        ];
        // SAFETY: the shading's layout holds the slot's set (its images, in the layouts the
        // set names since the barrier above) and a 40-byte compute push range, `push`'s size;
        // 8x8 groups cover the image (the shader returns past its edges), writing the slot's
        // output buffer, which holds the radiance and every mask, by address.
        unsafe {
            let (compute, push) = (vk::PipelineBindPoint::COMPUTE, bytemuck::cast_slice(&push));
            device.cmd_bind_pipeline(cmd, compute, p.shade);
            // The mask bound its own set 0 on the compute bind point: bind ours.
            device.cmd_bind_descriptor_sets(cmd, compute, p.layouts[1], 0, &[s.set], &[]);
            let stage = vk::ShaderStageFlags::COMPUTE;
            device.cmd_push_constants(cmd, p.layouts[1], stage, 0, push);
            device.cmd_dispatch(cmd, width.div_ceil(8), height.div_ceil(8), 1);
        }
        // 4. The output, read by the host after the fence.
        let to_host = memory(
            (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            (S::HOST, A::HOST_READ),
        );
        pipeline_barrier(device, cmd, &[], &to_host);
        Ok(())
    }
}
