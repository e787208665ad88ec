//! The engine: its settings, its geometry, its per-frame slots, setup and teardown.

use super::*;

/// What the engine is set up with.
#[derive(Debug, Clone)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Texels of every shadow map.
    pub shadow_size: (u32, u32),
    /// Keep each map's static layer across frames (`StaticLayer::Kept`): the world's still
    /// meshes never change in place.
    pub keep_static_layer: bool,
    /// Give the mask the G-buffer's motion (receivers followed along their path); off, every
    /// receiver stands still where the G-buffer shows it (cheaper, exact for still ones).
    pub receivers_move: bool,
}

/// A map's counts after its frame (`TemporalShadowMap::read_counters`).
#[derive(Debug, Clone, Copy)]
pub struct MapCounts {
    /// N_f: the fragments the collection stored; N_r: the ranges the generation made.
    pub node_count: u32,
    pub range_count: u32,
    pub range_capacity: u32,
    /// 1 where the collection stored ranges directly (no fragments).
    pub ranges_direct: u32,
}

/// A frame's results, read back once its fence signalled.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    pub frame: u32,
    /// The frame-in-flight slot that rendered it.
    pub slot: usize,
    /// Per light: its map's counts.
    pub counters: Vec<MapCounts>,
    /// Linear radiance per pixel (rgb; a = 1 where a surface is, 0 for the background).
    pub radiance: Vec<[f32; 4]>,
    /// Per light: the mask (lit share of the shutter) per pixel.
    pub masks: Vec<Vec<f32>>,
    /// Per light: whether the frame drew its map's static layer.
    pub static_layer_drawn: Vec<bool>,
}

/// Where a mesh lives in the engine's geometry buffers.
pub(super) struct MeshSlot {
    /// Byte offsets of its vertices and indices (each index run 4-byte aligned).
    pub(super) vertex_offset: u64,
    pub(super) index_offset: u64,
    pub(super) index_type: vk::IndexType,
    /// Global id of its first triangle (meshes' ids never overlap).
    pub(super) first_triangle_id: u32,
    /// Object-space positions and the indices: the CPU copy the room is reserved from.
    pub(super) positions: Vec<Vec3>,
    pub(super) indices: MeshIndices,
}

/// Everything one frame in flight writes.
pub(super) struct Slot {
    pub(super) cmd: vk::CommandBuffer,
    pub(super) fence: vk::Fence,
    pub(super) set: vk::DescriptorSet,
    /// The frame submitted with this slot and not yet retired, and its library frame number.
    pub(super) pending: Option<u32>,
    pub(super) submission: u64,
    pub(super) constants: HostBuffer,
    /// Radiance, then each light's mask (written by the shading pass).
    pub(super) output: HostBuffer,
    /// Depth, then `COLOR_FORMATS`' attachments: normal, albedo, motion, id.
    pub(super) gbuffer: Vec<Image>,
    pub(super) masks: Vec<Image>,
    pub(super) static_layer_drawn: Vec<bool>,
}

/// The deferred engine. Borrows the device for its whole life.
pub struct Engine<'h> {
    pub(super) gpu: &'h Gpu,
    pub(super) settings: Settings,
    pub(super) pipelines: Pipelines,
    pub(super) vertices: HostBuffer,
    pub(super) indices: HostBuffer,
    pub(super) meshes: Vec<MeshSlot>,
    pub(super) slots: Vec<Slot>,
    /// Per light: the light its shadow was made for (one that moved gets a new shadow).
    pub(super) shadows: Vec<(Light, LightShadow)>,
    /// Frames submitted so far: the frame numbers the library is told.
    pub(super) submissions: u64,
    // The teardown order (fields drop in order): the library's objects above before the
    // context, every allocation (the engine's and the context's) before the allocator.
    pub(super) ctx: Context,
    pub(super) allocator: SharedAllocator,
}

impl<'h> Engine<'h> {
    /// Sets the engine up for `world`'s meshes and lights with `settings`.
    pub fn new(gpu: &'h Gpu, world: &World, settings: Settings) -> Result<Self> {
        if world.lights.is_empty() || world.lights.len() > MAX_LIGHTS {
            return Err(format!(
                "{} lights: the engine shades 1 to {MAX_LIGHTS}",
                world.lights.len()
            )
            .into());
        }
        let allocator = new_allocator(gpu)?;
        // SAFETY: Gpu made the device from `physical` of `instance` for Vulkan 1.3, with a
        // graphics+compute queue of `queue_family` and the features in `enabled`; the
        // allocator is on that device with device addresses on. The Gpu outlives the engine,
        // which waits for its frames before the context drops.
        let ctx = unsafe {
            Context::from_raw_with_allocator(
                &gpu.instance,
                gpu.physical,
                gpu.device.clone(),
                gpu.queue_family,
                gpu.queue,
                &gpu.enabled,
                allocator.clone(),
            )
        }?;
        let (mut vertices, mut index_bytes, mut meshes, mut next_id) =
            (Vec::new(), Vec::<u8>::new(), Vec::new(), 0);
        for mesh in &world.meshes {
            let (index_offset, vertex_offset) =
                (index_bytes.len() as u64, size_of_val(&vertices[..]) as u64);
            let index_type = match &mesh.indices {
                MeshIndices::U16(i) => {
                    index_bytes.extend(i.iter().flat_map(|v| v.to_le_bytes()));
                    vk::IndexType::UINT16
                }
                MeshIndices::U32(i) => {
                    index_bytes.extend(i.iter().flat_map(|v| v.to_le_bytes()));
                    vk::IndexType::UINT32
                }
            };
            // The library reads 16-bit indices as whole words: each run starts 4-byte aligned.
            index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
            vertices.extend_from_slice(&mesh.vertices);
            let positions = mesh.vertices.iter().map(|v| Vec3::from(v.position)).collect();
            let indices = mesh.indices.clone();
            meshes.push(MeshSlot {
                vertex_offset,
                index_offset,
                index_type,
                first_triangle_id: next_id,
                positions,
                indices,
            });
            next_id += mesh.triangle_count();
        }
        // The rasterizer's vertex and index buffers are the shadow pass's streams too.
        let by_address =
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let mut engine = Engine {
            gpu,
            settings,
            pipelines: Pipelines::new(&gpu.device, gpu.queue_family)?,
            vertices: HostBuffer::with_data(
                gpu,
                &allocator,
                &vertices,
                by_address | vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: HostBuffer::with_data(
                gpu,
                &allocator,
                &index_bytes,
                by_address | vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            meshes,
            slots: Vec::new(),
            shadows: Vec::new(),
            submissions: 0,
            ctx,
            allocator,
        };
        for _ in 0..FRAMES_IN_FLIGHT {
            let slot = engine.new_slot(world.lights.len())?;
            engine.slots.push(slot);
        }
        Ok(engine)
    }

    fn new_slot(&self, lights: usize) -> Result<Slot> {
        let (gpu, allocator, p) = (self.gpu, &self.allocator, &self.pipelines);
        let size = (self.settings.width, self.settings.height);
        let pixels = u64::from(size.0) * u64::from(size.1);
        use vk::ImageUsageFlags as U;
        let image = |format, usage| Image::new(gpu, allocator, (format, usage | U::SAMPLED), size);
        let host = |bytes, usage| {
            HostBuffer::new(
                gpu,
                allocator,
                bytes,
                usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            )
        };
        let mut gbuffer = vec![image(DEPTH_FORMAT, U::DEPTH_STENCIL_ATTACHMENT)?];
        for format in COLOR_FORMATS {
            gbuffer.push(image(format, U::COLOR_ATTACHMENT)?);
        }
        let masks =
            (0..lights).map(|_| image(MASK_FORMAT, U::STORAGE)).collect::<Result<Vec<_>>>()?;
        // Depth, normal, albedo, mask 0 and mask 1 (light 0's again with one light).
        let read = vk::ImageLayout::READ_ONLY_OPTIMAL;
        let views = [
            (&gbuffer[0], read),
            (&gbuffer[1], read),
            (&gbuffer[2], read),
            (&masks[0], vk::ImageLayout::GENERAL),
            (masks.last().unwrap_or(&masks[0]), vk::ImageLayout::GENERAL),
        ];
        let infos = views.map(|(image, layout)| {
            [vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: image.view,
                image_layout: layout,
            }]
        });
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(p.command_pool)
            .command_buffer_count(1);
        let layouts = [p.set_layout];
        let sets = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(p.descriptor_pool)
            .set_layouts(&layouts);
        let constants =
            host(size_of::<FrameConstants>() as u64, vk::BufferUsageFlags::STORAGE_BUFFER)?;
        let output = host(pixels * (16 + 4 * lights as u64), vk::BufferUsageFlags::STORAGE_BUFFER)?;
        // SAFETY: the engine's pools (its queue family; sized for FRAMES_IN_FLIGHT sets),
        // whose buffers and sets go with them; the set's images are this slot's, kept with
        // it; the fence, made last, is destroyed by the engine's Drop.
        let (cmd, set, fence) = unsafe {
            let cmd = gpu.device.allocate_command_buffers(&alloc)?[0];
            let set = gpu.device.allocate_descriptor_sets(&sets)?[0];
            let writes: Vec<_> = (infos.iter().enumerate())
                .map(|(binding, info)| {
                    let write =
                        vk::WriteDescriptorSet::default().dst_set(set).dst_binding(binding as u32);
                    write.descriptor_type(vk::DescriptorType::SAMPLED_IMAGE).image_info(info)
                })
                .collect();
            gpu.device.update_descriptor_sets(&writes, &[]);
            (cmd, set, gpu.device.create_fence(&Default::default(), None)?)
        };
        Ok(Slot {
            cmd,
            fence,
            set,
            pending: None,
            submission: 0,
            constants,
            output,
            gbuffer,
            masks,
            static_layer_drawn: Vec::new(),
        })
    }

    /// The library's context (device information, validation messages).
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// Global id of mesh `mesh`'s first triangle.
    pub fn first_triangle_id(&self, mesh: usize) -> u32 {
        self.meshes[mesh].first_triangle_id
    }

    /// Light `light`'s map in frame slot `slot`: it holds that slot's last frame until the
    /// slot renders again.
    pub fn shadow_map(&self, slot: usize, light: usize) -> &TemporalShadowMap {
        self.shadows[light].1.map(self.slots[slot].submission)
    }

    /// The library's settings for `light`: the mask on, the engine's frames in flight; no
    /// shader of the engine reads the maps (only the mask does).
    pub(super) fn shadow_settings(&self, light: &Light) -> ShadowSettings {
        let s = &self.settings;
        ShadowSettings {
            map_size: s.shadow_size,
            static_layer: if s.keep_static_layer {
                StaticLayer::Kept
            } else {
                StaticLayer::Redrawn
            },
            mask: true,
            frames_in_flight: FRAMES_IN_FLIGHT as u32,
            lookup_stages: vk::PipelineStageFlags2::empty(),
            ..ShadowSettings::new(light.engine_light())
        }
    }
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        // SAFETY: once the device is idle no frame uses a fence (or anything else of the
        // engine's, which the fields drop next: pipelines, buffers and images, the library's
        // objects, the context, the allocator); each fence is destroyed once.
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            for slot in &self.slots {
                self.gpu.device.destroy_fence(slot.fence, None);
            }
        }
    }
}
