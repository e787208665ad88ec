//! The engine: its settings, its per-frame slots and their setup, and its teardown.

use super::*;

// ---------------------------------------------------------------------------------------
// The engine.
// ---------------------------------------------------------------------------------------

/// How the shading pass gets each light's visibility.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShadowLookup {
    /// From the mask images the library's visibility-mask pass wrote.
    MaskImages,
    /// `ms_lit_fraction` called by the engine's own shading shader.
    LitFractionInShader,
    /// `ms_visibility` at one shutter time, in the engine's own shading shader.
    VisibilityAt(f32),
}

/// What the engine is set up with.
#[derive(Debug, Clone)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Texels of every shadow map.
    pub shadow_size: (u32, u32),
    pub lookup: ShadowLookup,
    /// Keep each shadow map's static layer across frames (`StaticLayer::Kept`):
    /// the world's static meshes never change in place, and its lights do not move.
    pub keep_static_layer: bool,
    /// Give the mask pass the G-buffer's motion (receivers followed along their path); off,
    /// every receiver stands still where the G-buffer shows it (the mask's cheaper variant,
    /// exact for a world whose receivers do not move).
    pub receivers_move: bool,
}

/// A map's counts after its frame (`TemporalShadowMap::read_counters`).
#[derive(Debug, Clone, Copy)]
pub struct MapCounts {
    /// N_f: the fragments the collection stored.
    pub node_count: u32,
    /// N_r: the ranges the generation made, and the room for them.
    pub range_count: u32,
    pub range_capacity: u32,
    /// 1 where the collection stored ranges directly (no fragments), else 0.
    pub ranges_direct: u32,
}

/// A frame's results, read back once its fence signalled.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    pub frame: u32,
    /// The frame-in-flight slot that rendered it.
    pub slot: usize,
    /// Per light: the shadow map's counts after the frame.
    pub counters: Vec<MapCounts>,
    /// Linear radiance per pixel (rgb; a = 1 where a surface is, 0 for the background).
    pub radiance: Vec<[f32; 4]>,
    /// Per light: the visibility mask (lit fraction of the shutter) per pixel.
    pub masks: Vec<Vec<f32>>,
    /// Per light: whether the frame drew the static layer of its map (`ShadowFrame`).
    pub static_layer_drawn: Vec<bool>,
}

pub(super) const NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub(super) const ALBEDO_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// World-space motion over the shutter: half floats, as an engine stores motion vectors.
pub(super) const MOTION_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Each pixel's triangle: the global id the shadow pass's draws give it (`u32::MAX`: none).
pub(super) const ID_FORMAT: vk::Format = vk::Format::R32_UINT;
pub(super) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The masks: a lit fraction per pixel, in a format every device writes as a storage image.
pub(super) const MASK_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
pub(super) const RADIANCE_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The deferred engine. Borrows the device for its whole life.
pub struct Engine<'h> {
    pub(super) gpu: &'h Gpu,
    pub(super) settings: Settings,
    pub(super) pipelines: Pipelines,
    pub(super) geometry: Geometry,
    pub(super) slots: Vec<Slot>,
    /// Per light: the world's light its shadow was made for (a light that moved gets a new
    /// shadow), and the library's shadow (one map per frame in flight, its passes, the mask).
    pub(super) shadows: Vec<(Light, LightShadow)>,
    /// Frames submitted so far: the frame number the library is told (`record_frame`).
    pub(super) submissions: u64,
    // Every library object above must go before the context, and every allocation
    // (the engine's and the context's) before the allocator.
    pub(super) ctx: Context,
    pub(super) allocator: SharedAllocator,
}

/// What recording a frame reads: everything of the engine but the slots and shadows.
pub(super) struct Recorder<'a> {
    pub(super) device: &'a ash::Device,
    pub(super) ctx: &'a Context,
    pub(super) settings: &'a Settings,
    pub(super) pipelines: &'a Pipelines,
    pub(super) geometry: &'a Geometry,
}

/// Layout + access + stage in one tuple, for `Image::barrier`.
pub(super) type State = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// Everything one frame in flight writes.
pub(super) struct Slot {
    pub(super) cmd: vk::CommandBuffer,
    pub(super) fence: vk::Fence,
    /// The frame submitted with this slot and not yet retired.
    pub(super) pending: Option<u32>,
    /// Its submission's number (`Engine::submissions`): the library's frame number, what
    /// `Context::collect` and `LightShadow::finish_frame` are told once its fence signalled.
    pub(super) submission: u64,
    pub(super) frame_constants: HostBuffer,
    /// Last frame's and this frame's positions of the deformed meshes.
    pub(super) deformed: HostBuffer,
    pub(super) depth: Image,
    pub(super) normals: Image,
    pub(super) albedo: Image,
    /// Per pixel: the surface point's world displacement from frame f - 1 to frame f.
    pub(super) motion: Image,
    /// Per pixel: the global id of the triangle it shows (the mask's own-triangle skip,
    /// which moving receivers need).
    pub(super) ids: Image,
    /// One per light.
    pub(super) masks: Vec<Image>,
    pub(super) radiance: Image,
    pub(super) radiance_readback: HostBuffer,
    pub(super) mask_readback: Vec<HostBuffer>,
    pub(super) frame_set: vk::DescriptorSet,
    pub(super) image_set: vk::DescriptorSet,
    /// Per light: whether its frame drew the map's static layer.
    pub(super) static_layer_drawn: Vec<bool>,
}

impl<'h> Engine<'h> {
    /// Sets the engine up for `world` (its geometry, lights count) with `settings`.
    pub fn new(gpu: &'h Gpu, world: &World, settings: Settings) -> Result<Self> {
        if world.lights.is_empty() || world.lights.len() > MAX_LIGHTS {
            let lights = world.lights.len();
            return Err(format!("{lights} lights: the engine shades 1 to {MAX_LIGHTS}").into());
        }
        let sampled = vk::FormatFeatureFlags::SAMPLED_IMAGE;
        let needs = [
            (
                DEPTH_FORMAT,
                vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT | sampled,
            ),
            (
                NORMAL_FORMAT,
                vk::FormatFeatureFlags::COLOR_ATTACHMENT | sampled,
            ),
        ];
        for (format, needed) in needs {
            // SAFETY: the physical device is the instance's.
            let properties = unsafe {
                (gpu.instance).get_physical_device_format_properties(gpu.physical, format)
            };
            if !properties.optimal_tiling_features.contains(needed) {
                return Err(format!("{format:?} cannot be {needed:?} on this device").into());
            }
        }
        let allocator = new_allocator(gpu)?;
        // SAFETY: Gpu made `device` from `physical` of `instance`, Vulkan 1.3, with a
        // graphics+compute queue of `queue_family` and the features in `enabled`; the
        // allocator is on that device with device addresses on. The Gpu outlives the engine
        // (the borrow), which drops the context after waiting for its own frames. The library
        // never submits: the engine records its passes into its own command buffers.
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
        let mut engine = Engine {
            gpu,
            settings,
            pipelines: Pipelines::new(&gpu.device, gpu.queue_family)?,
            geometry: Geometry::upload(gpu, &allocator, world)?,
            slots: Vec::new(),
            shadows: Vec::new(),
            submissions: 0,
            ctx,
            allocator,
        };
        for _ in 0..FRAMES_IN_FLIGHT {
            let slot = engine.new_slot(world)?;
            engine.slots.push(slot);
        }
        Ok(engine)
    }

    /// The library's context (device information, validation messages).
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// The allocator the engine and the library allocate from.
    pub fn allocator(&self) -> &SharedAllocator {
        &self.allocator
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// How the shading pass takes visibility from the next frame on.
    pub fn set_lookup(&mut self, lookup: ShadowLookup) {
        self.settings.lookup = lookup;
    }

    /// Global id of mesh `mesh`'s first triangle.
    pub fn first_triangle_id(&self, mesh: usize) -> u32 {
        self.geometry.meshes[mesh].first_triangle_id
    }

    /// Light `light`'s shadow map in frame slot `slot`: holds the last frame that slot
    /// rendered until the slot renders again.
    pub fn shadow_map(&self, slot: usize, light: usize) -> &TemporalShadowMap {
        self.shadows[light].1.map(self.slots[slot].submission)
    }

    /// The library's shadow settings for `light`: the mask on, with the G-buffer's ids and
    /// (with `receivers_move`) motion, the engine's frames in flight.
    pub(super) fn shadow_settings(&self, light: &Light) -> ShadowSettings {
        ShadowSettings {
            map_size: self.settings.shadow_size,
            static_layer: if self.settings.keep_static_layer {
                StaticLayer::Kept
            } else {
                StaticLayer::Redrawn
            },
            mask: true,
            frames_in_flight: FRAMES_IN_FLIGHT as u32,
            // Only the shading pass, a compute shader, reads the maps itself.
            lookup_stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
            ..ShadowSettings::new(light.engine_light())
        }
    }

    pub(super) fn new_slot(&self, world: &World) -> Result<Slot> {
        let (gpu, allocator) = (self.gpu, &self.allocator);
        let size = (self.settings.width, self.settings.height);
        let pixels = size.0 as u64 * size.1 as u64;
        let lights = world.lights.len();
        let usage = vk::ImageUsageFlags::SAMPLED;
        let attachment = |format| {
            let usage = usage | vk::ImageUsageFlags::COLOR_ATTACHMENT;
            Image::new(gpu, allocator, (format, usage), size)
        };
        let storage = |format| {
            let usage = usage | vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
            Image::new(gpu, allocator, (format, usage), size)
        };
        let host_buffer = |bytes, usage| HostBuffer::new(gpu, allocator, bytes, usage);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pipelines.command_pool)
            .command_buffer_count(1);
        let set_layouts = [
            self.pipelines.frame_set_layout,
            self.pipelines.image_set_layout,
        ];
        let sets = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pipelines.descriptor_pool)
            .set_layouts(&set_layouts);
        // SAFETY: the engine's command pool (the device's queue family, RESET_COMMAND_BUFFER)
        // and descriptor pool (sized for FRAMES_IN_FLIGHT slots' two sets); command buffers and
        // sets go with their pools. An unsignalled fence has no precondition; the slot's owner
        // destroys it (the engine's Drop), or the error path below.
        let (cmd, sets, fence) = unsafe {
            let cmd = gpu.device.allocate_command_buffers(&alloc);
            let sets = gpu.device.allocate_descriptor_sets(&sets);
            let fence = gpu.device.create_fence(&Default::default(), None);
            (
                cmd.vk("vkAllocateCommandBuffers")?[0],
                sets.vk("vkAllocateDescriptorSets")?,
                fence.vk("vkCreateFence")?,
            )
        };
        let build = || -> Result<Slot> {
            let depth_usage = usage | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
            let slot = Slot {
                cmd,
                fence,
                pending: None,
                submission: 0,
                frame_constants: host_buffer(
                    std::mem::size_of::<FrameConstants>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                )?,
                deformed: host_buffer(
                    self.geometry.deformed_bytes,
                    vk::BufferUsageFlags::VERTEX_BUFFER
                        | vk::BufferUsageFlags::STORAGE_BUFFER
                        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
                )?,
                depth: Image::new(gpu, allocator, (DEPTH_FORMAT, depth_usage), size)?,
                normals: attachment(NORMAL_FORMAT)?,
                albedo: attachment(ALBEDO_FORMAT)?,
                motion: attachment(MOTION_FORMAT)?,
                ids: attachment(ID_FORMAT)?,
                masks: (0..lights)
                    .map(|_| storage(MASK_FORMAT))
                    .collect::<Result<_>>()?,
                radiance: storage(RADIANCE_FORMAT)?,
                radiance_readback: host_buffer(pixels * 16, vk::BufferUsageFlags::TRANSFER_DST)?,
                mask_readback: (0..lights)
                    .map(|_| host_buffer(pixels * 4, vk::BufferUsageFlags::TRANSFER_DST))
                    .collect::<Result<_>>()?,
                frame_set: sets[0],
                image_set: sets[1],
                static_layer_drawn: Vec::new(),
            };
            self.write_descriptors(&slot);
            Ok(slot)
        };
        // SAFETY: the slot was not built, so its fence was never submitted and is destroyed once,
        // here.
        build().inspect_err(|_| unsafe { gpu.device.destroy_fence(fence, None) })
    }

    /// The slot's descriptor sets point at its own images and uniform buffer, for good.
    pub(super) fn write_descriptors(&self, slot: &Slot) {
        let ubo = [vk::DescriptorBufferInfo {
            buffer: slot.frame_constants.buffer,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // A single light leaves binding 4 pointing at light 0's mask (never read then).
        let mask1 = slot.masks.get(1).unwrap_or(&slot.masks[0]);
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        // (binding, image, layout, type): shade.comp's set 1.
        let images = [
            (
                0,
                &slot.depth,
                vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                sampled,
            ),
            (1, &slot.normals, read_only, sampled),
            (2, &slot.albedo, read_only, sampled),
            (3, &slot.masks[0], read_only, sampled),
            (4, mask1, read_only, sampled),
            (
                5,
                &slot.radiance,
                vk::ImageLayout::GENERAL,
                vk::DescriptorType::STORAGE_IMAGE,
            ),
            (6, &slot.motion, read_only, sampled),
        ];
        let infos = images.map(|(_, image, image_layout, _)| {
            [vk::DescriptorImageInfo {
                sampler: self.pipelines.sampler,
                image_view: image.view,
                image_layout,
            }]
        });
        let mut writes = vec![
            vk::WriteDescriptorSet::default()
                .dst_set(slot.frame_set)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&ubo),
        ];
        for ((binding, _, _, ty), info) in images.iter().zip(&infos) {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(slot.image_set)
                    .dst_binding(*binding)
                    .descriptor_type(*ty)
                    .image_info(info),
            );
        }
        // SAFETY: the slot's sets are written once, while it is being built, before any command
        // buffer uses them; each write names an image view or buffer of this slot, alive as long as
        // it.
        unsafe { self.gpu.device.update_descriptor_sets(&writes, &[]) };
    }
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        // Frames still in flight use everything below: wait for them (the engine's own
        // fences; the library never waits on a host's device).
        self.wait_all();
        let device = &self.gpu.device;
        for slot in &self.slots {
            // SAFETY: wait_all just waited for every pending slot, so no fence is in use; each is
            // destroyed once.
            unsafe { device.destroy_fence(slot.fence, None) };
        }
        // The fields drop next: the pipelines and pools, the slots' images and buffers, the
        // library's objects, and the context last.
    }
}
