//! One frame's commands: the G-buffer, each light's shadow and mask (the library's), the
//! shading, and the engine's barriers between them, from the declared accesses.

use super::*;
use motion_shadows::research::gpu::begin_rendering_colors;
use motion_shadows::{HostBarrier, HostImage};

impl Engine<'_> {
    /// Records frame `frame` into its slot's command buffer (recording, outside rendering).
    pub(super) fn record(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
        let (device, s, p) = (&self.gpu.device, &mut self.slots[slot], &self.pipelines);
        let (settings, meshes, submission) = (&self.settings, &self.meshes, self.submissions);
        let (cmd, width, height, f) = (s.cmd, settings.width, settings.height, f64::from(frame));
        // Last frame's and this frame's transforms: the shutter's two ends.
        let at = |m: &Mesh, f: f64| (m.transform)(f).as_mat4();

        // 1. The G-buffer at t = 1, declared as the library's passes are: the barriers between
        //    the frame's passes (and from the slot's last frame) come from the declarations.
        let view = |i: usize| s.gbuffer[i].layer_view(0);
        let host_image = |i: &Image| HostImage {
            image: i.raw(),
            view: i.layer_view(0),
            range: i.layers_range(0, 1),
        };
        let images: Vec<_> = s.gbuffer.iter().chain(&s.masks).map(host_image).collect();
        let data = |stages, access| AccessData { stages, access };
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        let color = data(S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        let (depth_layout, color_layout) =
            (L::DEPTH_ATTACHMENT_OPTIMAL, L::COLOR_ATTACHMENT_OPTIMAL);
        let draws = PassAccesses::host_images(&[view(0)], depth_layout, data(tests, depth), true);
        let colors = PassAccesses::host_images(&[1, 2, 3, 4].map(view), color_layout, color, true);
        let draws = draws.and(&colors);
        // Cleared to zero, the ids to "no triangle", the depth to the far plane.
        let colors = [1, 2, 3, 4].map(|i| (view(i), if i == 4 { u32::MAX } else { 0 }));
        let rows = |m: Mat4| [m.row(0), m.row(1), m.row(2)];
        // The meshes, each described once for the shadows as it is drawn: the shadow's draw and
        // the room reserved come from the same description.
        let mut described = Vec::new();
        // SAFETY: recording outside rendering; the images are the slot's, where its last
        // frame's declared uses left them, and the barrier moves the attachments (of the
        // frame's size) to the layouts rendering uses; the pipeline was made for their formats; the push
        // constants are DrawConstants. The streams' contract: each mesh's buffers were made
        // with storage and device-address usage on the context's device, written before the
        // first submission and never again, and outlive every frame; its vertices have a
        // 24-byte stride, its indices are padded to a whole word.
        unsafe {
            HostBarrier::between(&s.last, &draws, &images).record(device, cmd);
            begin_rendering_colors(device, cmd, width, height, Some((view(0), 1.0)), &colors);
            p.gbuffer.bind(device, cmd);
            for (mesh, m) in world.meshes.iter().zip(meshes) {
                let (t0, t1) = (at(mesh, f - 1.0), at(mesh, f));
                let addresses = [s.constants.device_address(), m.vertices.device_address()];
                let (model, previous_model) = (rows(t1), rows(t0));
                let (albedo, first_id) = (mesh.albedo, m.first_triangle_id);
                let push = DrawConstants {
                    addresses,
                    model,
                    previous_model,
                    albedo,
                    first_id,
                };
                p.gbuffer.push(device, cmd, &push);
                let vertices = PositionStream::from_device_address(addresses[1], 24);
                let index = IndexStream::from_device_address(m.indices.device_address());
                let (n, cpu) = (m.positions.len() as u32, &m.positions[..]);
                let (shape, cpu) = match t0 == t1 {
                    true => (
                        ShadowMesh::still(vertices, n).transform(t1),
                        CpuGeometry::still(cpu),
                    ),
                    false => {
                        let shape = ShadowMesh::moving(vertices, vertices, n).transforms(t0, t1);
                        (shape, CpuGeometry::moving(cpu, cpu))
                    }
                };
                let (index_type, index, cpu) = match &mesh.indices {
                    MeshIndices::U16(i) => (
                        vk::IndexType::UINT16,
                        Indices::U16(index),
                        cpu.indices_u16(i),
                    ),
                    MeshIndices::U32(i) => (
                        vk::IndexType::UINT32,
                        Indices::U32(index),
                        cpu.indices_u32(i),
                    ),
                };
                let count = mesh.indices.count() as u32;
                device.cmd_bind_index_buffer(cmd, m.indices.raw(), 0, index_type);
                device.cmd_draw_indexed(cmd, count, 1, 0, 0, 0);
                let shape = shape
                    .indexed(index, count / 3)
                    .cpu(cpu)
                    .first_triangle_id(first_id);
                described.push(if mesh.closed { shape.closed() } else { shape });
            }
            device.cmd_end_rendering(cmd);
        }

        // 2. Per light, the library's shadow and mask. The masks' inputs: the G-buffer; moving
        //    receivers need the ids too (a turning face's own triangle would shadow it, and the
        //    mask refuses to run without them).
        let read = L::READ_ONLY_OPTIMAL;
        let inv_view_proj = world
            .camera
            .view_proj(width as f32 / height as f32)
            .inverse();
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
            let size = (width, height);
            let inputs = MaskInputs::new(view(0), read, mask.layer_view(0), size, inv_view_proj);
            let inputs = inputs.with_normals(normals).with_ids(ids);
            if settings.receivers_move {
                inputs.with_motion(motion, 1.0)
            } else {
                inputs
            }
        };
        let inputs: Vec<_> = s.masks.iter().map(mask_inputs).collect();
        // The shading's own uses: depth, normal, albedo and masks sampled by compute. Each
        // image the masks and the shading use goes into its declared layout.
        let sampled = data(S::COMPUTE_SHADER, A::SHADER_SAMPLED_READ);
        let shading = PassAccesses::host_images(&[0, 1, 2].map(view), read, sampled, false);
        let masks: Vec<_> = s.masks.iter().map(|i| i.layer_view(0)).collect();
        let masks = PassAccesses::host_images(&masks, L::GENERAL, sampled, false);
        let shading = shading.and(&masks);
        let mask_uses = |all: PassAccesses, i: &MaskInputs| all.and(&i.image_accesses());
        let declared = inputs.iter().fold(shading.clone(), mask_uses);
        // SAFETY: as the first barrier; the G-buffer is where the draws left it.
        unsafe { HostBarrier::between(&draws, &declared, &images).record(device, cmd) };
        let mut frames = Vec::new();
        for (shadow, inputs) in self.shadows.iter_mut().zip(&inputs) {
            // SAFETY: recording outside rendering on the context's graphics+compute queue,
            // after the shadow's earlier frames (one queue, submitted in order); the streams'
            // contract is kept above; the mask's views have the usages its inputs ask and are
            // in the layouts they name (the barrier just recorded).
            let recorded = unsafe {
                shadow.record_frame(&self.ctx, cmd, submission, &described, Some(inputs))
            };
            frames.push(recorded?);
        }
        s.layer_drawn = frames.iter().map(|f| f.static_layer_drawn).collect();

        // 3. The shading (each light read from its map's header), after the masks' declared
        //    last accesses; the generation's closing barrier made the maps readable.
        let masks = frames.iter().flat_map(|f| f.mask.as_ref());
        let written = masks.fold(PassAccesses::default(), |all, m| all.and(m));
        let reads = frames.iter().fold(shading, |all, f| all.and(&f.lookups));
        let into_shading = HostBarrier::between(&written, &reads, &images);
        s.last = written.and(&reads);
        // 4. The output, read by the host after the fence.
        let write = data(S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE);
        let to_host = HostBarrier::memory(write, data(S::HOST, A::HOST_READ));
        let (output, pixels) = (
            s.output.device_address(),
            u64::from(width) * u64::from(height),
        );
        let maps = [frames[0].map_header, frames[frames.len() - 1].map_header];
        let push = [
            s.constants.device_address(),
            output,
            output + 16 * pixels,
            maps[0],
            maps[1],
        ];
        // SAFETY: recording outside rendering; the masks' images are in the layouts they
        // declared. The shading's layout holds the slot's set (its images, in the layouts the
        // set names after `into_shading`) and 40 bytes of push constants, `push`'s size;
        // 8x8 groups cover the image (the shader returns past its edges), writing the slot's
        // output buffer, which holds the radiance and every mask, by address.
        unsafe {
            into_shading.record(device, cmd);
            p.shade.bind(device, cmd);
            // The mask bound its own set 0 on the compute bind point: bind ours.
            let (compute, set) = (vk::PipelineBindPoint::COMPUTE, [s.bindings.raw()]);
            device.cmd_bind_descriptor_sets(cmd, compute, p.shade.layout(), 0, &set, &[]);
            p.shade.push(device, cmd, &push);
            device.cmd_dispatch(cmd, width.div_ceil(8), height.div_ceil(8), 1);
            to_host.record(device, cmd);
        }
        Ok(())
    }
}
