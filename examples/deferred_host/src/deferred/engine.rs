//! The engine: its settings and outputs, its meshes, its frame slots, setup and teardown.

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

/// A frame read back after its fence: per pixel its radiance (a = 1 where a surface is) and
/// per light its mask (the lit share of the shutter) and whether it drew the static layer
/// (its map's counts: `Engine::shadow_map` of its slot, until the slot's next frame).
#[derive(Debug, Clone)]
pub struct FrameOutput {
    pub frame: u32,
    pub slot: usize,
    pub radiance: Vec<[f32; 4]>,
    pub masks: Vec<Vec<f32>>,
    pub static_layer_drawn: Vec<bool>,
}

/// A mesh's vertex and index buffers (read in place by the shadow pass too), its first
/// global triangle id (meshes' ids never overlap) and the CPU copy the room is reserved from.
pub(super) struct MeshSlot {
    pub(super) vertices: Buffer,
    pub(super) indices: Buffer,
    pub(super) first_triangle_id: u32,
    pub(super) positions: Vec<Vec3>,
}

/// What one frame in flight writes; `pending`: its frame until retired, `submission` the
/// library's number for it; `output`: radiance, then each light's mask.
pub(super) struct Slot {
    pub(super) cmd: vk::CommandBuffer,
    pub(super) fence: vk::Fence,
    pub(super) bindings: ImageBindings,
    pub(super) pending: Option<u32>,
    pub(super) submission: u64,
    pub(super) constants: Buffer,
    pub(super) output: Buffer,
    pub(super) gbuffer: Vec<Image>,
    pub(super) masks: Vec<Image>,
    pub(super) layer_drawn: Vec<bool>,
    /// What the slot's last frame used its images for (where it left them).
    pub(super) last: PassAccesses,
}

/// The deferred engine. Its fields drop after its Drop waited for the device: the library's
/// objects and the engine's buffers and images (allocations of the engine's allocator, which
/// goes with the context's last object).
pub struct Engine<'h> {
    pub(super) gpu: &'h Gpu,
    pub(super) settings: Settings,
    pub(super) pipelines: Pipelines,
    pub(super) meshes: Vec<MeshSlot>,
    pub(super) slots: Vec<Slot>,
    /// One per light, with the mask on.
    pub(super) shadows: Vec<LightShadow>,
    pub(super) submissions: u64,
    pub(super) ctx: Context,
    pool: vk::CommandPool,
}

impl<'h> Engine<'h> {
    /// Sets the engine up for `world`'s meshes and lights.
    pub fn new(gpu: &'h Gpu, world: &World, settings: Settings) -> Result<Self> {
        let lights = world.lights.len();
        if lights == 0 || lights > MAX_LIGHTS {
            return Err(format!("{lights} lights: the engine shades 1 to {MAX_LIGHTS}").into());
        }
        let g = gpu;
        // The engine's allocator, which the library allocates from too.
        let allocator = Context::new_allocator(&g.instance, g.physical, &g.device)?;
        // SAFETY: Gpu made the device from `physical` of `instance` for Vulkan 1.3, with a
        // graphics+compute queue of `queue_family` and the features in `enabled`; the
        // allocator is the device's, with device addresses on. The Gpu outlives the engine,
        // which waits for its frames before the context drops.
        let ctx = unsafe {
            let (device, physical, family, queue) =
                (g.device.clone(), g.physical, g.queue_family, g.queue);
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
        let (mut meshes, mut next_id) = (Vec::new(), 0);
        for mesh in &world.meshes {
            let mut indices = match &mesh.indices {
                MeshIndices::U16(i) => bytemuck::cast_slice::<u16, u8>(i).to_vec(),
                MeshIndices::U32(i) => bytemuck::cast_slice(i).to_vec(),
            };
            // The library reads 16-bit indices as whole words.
            indices.resize(indices.len().next_multiple_of(4), 0);
            let usage = BufferUsage::HostToDevice;
            meshes.push(MeshSlot {
                vertices: Buffer::with_data(&ctx, "vertices", usage, &mesh.vertices)?,
                indices: Buffer::with_data(&ctx, "indices", usage, &indices)?,
                first_triangle_id: next_id,
                positions: mesh.vertices.iter().map(|v| v.position.into()).collect(),
            });
            next_id += (mesh.indices.count() / 3) as u32;
        }
        let static_layer = match settings.keep_static_layer {
            true => StaticLayer::Kept,
            false => StaticLayer::Redrawn,
        };
        // One shadow per light, the mask on; the engine's shading reads each map's header
        // (compute). A light that moves gets new maps (`LightShadow::set_light`).
        let mut shadows = Vec::new();
        for light in &world.lights {
            let settings = ShadowSettings {
                map_size: settings.shadow_size,
                static_layer,
                mask: true,
                frames_in_flight: FRAMES_IN_FLIGHT as u32,
                lookup_stages: S::COMPUTE_SHADER,
                ..ShadowSettings::new(*light)
            };
            shadows.push(LightShadow::new(&ctx, settings)?);
        }
        let pipelines = Pipelines::new(&ctx)?;
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(g.queue_family);
        let info = info.flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `info` is a local; the pool is destroyed by the engine's Drop.
        let pool = unsafe { g.device.create_command_pool(&info, None) }?;
        let mut engine = Engine {
            gpu,
            settings,
            pipelines,
            meshes,
            slots: Vec::new(),
            shadows,
            submissions: 0,
            ctx,
            pool,
        };
        for _ in 0..FRAMES_IN_FLIGHT {
            let slot = engine.new_slot(lights)?;
            engine.slots.push(slot);
        }
        Ok(engine)
    }

    /// The library's context (device information, validation messages).
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// Global id of mesh `mesh`'s first triangle.
    pub fn first_triangle_id(&self, mesh: usize) -> u32 {
        self.meshes[mesh].first_triangle_id
    }

    /// Light `light`'s map in slot `slot`, holding that slot's last frame.
    pub fn shadow_map(&self, slot: usize, light: usize) -> &TemporalShadowMap {
        self.shadows[light].map(self.slots[slot].submission)
    }

    /// A frame slot: its G-buffer, masks, buffers, command buffer, descriptor set and fence.
    fn new_slot(&self, lights: usize) -> Result<Slot> {
        let (ctx, s) = (&self.ctx, &self.settings);
        use vk::ImageUsageFlags as U;
        let image =
            |name, format, usage| Image::new(ctx, name, (s.width, s.height, 1), format, usage);
        let usage = |i| match i {
            0 => U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED,
            _ => U::COLOR_ATTACHMENT | U::SAMPLED,
        };
        let gbuffer = (0..5).map(|i| image("g-buffer", FORMATS[i], usage(i)));
        let gbuffer = gbuffer.collect::<motion_shadows::Result<Vec<_>>>()?;
        // The masks: a lit share per pixel, a format every device writes as a storage image.
        let mask = |_| image("mask", vk::Format::R32_SFLOAT, U::STORAGE | U::SAMPLED);
        let masks = (0..lights)
            .map(mask)
            .collect::<motion_shadows::Result<Vec<_>>>()?;
        let pixels = u64::from(s.width) * u64::from(s.height);
        let constants = size_of::<FrameConstants>() as u64;
        let constants = Buffer::new(ctx, "constants", constants, BufferUsage::HostToDevice)?;
        let bytes = pixels * (16 + 4 * lights as u64);
        let output = Buffer::new(ctx, "output", bytes, BufferUsage::DeviceToHost)?;
        let mut bindings = self.pipelines.shade_set.allocate()?;
        // Depth, normal, albedo, mask 0 and mask 1 (light 0's again with one light).
        let read = |i: &Image| (i.layer_view(0), L::READ_ONLY_OPTIMAL);
        let images = [&gbuffer[0], &gbuffer[1], &gbuffer[2]].map(read);
        let general = |i: &Image| (i.layer_view(0), L::GENERAL);
        let images = [
            images.as_slice(),
            &[general(&masks[0]), general(&masks[lights - 1])],
        ];
        let alloc = vk::CommandBufferAllocateInfo::default().command_buffer_count(1);
        let (alloc, device) = (alloc.command_pool(self.pool), &self.gpu.device);
        // SAFETY: the set is new (in no command buffer), its images the slot's, kept with it;
        // the command buffer goes with the engine's pool; the fence, with the engine's Drop.
        let (cmd, fence) = unsafe {
            bindings.write(&images.concat());
            let cmd = device.allocate_command_buffers(&alloc)?[0];
            (cmd, device.create_fence(&Default::default(), None)?)
        };
        Ok(Slot {
            cmd,
            fence,
            bindings,
            pending: None,
            submission: 0,
            constants,
            output,
            gbuffer,
            masks,
            layer_drawn: Vec::new(),
            last: PassAccesses::default(),
        })
    }
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        // SAFETY: once the device is idle no frame uses a fence, the pool's command buffers,
        // nor anything the fields drop next; each is destroyed once.
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            for slot in &self.slots {
                self.gpu.device.destroy_fence(slot.fence, None);
            }
            self.gpu.device.destroy_command_pool(self.pool, None);
        }
    }
}
