//! The deferred host engine (`examples/deferred_host/src/deferred.rs`, the engine of the
//! `deferred_host` example) checked against the library's standalone renderer (the app, used
//! here as a reference only) and against the ray tracer's exact truth (`truth`). Its tests
//! against the lighting pass's own per-sample decisions and closed forms are the library's
//! (`tests/gpu/deferred_host.rs`), with which this file shares
//! `test-support/src/deferred_host.rs`.

use crate::support::gpu::{assert_no_validation_messages, context, render_with, renderer};
use crate::support::host::Host;
use crate::support::sampling::{CameraRays, hits, pixel_key, pixel_sample};
use ash::vk;
use deferred::{Engine, FrameOutput, World};
use glam::{DVec3, Vec3};
use motion_shadows::technique::{LightingView, TemporalShadowMap};
use motion_shadows_app::render::upload::camera_view;
use motion_shadows_app::render::{Method, ReceiverTest, RenderSettings};
use motion_shadows_app::scene as app;

use motion_shadows_deferred_host::deferred;

// The helpers this file shares with the library's deferred-host tests.
use crate::support::deferred_host::*;

mod truth;

/// Frame `frame` of the host's world as the app's scene lit by light `light` alone: every
/// mesh de-indexed, its positions at the shutter's ends (frames f - 1 and f) in world space.
fn app_scene(world: &World, lights: &[HostLight], frame: u32, light: usize) -> app::Scene {
    // The parameters are those of the light the engine drew with.
    assert_eq!(lights[light].engine_light(), world.lights[light]);
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
            t1: None,
        },
        light: match lights[light] {
            HostLight::Spot {
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
                t1: None,
            }),
            HostLight::Directional {
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
                t1: None,
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
/// whether the host's value is partial) over all compared pixels and the partly lit ones
/// alone: mean within 4 standard errors of 0 plus 0.004, RMSE below 0.0625 (see the test).
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
    lights: &[HostLight],
    host_frame: &FrameOutput,
    light: usize,
    renderer_rgb: &[f32],
) -> Vec<(f64, bool)> {
    let scene = app_scene(world, lights, host_frame.frame, light);
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
/// Both hold over all compared pixels and the partly lit ones alone. The brute-force
/// reference (256 time slices, ordinary shadow maps) meets the same bounds for one frame.
#[test]
fn host_image_equals_the_standalone_renderer_on_static_receivers() {
    let host = new_host();
    let (world, lights) = (World::demo(), demo_lights());
    // The library reserves each frame's room from the meshes' descriptions: no frame's
    // shadow overflows (`render` errors if one did), so every frame is submitted once.
    let (frames, counters) = {
        let mut engine = Engine::new(&host, &world, settings()).expect("engine");
        let frames = engine.render(&world, 0..4, &|_| true).expect("frames");
        assert_eq!(
            engine.context().validation_messages(),
            Vec::<String>::new(),
            "a from_raw context has no messenger of its own"
        );
        // Each slot's maps hold the slot's last frame (1, 2 and 3): their counts.
        let counts = |f: &FrameOutput| -> Vec<_> {
            (0..world.lights.len())
                .map(|l| {
                    engine
                        .shadow_map(f.slot, l)
                        .read_counters()
                        .expect("counts")
                })
                .collect()
        };
        let counters: Vec<_> = frames[1..].iter().map(counts).collect();
        (frames, counters)
    };
    assert_eq!(
        frames.iter().map(|f| (f.frame, f.slot)).collect::<Vec<_>>(),
        (0..4)
            .map(|f| (f, f as usize % deferred::FRAMES_IN_FLIGHT))
            .collect::<Vec<_>>()
    );
    for (frame, counters) in frames[1..].iter().zip(&counters) {
        eprintln!(
            "frame {} (slot {}): N_f / N_r per light: {:?}",
            frame.frame,
            frame.slot,
            counters
                .iter()
                .map(|c| (c.node_count, c.range_count))
                .collect::<Vec<_>>()
        );
        for c in counters {
            // The maps collect ranges directly (the exact construction with the static
            // layer): no node is stored, so the node count is no capacity's concern.
            assert_eq!(c.ranges_direct, 1);
            assert!(c.range_count <= c.range_capacity);
            assert!(c.node_count > 0 && c.range_count > 0);
        }
    }

    let ctx = context();
    let mut renderer = renderer(&ctx);
    let ambient = world.ambient * GROUND_ALBEDO as f32;
    for frame in &frames[2..] {
        let mut per_light = Vec::new();
        for light in 0..world.lights.len() {
            let scene = app_scene(&world, &lights, frame.frame, light);
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
            let result = render_with(&mut renderer, &scene, &settings);
            let diffs = compare_light(&world, &lights, frame, light, &result.image.rgb);
            let what = format!(
                "frame {} (slot {}), light {light}, temporal 64 spp",
                frame.frame, frame.slot
            );
            check_agreement(&what, &diffs, 150);
            per_light.push(result.image.rgb);
        }

        // Both lights together: the host's radiance against the sum of the renderer's
        // single-light images (each of which carries the ambient term once).
        let scene = app_scene(&world, &lights, frame.frame, 0);
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
    let scene = app_scene(&world, &lights, frame.frame, 0);
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
    let reference = render_with(&mut renderer, &scene, &settings);
    let what = format!(
        "frame 3, light 0, reference 256 slices ({:.1} s)",
        start.elapsed().as_secs_f64()
    );
    check_agreement(
        &what,
        &compare_light(&world, &lights, frame, 0, &reference.image.rgb),
        150,
    );

    assert_no_validation_messages(&ctx);
    host.assert_clean_teardown();
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
    let (world, lights) = (World::demo(), demo_lights());
    let mut engine = Engine::new(&host, &world, settings()).expect("engine");
    let frames = engine.render(&world, 0..4, &|f| f == 3).expect("frames");
    assert_eq!(frames.len(), 1);
    let slot = frames[0].slot;
    let ground_first_id = engine.first_triangle_id(0);

    let ctx = context();
    let mut renderer = renderer(&ctx);
    let ambient = f64::from(world.ambient) * GROUND_ALBEDO;
    for light in 0..world.lights.len() {
        let scene = app_scene(&world, &lights, 3, light);
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
        let result = render_with(&mut renderer, &scene, &settings);
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

mod lighting_target;
