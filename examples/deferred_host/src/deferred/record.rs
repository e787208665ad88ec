//! Recording one frame: the library's passes and the engine's G-buffer and shading.

use super::*;

impl Recorder<'_> {
    /// Records the whole frame into the slot's command buffer (recording, outside rendering).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record<'m>(
        &self,
        s: &mut Slot,
        world: &World,
        f: f64,
        frame: u64,
        meshes: &[ShadowMesh],
        shadows: impl Iterator<Item = &'m mut LightShadow>,
        constants: &FrameConstants,
    ) -> Result<()> {
        let device = self.device;
        let cmd = s.cmd;
        let (width, height) = (self.settings.width, self.settings.height);

        // 1. The G-buffer at t = 1. Its images' previous contents (the slot's last frame) were read
        //    by the compute passes: wait for those, discard the contents (UNDEFINED).
        let none = vk::AccessFlags2::NONE;
        let earlier_reads = vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::COPY;
        let fragment_tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let depth_attachment: State = (
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            fragment_tests,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
        );
        let color_attachment: State = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let discard: State = (vk::ImageLayout::UNDEFINED, earlier_reads, none);
        pipeline_barrier(
            device,
            cmd,
            &[
                s.depth.barrier(discard, depth_attachment),
                s.normals.barrier(discard, color_attachment),
                s.albedo.barrier(discard, color_attachment),
                s.motion.barrier(discard, color_attachment),
                s.ids.barrier(discard, color_attachment),
            ],
            &[],
        );
        self.record_gbuffer(world, s, f)?;

        // 2. Per light, the library's shadow: the collection and generation of its map, then
        //    the visibility mask. The G-buffer becomes read-only for compute shaders, the mask
        //    images writable (GENERAL), as the mask's inputs contract asks.
        let sampled = vk::AccessFlags2::SHADER_SAMPLED_READ;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let storage_write = (
            vk::ImageLayout::GENERAL,
            compute,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        let shader_read: State = (vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, compute, sampled);
        let mut barriers = vec![
            s.depth.barrier(
                depth_attachment,
                (
                    vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                    compute,
                    sampled,
                ),
            ),
            s.normals.barrier(color_attachment, shader_read),
            s.albedo.barrier(color_attachment, shader_read),
            s.motion.barrier(color_attachment, shader_read),
            s.ids.barrier(color_attachment, shader_read),
            s.radiance.barrier(discard, storage_write),
        ];
        barriers.extend(s.masks.iter().map(|m| m.barrier(discard, storage_write)));
        pipeline_barrier(device, cmd, &barriers, &[]);
        let inv_view_proj = constants.inv_view_proj;
        let mut maps = [0u64; MAX_LIGHTS];
        s.static_layer_drawn.clear();
        for ((address, shadow), mask) in maps.iter_mut().zip(shadows).zip(&s.masks) {
            let inputs = MaskInputs {
                depth: s.depth.view,
                depth_layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                normals: Some(NormalImage {
                    view: s.normals.view,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    encoding: NormalEncoding::Signed,
                }),
                output: mask.view,
                size: (width, height),
                inv_view_proj,
                background_depth: 1.0,
                // Receivers move: a surface point is followed from where it was at t = 0 to
                // where the G-buffer shows it (t = 1).
                motion: self.settings.receivers_move.then_some(MotionImage {
                    view: s.motion.view,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }),
                time: 1.0,
                // Required with moving receivers: a turning face's own triangle would
                // otherwise shadow it (the mask refuses to run without).
                ids: Some(TriangleIdImage {
                    view: s.ids.view,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }),
                positions: None,
                plane_test_where_still: false,
            };
            // SAFETY: recording outside rendering on the graphics+compute queue, after this
            // shadow's earlier frames; the streams' contract is kept by `shadow_meshes`; the
            // views have the usages and layouts stated above, and the barrier before made the
            // G-buffer visible to compute reads and ordered the masks' earlier reads before
            // these writes.
            let recorded =
                unsafe { shadow.record_frame(self.ctx, cmd, frame, meshes, Some(&inputs)) }?;
            // Changes when a map grows: pushed every frame.
            *address = recorded.map_header;
            s.static_layer_drawn.push(recorded.static_layer_drawn);
        }

        // 3. The engine's shading: masks written by the mask pass become sampled reads.
        let barriers: Vec<_> = s
            .masks
            .iter()
            .map(|m| m.barrier(storage_write, shader_read))
            .collect();
        pipeline_barrier(device, cmd, &barriers, &[]);
        let (lookup, time) = match self.settings.lookup {
            ShadowLookup::MaskImages => (LOOKUP_MASKS, 0.0),
            ShadowLookup::LitFractionInShader => (LOOKUP_LIT_FRACTION, 0.0),
            ShadowLookup::VisibilityAt(t) => (LOOKUP_AT_TIME, t),
        };
        let push = ShadeConstants { maps, lookup, time };
        let p = &self.pipelines;
        // SAFETY: the shade pipeline's layout holds both sets (frame constants, images) and a
        // compute push range of ShadeConstants' size, which `bytemuck::bytes_of(&push)` is; the images were
        // moved to the layouts the sets name by the barriers above, and 8x8 groups cover the image
        // (the shader returns past its edges).
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.shade);
            // The mask pass bound its own set 0 on the compute bind point: bind ours again.
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                p.shade_layout,
                0,
                &[s.frame_set, s.image_set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                p.shade_layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(&push),
            );
            device.cmd_dispatch(cmd, width.div_ceil(8), height.div_ceil(8), 1);
        }

        // 4. Read back the radiance and the masks (an engine would present or post-process;
        //    this one writes files and tests).
        let transfer_src: State = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        );
        let mut barriers = vec![s.radiance.barrier(storage_write, transfer_src)];
        barriers.extend(s.masks.iter().map(|m| m.barrier(shader_read, transfer_src)));
        pipeline_barrier(device, cmd, &barriers, &[]);
        let color = [vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                layer_count: 1,
                ..Default::default()
            })
            .image_extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })];
        // SAFETY: the radiance and mask images are in TRANSFER_SRC_OPTIMAL (the barriers above),
        // each readback buffer holds one image of width x height texels (made so in new_slot), and
        // the region is exactly that.
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                s.radiance.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                s.radiance_readback.buffer,
                &color,
            );
            for (mask, readback) in s.masks.iter().zip(&s.mask_readback) {
                device.cmd_copy_image_to_buffer(
                    cmd,
                    mask.image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.buffer,
                    &color,
                );
            }
        }
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        pipeline_barrier(device, cmd, &[], &to_host);
        Ok(())
    }

    /// The G-buffer pass: dynamic rendering into depth, normals, albedo, motion and ids; every mesh drawn
    /// with its own vertex and index buffers at t = 1.
    pub(super) fn record_gbuffer(&self, world: &World, s: &Slot, f: f64) -> Result<()> {
        let device = self.device;
        let cmd = s.cmd;
        let (width, height) = (self.settings.width, self.settings.height);
        // Cleared to zero, the ids to "no triangle".
        let no_id = vk::ClearColorValue {
            uint32: [u32::MAX; 4],
        };
        let colors = [
            (&s.normals, Default::default()),
            (&s.albedo, Default::default()),
            (&s.motion, Default::default()),
            (&s.ids, no_id),
        ]
        .map(|(image, color)| {
            vk::RenderingAttachmentInfo::default()
                .image_view(image.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue { color })
        });
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(s.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            });
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D { width, height },
        };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&colors)
            .depth_attachment(&depth);
        let p = &self.pipelines;
        let g = &self.geometry;
        // SAFETY: the barrier recorded just before record_gbuffer moved the attachments to the
        // layouts `info` names; their views are the slot's, of the render area's size, and the
        // pipeline was made for these formats.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.gbuffer);
            device.cmd_set_viewport(
                cmd,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: width as f32,
                    height: height as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                p.gbuffer_layout,
                0,
                &[s.frame_set],
                &[],
            );
        }
        for (mesh, m) in world.meshes.iter().zip(&g.meshes) {
            // Binding 0 = positions, binding 1 = normals, binding 2 = last frame's positions:
            // three views of one interleaved buffer, with the draw's own stride (dynamic
            // state). A rigid mesh's last positions are its vertices under last frame's model.
            let (model, previous_model, buffer, positions, normals, previous, stride) =
                match &mesh.motion {
                    Motion::Rigid(transform) => (
                        transform(f).as_mat4(),
                        transform(f - 1.0).as_mat4(),
                        g.static_vertices.buffer,
                        m.vertex_offset,
                        m.vertex_offset + 12,
                        m.vertex_offset,
                        24,
                    ),
                    Motion::Deformed(_) => (
                        Mat4::IDENTITY,
                        Mat4::IDENTITY,
                        s.deformed.buffer,
                        m.vertex_offset + 16,
                        m.vertex_offset + 32,
                        m.vertex_offset,
                        DEFORMED_STRIDE as u64,
                    ),
                };
            let rows = |m: Mat4| [m.row(0), m.row(1), m.row(2)];
            let push = DrawConstants {
                model: rows(model),
                previous_model: rows(previous_model),
                albedo: mesh.albedo.extend(1.0),
                first_id: m.first_triangle_id,
                pad: [0; 3],
            };
            // SAFETY: the buffers and offsets are the engine's (made by the upload, the stride its
            // vertex layout), the index buffer holds this mesh's indices at its offset, and the
            // push is DrawConstants' size, the layout's range; inside the rendering begun above
            // with the G-buffer pipeline bound.
            unsafe {
                device.cmd_bind_vertex_buffers2(
                    cmd,
                    0,
                    &[buffer, buffer, buffer],
                    &[positions, normals, previous],
                    None,
                    Some(&[stride, stride, stride]),
                );
                device.cmd_bind_index_buffer(cmd, g.indices.buffer, m.index_offset, m.index_type);
                device.cmd_push_constants(
                    cmd,
                    p.gbuffer_layout,
                    vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                    0,
                    bytemuck::bytes_of(&push),
                );
                device.cmd_draw_indexed(cmd, m.index_count, 1, 0, 0, 0);
            }
        }
        // SAFETY: the rendering began above and every mesh is drawn.
        unsafe { device.cmd_end_rendering(cmd) };
        Ok(())
    }
}
