//! A small deferred engine that uses motion-shadows the way a real renderer would.
//!
//! The engine owns everything a renderer owns: the device (`Host`, created without the
//! library), its vertex and index buffers, its images, its pipelines and shaders, its frame
//! loop with two frames in flight, and its lighting. The library is handed the device
//! (`Context::from_raw`) and records three passes into the engine's command buffers:
//!
//! ```text
//! per frame (slot = frame % 2, with its own command buffer, fence and resources):
//!   DrawList::record_update          the engine's draws: its own buffers, read in place
//!   per light: CollectionPass        prism fragments of every moving triangle, from the light
//!              GenerationPass        fragments -> depth-time ranges (the temporal shadow map)
//!   G-buffer (the engine's own)      depth, world normal, albedo at shutter time t = 1,
//!                                    world motion over the shutter (this frame's position
//!                                    minus last frame's, as engines keep for motion vectors)
//!                                    and each pixel's triangle id
//!   per light: VisibilityMaskPass    G-buffer depth + normals + motion + ids -> lit fraction
//!                                    of the shutter, each receiver followed along its path
//!                                    (the ids keep its own triangle from shadowing it)
//!   shading (the engine's own)       radiance = albedo / pi * sum(E cos falloff mask) + ambient
//! ```
//!
//! The shutter of frame f runs from frame f - 1 (t = 0) to frame f (t = 1): an engine keeps
//! last frame's positions for its motion vectors anyway, and that is exactly what the shadow
//! pass needs. Nothing here uses the app crate (the tests use it as a reference only).
//!
//! The `deferred_host` example's engine (`main.rs` runs it), a module of its crate so that
//! the tests (`tests/gpu/deferred_host.rs`, `app/tests/gpu/deferred_host.rs`) drive the same
//! code; `host` is the engine's device.

use crate::host::Host;
// Links shaderc (compiled into this program to build the host's own shaders) where the
// distribution's libshaderc.so cannot be linked as it is; see build-support/shaderc-link.
use ash::vk;
use glam::{DMat4, Mat4, UVec4, Vec3, Vec4};
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    CollectionPass, Counters, Draw, DrawList, GLSL_INCLUDE, GenerationPass, IndexStream, Indices,
    LightKind, LightView, MaskBindings, MaskInputs, MotionImage, NormalEncoding, NormalImage,
    PositionStream, TemporalShadowMap, TriangleIdImage, VisibilityMaskPass,
};
use motion_shadows_shaderc_link as _;

/// Errors of the engine: the library's, Vulkan's (with the call), shaderc's, or a sentence.
pub type Error = Box<dyn std::error::Error + Send + Sync>;
/// The engine's result type.
pub type Result<T> = std::result::Result<T, Error>;

/// Frames the CPU may record ahead of the GPU: each has its own copy of everything that a
/// frame writes (command buffer, fence, draw list, shadow maps, images, uniform buffer).
pub const FRAMES_IN_FLIGHT: usize = 2;
/// Lights the shading shader handles (`MAX_LIGHTS` in `glsl/frame.glsl`).
pub const MAX_LIGHTS: usize = 2;

// ---------------------------------------------------------------------------------------
// The world: what the engine draws. Plain data plus animation functions of the frame time.
// ---------------------------------------------------------------------------------------

/// A vertex as the engine stores it: 24 bytes, position then normal (object space).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// A mesh's index buffer contents: 16-bit indices for small meshes, 32-bit for large ones.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshIndices {
    U16(Vec<u16>),
    U32(Vec<u32>),
}

impl MeshIndices {
    pub fn len(&self) -> usize {
        match self {
            Self::U16(i) => i.len(),
            Self::U32(i) => i.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn get(&self, i: usize) -> u32 {
        match self {
            Self::U16(v) => u32::from(v[i]),
            Self::U32(v) => v[i],
        }
    }
}

/// How a mesh moves. `f` is the frame time in frames: frame f's shutter runs from f - 1 to f.
pub enum Motion {
    /// A rigid object: its vertices stay in the static vertex buffer, and only its
    /// object-to-world transform changes (the shadow pass gets last frame's and this
    /// frame's). Computed in f64, as an engine's scene graph might.
    Rigid(Box<dyn Fn(f64) -> DMat4>),
    /// Deformed on the CPU (think skinning): world-space vertices of frame time f, written
    /// each frame into a per-frame-in-flight vertex buffer next to last frame's positions.
    Deformed(Box<dyn Fn(f64) -> Vec<Vertex>>),
}

/// One mesh of the world.
pub struct Mesh {
    pub name: String,
    /// Object-space vertices (for a deformed mesh: its rest pose, unused by the GPU).
    pub vertices: Vec<Vertex>,
    pub indices: MeshIndices,
    pub albedo: Vec3,
    /// Watertight and wound counter-clockwise seen from outside (lets the shadow pass skip
    /// triangles facing away from the light all frame).
    pub closed: bool,
    pub motion: Motion,
}

impl Mesh {
    pub fn triangle_count(&self) -> u32 {
        (self.indices.len() / 3) as u32
    }

    /// World-space vertex positions at frame time `f`, as f32 (rigid transforms applied in
    /// f64 and then rounded, so a CPU model sees the same numbers whatever it does next).
    pub fn world_positions(&self, f: f64) -> Vec<Vec3> {
        match &self.motion {
            Motion::Rigid(transform) => {
                let m = transform(f);
                self.vertices
                    .iter()
                    .map(|v| {
                        m.transform_point3(Vec3::from(v.position).as_dvec3())
                            .as_vec3()
                    })
                    .collect()
            }
            Motion::Deformed(deform) => deform(f).iter().map(|v| Vec3::from(v.position)).collect(),
        }
    }

    /// The mesh as a triangle list (three world positions per triangle) at frame time `f`.
    pub fn world_triangles(&self, f: f64) -> Vec<Vec3> {
        let positions = self.world_positions(f);
        (0..self.indices.len())
            .map(|i| positions[self.indices.get(i) as usize])
            .collect()
    }
}

/// The engine's camera (right-handed, y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Full vertical field of view.
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// World -> Vulkan clip space (depth in [0, 1], y down).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
        let view = look_at_mat4(self.eye, self.target, self.up);
        // Vulkan's clip space: y down, depth in [0, 1] (near to far).
        let proj = vulkan::perspective(self.fov_y_deg.to_radians(), aspect, self.near, self.far);
        proj * view
    }
}

/// A light of the world. Each gets a temporal shadow map per frame in flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A point light with a hard cone; radiance falls off as 1 / d^2.
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_half_angle_deg: f32,
        /// W/sr.
        intensity: f32,
        /// The shadow map's depth range.
        near: f32,
        far: f32,
    },
    /// A parallel light; its shadow map is an orthographic box around `center`.
    Directional {
        direction: Vec3,
        /// W/m^2 on a surface facing the light.
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
    },
}

impl Light {
    /// The library's view of the light for a shadow map of `size` texels.
    pub fn view(&self, size: (u32, u32)) -> LightView {
        match *self {
            Light::Spot {
                position,
                direction,
                cone_half_angle_deg,
                intensity,
                near,
                far,
            } => LightView::spot(
                position,
                direction,
                cone_half_angle_deg,
                intensity,
                near,
                far,
                size,
            ),
            Light::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            } => LightView::directional(
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
                size,
            ),
        }
    }
}

/// Everything the engine draws.
pub struct World {
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// Radiance += ambient * albedo everywhere.
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// Four vertices per face, outward normals, counter-clockwise seen from outside.
pub fn cuboid(half: Vec3) -> (Vec<Vertex>, Vec<u16>) {
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    // (normal, u, v) with u x v = normal.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    for (n, u, v) in faces {
        let base = vertices.len() as u16;
        let (c, u, v) = (n * half, u * half, v * half);
        for p in [c - u - v, c + u - v, c + u + v, c - u + v] {
            vertices.push(Vertex {
                position: p.to_array(),
                normal: n.to_array(),
            });
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
    }
    (vertices, indices)
}

/// The static ground of both demo worlds: a light grey `ground_grid(6, 4)`, 32-bit indices.
pub fn ground_mesh() -> Mesh {
    let (vertices, indices) = ground_grid(6.0, 4);
    Mesh {
        name: "ground".into(),
        vertices,
        indices: MeshIndices::U32(indices),
        albedo: Vec3::splat(0.8),
        closed: false,
        motion: Motion::Rigid(Box::new(|_| DMat4::IDENTITY)),
    }
}

/// A flat grid in the xz plane facing +y: `cells` x `cells` quads over [-half, half]^2.
pub fn ground_grid(half: f32, cells: u32) -> (Vec<Vertex>, Vec<u32>) {
    let n = cells + 1;
    let step = 2.0 * half / cells as f32;
    let vertices = (0..n * n)
        .map(|i| Vertex {
            position: [
                -half + (i % n) as f32 * step,
                0.0,
                -half + (i / n) as f32 * step,
            ],
            normal: [0.0, 1.0, 0.0],
        })
        .collect();
    let mut indices = Vec::new();
    for row in 0..cells {
        for col in 0..cells {
            // a = (x0, z0), b = (x0, z1), c = (x1, z1), d = (x1, z0): (a, b, c) and (a, c, d)
            // are counter-clockwise seen from +y.
            let (a, d) = (row * n + col, row * n + col + 1);
            let (b, c) = (a + n, d + n);
            indices.extend([a, b, c, a, c, d]);
        }
    }
    (vertices, indices)
}

/// The bent strip's vertices: `segments` quads along its length, tilted by `tilt_deg` about
/// the x axis around `centre`, bent by a wave that travels with the frame time.
fn strip_vertices(centre: Vec3, tilt_deg: f32, segments: u32, f: f64) -> Vec<Vertex> {
    let (half_length, half_width, amplitude) = (1.2f32, 0.55f32, 0.22f32);
    let tilt = tilt_deg.to_radians();
    let (ex, ev) = (Vec3::X, Vec3::new(0.0, tilt.sin(), tilt.cos()));
    let en = ev.cross(ex); // the strip's unbent normal, upward
    let phase = f as f32 * 1.3;
    let mut out = Vec::new();
    for side in [-half_width, half_width] {
        for i in 0..=segments {
            let u = -half_length + 2.0 * half_length * i as f32 / segments as f32;
            let wave = amplitude * (2.2 * u + phase).sin();
            let slope = amplitude * 2.2 * (2.2 * u + phase).cos();
            out.push(Vertex {
                position: (centre + u * ex + side * ev + wave * en).to_array(),
                normal: (en - slope * ex).normalize().to_array(),
            });
        }
    }
    out
}

fn strip_indices(segments: u32) -> Vec<u32> {
    let n = segments + 1;
    let mut indices = Vec::new();
    for i in 0..segments {
        // Row 0 is the -v side, row 1 the +v side: (a, b, c), (a, c, d) face en.
        let (a, d) = (i, i + 1);
        let (b, c) = (i + n, i + 1 + n);
        indices.extend([a, b, c, a, c, d]);
    }
    indices
}

impl World {
    /// The example's world: a ground grid, a box flying across it and turning, a static
    /// pillar, and a bent strip that the CPU deforms every frame while it drifts; a spot
    /// light and a directional light.
    pub fn demo() -> World {
        let (box_v, box_i) = cuboid(Vec3::splat(0.5));
        let (pillar_v, pillar_i) = cuboid(Vec3::new(0.3, 0.8, 0.3));
        const SEGMENTS: u32 = 6;
        let strip = |f: f64| {
            let centre = Vec3::new(0.9, 1.5, -2.8 + 0.6 * f as f32);
            strip_vertices(centre, -30.0, SEGMENTS, f)
        };
        World {
            camera: Camera {
                eye: Vec3::new(0.0, 7.5, 8.5),
                target: Vec3::new(0.2, 0.0, -0.6),
                up: Vec3::Y,
                fov_y_deg: 45.0,
                near: 0.1,
                far: 50.0,
            },
            lights: vec![
                Light::Spot {
                    position: Vec3::new(-3.0, 7.5, -3.5),
                    direction: Vec3::new(3.3, -7.5, 4.0),
                    cone_half_angle_deg: 38.0,
                    intensity: 110.0,
                    near: 1.0,
                    far: 30.0,
                },
                Light::Directional {
                    direction: Vec3::new(0.45, -1.0, 0.3),
                    irradiance: 0.9,
                    center: Vec3::ZERO,
                    half_extent: 7.5,
                    distance: 15.0,
                    near: 1.0,
                    far: 40.0,
                },
            ],
            ambient: 0.04,
            meshes: vec![
                ground_mesh(),
                Mesh {
                    name: "flying box".into(),
                    vertices: box_v,
                    indices: MeshIndices::U16(box_i),
                    albedo: Vec3::new(0.8, 0.25, 0.2),
                    closed: true,
                    motion: Motion::Rigid(Box::new(|f| {
                        DMat4::from_translation(glam::DVec3::new(-3.0 + 1.2 * f, 1.5, 0.6))
                            * DMat4::from_rotation_y(0.35 * f)
                    })),
                },
                Mesh {
                    name: "pillar".into(),
                    vertices: pillar_v,
                    indices: MeshIndices::U16(pillar_i),
                    albedo: Vec3::new(0.3, 0.5, 0.8),
                    closed: true,
                    motion: Motion::Rigid(Box::new(|_| {
                        DMat4::from_translation(glam::DVec3::new(2.4, 0.8, 1.4))
                    })),
                },
                Mesh {
                    name: "bent strip".into(),
                    vertices: strip(0.0),
                    indices: MeshIndices::U32(strip_indices(SEGMENTS)),
                    albedo: Vec3::new(0.85, 0.75, 0.3),
                    closed: false,
                    motion: Motion::Deformed(Box::new(strip)),
                },
            ],
        }
    }
}

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
    /// Fragments and ranges every shadow map has room for at first. Too small only costs a
    /// re-render of a kept frame (see `Engine::render`).
    pub initial_capacity: (u32, u32),
    pub lookup: ShadowLookup,
    /// Keep each shadow map's static layer across frames (`LightView::keep_static_layer`):
    /// the world's static meshes never change in place, and its lights do not move.
    pub keep_static_layer: bool,
    /// Give the mask pass the G-buffer's motion (receivers followed along their path); off,
    /// every receiver stands still where the G-buffer shows it (the mask's cheaper variant,
    /// exact for a world whose receivers do not move).
    pub receivers_move: bool,
}

/// A frame's results, read back once its fence signalled.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    pub frame: u32,
    /// The frame-in-flight slot that rendered it.
    pub slot: usize,
    /// Submissions it took (more than 1 when a shadow map overflowed and was grown).
    pub attempts: u32,
    /// Per light: the shadow map's counters (N_f = node_count, N_r = range_count).
    pub counters: Vec<Counters>,
    /// Linear radiance per pixel (rgb; a = 1 where a surface is, 0 for the background).
    pub radiance: Vec<[f32; 4]>,
    /// Per light: the visibility mask (lit fraction of the shutter) per pixel.
    pub masks: Vec<Vec<f32>>,
}

const NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
const ALBEDO_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// World-space motion over the shutter: half floats, as an engine stores motion vectors.
const MOTION_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Each pixel's triangle: the global id the shadow pass's draws give it (`u32::MAX`: none).
const ID_FORMAT: vk::Format = vk::Format::R32_UINT;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
const RADIANCE_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The deferred engine. Borrows the host's device for its whole life.
pub struct Engine<'h> {
    host: &'h Host,
    settings: Settings,
    mask_format: vk::Format,
    pipelines: Pipelines,
    geometry: Geometry,
    slots: Vec<Slot>,
    passes: Passes,
    /// Submissions so far: the frame number the library is told (`Context::begin_frame`),
    /// counting re-rendered frames again, so that it only grows.
    submissions: u64,
    // Last: every library object above must go before the context.
    ctx: Context,
}

/// The library's passes: immutable, one set for every frame in flight and every light.
struct Passes {
    collection: CollectionPass,
    generation: GenerationPass,
    mask: VisibilityMaskPass,
}

/// What recording a frame reads: everything of the engine but the slots.
struct Recorder<'a> {
    device: &'a ash::Device,
    settings: &'a Settings,
    passes: &'a Passes,
    pipelines: &'a Pipelines,
    geometry: &'a Geometry,
}

/// Layout + access + stage in one tuple, for `Image::barrier`.
type State = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// Everything one frame in flight writes.
struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// The frame submitted with this slot and not yet retired.
    pending: Option<u32>,
    /// Its submission's number (`Engine::submissions`): what `Context::collect` is told once
    /// the slot's fence has signalled.
    submission: u64,
    attempts: u32,
    frame_constants: HostBuffer,
    /// Last frame's and this frame's positions of the deformed meshes.
    deformed: HostBuffer,
    depth: Image,
    normals: Image,
    albedo: Image,
    /// Per pixel: the surface point's world displacement from frame f - 1 to frame f.
    motion: Image,
    /// Per pixel: the global id of the triangle it shows (the mask's own-triangle skip,
    /// which moving receivers need).
    ids: Image,
    /// One per light.
    masks: Vec<Image>,
    radiance: Image,
    radiance_readback: HostBuffer,
    mask_readback: Vec<HostBuffer>,
    frame_set: vk::DescriptorSet,
    image_set: vk::DescriptorSet,
    // The library's per-frame objects.
    draws: DrawList,
    maps: Vec<TemporalShadowMap>,
    mask_bindings: Vec<MaskBindings>,
}

impl<'h> Engine<'h> {
    /// Sets the engine up for `world` (its geometry, lights count) with `settings`.
    pub fn new(host: &'h Host, world: &World, settings: Settings) -> Result<Self> {
        if world.lights.is_empty() || world.lights.len() > MAX_LIGHTS {
            return Err(format!(
                "{} lights: the engine shades 1 to {MAX_LIGHTS}",
                world.lights.len()
            )
            .into());
        }
        if !host.storage_image_write_without_format {
            return Err("the device lacks shaderStorageImageWriteWithoutFormat, which the visibility-mask pass needs".into());
        }
        let device = &host.device;
        // SAFETY: Host::new made `device` from `physical` of `instance`, Vulkan 1.3, with a
        // graphics+compute queue of `queue_family` and every feature the contract lists
        // (shaderStorageImageWriteWithoutFormat checked above). The host outlives the engine
        // (the borrow), which drops the context last, after waiting for its own frames. The
        // library never submits: the engine records its passes into its own command buffers.
        let ctx = unsafe {
            Context::from_raw(
                &host.instance,
                host.physical,
                host.device.clone(),
                host.queue_family,
                host.queue,
                &host.enabled,
            )
        }?;
        let mask_format = Self::pick_mask_format(host)?;
        for (format, features, what) in [
            (
                DEPTH_FORMAT,
                vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::FormatFeatureFlags::SAMPLED_IMAGE,
                "a sampled depth attachment",
            ),
            (
                NORMAL_FORMAT,
                vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE,
                "a sampled color attachment",
            ),
        ] {
            if !Self::format_features(host, format).contains(features) {
                return Err(format!("{format:?} cannot be {what} on this device").into());
            }
        }
        let pipelines = Pipelines::new(device, host.queue_family)?;
        let geometry = Geometry::upload(host, world)?;
        let mut engine = Engine {
            host,
            settings,
            mask_format,
            pipelines,
            geometry,
            slots: Vec::new(),
            submissions: 0,
            passes: Passes {
                collection: CollectionPass::new(&ctx)?,
                generation: GenerationPass::new(&ctx)?,
                mask: VisibilityMaskPass::new(&ctx)?,
            },
            ctx,
        };
        for _ in 0..FRAMES_IN_FLIGHT {
            let slot = engine.new_slot(world)?;
            engine.slots.push(slot);
        }
        Ok(engine)
    }

    fn format_features(host: &Host, format: vk::Format) -> vk::FormatFeatureFlags {
        // SAFETY: `host.physical` is a physical device of the host's live instance.
        unsafe {
            host.instance
                .get_physical_device_format_properties(host.physical, format)
        }
        .optimal_tiling_features
    }

    /// R16_UNORM masks (2 bytes, 1/65535 steps) where the device can write them as storage
    /// images, else R32_SFLOAT (which every device can).
    fn pick_mask_format(host: &Host) -> Result<vk::Format> {
        let needed = vk::FormatFeatureFlags::STORAGE_IMAGE
            | vk::FormatFeatureFlags::SAMPLED_IMAGE
            | vk::FormatFeatureFlags::TRANSFER_SRC;
        [vk::Format::R16_UNORM, vk::Format::R32_SFLOAT]
            .into_iter()
            .find(|&f| Self::format_features(host, f).contains(needed))
            .ok_or_else(|| "no single-channel storage format for the masks".into())
    }

    /// The library's context (device information, validation messages).
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// The mask images' format.
    pub fn mask_format(&self) -> vk::Format {
        self.mask_format
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
        &self.slots[slot].maps[light]
    }

    fn new_slot(&self, world: &World) -> Result<Slot> {
        let host = self.host;
        let device = &host.device;
        let size = (self.settings.width, self.settings.height);
        let pixels = size.0 as u64 * size.1 as u64;
        let lights = world.lights.len();
        let sampled = vk::ImageUsageFlags::SAMPLED;
        let color = vk::ImageAspectFlags::COLOR;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pipelines.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the engine's command pool, made for the host's queue family with
        // RESET_COMMAND_BUFFER; slots are made on this thread only.
        let cmd =
            unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        // Freed with the pool; the fence is destroyed by the engine's Drop once in the slot.
        // SAFETY: creating an unsignalled fence on the host's live device has no precondition.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .vk("vkCreateFence")?;
        let build = || -> Result<Slot> {
            let set_layouts = [
                self.pipelines.frame_set_layout,
                self.pipelines.image_set_layout,
            ];
            let alloc = vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(self.pipelines.descriptor_pool)
                .set_layouts(&set_layouts);
            // SAFETY: the pool was made for FRAMES_IN_FLIGHT slots' two sets each (its sizes count
            // every binding of both layouts), and at most that many slots are made.
            let sets = unsafe { device.allocate_descriptor_sets(&alloc) }
                .vk("vkAllocateDescriptorSets")?;
            let (sw, sh) = self.settings.shadow_size;
            let (nodes, ranges) = self.settings.initial_capacity;
            let slot = Slot {
                cmd,
                fence,
                pending: None,
                submission: 0,
                attempts: 0,
                frame_constants: HostBuffer::new(
                    host,
                    std::mem::size_of::<FrameConstants>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                )?,
                deformed: HostBuffer::new(
                    host,
                    self.geometry.deformed_bytes,
                    vk::BufferUsageFlags::VERTEX_BUFFER
                        | vk::BufferUsageFlags::STORAGE_BUFFER
                        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
                )?,
                depth: Image::new(
                    host,
                    DEPTH_FORMAT,
                    size,
                    vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | sampled,
                    vk::ImageAspectFlags::DEPTH,
                )?,
                normals: Image::new(
                    host,
                    NORMAL_FORMAT,
                    size,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | sampled,
                    color,
                )?,
                albedo: Image::new(
                    host,
                    ALBEDO_FORMAT,
                    size,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | sampled,
                    color,
                )?,
                motion: Image::new(
                    host,
                    MOTION_FORMAT,
                    size,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | sampled,
                    color,
                )?,
                ids: Image::new(
                    host,
                    ID_FORMAT,
                    size,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | sampled,
                    color,
                )?,
                masks: (0..lights)
                    .map(|_| {
                        Image::new(
                            host,
                            self.mask_format,
                            size,
                            vk::ImageUsageFlags::STORAGE
                                | sampled
                                | vk::ImageUsageFlags::TRANSFER_SRC,
                            color,
                        )
                    })
                    .collect::<Result<_>>()?,
                radiance: Image::new(
                    host,
                    RADIANCE_FORMAT,
                    size,
                    vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
                    color,
                )?,
                radiance_readback: HostBuffer::new(
                    host,
                    pixels * 16,
                    vk::BufferUsageFlags::TRANSFER_DST,
                )?,
                mask_readback: (0..lights)
                    .map(|_| {
                        HostBuffer::new(
                            host,
                            pixels * mask_texel_bytes(self.mask_format),
                            vk::BufferUsageFlags::TRANSFER_DST,
                        )
                    })
                    .collect::<Result<_>>()?,
                frame_set: sets[0],
                image_set: sets[1],
                draws: DrawList::new(&self.ctx, world.meshes.len() as u32)?,
                maps: (0..lights)
                    .map(|_| TemporalShadowMap::new(&self.ctx, sw, sh, nodes, ranges))
                    .collect::<motion_shadows::Result<_>>()?,
                mask_bindings: (0..lights)
                    .map(|_| self.passes.mask.bindings(&self.ctx, size))
                    .collect::<motion_shadows::Result<_>>()?,
            };
            self.write_descriptors(&slot);
            Ok(slot)
        };
        // SAFETY: the slot was not built, so its fence was never submitted and is destroyed once,
        // here.
        build().inspect_err(|_| unsafe { device.destroy_fence(fence, None) })
    }

    /// The slot's descriptor sets point at its own images and uniform buffer, for good.
    fn write_descriptors(&self, slot: &Slot) {
        let ubo = [vk::DescriptorBufferInfo {
            buffer: slot.frame_constants.buffer,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let sampled = |view, layout| {
            [vk::DescriptorImageInfo {
                sampler: self.pipelines.sampler,
                image_view: view,
                image_layout: layout,
            }]
        };
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // A single light leaves binding 4 pointing at light 0's mask (never read then).
        let mask1 = slot.masks.get(1).unwrap_or(&slot.masks[0]);
        let images = [
            sampled(
                slot.depth.view,
                vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            sampled(slot.normals.view, read_only),
            sampled(slot.albedo.view, read_only),
            sampled(slot.masks[0].view, read_only),
            sampled(mask1.view, read_only),
        ];
        let motion = sampled(slot.motion.view, read_only);
        let output = [vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: slot.radiance.view,
            image_layout: vk::ImageLayout::GENERAL,
        }];
        let mut writes = vec![
            vk::WriteDescriptorSet::default()
                .dst_set(slot.frame_set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&ubo),
            vk::WriteDescriptorSet::default()
                .dst_set(slot.image_set)
                .dst_binding(5)
                .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                .image_info(&output),
            vk::WriteDescriptorSet::default()
                .dst_set(slot.image_set)
                .dst_binding(6)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(&motion),
        ];
        for (binding, info) in images.iter().enumerate() {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(slot.image_set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .image_info(info),
            );
        }
        // SAFETY: the slot's sets are written once, while it is being built, before any command
        // buffer uses them; each write names an image view or buffer of this slot, alive as long as
        // it.
        unsafe { self.host.device.update_descriptor_sets(&writes, &[]) };
    }

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

    fn wait_all(&mut self) {
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
    fn retire(
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
    fn submit(&mut self, world: &World, slot: usize, frame: u32) -> Result<()> {
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
    fn shadow_draws(&self, world: &World, slot: usize, f: f64) -> Result<Vec<Draw>> {
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

impl Recorder<'_> {
    /// Records the whole frame into the slot's command buffer (recording, outside rendering).
    fn record(
        &self,
        s: &mut Slot,
        world: &World,
        f: f64,
        draws: &[Draw],
        lights: &[LightView],
        constants: &FrameConstants,
    ) -> Result<()> {
        let device = self.device;
        let cmd = s.cmd;
        let (width, height) = (self.settings.width, self.settings.height);

        // 1. The temporal shadow maps, one per light. Each records its own barriers (its
        //    contract): nothing of ours to synchronize here.
        // SAFETY: `cmd` is recording, outside rendering, on the graphics+compute queue; the
        // draw list, maps and passes are this slot's or shared immutable ones, not used by the
        // other slot's pending frame; the streams' contracts are kept by `shadow_draws`.
        unsafe {
            // Errors (a bad draw) come before anything is recorded.
            s.draws.record_update(device, cmd, draws)?;
            for (light, map) in lights.iter().zip(&s.maps) {
                self.passes
                    .collection
                    .record(device, cmd, &s.draws, light, map, None)?;
                self.passes.generation.record(device, cmd, map);
                // The counters, for the overflow check once the fence has signalled.
                map.record_counter_readback(device, cmd);
            }
        }

        // 2. The G-buffer at t = 1. Its images' previous contents (two frames ago) were read
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

        // 3. The visibility masks: the G-buffer becomes read-only for compute shaders, the
        //    mask images writable (GENERAL), as the mask pass's contract asks.
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
        for ((map, mask), bindings) in s.maps.iter().zip(&s.masks).zip(&mut s.mask_bindings) {
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
            // SAFETY: recording outside rendering; the bindings are this slot's and this
            // light's (used once in this command buffer, not by the other slot's frame); the
            // views have the usages and layouts stated above, and the barrier before made the
            // G-buffer visible to compute reads and ordered the masks' earlier reads before
            // these writes; the map's collection and generation were recorded above.
            unsafe { self.passes.mask.record(device, cmd, bindings, &inputs, map) }?;
        }

        // 4. The engine's shading: masks written by the mask pass become sampled reads.
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
        let mut maps = [0u64; MAX_LIGHTS];
        for (address, map) in maps.iter_mut().zip(&s.maps) {
            // Changes when a map grows: pushed every frame.
            *address = map.header_address();
        }
        let push = ShadeConstants { maps, lookup, time };
        let p = &self.pipelines;
        // SAFETY: the shade pipeline's layout holds both sets (frame constants, images) and a
        // compute push range of ShadeConstants' size, which `bytes_of(&push)` is; the images were
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
                bytes_of(&push),
            );
            device.cmd_dispatch(cmd, width.div_ceil(8), height.div_ceil(8), 1);
        }

        // 5. Read back the radiance and the masks (an engine would present or post-process;
        //    this one writes files and tests).
        let transfer_src: State = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        );
        let mut barriers = vec![s.radiance.barrier(storage_write, transfer_src)];
        barriers.extend(s.masks.iter().map(|m| m.barrier(shader_read, transfer_src)));
        pipeline_barrier(device, cmd, &barriers, &[]);
        let region = |aspect| {
            [vk::BufferImageCopy {
                buffer_offset: 0,
                buffer_row_length: 0,
                buffer_image_height: 0,
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: aspect,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                },
                image_offset: vk::Offset3D::default(),
                image_extent: vk::Extent3D {
                    width,
                    height,
                    depth: 1,
                },
            }]
        };
        let color = region(vk::ImageAspectFlags::COLOR);
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
    fn record_gbuffer(&self, world: &World, s: &Slot, f: f64) -> Result<()> {
        let device = self.device;
        let cmd = s.cmd;
        let (width, height) = (self.settings.width, self.settings.height);
        let clear = |color: [f32; 4]| vk::ClearValue {
            color: vk::ClearColorValue { float32: color },
        };
        let colors = [
            vk::RenderingAttachmentInfo::default()
                .image_view(s.normals.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear([0.0; 4])),
            vk::RenderingAttachmentInfo::default()
                .image_view(s.albedo.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear([0.0; 4])),
            vk::RenderingAttachmentInfo::default()
                .image_view(s.motion.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear([0.0; 4])),
            vk::RenderingAttachmentInfo::default()
                .image_view(s.ids.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    color: vk::ClearColorValue {
                        uint32: [u32::MAX; 4],
                    },
                }),
        ];
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
                    bytes_of(&push),
                );
                device.cmd_draw_indexed(cmd, m.index_count, 1, 0, 0, 0);
            }
        }
        // SAFETY: the rendering began above and every mesh is drawn.
        unsafe { device.cmd_end_rendering(cmd) };
        Ok(())
    }
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        // Frames still in flight use everything below: wait for them (the engine's own
        // fences; the library never waits on a host's device).
        self.wait_all();
        let device = &self.host.device;
        for slot in &self.slots {
            // SAFETY: wait_all just waited for every pending slot, so no fence is in use; each is
            // destroyed once.
            unsafe { device.destroy_fence(slot.fence, None) };
        }
        // The fields drop next: the pipelines and pools, the slots' images and buffers, the
        // library's objects, and the context last.
    }
}

// What the engine's shaders read, and where its geometry lives.

/// Per-frame constants, `Frame` in `glsl/frame.glsl` (std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
struct FrameConstants {
    view_proj: Mat4,
    inv_view_proj: Mat4,
    eye: Vec4,
    info: UVec4,
    shading: Vec4,
    lights: [LightConstants; MAX_LIGHTS],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
struct LightConstants {
    position: Vec4,
    direction: Vec4,
    emission: Vec4,
}

/// The G-buffer pass's push constants (`Draw` in gbuffer.vert): 128 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
struct DrawConstants {
    model: [Vec4; 3],
    previous_model: [Vec4; 3],
    albedo: Vec4,
    /// The mesh's first global triangle id (its `Draw`'s): plus the primitive's index, the
    /// id the G-buffer stores.
    first_id: u32,
    pad: [u32; 3],
}

/// The shading pass's push constants (`Push` in shade.comp): 24 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
struct ShadeConstants {
    maps: [u64; MAX_LIGHTS],
    lookup: u32,
    time: f32,
}

const LOOKUP_MASKS: u32 = 0;
const LOOKUP_LIT_FRACTION: u32 = 1;
const LOOKUP_AT_TIME: u32 = 2;

/// Bytes per deformed vertex in the per-frame vertex buffer: last frame's position, this
/// frame's position, this frame's normal, each padded to 16 bytes.
const DEFORMED_STRIDE: u32 = 48;

/// Where a mesh's data lives.
#[derive(Debug, Clone, Copy)]
struct MeshSlot {
    /// Rigid: byte offset of its vertices in the static vertex buffer. Deformed: in each
    /// frame's deformed-vertex buffer.
    vertex_offset: u64,
    vertex_count: u32,
    /// Byte offset of its indices in the index buffer, and their type.
    index_offset: u64,
    index_type: vk::IndexType,
    index_count: u32,
    /// Global id of its first triangle (ids of different meshes never overlap).
    first_triangle_id: u32,
}

/// The engine's own geometry buffers, shared by every frame (never written after upload).
struct Geometry {
    static_vertices: HostBuffer,
    indices: HostBuffer,
    meshes: Vec<MeshSlot>,
    /// Bytes of deformed vertices each frame writes.
    deformed_bytes: u64,
}

impl Geometry {
    fn upload(host: &Host, world: &World) -> Result<Self> {
        let (mut vertices, mut index_bytes, mut meshes) =
            (Vec::new(), Vec::<u8>::new(), Vec::new());
        let (mut deformed_bytes, mut next_id) = (0u64, 0u32);
        for mesh in &world.meshes {
            // Indices: each mesh at a 4-byte aligned offset of one buffer.
            index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
            let index_offset = index_bytes.len() as u64;
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
            let vertex_offset = match mesh.motion {
                Motion::Rigid(_) => {
                    let offset = (vertices.len() * std::mem::size_of::<Vertex>()) as u64;
                    vertices.extend_from_slice(&mesh.vertices);
                    offset
                }
                Motion::Deformed(_) => {
                    let offset = deformed_bytes;
                    deformed_bytes += mesh.vertices.len() as u64 * DEFORMED_STRIDE as u64;
                    offset
                }
            };
            meshes.push(MeshSlot {
                vertex_offset,
                vertex_count: mesh.vertices.len() as u32,
                index_offset,
                index_type,
                index_count: mesh.indices.len() as u32,
                first_triangle_id: next_id,
            });
            next_id += mesh.triangle_count();
        }
        // The library reads 16-bit indices as whole 32-bit words: pad the buffer's end.
        index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
        // Vertex or index buffers for the rasterizer, storage buffers with a device address
        // for the library's shadow pass: one buffer, both usages.
        let shared =
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        Ok(Self {
            static_vertices: HostBuffer::with_data(
                host,
                &vertices,
                vk::BufferUsageFlags::VERTEX_BUFFER | shared,
            )?,
            indices: HostBuffer::with_data(
                host,
                &index_bytes,
                vk::BufferUsageFlags::INDEX_BUFFER | shared,
            )?,
            meshes,
            deformed_bytes,
        })
    }
}

fn mask_texel_bytes(format: vk::Format) -> u64 {
    if format == vk::Format::R16_UNORM {
        2
    } else {
        4
    }
}

fn read_mask(buffer: &HostBuffer, format: vk::Format, pixels: usize) -> Result<Vec<f32>> {
    Ok(if format == vk::Format::R16_UNORM {
        buffer
            .read::<u16>(pixels)?
            .into_iter()
            .map(|v| v as f32 / 65535.0)
            .collect()
    } else {
        buffer.read::<f32>(pixels)?
    })
}

// ---------------------------------------------------------------------------------------
// Shaders: GLSL compiled at run time by shaderc, the library's header served from the Rust
// constant `GLSL_INCLUDE` by the include callback, exactly as a host's shader system would.
// ---------------------------------------------------------------------------------------

/// The host's own shader sources (the crate's `glsl/`).
pub mod sources {
    pub const FRAME_GLSL: &str = include_str!("../glsl/frame.glsl");
    pub const GBUFFER_VERT: &str = include_str!("../glsl/gbuffer.vert");
    pub const GBUFFER_FRAG: &str = include_str!("../glsl/gbuffer.frag");
    pub const SHADE_COMP: &str = include_str!("../glsl/shade.comp");
    pub const PROBE_COMP: &str = include_str!("../glsl/probe.comp");
    pub const SAMPLES_PROBE_COMP: &str = include_str!("../glsl/samples_probe.comp");
    pub const MOVING_PROBE_COMP: &str = include_str!("../glsl/moving_probe.comp");
    /// The library's own per-texel test of a pixel's samples (not part of the public
    /// include), for the test that holds it to `ms_texel_shadowed`.
    pub const TEMPORAL_SAMPLES_GLSL: &str = include_str!(env!("TEMPORAL_SAMPLES_GLSL"));
}

/// Compiles one GLSL stage to SPIR-V. `#include "motion_shadows.glsl"` resolves to the
/// library's header, `#include "frame.glsl"` to the host's own.
pub fn compile_glsl(name: &str, source: &str, kind: shaderc::ShaderKind) -> Result<Vec<u32>> {
    let compiler = shaderc::Compiler::new()?;
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_include_callback(|requested, _kind, _from, _depth| {
        let content = match requested {
            "motion_shadows.glsl" => GLSL_INCLUDE,
            "frame.glsl" => sources::FRAME_GLSL,
            "temporal_samples.glsl" => sources::TEMPORAL_SAMPLES_GLSL,
            other => return Err(format!("no header {other}")),
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: requested.to_owned(),
            content: content.to_owned(),
        })
    });
    let artifact = compiler.compile_into_spirv(source, kind, name, "main", Some(&options))?;
    Ok(artifact.as_binary().to_vec())
}

/// A shader module of `code`, destroyed by the caller once the pipeline exists.
pub fn shader_module(device: &ash::Device, code: &[u32]) -> Result<vk::ShaderModule> {
    let info = vk::ShaderModuleCreateInfo::default().code(code);
    // SAFETY: `code` is SPIR-V that shaderc compiled from the engine's own GLSL for Vulkan 1.3,
    // read into aligned words.
    unsafe { device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")
}

/// A compute pipeline of one GLSL source.
pub fn compute_pipeline(
    device: &ash::Device,
    name: &str,
    source: &str,
    layout: vk::PipelineLayout,
) -> Result<vk::Pipeline> {
    let module = shader_module(
        device,
        &compile_glsl(name, source, shaderc::ShaderKind::Compute)?,
    )?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    // SAFETY: the module holds shaderc's SPIR-V of the engine's GLSL, whose push constants and
    // bindings `layout` was made for; `info` lives through the call.
    let pipeline =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    // SAFETY: pipeline creation has returned, and a module may go once its pipelines are made.
    unsafe { device.destroy_shader_module(module, None) };
    Ok(pipeline
        .map_err(|(_, e)| e)
        .vk("vkCreateComputePipelines")?[0])
}

// ---------------------------------------------------------------------------------------
// The engine's pipelines (created once, shared by all frames).
// ---------------------------------------------------------------------------------------

/// The engine's pipelines and layouts (created once, shared by all frames).
struct Pipelines {
    device: ash::Device,
    frame_set_layout: vk::DescriptorSetLayout,
    image_set_layout: vk::DescriptorSetLayout,
    gbuffer_layout: vk::PipelineLayout,
    gbuffer: vk::Pipeline,
    shade_layout: vk::PipelineLayout,
    shade: vk::Pipeline,
    sampler: vk::Sampler,
    descriptor_pool: vk::DescriptorPool,
    command_pool: vk::CommandPool,
}

impl Pipelines {
    fn new(device: &ash::Device, queue_family: u32) -> Result<Self> {
        let mut p = Pipelines {
            device: device.clone(),
            frame_set_layout: vk::DescriptorSetLayout::null(),
            image_set_layout: vk::DescriptorSetLayout::null(),
            gbuffer_layout: vk::PipelineLayout::null(),
            gbuffer: vk::Pipeline::null(),
            shade_layout: vk::PipelineLayout::null(),
            shade: vk::Pipeline::null(),
            sampler: vk::Sampler::null(),
            descriptor_pool: vk::DescriptorPool::null(),
            command_pool: vk::CommandPool::null(),
        };
        // On error, dropping `p` destroys what was created.
        p.create(device, queue_family)?;
        Ok(p)
    }

    fn create(&mut self, device: &ash::Device, queue_family: u32) -> Result<()> {
        let pool = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the host's queue family, with a pool per engine; destroyed in Pipelines' Drop.
        self.command_pool =
            unsafe { device.create_command_pool(&pool, None) }.vk("vkCreateCommandPool")?;
        let binding = |binding, ty, stages| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(stages)
        };
        // Set 0: the frame's constants, read by every stage of both passes.
        let frame = [binding(
            0,
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::ShaderStageFlags::VERTEX
                | vk::ShaderStageFlags::FRAGMENT
                | vk::ShaderStageFlags::COMPUTE,
        )];
        // SAFETY: `frame` is a local binding list alive for the call.
        self.frame_set_layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&frame),
                None,
            )
        }
        .vk("vkCreateDescriptorSetLayout")?;
        // Set 1 of the shading pass: depth, normals, albedo, two masks, the output, motion.
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let c = vk::ShaderStageFlags::COMPUTE;
        let images = [
            binding(0, sampled, c),
            binding(1, sampled, c),
            binding(2, sampled, c),
            binding(3, sampled, c),
            binding(4, sampled, c),
            binding(5, vk::DescriptorType::STORAGE_IMAGE, c),
            binding(6, sampled, c),
        ];
        // SAFETY: `images` is a local binding list alive for the call.
        self.image_set_layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&images),
                None,
            )
        }
        .vk("vkCreateDescriptorSetLayout")?;
        let n = FRAMES_IN_FLIGHT as u32;
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: n,
            },
            vk::DescriptorPoolSize {
                ty: sampled,
                descriptor_count: 6 * n,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_IMAGE,
                descriptor_count: n,
            },
        ];
        // SAFETY: `sizes` is a local alive for the call, counting every binding of both set layouts
        // for each of the FRAMES_IN_FLIGHT slots.
        self.descriptor_pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(2 * n)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .vk("vkCreateDescriptorPool")?;
        // Exact texel reads (texelFetch ignores the filter, but a sampler is required).
        let sampler = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        // SAFETY: a sampler of fixed, always-supported state (nearest, clamp to edge).
        self.sampler = unsafe { device.create_sampler(&sampler, None) }.vk("vkCreateSampler")?;

        let draw_push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: std::mem::size_of::<DrawConstants>() as u32,
        }];
        let set_layouts = [self.frame_set_layout];
        // SAFETY: the frame set layout is made above; one push range for the vertex and fragment
        // stages of DrawConstants' size, within any device's 128 bytes.
        self.gbuffer_layout = unsafe {
            device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&draw_push),
                None,
            )
        }
        .vk("vkCreatePipelineLayout")?;
        let shade_push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::COMPUTE,
            offset: 0,
            size: std::mem::size_of::<ShadeConstants>() as u32,
        }];
        let set_layouts = [self.frame_set_layout, self.image_set_layout];
        // SAFETY: both set layouts are made above; one compute push range of ShadeConstants' size.
        self.shade_layout = unsafe {
            device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&shade_push),
                None,
            )
        }
        .vk("vkCreatePipelineLayout")?;
        self.gbuffer = gbuffer_pipeline(device, self.gbuffer_layout)?;
        self.shade =
            compute_pipeline(device, "shade.comp", sources::SHADE_COMP, self.shade_layout)?;
        Ok(())
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        // Null handles (a failed `new`) are ignored; the command buffers go with their pool,
        // the descriptor sets with theirs.
        let device = &self.device;
        // SAFETY: the engine drops its pipelines after waiting for every slot's frame (its own
        // Drop), so none is in use; null handles of a failed `new` are ignored by the destroy
        // calls.
        unsafe {
            device.destroy_pipeline(self.gbuffer, None);
            device.destroy_pipeline(self.shade, None);
            device.destroy_pipeline_layout(self.gbuffer_layout, None);
            device.destroy_pipeline_layout(self.shade_layout, None);
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_descriptor_set_layout(self.frame_set_layout, None);
            device.destroy_descriptor_set_layout(self.image_set_layout, None);
            device.destroy_sampler(self.sampler, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}

/// The G-buffer pipeline: two vertex bindings (positions, normals) with dynamic strides, a
/// depth test, two color attachments, dynamic rendering (no render pass object).
fn gbuffer_pipeline(device: &ash::Device, layout: vk::PipelineLayout) -> Result<vk::Pipeline> {
    let vert = shader_module(
        device,
        &compile_glsl(
            "gbuffer.vert",
            sources::GBUFFER_VERT,
            shaderc::ShaderKind::Vertex,
        )?,
    )?;
    let frag = match compile_glsl(
        "gbuffer.frag",
        sources::GBUFFER_FRAG,
        shaderc::ShaderKind::Fragment,
    )
    .and_then(|code| shader_module(device, &code))
    {
        Ok(m) => m,
        Err(e) => {
            // SAFETY: the fragment module failed, so the vertex module is used by nothing and
            // destroyed once.
            unsafe { device.destroy_shader_module(vert, None) };
            return Err(e);
        }
    };
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vert)
            .name(c"main"),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(frag)
            .name(c"main"),
    ];
    let bindings = [0, 1, 2].map(|binding| vk::VertexInputBindingDescription {
        binding,
        stride: 24, // overridden per draw (VERTEX_INPUT_BINDING_STRIDE is dynamic)
        input_rate: vk::VertexInputRate::VERTEX,
    });
    let attributes = [0, 1, 2].map(|i| vk::VertexInputAttributeDescription {
        location: i,
        binding: i,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    });
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // No culling: the ground and the strip are seen from either side.
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::LESS);
    let blend = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA); 4];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
    let dynamic = [
        vk::DynamicState::VIEWPORT,
        vk::DynamicState::SCISSOR,
        vk::DynamicState::VERTEX_INPUT_BINDING_STRIDE,
    ];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
    let formats = [NORMAL_FORMAT, ALBEDO_FORMAT, MOTION_FORMAT, ID_FORMAT];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&formats)
        .depth_attachment_format(DEPTH_FORMAT);
    let info = [vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering)];
    // SAFETY: every state struct `info` points at is a local alive for the call, the modules hold
    // the engine's compiled GLSL, and `layout` was made for its push constants and sets.
    let pipeline =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &info, None) };
    // SAFETY: pipeline creation has returned; the modules are needed only while it runs.
    unsafe {
        device.destroy_shader_module(vert, None);
        device.destroy_shader_module(frag, None);
    }
    Ok(pipeline
        .map_err(|(_, e)| e)
        .vk("vkCreateGraphicsPipelines")?[0])
}

// ---------------------------------------------------------------------------------------
// Engine resources: buffers and images with their own memory (a real engine suballocates
// from a few large blocks; one allocation each keeps the example short).
// ---------------------------------------------------------------------------------------

fn memory_type(
    props: &vk::PhysicalDeviceMemoryProperties,
    bits: u32,
    flags: vk::MemoryPropertyFlags,
) -> Result<u32> {
    (0..props.memory_type_count)
        .find(|&i| {
            bits & (1 << i) != 0
                && props.memory_types[i as usize]
                    .property_flags
                    .contains(flags)
        })
        .ok_or_else(|| format!("no memory type with {flags:?}").into())
}

/// A buffer in host-visible, coherent memory, mapped for its whole life. The engine's vertex,
/// index, uniform and readback buffers. With `SHADER_DEVICE_ADDRESS` usage its device address
/// is what the library's position and index streams point at.
pub struct HostBuffer {
    device: ash::Device,
    pub buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    mapped: *mut u8,
    pub size: u64,
}

impl HostBuffer {
    pub fn new(host: &Host, size: u64, usage: vk::BufferUsageFlags) -> Result<Self> {
        let device = &host.device;
        let mut buffer = HostBuffer {
            device: device.clone(),
            buffer: vk::Buffer::null(),
            memory: vk::DeviceMemory::null(),
            mapped: std::ptr::null_mut(),
            size: size.max(4),
        };
        // From here on, Drop frees whatever was created.
        let info = vk::BufferCreateInfo::default()
            .size(buffer.size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `info` is a local; a host-visible buffer of the requested size and usage.
        buffer.buffer = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `buffer.buffer` was just created on this device.
        let req = unsafe { device.get_buffer_memory_requirements(buffer.buffer) };
        // SAFETY: `host.physical` is a physical device of the host's live instance.
        let props = unsafe {
            host.instance
                .get_physical_device_memory_properties(host.physical)
        };
        let index = memory_type(
            &props,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        )?;
        // Buffers reached by device address need memory allocated for it.
        let mut flags =
            vk::MemoryAllocateFlagsInfo::default().flags(vk::MemoryAllocateFlags::DEVICE_ADDRESS);
        let mut alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(index);
        if usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS) {
            alloc = alloc.push_next(&mut flags);
        }
        // SAFETY: the memory type was chosen from the buffer's requirements' type bits, of its
        // size, with the device-address flag where the usage needs it.
        buffer.memory = unsafe { device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: the memory was allocated for this buffer's requirements and is bound once, at
        // offset 0.
        unsafe { device.bind_buffer_memory(buffer.buffer, buffer.memory, 0) }
            .vk("vkBindBufferMemory")?;
        // SAFETY: the memory is host-visible (chosen so) and not mapped yet; it stays mapped until
        // it is freed.
        buffer.mapped = unsafe {
            device.map_memory(
                buffer.memory,
                0,
                vk::WHOLE_SIZE,
                vk::MemoryMapFlags::empty(),
            )
        }
        .vk("vkMapMemory")? as *mut u8;
        Ok(buffer)
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Copy>(
        host: &Host,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let mut buffer = Self::new(host, std::mem::size_of_val(data) as u64, usage)?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    /// Copies `data` to byte `offset`. Only while no pending submission reads the bytes: the
    /// engine writes a frame slot's buffers after waiting for that slot's fence. Host-coherent
    /// memory written before `vkQueueSubmit` is visible to the submitted work without a
    /// barrier (the submission is a host memory dependency).
    pub fn write<T: Copy>(&mut self, offset: u64, data: &[T]) -> Result<()> {
        let bytes = std::mem::size_of_val(data) as u64;
        if offset + bytes > self.size {
            return Err(format!("writing {bytes} bytes at {offset} into {}", self.size).into());
        }
        // SAFETY: in bounds of the mapping; T is plain data.
        unsafe {
            std::ptr::copy_nonoverlapping(
                data.as_ptr() as *const u8,
                self.mapped.add(offset as usize),
                bytes as usize,
            )
        };
        Ok(())
    }

    /// Reads `count` values from the start, after the GPU's writes were made available to
    /// the host (a barrier to HOST_READ) and the submission's fence was waited on.
    pub fn read<T: Copy + Default>(&self, count: usize) -> Result<Vec<T>> {
        let bytes = count * std::mem::size_of::<T>();
        if bytes as u64 > self.size {
            return Err(format!("reading {bytes} bytes from {}", self.size).into());
        }
        let mut out = vec![T::default(); count];
        // SAFETY: in bounds of the mapping; T is plain data.
        unsafe { std::ptr::copy_nonoverlapping(self.mapped, out.as_mut_ptr() as *mut u8, bytes) };
        Ok(out)
    }

    /// The buffer's device address (it must have SHADER_DEVICE_ADDRESS usage).
    pub fn address(&self) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.buffer);
        // SAFETY: every buffer the engine asks the address of was made with SHADER_DEVICE_ADDRESS
        // usage and device-address memory (this method's documented precondition).
        unsafe { self.device.get_buffer_device_address(&info) }
    }
}

impl Drop for HostBuffer {
    fn drop(&mut self) {
        // Null handles (a failed `new`) are ignored by the destroy calls; freeing the memory
        // unmaps it.
        // SAFETY: the engine drops its buffers after waiting for the frames that use them; freeing
        // the memory unmaps it; null handles of a failed `new` are ignored.
        unsafe {
            self.device.destroy_buffer(self.buffer, None);
            self.device.free_memory(self.memory, None);
        }
    }
}

/// A 2D image in device-local memory with one view.
pub struct Image {
    device: ash::Device,
    pub image: vk::Image,
    memory: vk::DeviceMemory,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub aspect: vk::ImageAspectFlags,
}

impl Image {
    pub fn new(
        host: &Host,
        format: vk::Format,
        size: (u32, u32),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let device = &host.device;
        let mut image = Image {
            device: device.clone(),
            image: vk::Image::null(),
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
            format,
            aspect,
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: size.0,
                height: size.1,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: Engine::new checked that the device supports the engine's attachment formats for
        // these uses (its format checks), and the storage formats are those every device with the
        // library's features writes; `info` is a local.
        image.image = unsafe { device.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: `image.image` was just created on this device.
        let req = unsafe { device.get_image_memory_requirements(image.image) };
        // SAFETY: `host.physical` is a physical device of the host's live instance.
        let props = unsafe {
            host.instance
                .get_physical_device_memory_properties(host.physical)
        };
        let index = memory_type(
            &props,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::DEVICE_LOCAL,
        )?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(index);
        // SAFETY: the memory type was chosen from the image's requirements, device-local, of its
        // size.
        image.memory = unsafe { device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: the memory was allocated for this image's requirements and is bound once, at
        // offset 0.
        unsafe { device.bind_image_memory(image.image, image.memory, 0) }
            .vk("vkBindImageMemory")?;
        let view = vk::ImageViewCreateInfo::default()
            .image(image.image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        // SAFETY: the image is bound to memory, and the view's format and aspect are the image's
        // own.
        image.view = unsafe { device.create_image_view(&view, None) }.vk("vkCreateImageView")?;
        Ok(image)
    }

    /// A synchronization2 layout transition of the whole image.
    pub fn barrier(
        &self,
        (old, src_stage, src_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
        (new, dst_stage, dst_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    ) -> vk::ImageMemoryBarrier2<'static> {
        vk::ImageMemoryBarrier2::default()
            .src_stage_mask(src_stage)
            .src_access_mask(src_access)
            .dst_stage_mask(dst_stage)
            .dst_access_mask(dst_access)
            .old_layout(old)
            .new_layout(new)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(self.image)
            .subresource_range(range(self.aspect))
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the engine drops its images after waiting for the frames that use them; the view
        // goes before its image, the image before its memory.
        unsafe {
            self.device.destroy_image_view(self.view, None);
            self.device.destroy_image(self.image, None);
            self.device.free_memory(self.memory, None);
        }
    }
}

fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

pub fn pipeline_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: &[vk::ImageMemoryBarrier2],
    memory: &[vk::MemoryBarrier2],
) {
    let dependency = vk::DependencyInfo::default()
        .image_memory_barriers(images)
        .memory_barriers(memory);
    // SAFETY: every caller passes its slot's command buffer, recording outside any rendering, and
    // barriers of its own images and buffers; `dependency` lives through the call.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// The bytes of a plain-data value (push constants, uniform buffers).
fn bytes_of<T: Copy>(value: &T) -> &[u8] {
    // SAFETY: T is plain data (repr(C) structs of f32, u32, u64 and glam vectors).
    unsafe { std::slice::from_raw_parts(value as *const T as *const u8, std::mem::size_of::<T>()) }
}

/// Attaches the Vulkan call to an error code.
trait VkCheck<T> {
    fn vk(self, call: &str) -> Result<T>;
}

impl<T> VkCheck<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &str) -> Result<T> {
        self.map_err(|e| format!("{call}: {e}").into())
    }
}
