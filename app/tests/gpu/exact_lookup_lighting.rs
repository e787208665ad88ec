//! The forward frame's lighting pass with the exact lookup (`Lookup::Exact`, `--lookup exact`):
//! each sample's shadow ray at its own time against the triangles its texel names
//! (`ms_visible_exact`), against the ray tracer on the same samples (same seed: the same
//! positions and times; no shadow map, nothing shared with the technique's passes). A still
//! block and ground, a cube and a plate flying past (moving casters, and moving receivers
//! on their faces), under a directional and a spot light, at a fine and a coarse map: the
//! map's resolution must not matter. The depth-line lookup on the same frames is printed
//! beside it, and must be worse at the coarse map (shadows a texel can misplace). With the
//! analytic estimator, against the exact lit shares of the same samples' points.

use crate::support::frame::render_draws;
use crate::support::gpu::{assert_no_validation_messages, context, render_with, renderer};
use crate::support::ray_traced::rmse_against_the_ray_tracer;
use glam::{DVec3, Vec2, Vec3};
use motion_shadows::technique::sampling::{pixel_key, pixel_sample};
use motion_shadows::technique::{
    CameraParams, LightView, LightingView, Lookup, ShadowEstimator, ShadowFilter,
};
use motion_shadows_app::compare::error_stats;
use motion_shadows_app::output::RadianceImage;
use motion_shadows_app::raytrace::bvh::Bvh;
use motion_shadows_app::raytrace::pixels::CameraRays;
use motion_shadows_app::raytrace::shade::{Shading, ShadingLight};
use motion_shadows_app::raytrace::shutter::lit_fraction;
use motion_shadows_app::raytrace::triangles::scene_triangles;
use motion_shadows_app::render::upload::{SceneGeometry, camera_view, light_view};
use motion_shadows_app::render::{RenderResult, RenderSettings};
use motion_shadows_app::scene::{
    Camera, DirectionalLight, Light, Mesh, Scene, SpotLight, box_mesh, plane_mesh,
};

const SIZE: (u32, u32) = (160, 120);
/// The exact lookup's RMSE against the ray tracer, at any map size (issue 35's target).
const EXACT_RMSE: f64 = 0.0005;

fn mesh(name: &str, t0: Vec<Vec3>, t1: Vec<Vec3>, closed: bool) -> Mesh {
    Mesh {
        name: name.into(),
        albedo: Vec3::splat(0.7),
        closed,
        t0,
        t1,
    }
}

fn moved(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|&p| p + by).collect()
}

/// Ground, a still block (1.6 x 0.8 x 1.6) on it, a cube (side 0.4) flying 1.5 along z at
/// height 2 and a plate sliding 1 along x at height 1.4, under `light`.
fn block_and_flying_casters(light: Light) -> Scene {
    let ground = plane_mesh(Vec2::splat(8.0), 8);
    let block = moved(
        &box_mesh(Vec3::new(1.6, 0.8, 1.6), 2),
        Vec3::new(-0.5, 0.4, 0.5),
    );
    let cube = moved(&box_mesh(Vec3::splat(0.4), 1), Vec3::new(1.0, 2.0, -2.0));
    let plate = [
        (0.0, 0.0),
        (0.0, 0.8),
        (0.8, 0.8),
        (0.0, 0.0),
        (0.8, 0.8),
        (0.8, 0.0),
    ]
    .map(|(x, z)| Vec3::new(x - 2.5, 1.4, z - 1.0))
    .to_vec();
    Scene {
        name: "block-and-flying-casters".into(),
        camera: Camera {
            position: Vec3::new(2.5, 4.0, 4.5),
            target: Vec3::new(-0.3, 0.3, 0.0),
            up: Vec3::Y,
            fov_y_deg: 40.0,
            near: 0.1,
            far: 50.0,
            t1: None,
        },
        light,
        ambient: 0.05,
        meshes: vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("block", block.clone(), block, true),
            mesh(
                "cube",
                cube.clone(),
                moved(&cube, Vec3::new(0.0, 0.0, 1.5)),
                true,
            ),
            mesh("plate", plate.clone(), moved(&plate, Vec3::X), false),
        ],
    }
}

/// 22 degrees above the ground's plane, and a spot light up and to the side.
fn lights() -> [(&'static str, Light); 2] {
    [
        (
            "directional",
            Light::Directional(DirectionalLight {
                direction: Vec3::new(2.0, -1.0, 1.2),
                irradiance: 3.0,
                center: Vec3::ZERO,
                half_extent: 5.0,
                distance: 10.0,
                near: 0.5,
                far: 30.0,
                t1: None,
            }),
        ),
        (
            "spot",
            Light::Spot(SpotLight {
                position: Vec3::new(-3.0, 5.0, -2.0),
                direction: Vec3::new(0.5, -1.0, 0.35).normalize(),
                cone_angle_deg: 50.0,
                intensity: 60.0,
                near: 0.5,
                far: 30.0,
                t1: None,
            }),
        ),
    ]
}

fn settings(shadow: u32, lookup: Lookup) -> RenderSettings {
    RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        spp: 4,
        seed: 7,
        shadow_size: Some((shadow, shadow)),
        lookup,
        ..RenderSettings::default()
    }
}

#[test]
fn the_forward_exact_lookup_matches_the_ray_tracer_at_fine_and_coarse_maps() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    for (name, light) in lights() {
        let scene = block_and_flying_casters(light);
        for shadow in [512, 64] {
            let mut rmse = |lookup| {
                let s = settings(shadow, lookup);
                let r: RenderResult = render_with(&mut renderer, &scene, &s);
                assert_eq!(r.stats.method, s.method_name());
                // For a look at the frames: MOTION_SHADOWS_TEST_IMAGES=DIR.
                if let Ok(dir) = std::env::var("MOTION_SHADOWS_TEST_IMAGES") {
                    let dir = std::path::Path::new(&dir);
                    std::fs::create_dir_all(dir).expect("image directory");
                    let path = dir.join(format!("{name}-{shadow}-{}.png", s.method_name()));
                    motion_shadows_app::output::write_png(&path, &r.image, 0.0).expect("png");
                }
                rmse_against_the_ray_tracer(&scene, &s, &r.image)
            };
            let (exact, depth) = (rmse(Lookup::Exact), rmse(Lookup::DepthLine));
            println!(
                "{name}, {shadow}x{shadow} map: RMSE against the ray tracer: exact {exact:.2e}, \
                 depth line {depth:.2e}"
            );
            assert!(exact <= EXACT_RMSE, "{name} {shadow}: exact {exact}");
            if shadow == 64 {
                assert!(
                    depth > 4.0 * exact.max(EXACT_RMSE / 4.0),
                    "{name}: depth line {depth}"
                );
            }
        }
    }
    assert_no_validation_messages(&ctx);
}

/// The expectation of the analytic estimator, from the ray tracer's parts (f64, no shadow
/// map): each sample of the lighting pass (the same positions and times) traced to its hit;
/// a hit on a still triangle lit for its point's exact share of the shutter
/// (`shutter::lit_fraction`), one on a moving triangle by its shadow ray at the sample's
/// time; averaged per pixel, as the ray tracer averages.
fn analytic_expectation(scene: &Scene, s: &RenderSettings) -> RadianceImage {
    let (width, height) = (s.width, s.height);
    let bvh = Bvh::new(&scene_triangles(scene));
    let view = LightingView {
        camera: camera_view(scene, (width, height)),
        seed: s.seed,
        ambient: scene.ambient,
        estimator: ShadowEstimator::Analytic,
        filter: Default::default(),
    };
    let rays = CameraRays::new(&CameraParams::new(&view, (width, height), s.spp));
    let (lo, hi) = scene.bounds();
    let scale = f64::from((hi - lo).length().max(lo.abs().max(hi.abs()).max_element()));
    let ambient = f64::from(scene.ambient);
    let shading = Shading {
        bvh: &bvh,
        light: ShadingLight::new(&light_view(scene, s.shadow_size()), scale),
        albedo: scene
            .meshes
            .iter()
            .map(|m| (m.albedo.as_dvec3(), ambient * m.albedo.as_dvec3()))
            .collect(),
    };
    let (near, far) = (f64::from(scene.camera.near), f64::from(scene.camera.far));
    let mut rgb = Vec::with_capacity((3 * width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let key = pixel_key(x, y, s.seed);
            let mut sum = DVec3::ZERO;
            for k in 0..s.spp {
                let (t, offset) = pixel_sample(key, k, s.spp);
                let t = f64::from(t);
                let ray = rays.ray(Vec2::new(x as f32, y as f32) + offset);
                let Some(hit) = bvh.closest(&ray, t, near, far) else {
                    continue;
                };
                let tri = &bvh.triangles()[hit.index as usize];
                let p = ray.origin + hit.s * ray.dir;
                let (direct, ambient) = shading.unshadowed(p, ray.dir, tri, t);
                let lit = match (direct, tri.moving) {
                    (None, _) => 0.0,
                    (Some(_), true) => f64::from(u8::from(!shading.occluded(p, t, tri.id))),
                    (Some(_), false) => lit_fraction(&bvh, &shading.light, p, p, tri.id),
                };
                sum += ambient + direct.unwrap_or(DVec3::ZERO) * lit;
            }
            rgb.extend((sum / f64::from(s.spp)).as_vec3().to_array());
        }
    }
    RadianceImage::new(width, height, rgb).expect("an image of the frame's size")
}

/// With the analytic estimator, a sample on a still triangle takes its point's exact lit
/// share of the shutter (`ms_lit_fraction_exact`), one on a moving triangle its exact
/// visibility at its time: the frame matches the expectation above to RMSE <= 0.0005 at a
/// fine and a coarse map, both lights. The sampled exact frame differs from it by its time
/// noise (it is the ray tracer's), which shows the comparison sees the estimator.
#[test]
fn the_forward_exact_lookup_with_the_analytic_estimator_takes_exact_lit_shares() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    for (name, light) in lights() {
        let scene = block_and_flying_casters(light);
        for shadow in [512, 64] {
            let settings = |estimator| RenderSettings {
                shadow_estimator: estimator,
                ..settings(shadow, Lookup::Exact)
            };
            let analytic = settings(ShadowEstimator::Analytic);
            let expected = analytic_expectation(&scene, &analytic);
            let mut rmse = |s: &RenderSettings| {
                let image = render_with(&mut renderer, &scene, s).image;
                error_stats(&image, &expected, None)
                    .expect("images of one size")
                    .rmse
            };
            let (exact, sampled) = (rmse(&analytic), rmse(&settings(ShadowEstimator::Sampled)));
            println!(
                "{name}, {shadow}x{shadow} map: RMSE against the exact lit shares: analytic \
                 {exact:.2e}, sampled {sampled:.2e}"
            );
            assert!(exact <= EXACT_RMSE, "{name} {shadow}: analytic {exact}");
            assert!(
                sampled > 4.0 * EXACT_RMSE,
                "{name} {shadow}: sampled {sampled}"
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

/// The library's lighting pass reads a map built for the exact lookup (it refused it before)
/// and refuses a shadow filter with it by name (the exact test has no texels to filter)
/// rather than dropping the filter.
#[test]
fn the_lighting_pass_reads_an_exact_map_and_refuses_a_filter_with_it() {
    let ctx = context();
    let scene = block_and_flying_casters(lights()[0].1.clone());
    let geometry = SceneGeometry::upload(&ctx, &scene).expect("upload");
    let size = (32, 24);
    let view = |filter| LightingView {
        camera: camera_view(&scene, size),
        seed: 1,
        ambient: scene.ambient,
        estimator: Default::default(),
        filter,
    };
    let exact = LightView {
        lookup: Lookup::Exact,
        ..light_view(&scene, (64, 64))
    };
    render_draws(
        &ctx,
        &geometry.draws,
        &exact,
        &view(ShadowFilter::None),
        size,
        (64, 64),
        1,
    )
    .expect("the exact map lights the frame");
    for filter in [ShadowFilter::Bilinear, ShadowFilter::Footprint] {
        let refused = render_draws(
            &ctx,
            &geometry.draws,
            &exact,
            &view(filter),
            size,
            (64, 64),
            1,
        )
        .err()
        .expect("a filter is refused with the exact lookup");
        assert!(
            refused
                .to_string()
                .contains(&format!("ShadowFilter::{filter:?}")),
            "{refused}"
        );
    }
    drop(geometry);
    assert_no_validation_messages(&ctx);
}
