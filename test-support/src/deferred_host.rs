//! What the deferred host engine's tests share: the library's (`tests/gpu/deferred_host.rs`)
//! and the app's (`app/tests/gpu/deferred_host.rs`, which compares the engine with the
//! standalone renderer).

use crate::host::Host;
use crate::host_memory::{HostBuffer, Memory, pipeline_barrier};
use crate::sampling::CameraRays;
use crate::test_shader::compile_compute;
use ash::vk;
use glam::DVec3;
use glam::Vec3;
use motion_shadows::technique::{CameraView, LightKind, TemporalShadowMap};
use motion_shadows_deferred_host::deferred::{Light, Mesh, MeshIndices, Settings, World};

/// The host's debugging probes (`tests/glsl/`): compute shaders a host would write, calling
/// the library's public include on a map by device address.
pub const PROBE_COMP: &str = include_str!("../../tests/glsl/host_probe.comp");
/// Eight samples of one pixel per invocation against `ms_texel_shadowed`.
pub const SAMPLES_PROBE_COMP: &str = include_str!("../../tests/glsl/host_samples_probe.comp");
/// A receiver moving between two points (two queries per invocation).
pub const MOVING_PROBE_COMP: &str = include_str!("../../tests/glsl/host_moving_probe.comp");

/// A light by its parameters, as the tests' CPU models and the app's scenes take it (the
/// engine takes the library's `Light`: `engine_light`): a spot (hard cone, 1 / d^2,
/// `intensity` in W/sr) or a directional light (`irradiance` in W/m^2; its map an
/// orthographic box around `center`). `near`, `far`: the map's depth range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HostLight {
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_half_angle_deg: f32,
        intensity: f32,
        near: f32,
        far: f32,
    },
    Directional {
        direction: Vec3,
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
    },
}

impl HostLight {
    /// The library's description of the light (what its shadow is made for).
    pub fn engine_light(&self) -> motion_shadows::Light {
        match *self {
            HostLight::Spot {
                position,
                direction,
                cone_half_angle_deg: cone,
                intensity,
                near,
                far,
            } => {
                let light = motion_shadows::Light::spot(position, direction).cone_half_angle(cone);
                light.intensity(intensity).depth_range(near, far)
            }
            HostLight::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            } => {
                let light = motion_shadows::Light::directional(direction, center, half_extent);
                light
                    .distance(distance)
                    .intensity(irradiance)
                    .depth_range(near, far)
            }
        }
    }
}

/// `World::demo()`'s lights by their parameters (the app's tests' `app_scene` checks each
/// against the light the engine drew with).
pub fn demo_lights() -> Vec<HostLight> {
    let spot = HostLight::Spot {
        position: Vec3::new(-3.0, 7.5, -3.5),
        direction: Vec3::new(3.3, -7.5, 4.0),
        cone_half_angle_deg: 38.0,
        intensity: 110.0,
        near: 1.0,
        far: 30.0,
    };
    let sun = HostLight::Directional {
        direction: Vec3::new(0.45, -1.0, 0.3),
        irradiance: 0.9,
        center: Vec3::ZERO,
        half_extent: 7.5,
        distance: 15.0,
        near: 1.0,
        far: 40.0,
    };
    vec![spot, sun]
}

pub const SIZE: (u32, u32) = (160, 120);
pub const SHADOW: (u32, u32) = (256, 256);
pub const SEED: u32 = 11;
/// The ground's albedo in the demo world (every channel): 204/255, exact in the RGBA8
/// G-buffer.
pub const GROUND_ALBEDO: f64 = 0.8;

pub fn new_host() -> Host {
    Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"))
}

/// Where a mesh of the engine's world is at a frame time, for the tests' CPU models.
pub trait MeshAtTime {
    /// World-space vertex positions at frame time `f`, as f32 (rigid transforms applied in
    /// f64 and then rounded, so a CPU model sees the same numbers whatever it does next).
    fn world_positions(&self, f: f64) -> Vec<Vec3>;
    /// The mesh as a triangle list (three world positions per triangle) at frame time `f`.
    fn world_triangles(&self, f: f64) -> Vec<Vec3>;
}

impl MeshAtTime for Mesh {
    fn world_positions(&self, f: f64) -> Vec<Vec3> {
        let m = (self.transform)(f);
        (self.vertices.iter())
            .map(|v| (m.transform_point3(Vec3::from(v.position).as_dvec3())).as_vec3())
            .collect()
    }

    fn world_triangles(&self, f: f64) -> Vec<Vec3> {
        let positions = self.world_positions(f);
        let index = |i: usize| match &self.indices {
            MeshIndices::U16(v) => u32::from(v[i]),
            MeshIndices::U32(v) => v[i],
        };
        (0..self.indices.count())
            .map(|i| positions[index(i) as usize])
            .collect()
    }
}

pub fn settings() -> Settings {
    Settings {
        width: SIZE.0,
        height: SIZE.1,
        shadow_size: SHADOW,
        keep_static_layer: false,
        receivers_move: true,
    }
}

/// The lighting pass's camera rays for the world's camera at `SIZE` (`shared.glsl`'s
/// `camera_ray`; the `CameraView` the app's renderer builds for the same camera).
pub fn camera_rays(world: &World) -> CameraRays {
    let c = &world.camera;
    let view = CameraView::perspective(
        c.eye,
        c.target,
        c.up,
        c.fov_y_deg,
        SIZE.0 as f32 / SIZE.1 as f32,
        c.near,
        c.far,
    );
    CameraRays::of(&view, SIZE)
}

/// Where the ray through image position (x, y) meets the ground plane y = 0, inside the
/// ground's square of half-width `half` (less a margin).
pub fn ground_point(rays: &CameraRays, x: f32, y: f32, half: f64) -> Option<DVec3> {
    let dir = rays.direction(x, y);
    let origin = rays.origin.as_dvec3();
    if dir.y >= 0.0 {
        return None;
    }
    let p = origin - origin.y / dir.y * dir;
    (p.x.abs() < half - 0.1 && p.z.abs() < half - 0.1).then_some(p)
}

/// Unshadowed direct radiance of a ground point (normal +y, albedo `albedo`) from `light`,
/// with the shading of the renderer and of the host's shade.comp. `None` near a decision
/// edge (grazing light, the spot's cone within `cone_margin` in cosine), where a pixel's
/// area or a float ulp decides.
pub fn ground_direct(light: &Light, p: DVec3, albedo: f64, cone_margin: f64) -> Option<f64> {
    let view = light.view(SHADOW).expect("light view");
    let (to_light, dist2, emission) = match view.kind {
        LightKind::Spot { intensity, .. } => {
            let d = view.position.as_dvec3() - p;
            (d, d.length_squared(), f64::from(intensity))
        }
        LightKind::Directional { irradiance } => {
            (-view.direction.as_dvec3(), 1.0, f64::from(irradiance))
        }
    };
    let l = to_light.normalize();
    let cos_theta = l.y;
    if cos_theta < 0.05 {
        return None;
    }
    if let LightKind::Spot { cos_cone, .. } = view.kind {
        let cos_axis = (-l).dot(view.direction.as_dvec3());
        if (cos_axis - f64::from(cos_cone)).abs() < cone_margin {
            return None;
        }
        if cos_axis < f64::from(cos_cone) {
            return Some(0.0);
        }
    }
    Some(albedo / std::f64::consts::PI * emission * cos_theta / dist2)
}

/// Per caster (every mesh but the ground, mesh 0), the screen-space box in pixels that holds
/// it during frame `frame`'s whole shutter, grown by `margin` pixels: the convex hull of its
/// vertices' projections at both ends holds every position in between (lines project to
/// lines in front of the camera).
pub fn caster_boxes(world: &World, frame: u32, margin: f32) -> Vec<[f32; 4]> {
    let view_proj = world.camera.view_proj(SIZE.0 as f32 / SIZE.1 as f32);
    let f = frame as f64;
    world.meshes[1..]
        .iter()
        .map(|m| {
            let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
            for p in m
                .world_positions(f - 1.0)
                .into_iter()
                .chain(m.world_positions(f))
            {
                let clip = view_proj * p.extend(1.0);
                assert!(clip.w > 0.0, "a caster behind the camera");
                let x = (clip.x / clip.w * 0.5 + 0.5) * SIZE.0 as f32;
                let y = (clip.y / clip.w * 0.5 + 0.5) * SIZE.1 as f32;
                b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            }
            [b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin]
        })
        .collect()
}

pub fn in_any_box(boxes: &[[f32; 4]], x: u32, y: u32) -> bool {
    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
    boxes
        .iter()
        .any(|b| cx >= b[0] && cx <= b[2] && cy >= b[1] && cy <= b[3])
}

/// Whether a mask changes by more than `step` to one of the pixel's 8 neighbours: a shadow
/// edge (or a shadow-map texel step) crosses the pixel, where a pixel-area average and a
/// pixel-centre value differ by a share of the step.
pub fn near_mask_edge(mask: &[f32], x: u32, y: u32, step: f32) -> bool {
    let centre = mask[(y * SIZE.0 + x) as usize];
    (-1i32..=1).any(|dy| {
        (-1i32..=1).any(|dx| {
            let (nx, ny) = (x as i32 + dx, y as i32 + dy);
            if nx < 0 || ny < 0 || nx >= SIZE.0 as i32 || ny >= SIZE.1 as i32 {
                return true;
            }
            (mask[(ny as u32 * SIZE.0 + nx as u32) as usize] - centre).abs() > step
        })
    })
}

/// A query of the host's probe shader (`Query` in tests/glsl/host_probe.comp).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Query {
    pub position: [f32; 3],
    pub time: f32,
    pub normal: [f32; 3],
    pub own: u32,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ProbePush {
    pub map: u64,
    pub queries: u64,
    pub results: u64,
    pub count: u32,
    pub reserved: u32,
}

/// Lit-fraction queries (time -1, own id none, normal up) at the centres of the shadow-map
/// texels of the row through ground depth `z`, on the ground, for the probe shader.
pub fn lit_fraction_queries_along_texel_row(world: &World, z: f64) -> Vec<Query> {
    let light = world.lights[0].view(SHADOW).expect("light view");
    let view_proj = (light.proj * light.view).as_dmat4();
    let to_world = view_proj.inverse();
    let row = {
        let ndc = view_proj * DVec3::new(0.0, 0.0, z).extend(1.0);
        ((ndc.y / ndc.w * 0.5 + 0.5) * f64::from(SHADOW.1)).floor()
    };
    (0..SHADOW.0)
        .map(|column| {
            let ndc_x = (f64::from(column) + 0.5) / f64::from(SHADOW.0) * 2.0 - 1.0;
            let ndc_y = (row + 0.5) / f64::from(SHADOW.1) * 2.0 - 1.0;
            let p = to_world * glam::DVec4::new(ndc_x, ndc_y, 0.5, 1.0);
            Query {
                position: [(p.x / p.w) as f32, 0.0, (p.z / p.w) as f32],
                time: -1.0,
                normal: [0.0, 1.0, 0.0],
                own: u32::MAX,
            }
        })
        .collect()
}

/// Runs the host's probe shader (its own GLSL, including the library's header) on `queries`
/// against `map`, in the host's own command buffer.
pub fn probe(host: &Host, map: &TemporalShadowMap, queries: &[Query]) -> Vec<f32> {
    run_probe(
        host,
        map,
        queries,
        PROBE_COMP,
        Shape {
            per_invocation: 1,
            workgroup: 64,
            results_per_query: 1,
        },
    )
}

/// How a probe shader takes its queries: `per_invocation` queries each (its push
/// constants' `count` is the number of invocations), `workgroup` invocations per group, and
/// writes `results_per_query` floats per query.
pub struct Shape {
    pub per_invocation: usize,
    pub workgroup: u32,
    pub results_per_query: usize,
}

/// Runs the probe shader `source` on `queries` against `map` in the host's command buffer.
pub fn run_probe(
    host: &Host,
    map: &TemporalShadowMap,
    queries: &[Query],
    source: &str,
    shape: Shape,
) -> Vec<f32> {
    let device = &host.device;
    let push = [vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::COMPUTE,
        offset: 0,
        size: std::mem::size_of::<ProbePush>() as u32,
    }];
    // SAFETY: `push` is a local alive for the call and the host's device is live; one compute push
    // range, within any device's 128-byte minimum.
    let layout = unsafe {
        device.create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push),
            None,
        )
    }
    .expect("probe layout");
    let spirv = compile_compute("probe", source);
    let code = ash::util::read_spv(&mut std::io::Cursor::new(&spirv)).expect("SPIR-V words");
    let info = vk::ShaderModuleCreateInfo::default().code(&code);
    // SAFETY: `code` is SPIR-V words that shaderc compiled from the probe's GLSL.
    let module = unsafe { device.create_shader_module(&info, None) }.expect("probe module");
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    // SAFETY: the module holds the probe's SPIR-V, whose push constants `layout` was made for;
    // the module goes once the pipeline is made.
    let pipeline = unsafe {
        let pipeline = device.create_compute_pipelines(vk::PipelineCache::null(), &info, None);
        device.destroy_shader_module(module, None);
        pipeline.expect("probe pipeline")[0]
    };
    // The allocator goes with the buffers' last handle on it.
    let memory = Memory::new(host).expect("allocator");
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
    let bytes = std::mem::size_of_val(queries) as u64;
    let mut query_buffer = HostBuffer::new(&memory, bytes, usage).expect("query buffer");
    query_buffer.write(queries).expect("queries");
    let result_count = shape.results_per_query * queries.len();
    let mut results = HostBuffer::new(&memory, 4 * result_count as u64, usage).expect("results");
    let invocations = queries.len().div_ceil(shape.per_invocation);
    let constants = ProbePush {
        map: map.header_address(),
        queries: query_buffer.address(),
        results: results.address(),
        count: invocations as u32,
        reserved: 0,
    };
    // SAFETY: `cmd` is the host's command buffer, recording (record_and_wait began it) outside
    // rendering on its graphics and compute queue; `pipeline` uses `layout`, whose push range is
    // ProbePush's size, and `bytes` views exactly that local struct; the shader returns past
    // `count` invocations and writes results_per_query floats per query, the results' size, and
    // every buffer outlives the wait.
    host.record_and_wait(|cmd| unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
        let bytes = bytemuck::bytes_of(&constants);
        device.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, bytes);
        device.cmd_dispatch(cmd, (invocations as u32).div_ceil(shape.workgroup), 1, 1);
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        pipeline_barrier(device, cmd, &[], &to_host);
    })
    .expect("probe submission");
    let out = results.read::<f32>(result_count).expect("results");
    // SAFETY: record_and_wait waited for the host's fence, so the probe's pipeline and layout are
    // in no pending work; each is destroyed once.
    unsafe {
        device.destroy_pipeline(pipeline, None);
        device.destroy_pipeline_layout(layout, None);
    }
    out
}

/// The ground grid's triangle (index within the mesh) under world point (x, z), `None` within
/// `margin` of a diagonal (cell edges are shared by coplanar triangles of one surface, where
/// either id gives the same answer). Mirrors `deferred::ground_grid(6, 4)`.
pub fn ground_triangle(p: DVec3, margin: f64) -> Option<u32> {
    let (half, cells) = (6.0, 4u32);
    let step = 2.0 * half / cells as f64;
    let col = ((p.x + half) / step).floor() as u32;
    let row = ((p.z + half) / step).floor() as u32;
    let (u, w) = (
        p.x + half - col as f64 * step,
        p.z + half - row as f64 * step,
    );
    if (u - w).abs() < margin || col >= cells || row >= cells {
        return None;
    }
    // (a, b, c) holds the part with w > u, (a, c, d) the rest.
    Some(2 * (row * cells + col) + u32::from(w < u))
}
