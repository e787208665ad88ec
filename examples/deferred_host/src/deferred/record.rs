//! One frame's commands: the G-buffer, each light's shadow and mask (the library's), the
//! shading, and the engine's barriers between them, from the declared accesses.

use super::*;
use motion_shadows::{AccessData, PassAccesses, Resource, ResourceUse};
use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};

impl Engine<'_> {
    /// Records frame `frame` into its slot's command buffer (recording, outside rendering).
    pub(super) fn record(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        let Engine {
            gpu,
            settings,
            pipelines: p,
            vertices,
            indices,
            meshes,
            slots,
            shadows,
            submissions,
            ctx,
            ..
        } = self;
        let (device, s, f, (width, height)) =
            (&gpu.device, &mut slots[slot], f64::from(frame), (settings.width, settings.height));
        let cmd = s.cmd;
        // Last frame's and this frame's transforms: the shutter's two ends.
        let transforms: Vec<_> = world
            .meshes
            .iter()
            .map(|m| ((m.transform)(f - 1.0).as_mat4(), (m.transform)(f).as_mat4()))
            .collect();

        // 1. The G-buffer at t = 1. Its images' last contents were read by the slot's last
        //    frame's compute passes: wait for those, discard the contents.
        let after_reads: State = (L::UNDEFINED, S::COMPUTE_SHADER, A::NONE);
        let depth_tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_written = (
            L::ATTACHMENT_OPTIMAL,
            depth_tests,
            A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
        );
        let written = |i| {
            if i == 0 {
                depth_written
            } else {
                (L::ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE)
            }
        };
        let barriers: Vec<_> = s
            .gbuffer
            .iter()
            .enumerate()
            .map(|(i, image)| image.barrier(after_reads, written(i)))
            .collect();
        pipeline_barrier(device, cmd, &barriers, &[]);
        // Cleared to zero, the ids to "no triangle", the depth to the far plane.
        let clear = |i| match i {
            0 => vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            },
            4 => vk::ClearValue { color: vk::ClearColorValue { uint32: [u32::MAX; 4] } },
            _ => vk::ClearValue::default(),
        };
        let attachments: Vec<_> = (s.gbuffer.iter().enumerate())
            .map(|(i, image)| {
                let info = vk::RenderingAttachmentInfo::default()
                    .image_view(image.view)
                    .image_layout(L::ATTACHMENT_OPTIMAL);
                info.load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(clear(i))
            })
            .collect();
        let area =
            vk::Rect2D { offset: Default::default(), extent: vk::Extent2D { width, height } };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&attachments[1..]);
        let info = info.depth_attachment(&attachments[0]);
        let viewport = vk::Viewport {
            width: width as f32,
            height: height as f32,
            max_depth: 1.0,
            ..Default::default()
        };
        let rows = |m: Mat4| [m.row(0), m.row(1), m.row(2)];
        // SAFETY: the barrier above moved the attachments (the slot's, of the render area's
        // size) to the layout `info` names; the pipeline was made for their formats; each
        // mesh's indices lie in the index buffer at its offset, its vertices from its base;
        // the push constants are DrawConstants, the layout's range.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.gbuffer);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.buffer], &[0]);
            for ((mesh, m), (t0, t1)) in world.meshes.iter().zip(meshes.iter()).zip(&transforms) {
                let (frame, model, previous_model, first_id) =
                    ([s.constants.address(), 0], rows(*t1), rows(*t0), m.first_triangle_id);
                let push =
                    DrawConstants { frame, model, previous_model, albedo: mesh.albedo, first_id };
                let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
                device.cmd_push_constants(
                    cmd,
                    p.gbuffer_layout,
                    stages,
                    0,
                    bytemuck::bytes_of(&push),
                );
                device.cmd_bind_index_buffer(cmd, indices.buffer, m.index_offset, m.index_type);
                let base = (m.vertex_offset / size_of::<Vertex>() as u64) as i32;
                device.cmd_draw_indexed(cmd, m.indices.count() as u32, 1, 0, base, 0);
            }
            device.cmd_end_rendering(cmd);
        }

        // 2. Per light, the library's shadow of the meshes, each described once: the draw and
        //    the room reserved come from the same description.
        let mut described = Vec::new();
        for ((mesh, m), &(t0, t1)) in world.meshes.iter().zip(meshes.iter()).zip(&transforms) {
            // SAFETY: the streams' contract: the engine's vertex and index buffers were made
            // with STORAGE_BUFFER and SHADER_DEVICE_ADDRESS usage on the context's device,
            // written before the first submission and never again, and outlive every frame;
            // each mesh's vertices (24-byte stride) and indices (4-byte aligned runs, padded
            // to a whole word) lie inside them at its offsets.
            let (at, index) = unsafe {
                let at =
                    PositionStream::from_device_address(vertices.address() + m.vertex_offset, 24);
                (at, IndexStream::from_device_address(indices.address() + m.index_offset))
            };
            let (n, cpu) = (m.positions.len() as u32, &m.positions[..]);
            let (shape, cpu) = match t0 == t1 {
                true => (ShadowMesh::still(at, n).transform(t1), CpuGeometry::still(cpu)),
                false => (
                    ShadowMesh::moving(at, at, n).transforms(t0, t1),
                    CpuGeometry::moving(cpu, cpu),
                ),
            };
            let (index, cpu) = match &m.indices {
                MeshIndices::U16(i) => (Indices::U16(index), cpu.indices_u16(i)),
                MeshIndices::U32(i) => (Indices::U32(index), cpu.indices_u32(i)),
            };
            let shape = shape
                .indexed(index, (m.indices.count() / 3) as u32)
                .first_triangle_id(m.first_triangle_id)
                .cpu(cpu);
            described.push(if mesh.closed { shape.closed() } else { shape });
        }
        // The masks' inputs: the G-buffer; moving receivers need the ids too (a turning face's
        // own triangle would shadow it, and the mask refuses to run without them).
        let (view, read) = (|i: usize| s.gbuffer[i].view, L::READ_ONLY_OPTIMAL);
        let inv_view_proj = world.camera.view_proj(width as f32 / height as f32).inverse();
        let inputs: Vec<_> = (s.masks.iter())
            .map(|mask| {
                let inputs =
                    MaskInputs::new(view(0), read, mask.view, (width, height), inv_view_proj);
                let inputs = inputs.with_normals(NormalImage {
                    view: view(1),
                    layout: read,
                    encoding: NormalEncoding::Signed,
                });
                let inputs = inputs.with_ids(TriangleIdImage { view: view(4), layout: read });
                let motion = MotionImage { view: view(3), layout: read };
                if settings.receivers_move { inputs.with_motion(motion, 1.0) } else { inputs }
            })
            .collect();
        // The shading's own uses: depth, normal, albedo and masks sampled by compute.
        let sampled = AccessData { stages: S::COMPUTE_SHADER, access: A::SHADER_SAMPLED_READ };
        let reads =
            s.gbuffer[..3].iter().map(|i| (i, read)).chain(s.masks.iter().map(|i| (i, L::GENERAL)));
        let resource = |i: &Image, layout| Resource::ImageView { view: i.view, layout };
        let uses = reads.map(|(i, layout)| ResourceUse {
            resource: resource(i, layout),
            first: sampled,
            last: sampled,
            writes: false,
        });
        let shading = PassAccesses { uses: uses.collect() };
        // Each image the masks and the shading use, from where it is (G-buffer written, masks
        // discarded) into its declared layout, before its declared first accesses.
        let declared =
            inputs.iter().fold(shading.clone(), |all, inputs| all.and(&inputs.image_accesses()));
        let now = |view| match s.gbuffer.iter().position(|i| i.view == view) {
            Some(i) => Some((&s.gbuffer[i], written(i))),
            None => Some((s.masks.iter().find(|i| i.view == view)?, after_reads)),
        };
        let barriers: Vec<_> = (declared.uses.iter())
            .filter_map(|u| match u.resource {
                Resource::ImageView { view, layout } => now(view)
                    .map(|(i, from)| i.barrier(from, (layout, u.first.stages, u.first.access))),
                _ => None,
            })
            .collect();
        pipeline_barrier(device, cmd, &barriers, &[]);
        // SAFETY: recording outside rendering on the context's graphics+compute queue, after
        // each shadow's earlier frames (one queue, submitted in order); the streams' contract
        // is kept above; the mask's views have the usages its inputs ask and are in the
        // layouts they name (the barrier just recorded).
        let frames = unsafe {
            let record = shadows.iter_mut().zip(&inputs).map(|((_, shadow), i)| {
                shadow.record_frame(ctx, cmd, *submissions, &described, Some(i))
            });
            record.collect::<std::result::Result<Vec<_>, _>>()
        }?;
        s.static_layer_drawn = frames.iter().map(|f| f.static_layer_drawn).collect();

        // 3. The shading, after the masks' declared last accesses (no shader of the engine
        //    reads the maps themselves: the generation's closing barrier is the library's).
        let masks = frames
            .iter()
            .flat_map(|f| f.mask.as_ref())
            .fold(PassAccesses::default(), |all, m| all.and(m));
        let memory = |(src_stage, src_access), (dst_stage, dst_access)| {
            let barrier =
                vk::MemoryBarrier2::default().src_stage_mask(src_stage).src_access_mask(src_access);
            [barrier.dst_stage_mask(dst_stage).dst_access_mask(dst_access)]
        };
        let (written, reads) = (masks.last(), shading.first());
        pipeline_barrier(
            device,
            cmd,
            &[],
            &memory((written.stages, written.access), (reads.stages, reads.access)),
        );
        let output = s.output.address();
        let push =
            [s.constants.address(), output, output + 16 * u64::from(width) * u64::from(height)];
        // SAFETY: the shading's layout holds the slot's set (its images, in the layouts the
        // set names since the barrier above) and a 24-byte compute push range, `push`'s size;
        // 8x8 groups cover the image (the shader returns past its edges), writing the slot's
        // output buffer, which holds the radiance and every mask, by address.
        unsafe {
            let compute = vk::PipelineBindPoint::COMPUTE;
            device.cmd_bind_pipeline(cmd, compute, p.shade);
            // The mask bound its own set 0 on the compute bind point: bind ours.
            device.cmd_bind_descriptor_sets(cmd, compute, p.shade_layout, 0, &[s.set], &[]);
            device.cmd_push_constants(
                cmd,
                p.shade_layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::cast_slice(&push),
            );
            device.cmd_dispatch(cmd, width.div_ceil(8), height.div_ceil(8), 1);
        }
        // 4. The output, read by the host after the fence.
        pipeline_barrier(
            device,
            cmd,
            &[],
            &memory((S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE), (S::HOST, A::HOST_READ)),
        );
        Ok(())
    }
}
