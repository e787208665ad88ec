//! The engine: its settings and outputs, its geometry, its frame slots, setup and teardown.

use super::*;

/// `keep_static_layer`: keep each map's static layer (the still meshes never change in
/// place). `receivers_move`: give the mask the G-buffer's motion (off: receivers stand still).
#[derive(Debug, Clone)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub shadow_size: (u32, u32),
    pub keep_static_layer: bool,
    pub receivers_move: bool,
}

/// A map's counts after its frame: fragments and ranges stored, the room for ranges, and 1
/// where the collection stored ranges directly.
#[derive(Debug, Clone, Copy)]
pub struct MapCounts {
    pub node_count: u32,
    pub range_count: u32,
    pub range_capacity: u32,
    pub ranges_direct: u32,
}

/// A frame read back after its fence: per pixel its radiance (a = 1 where a surface is) and
/// per light its mask (the lit share of the shutter); per light its map's counts and whether
/// it drew the static layer.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    pub frame: u32,
    pub slot: usize,
    pub counters: Vec<MapCounts>,
    pub radiance: Vec<[f32; 4]>,
    pub masks: Vec<Vec<f32>>,
    pub static_layer_drawn: Vec<bool>,
}

/// A mesh in the engine's buffers (byte offsets), its first global triangle id (meshes' ids
/// never overlap) and its positions, the CPU copy the room is reserved from.
pub(super) struct MeshSlot {
    pub(super) vertex_offset: u64,
    pub(super) index_offset: u64,
    pub(super) first_triangle_id: u32,
    pub(super) positions: Vec<Vec3>,
}

/// What one frame in flight writes; `pending`: its frame until retired, `submission` the
/// library's number for it; `output`: radiance, then each light's mask.
pub(super) struct Slot {
    pub(super) cmd: vk::CommandBuffer,
    pub(super) fence: vk::Fence,
    pub(super) set: vk::DescriptorSet,
    pub(super) pending: Option<u32>,
    pub(super) submission: u64,
    pub(super) constants: HostBuffer,
    pub(super) output: HostBuffer,
    pub(super) gbuffer: Vec<Image>,
    pub(super) masks: Vec<Image>,
    pub(super) layer_drawn: Vec<bool>,
}

/// The deferred engine. Its fields drop in order: the library's objects before the context,
/// every allocation (the engine's and the context's) before the allocator (last).
pub struct Engine<'h> {
    pub(super) gpu: &'h Gpu,
    pub(super) settings: Settings,
    pub(super) pipelines: Pipelines,
    /// The vertex and index buffers, and where each mesh lies in them.
    pub(super) geometry: (HostBuffer, HostBuffer, Vec<MeshSlot>),
    pub(super) slots: Vec<Slot>,
    /// Per light: the light its shadow was made for (one that moved gets a new shadow).
    pub(super) shadows: Vec<(Light, LightShadow)>,
    pub(super) submissions: u64,
    pub(super) ctx: Context,
    _memory: Memory,
}

impl<'h> Engine<'h> {
    /// Sets the engine up for `world`'s meshes and lights.
    pub fn new(gpu: &'h Gpu, world: &World, settings: Settings) -> Result<Self> {
        let lights = world.lights.len();
        if lights == 0 || lights > MAX_LIGHTS {
            return Err(format!("{lights} lights: the engine shades 1 to {MAX_LIGHTS}").into());
        }
        let (memory, g) = (Memory::new(gpu)?, gpu);
        let (device, allocator) = (g.device.clone(), memory.allocator.clone());
        // SAFETY: Gpu made the device from `physical` of `instance` for Vulkan 1.3, with a
        // graphics+compute queue of `queue_family` and the features in `enabled`; the
        // allocator is the device's, with device addresses on. The Gpu outlives the engine,
        // which waits for its frames before the context drops.
        let ctx = unsafe {
            let (physical, family, queue) = (g.physical, g.queue_family, g.queue);
            Context::from_raw_with_allocator(
                &g.instance,
                physical,
                device,
                family,
                queue,
                &g.enabled,
                allocator,
            )
        }?;
        let (mut vertices, mut index_bytes, mut meshes, mut next_id) = (vec![], vec![], vec![], 0);
        for mesh in &world.meshes {
            let vertex_offset = vertices.len() as u64;
            let index_offset = index_bytes.len() as u64;
            index_bytes.extend_from_slice(match &mesh.indices {
                MeshIndices::U16(i) => bytemuck::cast_slice::<u16, u8>(i),
                MeshIndices::U32(i) => bytemuck::cast_slice(i),
            });
            // The library reads 16-bit indices as whole words: each run starts 4-byte aligned.
            index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
            let positions = mesh
                .vertices
                .iter()
                .map(|v| Vec3::from(v.position))
                .collect();
            let first_triangle_id = next_id;
            meshes.push(MeshSlot {
                vertex_offset,
                index_offset,
                first_triangle_id,
                positions,
            });
            next_id += (mesh.indices.count() / 3) as u32;
            vertices.extend_from_slice(bytemuck::cast_slice(&mesh.vertices));
        }
        // The rasterizer's index buffer is the shadow pass's index stream too.
        use vk::BufferUsageFlags as U;
        let upload = |bytes: &[u8], usage| -> Result<HostBuffer> {
            let usage = usage | U::STORAGE_BUFFER | U::SHADER_DEVICE_ADDRESS;
            let mut buffer = HostBuffer::new(&memory, bytes.len() as u64, usage)?;
            buffer.write(bytes).map(|()| buffer)
        };
        let (vertices, indices) = (
            upload(&vertices, U::empty())?,
            upload(&index_bytes, U::INDEX_BUFFER)?,
        );
        let pipelines = Pipelines::new(&gpu.device, gpu.queue_family)?;
        let slot = |_| new_slot(&memory, &pipelines, &settings, lights);
        let slots = (0..FRAMES_IN_FLIGHT).map(slot).collect::<Result<_>>()?;
        let geometry = (vertices, indices, meshes);
        let (shadows, submissions, _memory) = (Vec::new(), 0, memory);
        Ok(Engine {
            gpu,
            settings,
            pipelines,
            geometry,
            slots,
            shadows,
            submissions,
            ctx,
            _memory,
        })
    }

    /// The library's context (device information, validation messages).
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// Global id of mesh `mesh`'s first triangle.
    pub fn first_triangle_id(&self, mesh: usize) -> u32 {
        self.geometry.2[mesh].first_triangle_id
    }

    /// Light `light`'s map in slot `slot`, holding that slot's last frame.
    pub fn shadow_map(&self, slot: usize, light: usize) -> &TemporalShadowMap {
        self.shadows[light].1.map(self.slots[slot].submission)
    }
}

/// A frame slot: its G-buffer, masks, buffers, command buffer, descriptor set and fence.
fn new_slot(memory: &Memory, p: &Pipelines, settings: &Settings, lights: usize) -> Result<Slot> {
    let size = (settings.width, settings.height);
    use vk::{BufferUsageFlags as B, FormatFeatureFlags as F, ImageUsageFlags as U};
    let image = |format, (usage, feature): Usage| {
        Image::new(
            memory,
            format,
            (usage | U::SAMPLED, feature | F::SAMPLED_IMAGE),
            size,
        )
    };
    let depth = (U::DEPTH_STENCIL_ATTACHMENT, F::DEPTH_STENCIL_ATTACHMENT);
    let uses = [depth, (U::COLOR_ATTACHMENT, F::COLOR_ATTACHMENT)];
    let gbuffer = (0..5).map(|i| image(FORMATS[i], uses[i.min(1)]));
    let gbuffer = gbuffer.collect::<Result<Vec<_>>>()?;
    // The masks: a lit share per pixel, a format every device writes as a storage image.
    let mask = |_| image(vk::Format::R32_SFLOAT, (U::STORAGE, F::STORAGE_IMAGE));
    let masks = (0..lights).map(mask).collect::<Result<Vec<_>>>()?;
    let usage = B::STORAGE_BUFFER | B::SHADER_DEVICE_ADDRESS;
    let constants = HostBuffer::new(memory, size_of::<FrameConstants>() as u64, usage)?;
    let pixels = u64::from(size.0) * u64::from(size.1);
    let output = HostBuffer::new(memory, pixels * (16 + 4 * lights as u64), usage)?;
    // Depth, normal, albedo, mask 0 and mask 1 (light 0's again with one light).
    let (read, general) = (vk::ImageLayout::READ_ONLY_OPTIMAL, vk::ImageLayout::GENERAL);
    let images = [
        (&gbuffer[0], read),
        (&gbuffer[1], read),
        (&gbuffer[2], read),
    ];
    let images = images
        .into_iter()
        .chain([(&masks[0], general), (&masks[lights - 1], general)]);
    let info = |(image, layout): (&Image, _)| {
        [vk::DescriptorImageInfo::default()
            .image_view(image.view)
            .image_layout(layout)]
    };
    let infos: Vec<_> = images.map(info).collect();
    let alloc = vk::CommandBufferAllocateInfo::default().command_buffer_count(1);
    let (alloc, layouts) = (alloc.command_pool(p.command_pool), [p.set_layout]);
    let sets = vk::DescriptorSetAllocateInfo::default().descriptor_pool(p.descriptor_pool);
    let (sets, device) = (sets.set_layouts(&layouts), &memory.gpu.device);
    // SAFETY: the engine's pools (its queue family; a set for each of FRAMES_IN_FLIGHT slots),
    // whose buffers and sets go with them; the set's images are the slot's, kept with it; the
    // fence, made last, is destroyed by the engine's Drop.
    let (cmd, set, fence) = unsafe {
        let cmd = device.allocate_command_buffers(&alloc)?[0];
        let set = device.allocate_descriptor_sets(&sets)?[0];
        let sampled = vk::DescriptorType::SAMPLED_IMAGE;
        let writes: Vec<_> = (infos.iter().enumerate())
            .map(|(binding, info)| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .image_info(info);
                write.dst_binding(binding as u32).descriptor_type(sampled)
            })
            .collect();
        device.update_descriptor_sets(&writes, &[]);
        (cmd, set, device.create_fence(&Default::default(), None)?)
    };
    let (pending, submission, layer_drawn) = (None, 0, Vec::new());
    Ok(Slot {
        cmd,
        fence,
        set,
        pending,
        submission,
        constants,
        output,
        gbuffer,
        masks,
        layer_drawn,
    })
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        // SAFETY: once the device is idle no frame uses a fence (nor anything the fields drop
        // next); each fence is destroyed once.
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            for slot in &self.slots {
                self.gpu.device.destroy_fence(slot.fence, None);
            }
        }
    }
}
