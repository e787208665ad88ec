//! The deferred host engine (`tests/support/deferred.rs`, the engine of
//! `examples/deferred_host.rs`): its own device, buffers, G-buffer, two frames in flight and
//! two lights, with the library's shadow and mask passes recorded into its command buffers.
//! Checked against the library's standalone renderer (the app, used here as a reference
//! only), against the lighting pass's own per-sample decisions, and against a closed form.

use crate::support::gpu::{assert_no_validation_messages, context, render};
use crate::support::host::{self, Host};
use crate::support::sampling::{CameraRays, hits, pixel_key, pixel_sample};
use ash::vk;
use deferred::{
    Camera, Engine, FrameOutput, HostBuffer, Light, Mesh, MeshIndices, Motion, Settings,
    ShadowLookup, Vertex, World,
};
use glam::{DMat4, DVec3, Vec3};
use motion_shadows::technique::{LightingView, TemporalShadowMap};
use motion_shadows_app::render::upload::camera_view;
use motion_shadows_app::render::{Method, ReceiverTest, RenderSettings};
use motion_shadows_app::scene as app;

// `deferred` finds the host's device type as `super::host`.
#[allow(dead_code)]
#[path = "../support/deferred.rs"]
mod deferred;

#[path = "deferred_moving.rs"]
mod moving;

#[path = "deferred_host_truth.rs"]
mod truth;

const SIZE: (u32, u32) = (160, 120);
const SHADOW: (u32, u32) = (256, 256);
const SEED: u32 = 11;
/// The ground's albedo in the demo world (every channel): 204/255, exact in the RGBA8
/// G-buffer.
const GROUND_ALBEDO: f64 = 0.8;

fn new_host() -> Host {
    Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"))
}

fn settings(initial_capacity: (u32, u32)) -> Settings {
    Settings {
        width: SIZE.0,
        height: SIZE.1,
        shadow_size: SHADOW,
        initial_capacity,
        lookup: ShadowLookup::MaskImages,
        keep_static_layer: false,
    }
}

/// Frame `frame` of the host's world as the app's scene lit by light `light` alone: every
/// mesh de-indexed, its positions at the shutter's ends (frames f - 1 and f) in world space.
fn app_scene(world: &World, frame: u32, light: usize) -> app::Scene {
    let f = frame as f64;
    let c = &world.camera;
    app::Scene {
        name: format!("deferred-host-frame-{frame}-light-{light}"),
        camera: app::Camera {
            position: c.eye,
            target: c.target,
            up: c.up,
            fov_y_deg: c.fov_y_deg,
            near: c.near,
            far: c.far,
        },
        light: match world.lights[light] {
            Light::Spot {
                position,
                direction,
                cone_half_angle_deg,
                intensity,
                near,
                far,
            } => app::Light::Spot(app::SpotLight {
                position,
                direction,
                cone_angle_deg: cone_half_angle_deg,
                intensity,
                near,
                far,
            }),
            Light::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            } => app::Light::Directional(app::DirectionalLight {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            }),
        },
        ambient: world.ambient,
        meshes: world
            .meshes
            .iter()
            .map(|m| app::Mesh {
                name: m.name.clone(),
                albedo: m.albedo,
                closed: m.closed,
                t0: m.world_triangles(f - 1.0),
                t1: m.world_triangles(f),
            })
            .collect(),
    }
}

/// The renderer's camera rays for `scene` (`shared.glsl`'s `camera_ray`).
fn camera_rays(scene: &app::Scene) -> CameraRays {
    CameraRays::of(&camera_view(scene, SIZE), SIZE)
}

/// Where the ray through image position (x, y) meets the ground plane y = 0, inside the
/// ground's square of half-width `half` (less a margin).
fn ground_point(rays: &CameraRays, x: f32, y: f32, half: f64) -> Option<DVec3> {
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
fn ground_direct(light: &Light, p: DVec3, albedo: f64, cone_margin: f64) -> Option<f64> {
    let view = light.view(SHADOW);
    let (to_light, dist2, emission) = match *light {
        Light::Spot { intensity, .. } => {
            let d = view.position.as_dvec3() - p;
            (d, d.length_squared(), f64::from(intensity))
        }
        Light::Directional { irradiance, .. } => {
            (-view.direction.as_dvec3(), 1.0, f64::from(irradiance))
        }
    };
    let l = to_light.normalize();
    let cos_theta = l.y;
    if cos_theta < 0.05 {
        return None;
    }
    if let motion_shadows::technique::LightKind::Spot { cos_cone, .. } = view.kind {
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
fn caster_boxes(world: &World, frame: u32, margin: f32) -> Vec<[f32; 4]> {
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

fn in_any_box(boxes: &[[f32; 4]], x: u32, y: u32) -> bool {
    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
    boxes
        .iter()
        .any(|b| cx >= b[0] && cx <= b[2] && cy >= b[1] && cy <= b[3])
}

/// Whether a mask changes by more than `step` to one of the pixel's 8 neighbours: a shadow
/// edge (or a shadow-map texel step) crosses the pixel, where a pixel-area average and a
/// pixel-centre value differ by a share of the step.
fn near_mask_edge(mask: &[f32], x: u32, y: u32, step: f32) -> bool {
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

/// Mean, standard deviation, RMSE and largest magnitude of differences.
fn stats(diffs: &[f64]) -> (f64, f64, f64, f64) {
    let n = diffs.len().max(1) as f64;
    let mean = diffs.iter().sum::<f64>() / n;
    let var = diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    let rmse = (diffs.iter().map(|d| d * d).sum::<f64>() / n).sqrt();
    let max = diffs.iter().map(|d| d.abs()).fold(0.0, f64::max);
    (mean, var.sqrt(), rmse, max)
}

/// Prints and checks the differences (renderer minus host, in visibility units, each with
/// whether the host's value is partial) over all compared pixels and over the partly lit
/// ones alone: the mean within 4 standard errors of 0 plus 0.004, the RMSE below 0.0625 (see
/// the test's documentation).
fn check_agreement(what: &str, diffs: &[(f64, bool)], min_partial: usize) {
    let all: Vec<f64> = diffs.iter().map(|d| d.0).collect();
    let partial: Vec<f64> = diffs.iter().filter(|d| d.1).map(|d| d.0).collect();
    eprintln!("{what}:");
    for (name, set) in [("all", &all), ("partly lit", &partial)] {
        let (mean, std, rmse, max) = stats(set);
        let standard_error = std / (set.len().max(1) as f64).sqrt();
        eprintln!(
            "  {name:>10}: {:5} pixels, mean {mean:+.5} (standard error {standard_error:.5}), \
             std {std:.4}, RMSE {rmse:.4}, max {max:.3}",
            set.len()
        );
        assert!(
            mean.abs() <= 4.0 * standard_error + 0.004,
            "{what}, {name}: the mean difference {mean} is biased"
        );
        assert!(rmse < 0.0625, "{what}, {name}: RMSE {rmse}");
    }
    assert!(
        all.len() > 2000,
        "{what}: only {} pixels compared",
        all.len()
    );
    assert!(
        partial.len() >= min_partial,
        "{what}: only {} partly lit pixels compared",
        partial.len()
    );
}

/// The host's visibility mask of light `light` against the renderer's image of the same
/// frame lit by that light alone, on ground pixels that no caster touches during the shutter,
/// away from the spot's cone edge and from shadow edges. Returns the differences (renderer
/// minus host, in visibility units: radiance less ambient, over the unshadowed direct
/// radiance at the pixel centre), each with whether the host's value is partial.
fn compare_light(
    world: &World,
    host_frame: &FrameOutput,
    light: usize,
    renderer_rgb: &[f32],
) -> Vec<(f64, bool)> {
    let scene = app_scene(world, host_frame.frame, light);
    let rays = camera_rays(&scene);
    let boxes = caster_boxes(world, host_frame.frame, 2.0);
    let mask = &host_frame.masks[light];
    let ambient = f64::from(world.ambient) * GROUND_ALBEDO;
    let mut diffs = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if in_any_box(&boxes, x, y) || near_mask_edge(mask, x, y, 0.2) {
                continue;
            }
            let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                continue;
            };
            let Some(direct) = ground_direct(&world.lights[light], p, GROUND_ALBEDO, 0.01) else {
                continue;
            };
            if direct < 0.02 {
                continue; // outside the cone: no visibility to compare
            }
            let i = (y * SIZE.0 + x) as usize;
            let v_renderer = (f64::from(renderer_rgb[3 * i]) - ambient) / direct;
            let v_host = f64::from(mask[i]);
            diffs.push((v_renderer - v_host, v_host > 1e-3 && v_host < 1.0 - 1e-3));
        }
    }
    diffs
}

/// The host's image equals the standalone renderer's on static receivers, per light and for
/// both lights together, for the frames of both frame-in-flight slots.
///
/// Tolerances. The renderer averages visibility over the pixel's area and over 64 stratified
/// sample times; the host's mask is the exact lit fraction (no time noise) at the pixel
/// centre. On pixels away from shadow edges their expectations agree up to second-order
/// terms, so:
/// - the mean difference (renderer minus host) must be within 4 standard errors of 0, plus
///   0.004 for the residual bias of pixel-area against pixel-centre values on piecewise
///   linear penumbra profiles and shadow-map texel steps (up to 0.2 between neighbours, the
///   edge filter's threshold) that the two sample differently;
/// - the RMSE must stay below 0.0625 = 0.5 / sqrt(64): the standard deviation of a 64-sample
///   Bernoulli estimate at visibility 1/2, the worst case before stratification (which only
///   lowers it).
///
/// Both hold over all compared pixels and over the partly lit ones alone. The brute-force
/// reference (256 time slices, ordinary shadow maps) is held to the same bounds for one
/// frame.
#[test]
fn host_image_equals_the_standalone_renderer_on_static_receivers() {
    let host = new_host();
    let world = World::demo();
    // Small starting capacities: the first frame of each slot overflows, its maps grow, and
    // the kept frame is rendered again.
    let frames = {
        let mut engine = Engine::new(&host, &world, settings((4096, 4096))).expect("engine");
        let frames = engine.render(&world, 0..4, &|_| true).expect("frames");
        assert_eq!(
            engine.context().validation_messages(),
            Vec::<String>::new(),
            "a from_raw context has no messenger of its own"
        );
        frames
    };
    assert_eq!(
        frames.iter().map(|f| (f.frame, f.slot)).collect::<Vec<_>>(),
        [(0, 0), (1, 1), (2, 0), (3, 1)]
    );
    // Each slot's maps grow once, with headroom for the next frames.
    assert_eq!(
        frames.iter().map(|f| f.attempts).collect::<Vec<_>>(),
        [2, 2, 1, 1],
        "4096-entry maps overflow in the first frame of each slot, and only there"
    );
    for frame in &frames {
        eprintln!(
            "frame {} (slot {}): {} submission(s); N_f / N_r per light: {:?}",
            frame.frame,
            frame.slot,
            frame.attempts,
            frame
                .counters
                .iter()
                .map(|c| (c.node_count, c.range_count))
                .collect::<Vec<_>>()
        );
        for c in &frame.counters {
            // The maps collect ranges directly (the exact construction with the static
            // layer): no node is stored, so the node count is no capacity's concern.
            assert_eq!(c.ranges_direct, 1);
            assert!(c.range_count <= c.range_capacity);
            assert!(c.node_count > 0 && c.range_count > 0);
        }
    }

    let ctx = context();
    let ambient = world.ambient * GROUND_ALBEDO as f32;
    for frame in &frames[2..] {
        let mut per_light = Vec::new();
        for light in 0..world.lights.len() {
            let scene = app_scene(&world, frame.frame, light);
            let settings = RenderSettings {
                width: SIZE.0,
                height: SIZE.1,
                spp: 64,
                seed: SEED,
                shadow_size: Some(SHADOW),
                method: Method::Temporal,
                // The host's lights keep the library's default receiver test (the normal offset).
                receiver: ReceiverTest::Offset,
                ..RenderSettings::default()
            };
            let result = render(&ctx, &scene, &settings);
            let diffs = compare_light(&world, frame, light, &result.image.rgb);
            let what = format!(
                "frame {} (slot {}), light {light}, temporal 64 spp",
                frame.frame, frame.slot
            );
            check_agreement(&what, &diffs, 150);
            per_light.push(result.image.rgb);
        }

        // Both lights together: the host's radiance against the sum of the renderer's
        // single-light images (each of which carries the ambient term once).
        let scene = app_scene(&world, frame.frame, 0);
        let rays = camera_rays(&scene);
        let boxes = caster_boxes(&world, frame.frame, 2.0);
        let mut diffs = Vec::new();
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                if in_any_box(&boxes, x, y)
                    || frame.masks.iter().any(|m| near_mask_edge(m, x, y, 0.2))
                {
                    continue;
                }
                let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                    continue;
                };
                let direct: Option<Vec<f64>> = world
                    .lights
                    .iter()
                    .map(|l| ground_direct(l, p, GROUND_ALBEDO, 0.01))
                    .collect();
                let Some(direct) = direct else { continue };
                let i = (y * SIZE.0 + x) as usize;
                let expected = per_light[0][3 * i] + per_light[1][3 * i] - ambient;
                let got = frame.radiance[i][0];
                let partial = frame.masks.iter().any(|m| m[i] > 1e-3 && m[i] < 1.0 - 1e-3);
                diffs.push((
                    f64::from(expected - got) / direct.iter().sum::<f64>(),
                    partial,
                ));
            }
        }
        let what = format!(
            "frame {} (slot {}), both lights (relative to the summed direct radiance)",
            frame.frame, frame.slot
        );
        check_agreement(&what, &diffs, 150);
        if let Ok(dir) = std::env::var("MOTION_SHADOWS_TEST_IMAGES") {
            write_side_by_side(std::path::Path::new(&dir), frame, &per_light, ambient);
        }
    }

    // The brute-force reference, for the last frame's spot light.
    let frame = &frames[3];
    let scene = app_scene(&world, frame.frame, 0);
    let settings = RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        spp: 1,
        seed: SEED,
        shadow_size: Some(SHADOW),
        method: Method::Reference { slices: 256 },
        // The host's lights keep the library's default receiver test (the normal offset).
        receiver: ReceiverTest::Offset,
        ..RenderSettings::default()
    };
    let start = std::time::Instant::now();
    let reference = render(&ctx, &scene, &settings);
    let what = format!(
        "frame 3, light 0, reference 256 slices ({:.1} s)",
        start.elapsed().as_secs_f64()
    );
    check_agreement(
        &what,
        &compare_light(&world, frame, 0, &reference.image.rgb),
        150,
    );

    assert_no_validation_messages(&ctx);
    host.assert_clean_teardown();
}

/// A query of the host's probe shader (`Query` in tests/glsl/probe.comp).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
struct Query {
    position: [f32; 3],
    time: f32,
    normal: [f32; 3],
    own: u32,
}

#[repr(C)]
#[derive(Debug, Clone, Copy)]
struct ProbePush {
    map: u64,
    queries: u64,
    results: u64,
    count: u32,
    reserved: u32,
}

/// Lit-fraction queries (time -1, own id none, normal up) at the centres of the shadow-map
/// texels of the row through ground depth `z`, on the ground, for the probe shader.
fn lit_fraction_queries_along_texel_row(world: &World, z: f64) -> Vec<Query> {
    let light = world.lights[0].view(SHADOW);
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
fn probe(host: &Host, map: &TemporalShadowMap, queries: &[Query]) -> Vec<f32> {
    run_probe(
        host,
        map,
        queries,
        deferred::sources::PROBE_COMP,
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
struct Shape {
    per_invocation: usize,
    workgroup: u32,
    results_per_query: usize,
}

/// Runs the probe shader `source` on `queries` against `map` in the host's command buffer.
fn run_probe(
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
    let layout = unsafe {
        device.create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push),
            None,
        )
    }
    .expect("probe layout");
    let pipeline = deferred::compute_pipeline(device, "probe", source, layout).expect("probe");
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
    let query_buffer = HostBuffer::with_data(host, queries, usage).expect("queries");
    let result_count = shape.results_per_query * queries.len();
    let results = HostBuffer::new(host, 4 * result_count as u64, usage).expect("results");
    let invocations = queries.len().div_ceil(shape.per_invocation);
    let constants = ProbePush {
        map: map.header_address(),
        queries: query_buffer.address(),
        results: results.address(),
        count: invocations as u32,
        reserved: 0,
    };
    host.record_and_wait(|cmd| unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
        let bytes = std::slice::from_raw_parts(
            &constants as *const ProbePush as *const u8,
            std::mem::size_of::<ProbePush>(),
        );
        device.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, bytes);
        device.cmd_dispatch(cmd, (invocations as u32).div_ceil(shape.workgroup), 1, 1);
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        deferred::pipeline_barrier(device, cmd, &[], &to_host);
    })
    .expect("probe submission");
    let out = results.read::<f32>(result_count).expect("results");
    unsafe {
        device.destroy_pipeline(pipeline, None);
        device.destroy_pipeline_layout(layout, None);
    }
    out
}

/// The ground grid's triangle (index within the mesh) under world point (x, z), `None` within
/// `margin` of a diagonal (cell edges are shared by coplanar triangles of one surface, where
/// either id gives the same answer). Mirrors `deferred::ground_grid(6, 4)`.
fn ground_triangle(p: DVec3, margin: f64) -> Option<u32> {
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

/// The GLSL include in a shader that is not the library's: the host's probe shader calls
/// `ms_visibility` at the points and times of the renderer's 1-spp samples on the ground, with
/// the ground triangle's id as its own, against the host's map of the same frame. Where the
/// renderer's lighting pass (which calls the same function) found the sample lit (radiance
/// above the ambient term by half the direct radiance), the probe must say 1, else 0.
///
/// The two hit points differ by float rounding (the GPU intersects in f32, this test in f64),
/// and the maps by the transforms (applied by the GPU in f32 here, on the CPU in f64 for the
/// renderer's scene): a sample within that distance of a shadow boundary can go either way.
/// Such samples are few: at most 0.5% may disagree.
#[test]
fn glsl_include_in_a_host_shader_agrees_with_the_library_lighting_pass() {
    let host = new_host();
    let world = World::demo();
    let mut engine = Engine::new(&host, &world, settings((600_000, 300_000))).expect("engine");
    let frames = engine.render(&world, 0..4, &|f| f == 3).expect("frames");
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].attempts, 1, "the capacities are generous");
    let slot = frames[0].slot;
    let ground_first_id = engine.first_triangle_id(0);

    let ctx = context();
    let ambient = f64::from(world.ambient) * GROUND_ALBEDO;
    for light in 0..world.lights.len() {
        let scene = app_scene(&world, 3, light);
        let settings = RenderSettings {
            width: SIZE.0,
            height: SIZE.1,
            spp: 1,
            seed: SEED,
            shadow_size: Some(SHADOW),
            method: Method::Temporal,
            // The host's lights keep the library's default receiver test (the normal offset).
            receiver: ReceiverTest::Offset,
            ..RenderSettings::default()
        };
        let result = render(&ctx, &scene, &settings);
        let rays = camera_rays(&scene);
        let casters: Vec<(Vec<Vec3>, Vec<Vec3>)> = scene.meshes[1..]
            .iter()
            .map(|m| (m.t0.clone(), m.t1.clone()))
            .collect();
        let ground = &scene.meshes[0];
        let (mut queries, mut expected, mut directs) = (Vec::new(), Vec::new(), Vec::new());
        let mut skipped = 0;
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let (t, offset) = pixel_sample(pixel_key(x, y, SEED), 0, 1);
                let (px, py) = (x as f32 + offset[0], y as f32 + offset[1]);
                let dir = rays.direction(px, py);
                let at = |(t0, t1): &(Vec<Vec3>, Vec<Vec3>), i: usize| -> [DVec3; 3] {
                    [0, 1, 2].map(|k| t0[3 * i + k].lerp(t1[3 * i + k], t).as_dvec3())
                };
                // The sample must see the ground: no caster in front at its time, and a clear
                // hit of one ground triangle.
                let caster_answers: Vec<Option<bool>> = casters
                    .iter()
                    .flat_map(|c| (0..c.0.len() / 3).map(move |i| (c, i)))
                    .map(|(c, i)| hits(&rays, dir, at(c, i), 1e-4))
                    .collect();
                if caster_answers.contains(&Some(true)) {
                    continue;
                }
                let Some(p) = ground_point(&rays, px, py, 6.0) else {
                    continue;
                };
                let Some(tri) = ground_triangle(p, 1e-3) else {
                    skipped += 1;
                    continue;
                };
                let ground_tri = [0, 1, 2].map(|k| ground.t0[3 * tri as usize + k].as_dvec3());
                if caster_answers.contains(&None)
                    || hits(&rays, dir, ground_tri, 1e-4) != Some(true)
                {
                    skipped += 1;
                    continue;
                }
                let Some(direct) = ground_direct(&world.lights[light], p, GROUND_ALBEDO, 0.005)
                else {
                    skipped += 1;
                    continue;
                };
                if direct < 0.02 {
                    continue; // outside the cone: ambient either way
                }
                let radiance = f64::from(result.image.rgb[3 * (y * SIZE.0 + x) as usize]);
                queries.push(Query {
                    position: p.as_vec3().to_array(),
                    time: t,
                    normal: [0.0, 1.0, 0.0],
                    own: ground_first_id + tri,
                });
                expected.push(radiance - ambient > 0.5 * direct);
                directs.push(direct);
            }
        }
        let visibility = probe(&host, engine.shadow_map(slot, light), &queries);
        let disagree: Vec<usize> = (0..queries.len())
            .filter(|&i| (visibility[i] > 0.5) != expected[i])
            .collect();
        let unlit = expected.iter().filter(|&&lit| !lit).count();
        eprintln!(
            "light {light}: {} ground samples, {unlit} in shadow, {} disagree ({:.3}%), {skipped} \
             too close to an edge to call",
            queries.len(),
            disagree.len(),
            100.0 * disagree.len() as f64 / queries.len().max(1) as f64
        );
        for &i in disagree.iter().take(5) {
            eprintln!(
                "  {:?}: probe {}, renderer lit {}",
                queries[i], visibility[i], expected[i]
            );
        }
        assert!(
            visibility.iter().all(|&v| v == 0.0 || v == 1.0),
            "ms_visibility is 0 or 1"
        );
        assert!(queries.len() > 5000, "only {} samples", queries.len());
        assert!(unlit > 300, "only {unlit} samples in shadow");
        assert!(
            disagree.len() * 200 <= queries.len(),
            "{} of {} samples disagree",
            disagree.len(),
            queries.len()
        );
    }
    drop(engine);
    assert_no_validation_messages(&ctx);
    host.assert_clean_teardown();
}

/// A square of side `SIDE` at height 1 translating by `TRAVEL` in +x over the shutter, under
/// a directional light straight down: a ground point (x, z) with z under the square is in
/// shadow while a + TRAVEL t <= x <= a + SIDE + TRAVEL t, so its lit fraction is 1 minus the
/// length of [(x - a - SIDE) / TRAVEL, (x - a) / TRAVEL] within [0, 1].
fn square_world() -> (World, f64, f64) {
    const START: f64 = -4.0;
    const Z0: f32 = -1.0;
    let square = [[0.0, 0.0], [0.0, SIDE], [SIDE, SIDE], [SIDE, 0.0]].map(|[x, z]| Vertex {
        position: [x, 0.0, z],
        normal: [0.0, 1.0, 0.0],
    });
    let world = World {
        camera: Camera {
            eye: Vec3::new(0.0, 9.0, 7.0),
            target: Vec3::new(-1.0, 0.0, 0.0),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 50.0,
        },
        lights: vec![Light::Directional {
            direction: Vec3::NEG_Y,
            irradiance: 2.0,
            center: Vec3::ZERO,
            half_extent: 6.0,
            distance: 10.0,
            near: 0.5,
            far: 20.0,
        }],
        ambient: 0.05,
        meshes: vec![
            deferred::ground_mesh(),
            Mesh {
                name: "square".into(),
                vertices: square.to_vec(),
                indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
                albedo: Vec3::splat(0.5),
                closed: false,
                motion: Motion::Rigid(Box::new(|f| {
                    DMat4::from_translation(DVec3::new(
                        START + f64::from(TRAVEL) * f,
                        1.0,
                        f64::from(Z0),
                    ))
                })),
            },
        ],
    };
    (world, START, f64::from(Z0))
}

const SIDE: f32 = 2.0;
const TRAVEL: f32 = 4.0;

/// `ms_lit_fraction` (through the mask pass, and through the host's own shader) against the
/// closed form of `square_world`, at the centres of ground pixels that the square does not
/// cover at t = 1 and that lie more than 1.5 shadow texels from the shadow's sides (z edges).
///
/// Tolerance: 2e-3 (the prism's rasterization snaps vertices to 1/256 texel, plus f32
/// rounding), plus what a shadow-map texel of motion implies: the map holds the interval
/// during which the square covers the texel's centre, which lies up to half a texel from the
/// point along the motion, so both ends of the interval move by up to 0.5 texel / TRAVEL;
/// its length changes only where one end is clipped to the shutter, by at most that much.
#[test]
fn lit_fraction_matches_the_closed_form_for_a_translating_square() {
    let host = new_host();
    let (world, start, z0) = square_world();
    let mut engine = Engine::new(&host, &world, settings((300_000, 200_000))).expect("engine");
    let frame = engine
        .render(&world, 0..2, &|f| f == 1)
        .expect("frames")
        .pop()
        .expect("frame 1 kept");
    let texel = 2.0 * 6.0 / f64::from(SHADOW.1);
    let tolerance = 2e-3 + 0.5 * texel / f64::from(TRAVEL);
    let (side, travel) = (f64::from(SIDE), f64::from(TRAVEL));
    let closed_form = |p: DVec3| -> f64 {
        if p.z < z0 || p.z > z0 + side {
            return 1.0;
        }
        let enter = ((p.x - start - side) / travel).clamp(0.0, 1.0);
        let leave = ((p.x - start) / travel).clamp(0.0, 1.0);
        1.0 - (leave - enter).max(0.0)
    };

    // Frame 1's shutter: the square from x = start to start + travel. Pixels showing the
    // square itself at t = 1 (the G-buffer's time) are not ground.
    let scene = app_scene(&world, 1, 0);
    let rays = camera_rays(&scene);
    let covered = caster_boxes(&world, 1, 2.0);
    let covered_at_1 = {
        let view_proj = world.camera.view_proj(SIZE.0 as f32 / SIZE.1 as f32);
        let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
        for p in world.meshes[1].world_positions(1.0) {
            let clip = view_proj * p.extend(1.0);
            let x = (clip.x / clip.w * 0.5 + 0.5) * SIZE.0 as f32;
            let y = (clip.y / clip.w * 0.5 + 0.5) * SIZE.1 as f32;
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
        [b[0] - 2.0, b[1] - 2.0, b[2] + 2.0, b[3] + 2.0]
    };
    let (mut compared, mut partial, mut worst) = (0, 0, 0.0f64);
    let mut points = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if in_any_box(&[covered_at_1], x, y) {
                continue;
            }
            let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                continue;
            };
            if (p.z - z0).abs() < 1.5 * texel || (p.z - z0 - side).abs() < 1.5 * texel {
                continue;
            }
            let expected = closed_form(p);
            let got = f64::from(frame.masks[0][(y * SIZE.0 + x) as usize]);
            let error = (got - expected).abs();
            assert!(
                error <= tolerance,
                "pixel ({x},{y}) at ({:.3}, {:.3}): mask {got}, closed form {expected} \
                 (tolerance {tolerance:.4})",
                p.x,
                p.z
            );
            compared += 1;
            partial += usize::from(expected > 0.0 && expected < 1.0);
            worst = worst.max(error);
            points.push((x, y, p, expected));
        }
    }
    eprintln!(
        "mask vs closed form: {compared} ground pixels ({partial} partly lit, {} under the \
         square's path), max error {worst:.5}, tolerance {tolerance:.5}",
        points
            .iter()
            .filter(|(x, y, ..)| in_any_box(&covered, *x, *y))
            .count()
    );
    assert!(
        compared > 5000 && partial > 500,
        "{compared} pixels, {partial} partial"
    );

    // The host's own shader calling ms_lit_fraction gives the masks' values (the R16 masks
    // round to 1/65535).
    // Irradiance 2 straight down on the ground: cos(theta) = 1 everywhere.
    let direct = |_: DVec3| GROUND_ALBEDO / std::f64::consts::PI * 2.0;
    let ambient = 0.05 * GROUND_ALBEDO;
    engine.set_lookup(ShadowLookup::LitFractionInShader);
    let in_shader = engine
        .render(&world, 1..2, &|_| true)
        .expect("frame")
        .pop()
        .expect("kept");
    let mut worst_shader = 0.0f64;
    for &(x, y, p, _) in &points {
        let i = (y * SIZE.0 + x) as usize;
        let lit = (f64::from(in_shader.radiance[i][0]) - ambient) / direct(p);
        worst_shader = worst_shader.max((lit - f64::from(frame.masks[0][i])).abs());
    }
    eprintln!(
        "ms_lit_fraction in the host's shader vs the mask: max difference {worst_shader:.2e}"
    );
    assert!(worst_shader < 1e-4);

    // And ms_visibility at one instant, t = 0.5: in shadow exactly under the square then (away
    // from its edges by 1.5 texels).
    engine.set_lookup(ShadowLookup::VisibilityAt(0.5));
    let instant = engine
        .render(&world, 1..2, &|_| true)
        .expect("frame")
        .pop()
        .expect("kept");
    let x_at = start + 0.5 * travel;
    let mut checked = 0;
    for &(x, y, p, _) in &points {
        let dx = (p.x - x_at).min(x_at + side - p.x);
        if dx.abs() < 1.5 * texel {
            continue;
        }
        let under = p.z > z0 && p.z < z0 + side && dx > 0.0;
        let i = (y * SIZE.0 + x) as usize;
        let lit = (f64::from(instant.radiance[i][0]) - ambient) / direct(p);
        assert!(
            (lit - if under { 0.0 } else { 1.0 }).abs() < 1e-3,
            "pixel ({x},{y}) at ({:.3}, {:.3}), t = 0.5: lit {lit}, under the square: {under}",
            p.x,
            p.z
        );
        checked += 1;
    }
    eprintln!("ms_visibility at t = 0.5: {checked} pixels match");

    // At texel centres the map holds exactly the intervals of the point itself (no half
    // texel of motion): there ms_lit_fraction equals the closed form to 1e-3, along a row of
    // texels across the square's whole path, through the host's own probe shader.
    // The texel row through the middle of the square's z extent.
    let queries = lit_fraction_queries_along_texel_row(&world, z0 + 0.5 * side);
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    let (mut worst_centre, mut partly) = (0.0f64, 0);
    for (q, &got) in queries.iter().zip(&lit) {
        let p = DVec3::new(f64::from(q.position[0]), 0.0, f64::from(q.position[2]));
        let expected = closed_form(p);
        partly += usize::from(expected > 0.0 && expected < 1.0);
        worst_centre = worst_centre.max((f64::from(got) - expected).abs());
    }
    eprintln!(
        "ms_lit_fraction at {} texel centres ({partly} partly lit): max error {worst_centre:.2e}",
        queries.len()
    );
    assert!(partly > 50, "{partly} partly lit texels");
    assert!(
        worst_centre < 1e-3,
        "max error {worst_centre} at texel centres"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The papers' lighting pass written into a host's own storage image
/// (`LightingImageOutput`) holds exactly the radiance the lighting target reads back, on the
/// host's device and in the host's command buffer.
#[test]
fn lighting_pass_writes_into_a_host_image() {
    use motion_shadows::gpu::Context;
    use motion_shadows::technique::{
        CollectionPass, DrawList, GenerationPass, LightingImageOutput, LightingPass,
        LightingTarget, ShadowSource,
    };
    use motion_shadows_app::render::upload::{SceneGeometry, light_view};
    let host = Host::new(true).unwrap_or_else(|e| panic!("needs a Vulkan device: {e}"));
    assert!(
        host.storage_image_write_without_format,
        "lavapipe and desktop GPUs support shaderStorageImageWriteWithoutFormat"
    );
    let size = (64u32, 48u32);
    let rgb_host;
    let rgb_target;
    {
        // SAFETY: Host::new enables every feature from_raw lists (and the optional one it
        // reports); the host outlives the context (dropped at the end of this block).
        let ctx = unsafe {
            Context::from_raw(
                &host.instance,
                host.physical,
                host.device.clone(),
                host.queue_family,
                host.queue,
                &host.enabled,
            )
        }
        .expect("from_raw");
        let scene = app::builtin("cubes-toward-light", &app::BuiltinOptions::default()).unwrap();
        let geometry = SceneGeometry::upload(&ctx, &scene).unwrap();
        let mut draws = DrawList::new(&ctx, geometry.draws.len() as u32).unwrap();
        let light = light_view(&scene, size);
        let view = LightingView {
            camera: camera_view(&scene, size),
            seed: 3,
            ambient: scene.ambient,
            estimator: Default::default(),
            filter: Default::default(),
        };
        let collection = CollectionPass::new(&ctx).unwrap();
        let generation = GenerationPass::new(&ctx).unwrap();
        let lighting = LightingPass::new(&ctx).unwrap();
        let output = LightingImageOutput::new(&ctx).unwrap();
        let mut bindings = output.bindings().unwrap();
        let target = LightingTarget::new(&ctx, size.0, size.1, 4, 16).unwrap();
        let map = TemporalShadowMap::new(&ctx, size.0, size.1, 1 << 16, 1 << 15).unwrap();
        let image = deferred::Image::new(
            &host,
            vk::Format::R32G32B32A32_SFLOAT,
            size,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )
        .unwrap();
        let pixels = (size.0 * size.1) as u64;
        let readback =
            deferred::HostBuffer::new(&host, pixels * 16, vk::BufferUsageFlags::TRANSFER_DST)
                .unwrap();
        let device = &host.device;
        host.record_and_wait(|cmd| {
            use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
            // SAFETY: the host's command buffer, recording, outside rendering; every object
            // outlives the wait.
            unsafe {
                draws.record_update(device, cmd, &geometry.draws).unwrap();
                collection
                    .record(device, cmd, &draws, &light, &map, None)
                    .unwrap();
                generation.record(device, cmd, &map);
                lighting
                    .record(
                        device,
                        cmd,
                        &draws,
                        &view,
                        ShadowSource::Temporal(&map),
                        &target,
                        None,
                    )
                    .unwrap();
                target.record_readback(device, cmd);
                deferred::pipeline_barrier(
                    device,
                    cmd,
                    &[image.barrier(
                        (L::UNDEFINED, S::NONE, A::NONE),
                        (L::GENERAL, S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                    )],
                    &[],
                );
                output.record(device, cmd, &mut bindings, &target, image.view);
                deferred::pipeline_barrier(
                    device,
                    cmd,
                    &[image.barrier(
                        (L::GENERAL, S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                        (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ),
                    )],
                    &[],
                );
                let region = vk::BufferImageCopy::default()
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: 0,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width: size.0,
                        height: size.1,
                        depth: 1,
                    });
                device.cmd_copy_image_to_buffer(
                    cmd,
                    image.image,
                    L::TRANSFER_SRC_OPTIMAL,
                    readback.buffer,
                    &[region],
                );
                let to_host = [vk::MemoryBarrier2::default()
                    .src_stage_mask(S::COPY)
                    .src_access_mask(A::TRANSFER_WRITE)
                    .dst_stage_mask(S::HOST)
                    .dst_access_mask(A::HOST_READ)];
                deferred::pipeline_barrier(device, cmd, &[], &to_host);
            }
        })
        .unwrap();
        let rgba: Vec<f32> = readback.read(pixels as usize * 4).unwrap();
        rgb_host = rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect::<Vec<f32>>();
        rgb_target = target.read_rgb().unwrap();
    }
    assert_eq!(rgb_host.len(), rgb_target.len());
    let differing = rgb_host
        .iter()
        .zip(&rgb_target)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{differing} channels differ");
    assert!(rgb_host.iter().any(|&v| v > 0.0), "not a black image");
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// With `MOTION_SHADOWS_TEST_IMAGES=DIR`: the host's image beside the standalone renderer's
/// (both lights: the sum of its single-light images, one ambient term), one exposure, as
/// `DIR/deferred-host-vs-renderer-frame-N.png`, for people to look at.
fn write_side_by_side(
    dir: &std::path::Path,
    frame: &FrameOutput,
    per_light: &[Vec<f32>],
    ambient: f32,
) {
    use motion_shadows_app::compare::{Rgb8Image, side_by_side};
    use motion_shadows_app::output::{RadianceImage, auto_exposure, write_rgb8_png};
    let host_rgb: Vec<f32> = frame
        .radiance
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let renderer_rgb: Vec<f32> = (0..host_rgb.len())
        .map(|i| per_light[0][i] + per_light[1][i] - ambient)
        .collect();
    let host = RadianceImage::new(SIZE.0, SIZE.1, host_rgb).unwrap();
    let renderer = RadianceImage::new(SIZE.0, SIZE.1, renderer_rgb).unwrap();
    let exposure = auto_exposure(&renderer);
    let panels = [
        (
            "host + mask",
            Rgb8Image::from_radiance(&host, exposure).unwrap(),
        ),
        (
            "renderer",
            Rgb8Image::from_radiance(&renderer, exposure).unwrap(),
        ),
    ];
    let refs: Vec<(&str, &Rgb8Image)> = panels.iter().map(|(l, i)| (*l, i)).collect();
    let image = side_by_side(&refs, [24, 24, 24]);
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(format!(
        "deferred-host-vs-renderer-frame-{}.png",
        frame.frame
    ));
    write_rgb8_png(&path, image.width, image.height, &image.data).unwrap();
    eprintln!("wrote {}", path.display());
}

/// A comb of `slats` slats of width `COMB_WIDTH`, one every `COMB_PERIOD` in x, at height 1
/// over z in [-COMB_HALF_Z, COMB_HALF_Z], travelling twice its length in +x over frame 1's
/// shutter under a directional light straight down. Every ground point of the middle stretch
/// (from the comb's end at t = 0 to its start at t = 1) is passed by every slat, in disjoint
/// intervals of width / travel each, so it is lit for 1 - width / (2 period) of the shutter.
fn comb_world(slats: usize) -> World {
    let (mut world, _, _) = square_world();
    let travel = 2.0 * slats as f64 * f64::from(COMB_PERIOD);
    let start = -0.5 * travel - 0.5 * slats as f64 * f64::from(COMB_PERIOD);
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for k in 0..slats {
        let x0 = k as f32 * COMB_PERIOD;
        let first = vertices.len() as u16;
        for [x, z] in [
            [x0, -COMB_HALF_Z],
            [x0, COMB_HALF_Z],
            [x0 + COMB_WIDTH, COMB_HALF_Z],
            [x0 + COMB_WIDTH, -COMB_HALF_Z],
        ] {
            vertices.push(Vertex {
                position: [x, 0.0, z],
                normal: [0.0, 1.0, 0.0],
            });
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|i| first + i));
    }
    world.meshes[1] = Mesh {
        name: "comb".into(),
        vertices,
        indices: MeshIndices::U16(indices),
        albedo: Vec3::splat(0.5),
        closed: false,
        motion: Motion::Rigid(Box::new(move |f| {
            DMat4::from_translation(DVec3::new(start + travel * f, 1.0, 0.0))
        })),
    };
    world
}

const COMB_WIDTH: f32 = 0.025;
const COMB_PERIOD: f32 = 0.05;
const COMB_HALF_Z: f32 = 1.5;

/// On a device that leaves long loops (lavapipe), the mask pass says which pixels' lookups
/// may have been cut short instead of writing wrong values silently: a comb of 28 slats
/// (28 disjoint shadow intervals per point, kept in private memory) renders and matches its
/// closed form; one of 72 slats (more than 32 intervals: the long path, about 2 x 72^2 loop
/// iterations per pixel) is refused there with the count, and matches the closed form on
/// devices without the limit.
#[test]
fn the_mask_reports_pixels_past_the_device_loop_limit() {
    let host = new_host();
    for slats in [28usize, 72] {
        let world = comb_world(slats);
        let mut engine =
            Engine::new(&host, &world, settings((1_000_000, 1_000_000))).expect("engine");
        let limited = engine.context().info().shader_loop_limit.is_some();
        let result = engine.render(&world, 0..2, &|f| f == 1);
        if limited && slats == 72 {
            let error = result
                .expect_err("refused on a loop-limited device")
                .to_string();
            eprintln!("{slats} slats: {error}");
            assert!(
                error.contains("mask pixel(s) need more loop iterations"),
                "{error}"
            );
            continue;
        }
        let frame = result.expect("frames").pop().expect("frame 1 kept");
        let scene = app_scene(&world, 1, 0);
        let rays = camera_rays(&scene);
        let half_stretch = 0.5 * slats as f64 * f64::from(COMB_PERIOD);
        let expected = 1.0 - f64::from(COMB_WIDTH) / (2.0 * f64::from(COMB_PERIOD));
        let (mut compared, mut worst) = (0, 0.0f64);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                    continue;
                };
                if p.x.abs() > half_stretch - 0.2 || p.z.abs() > f64::from(COMB_HALF_Z) - 0.2 {
                    continue;
                }
                let got = f64::from(frame.masks[0][(y * SIZE.0 + x) as usize]);
                worst = worst.max((got - expected).abs());
                compared += 1;
            }
        }
        eprintln!(
            "{slats} slats: {compared} ground pixels, lit fraction {expected}, max error \
             {worst:.2e}"
        );
        assert!(compared > 200, "{compared} pixels compared");
        assert!(worst < 2e-3, "max error {worst}");
        drop(engine);
    }
    host.assert_clean_teardown();
}

/// An engine that keeps its shadow maps' static layers across frames
/// (`LightView::keep_static_layer`) renders what one that redraws them every frame renders,
/// bit for bit, while drawing each map's static layer once; when a light moves, the layers
/// are drawn again and the frames still match.
#[test]
fn a_kept_static_layer_renders_what_a_redrawn_one_renders() {
    let host = new_host();
    let world = World::demo();
    let mut moved = World::demo();
    for light in &mut moved.lights {
        match light {
            Light::Spot { position, .. } => *position += Vec3::new(0.3, 0.0, -0.2),
            Light::Directional { direction, .. } => *direction += Vec3::new(0.05, 0.0, 0.0),
        }
    }
    let engine = |keep: bool| {
        let mut s = settings((300_000, 200_000));
        s.keep_static_layer = keep;
        Engine::new(&host, &world, s).expect("engine")
    };
    let (mut kept, mut redrawn) = (engine(true), engine(false));
    let builds = |e: &Engine, slot: usize| -> Vec<u32> {
        (0..world.lights.len())
            .map(|light| e.shadow_map(slot, light).static_layer_builds())
            .collect()
    };
    let frames = 0..6;
    for (part, (w, range)) in [(&world, 0..6u32), (&moved, 6..10)].into_iter().enumerate() {
        let a = kept.render(w, range.clone(), &|_| true).expect("kept");
        let b = redrawn
            .render(w, range.clone(), &|_| true)
            .expect("redrawn");
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.frame, y.frame);
            assert!(
                x.radiance == y.radiance,
                "frame {}: radiance differs",
                x.frame
            );
            assert!(x.masks == y.masks, "frame {}: masks differ", x.frame);
        }
        // Two frames in flight: each slot's maps drew their layers once per light setup.
        for slot in 0..2 {
            assert_eq!(
                builds(&kept, slot),
                vec![part as u32 + 1; world.lights.len()]
            );
        }
        eprintln!(
            "frames {range:?}: identical; static layer builds per map, kept {:?} / redrawn {:?}",
            builds(&kept, 0),
            builds(&redrawn, 0)
        );
    }
    assert!(builds(&redrawn, 0)[0] as usize >= frames.len() / 2);
    drop((kept, redrawn));
    host.assert_clean_teardown();
}

/// A caster of `interval_world`: a square of `width` (x) by `SIDE` (z), its corner moving
/// from (`x0`, `h0`) at t = 0 to (`x0 + travel`, `h1`) at t = 1 (x, height), at z = `Z0`.
struct Caster {
    x0: f64,
    travel: f64,
    h0: f64,
    h1: f64,
    width: f64,
}

/// Two squares sliding over the ground at different heights and speeds (one fast and narrow,
/// one slow and wide: over some points their shadow intervals overlap, over others one nests
/// in the other) and one that sinks straight down through the ground (its depth crosses the
/// ground's a quarter into the shutter).
const INTERVAL_CASTERS: [Caster; 3] = [
    Caster {
        x0: -5.5,
        travel: 6.0,
        h0: 1.0,
        h1: 1.0,
        width: 2.5,
    },
    Caster {
        x0: -4.5,
        travel: 2.5,
        h0: 2.0,
        h1: 2.0,
        width: 2.5,
    },
    Caster {
        x0: 3.5,
        travel: 0.0,
        h0: 1.0,
        h1: -3.0,
        width: 2.0,
    },
];
const Z0: f64 = -1.0;

fn interval_world() -> World {
    let (world, _, _) = square_world();
    let mut meshes = vec![deferred::ground_mesh()];
    for (i, c) in INTERVAL_CASTERS.iter().enumerate() {
        let w = c.width as f32;
        let square = [[0.0, 0.0], [0.0, SIDE], [w, SIDE], [w, 0.0]].map(|[x, z]| Vertex {
            position: [x, 0.0, z],
            normal: [0.0, 1.0, 0.0],
        });
        let (x0, travel, h0, h1) = (c.x0, c.travel, c.h0, c.h1);
        meshes.push(Mesh {
            name: format!("caster-{i}"),
            vertices: square.to_vec(),
            indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
            albedo: Vec3::splat(0.5),
            closed: false,
            motion: Motion::Rigid(Box::new(move |f| {
                DMat4::from_translation(DVec3::new(x0 + travel * f, h0 + (h1 - h0) * f, Z0))
            })),
        });
    }
    World { meshes, ..world }
}

/// `interval_world`'s engine after frame 1 (whose shutter the casters' motions span), and
/// that frame.
fn interval_frame(host: &Host) -> (Engine<'_>, FrameOutput) {
    let world = interval_world();
    let mut engine = Engine::new(host, &world, settings((300_000, 200_000))).expect("engine");
    let frame = engine
        .render(&world, 0..2, &|f| f == 1)
        .expect("frames")
        .pop()
        .expect("frame 1 kept");
    (engine, frame)
}

/// The times in frame 1's shutter during which caster `c` covers ground point (x, z) and is
/// nearer to the overhead light than the ground there (its height above `depth_margin`).
fn caster_interval(c: &Caster, x: f64, z: f64, depth_margin: f64) -> Option<(f64, f64)> {
    if z <= Z0 || z >= Z0 + f64::from(SIDE) {
        return None;
    }
    let (mut from, mut to) = if c.travel == 0.0 {
        if x <= c.x0 || x >= c.x0 + c.width {
            return None;
        }
        (0.0, 1.0)
    } else {
        ((x - c.x0 - c.width) / c.travel, (x - c.x0) / c.travel)
    };
    // Above the ground: h0 + (h1 - h0) t > margin.
    if c.h1 < c.h0 {
        to = to.min((c.h0 - depth_margin) / (c.h0 - c.h1));
    }
    from = from.max(0.0);
    to = to.min(1.0);
    (to > from).then_some((from, to))
}

/// The length of the union of intervals.
fn union_length(mut intervals: Vec<(f64, f64)>) -> f64 {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut length, mut covered_to) = (0.0, f64::NEG_INFINITY);
    for (from, to) in intervals {
        length += (to - from.max(covered_to)).max(0.0);
        covered_to = covered_to.max(to);
    }
    length
}

/// `ms_lit_fraction` where the ranges over a receiver overlap, nest, and cross its depth:
/// at the texel centres of a row across every caster's path, through the host's probe shader,
/// against 1 minus the length of the union of the closed-form intervals during which a
/// caster is nearer to the light than the ground point (the sinking square's interval ends
/// where its depth passes the receiver's, near a quarter into the shutter: the receiver is
/// the ground point moved up by the light's normal offset of one texel, its depth less the
/// relative bias of 1e-4).
/// Tolerance 1e-3 (f32 rounding; at texel centres the map holds the point's own intervals).
/// The row is chosen, and checked, to hold texels where intervals overlap partly, where one
/// nests in another, and where the crossing decides: summing instead of uniting, or taking
/// the wrong side of the crossing, moves those by more than 0.1.
#[test]
fn lit_fraction_unites_overlapping_ranges_and_cuts_at_the_depth_crossing() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let queries =
        lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.5 * f64::from(SIDE));
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    // The receiver tested: the ground point moved up by the light's normal offset (one
    // texel: the box is 12 units across the map), its depth less the relative bias 1e-4.
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let margin = 10.0 - (10.0 - texel) * (1.0 - 1e-4);
    let (mut overlapping, mut nested, mut crossing, mut worst) = (0, 0, 0, 0.0f64);
    for (q, &got) in queries.iter().zip(&lit) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let intervals: Vec<(f64, f64)> = INTERVAL_CASTERS
            .iter()
            .filter_map(|c| caster_interval(c, x, z, margin))
            .collect();
        let expected = 1.0 - union_length(intervals.clone()).min(1.0);
        let error = (f64::from(got) - expected).abs();
        assert!(
            error <= 1e-3,
            "texel centre x = {x:.3}: ms_lit_fraction {got}, closed form {expected} \
             (intervals {intervals:?})"
        );
        worst = worst.max(error);
        let summed: f64 = intervals.iter().map(|(a, b)| b - a).sum();
        if summed - union_length(intervals.clone()) > 0.1 {
            let (a, b) = (intervals[0], intervals[1]);
            let nests = (a.0 <= b.0 && b.1 <= a.1) || (b.0 <= a.0 && a.1 <= b.1);
            if nests {
                nested += 1;
            } else {
                overlapping += 1;
            }
        }
        let sinking = &INTERVAL_CASTERS[2];
        if caster_interval(sinking, x, z, margin).is_some()
            && intervals.len() == 1
            && (expected - 0.76).abs() < 0.01
        {
            crossing += 1;
        }
    }
    eprintln!(
        "ms_lit_fraction at {} texel centres: {overlapping} with overlapping intervals, \
         {nested} nested, {crossing} decided by a depth crossing; max error {worst:.2e}",
        queries.len()
    );
    assert!(
        overlapping >= 15 && nested >= 15 && crossing >= 15,
        "{overlapping} overlapping, {nested} nested, {crossing} crossing"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The self-shadow rule: a receiver's own triangle never shadows it. Points just below a
/// moving caster's surface (at a time it covers them, away from its diagonal and from the
/// other casters) and just below the ground (where no caster covers them then) are in the
/// shadow of their own surface by depth: `ms_visibility` must say 1 with their own triangle's
/// id, and 0 without one (`MS_NO_TRIANGLE`). The ground's own test is the static layer's, the
/// caster's its ranges'.
#[test]
fn a_receivers_own_triangle_never_shadows_it() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let z = Z0 + 0.37 * f64::from(SIDE);
    let (mut queries, mut owns) = (Vec::new(), Vec::new());
    for t in [0.2, 0.5, 0.8] {
        for i in 0..240 {
            let x = -5.8 + 11.6 * f64::from(i) / 240.0;
            let covering: Vec<usize> = INTERVAL_CASTERS
                .iter()
                .enumerate()
                .filter(|(_, c)| {
                    let left = c.x0 + c.travel * t;
                    x > left - 2.0 * texel && x < left + c.width + 2.0 * texel
                })
                .map(|(k, _)| k)
                .collect();
            let (position, own) = match covering[..] {
                // Below the ground, its own triangle's id (away from the grid's diagonals and
                // its cells' edges, every 3 units, where a texel may be a neighbour's).
                [] => match ground_triangle(DVec3::new(x, 0.0, z), 2.0 * texel) {
                    Some(id) if ((x + 6.0).rem_euclid(3.0) - 1.5).abs() < 1.5 - 2.0 * texel => {
                        ([x as f32, -0.2, z as f32], id)
                    }
                    _ => continue,
                },
                // Just below a flat caster that alone covers the point, inside it by two
                // texels (the ranges of its texel are its own).
                [k] if INTERVAL_CASTERS[k].h0 == INTERVAL_CASTERS[k].h1 => {
                    let c = &INTERVAL_CASTERS[k];
                    let (u, w) = (
                        (x - c.x0 - c.travel * t) / c.width,
                        (z - Z0) / f64::from(SIDE),
                    );
                    if !(2.0 * texel / c.width..1.0 - 2.0 * texel / c.width).contains(&u)
                        || (u - w).abs() < 2.0 * texel
                    {
                        continue;
                    }
                    // (0, 1, 2) is the half with w > u.
                    let id = ground_triangles + 2 * k as u32 + u32::from(w < u);
                    ([x as f32, (c.h0 - 0.2) as f32, z as f32], id)
                }
                _ => continue,
            };
            for own in [own, u32::MAX] {
                queries.push(Query {
                    position,
                    time: t as f32,
                    normal: [0.0, 1.0, 0.0],
                    own,
                });
                owns.push(own != u32::MAX);
            }
        }
    }
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    let (mut under_ground, mut under_caster) = (0, 0);
    for ((q, &own), &got) in queries.iter().zip(&owns).zip(&lit) {
        let expected = if own { 1.0 } else { 0.0 };
        assert_eq!(
            got, expected,
            "point {:?} at t = {}, own id {}: ms_visibility {got}",
            q.position, q.time, q.own
        );
        if own {
            if q.position[1] < 0.0 {
                under_ground += 1;
            } else {
                under_caster += 1;
            }
        }
    }
    eprintln!(
        "own triangle skipped: {under_ground} points under the ground, {under_caster} under a caster"
    );
    assert!(
        under_ground >= 50 && under_caster >= 50,
        "{under_ground} / {under_caster}"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The own-triangle rule in the lit fraction: points 0.2 below the slow wide caster (the only
/// one above them), at texel centres along a row across its path. The square's two triangles
/// pass over such a point one after the other (its diagonal splits each pass), so with the
/// id of one of them `ms_lit_fraction` is 1 minus the time the other covers the point, and
/// with no id 1 minus the time the square does (closed forms from the caster's motion;
/// tolerance 1e-3). Fails when the lit fraction counts the receiver's own ranges.
#[test]
fn a_receivers_own_triangle_never_darkens_its_lit_fraction() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster ((0, 1, 2) is the half of
    // the square with w > u).
    let ground_triangles = 2 * 4 * 4;
    let k = 1;
    let c = &INTERVAL_CASTERS[k];
    let first = ground_triangles + 2 * k as u32;
    // The time during which the square's u (0 at its leading... trailing edge x0 + travel t,
    // 1 at the other) lies in [a, b] at world x.
    let covered = |x: f64, a: f64, b: f64| {
        let from = ((x - c.x0 - b * c.width) / c.travel).max(0.0);
        let to = ((x - c.x0 - a * c.width) / c.travel).min(1.0);
        (to - from).max(0.0)
    };
    let (mut queries, mut expected) = (Vec::new(), Vec::new());
    let mut decided = 0;
    for q in lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.37 * f64::from(SIDE)) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let w = (z - Z0) / f64::from(SIDE);
        // Triangle `first` covers u < w, triangle `first + 1` u > w.
        let (upper, lower) = (covered(x, 0.0, w), covered(x, w, 1.0));
        if upper + lower == 0.0 {
            continue;
        }
        let position = [q.position[0], (c.h0 - 0.2) as f32, q.position[2]];
        for (own, lit) in [
            (u32::MAX, 1.0 - (upper + lower)),
            (first, 1.0 - lower),
            (first + 1, 1.0 - upper),
        ] {
            queries.push(Query {
                position,
                time: -1.0,
                normal: [0.0, 1.0, 0.0],
                own,
            });
            expected.push(lit);
        }
        decided += usize::from(upper > 0.05) + usize::from(lower > 0.05);
    }
    let got = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    for ((q, &want), &got) in queries.iter().zip(&expected).zip(&got) {
        assert!(
            (f64::from(got) - want).abs() <= 1e-3,
            "point {:?}, own id {}: ms_lit_fraction {got}, closed form {want}",
            q.position,
            q.own
        );
    }
    eprintln!(
        "{} queries; {decided} where the own triangle covers the point 5% of the shutter or more",
        queries.len()
    );
    assert!(decided >= 20, "{decided}");
    drop(engine);
    host.assert_clean_teardown();
}

/// The lighting pass tests a pixel's samples per texel (`ms_samples_shadowed`, glsl/
/// temporal_samples.glsl, not part of the public include); each sample must get exactly what
/// `ms_texel_shadowed` answers for it alone. Groups of 8 receivers around one point (within
/// a texel or two, so some share a texel and some do not), at random times, on the ground or
/// just below a caster, with their own triangle's id, another triangle's, or none: the two
/// answers agree for every one, and the own ids decide many of them (the test fails when
/// either function drops the own-triangle skip, or the static layer, coverage or time test).
#[test]
fn per_texel_sample_tests_answer_as_ms_texel_shadowed() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let ids: Vec<u32> = (0..ground_triangles + 6).collect();
    let mut queries = Vec::new();
    for _ in 0..400 {
        let (x, z) = (-5.5 + 11.0 * uniform(), Z0 + f64::from(SIDE) * uniform());
        // Below the ground, below the low caster, or below the high one.
        let surface = (uniform() * 3.0) as usize;
        let height = [-0.2, 0.8, 1.8][surface];
        for _ in 0..8 {
            let (px, pz) = (
                x + 2.0 * texel * (uniform() - 0.5),
                z + 2.0 * texel * (uniform() - 0.5),
            );
            // A third each: the id of the surface just above (either triangle of a caster),
            // any id, none.
            let own = match (uniform() * 3.0) as usize {
                0 if surface == 0 => ground_triangle(DVec3::new(px, 0.0, pz), 0.0).unwrap_or(0),
                0 => ground_triangles + 2 * (surface as u32 - 1) + u32::from(uniform() < 0.5),
                1 => ids[(uniform() * ids.len() as f64) as usize],
                _ => u32::MAX,
            };
            queries.push(Query {
                position: [px as f32, height as f32, pz as f32],
                time: uniform() as f32,
                normal: [0.0, 1.0, 0.0],
                own,
            });
        }
    }
    let map = engine.shadow_map(frame.slot, 0);
    let answers = run_probe(
        &host,
        map,
        &queries,
        deferred::sources::SAMPLES_PROBE_COMP,
        Shape {
            per_invocation: 8,
            workgroup: 16,
            results_per_query: 2,
        },
    );
    // The same receivers without their own ids: how many answers the ids decide.
    let anonymous: Vec<Query> = queries
        .iter()
        .map(|q| Query {
            own: u32::MAX,
            ..*q
        })
        .collect();
    let without_ids = probe(&host, map, &anonymous);
    let (mut shadowed, mut decided_by_id) = (0, 0);
    for (i, (q, pair)) in queries.iter().zip(answers.chunks_exact(2)).enumerate() {
        assert_eq!(
            pair[0], pair[1],
            "query {i} {q:?}: per texel {}, alone {}",
            pair[0], pair[1]
        );
        shadowed += usize::from(pair[1] == 1.0);
        // Shadowed without an id (probe gives visibility: 0), lit with its own.
        decided_by_id += usize::from(pair[1] == 0.0 && without_ids[i] == 0.0);
    }
    eprintln!(
        "{} receivers: {shadowed} shadowed, {decided_by_id} lit only by their own id",
        queries.len()
    );
    assert!(
        shadowed >= 300 && queries.len() - shadowed >= 300 && decided_by_id >= 100,
        "{shadowed} shadowed, {decided_by_id} decided by the id"
    );
    drop(engine);
    host.assert_clean_teardown();
}
