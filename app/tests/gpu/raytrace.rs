//! `--method raytrace` against answers it did not compute: the shading formula worked out in
//! closed form on a static scene (no GPU), and the brute-force GPU reference on a scene with a
//! moving blocker (lavapipe, validation on).

use glam::{DVec3, Vec2, Vec3};
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::sampling::{pixel_key, pixel_sample};
use motion_shadows::technique::{CameraParams, LightingView};
use motion_shadows_app::compare::rmse;
use motion_shadows_app::render::upload::camera_view;
use motion_shadows_app::render::{Method, RenderResult, RenderSettings, Renderer};
use motion_shadows_app::scene::{
    Camera, DirectionalLight, Light, Mesh, Scene, SpotLight, box_mesh, plane_mesh,
};

const GROUND_ALBEDO: Vec3 = Vec3::new(0.8, 0.6, 0.4);
const BLOCKER_ALBEDO: Vec3 = Vec3::new(0.2, 0.9, 0.3);
const AMBIENT: f32 = 0.05;
/// The blocker of the static scene: a horizontal rectangle at this height over x0..x1, z0..z1.
const BLOCKER: [f64; 5] = [1.0, -1.5, 1.0, -1.0, 1.0];

fn mesh(name: &str, albedo: Vec3, t0: Vec<Vec3>, t1: Vec<Vec3>, closed: bool) -> Mesh {
    Mesh {
        name: name.into(),
        albedo,
        closed,
        t0,
        t1,
    }
}

fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 6.0, 8.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: 100.0,
        t1: None,
    }
}

fn spot() -> Light {
    Light::Spot(SpotLight {
        position: Vec3::new(0.3, 5.0, 0.2),
        direction: Vec3::new(0.05, -1.0, 0.1),
        cone_angle_deg: 35.0,
        intensity: 40.0,
        near: 0.5,
        far: 50.0,
        t1: None,
    })
}

fn directional() -> Light {
    Light::Directional(DirectionalLight {
        direction: Vec3::new(1.0, -1.0, 0.6),
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent: 6.0,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
        t1: None,
    })
}

/// A tessellated ground (its inner edges are where a leaky triangle test shows) and a static
/// rectangle above it.
fn static_scene(light: Light) -> Scene {
    let [h, x0, x1, z0, z1] = BLOCKER.map(|v| v as f32);
    let (a, b, c, d) = (
        Vec3::new(x0, h, z0),
        Vec3::new(x0, h, z1),
        Vec3::new(x1, h, z1),
        Vec3::new(x1, h, z0),
    );
    let blocker = vec![a, b, c, a, c, d];
    let ground = plane_mesh(Vec2::splat(10.0), 8);
    Scene {
        name: "static".into(),
        camera: camera(),
        light,
        ambient: AMBIENT,
        meshes: vec![
            mesh("ground", GROUND_ALBEDO, ground.clone(), ground, false),
            mesh("blocker", BLOCKER_ALBEDO, blocker.clone(), blocker, false),
        ],
    }
}

/// Where the ray `o + s d` meets the plane y = h inside [x0, x1] x [z0, z1], with the
/// distance to the rectangle's border (negative outside).
fn rectangle(o: DVec3, d: DVec3, h: f64, [x0, x1, z0, z1]: [f64; 4]) -> Option<(f64, f64)> {
    if d.y == 0.0 {
        return None;
    }
    let s = (h - o.y) / d.y;
    let p = o + s * d;
    let inside = (p.x - x0).min(x1 - p.x).min(p.z - z0).min(z1 - p.z);
    Some((s, inside))
}

/// The radiance of one sample, worked out for the static scene: the ray meets the blocker or
/// the ground (planes), the ground point is shadowed iff its segment to the light (or its ray
/// against a directional light) crosses the blocker's rectangle. `None` where the answer is
/// within `margin` of changing (an edge, the cone's border).
fn expected_sample(scene: &Scene, o: DVec3, d: DVec3, margin: f64) -> Option<DVec3> {
    let [h, x0, x1, z0, z1] = BLOCKER;
    let ambient = f64::from(AMBIENT);
    let near = f64::from(scene.camera.near);
    let blocker = rectangle(o, d, h, [x0, x1, z0, z1]).filter(|&(s, _)| s >= near);
    if let Some((_, inside)) = blocker {
        if inside.abs() < margin {
            return None;
        }
    }
    let (p, n, albedo, on_blocker) = match blocker {
        Some((s, inside)) if inside > 0.0 => (o + s * d, DVec3::Y, BLOCKER_ALBEDO, true),
        _ => {
            let (s, inside) = rectangle(o, d, 0.0, [-5.0, 5.0, -5.0, 5.0])?;
            if inside.abs() < margin || s < near {
                return None;
            }
            if inside < 0.0 {
                return Some(DVec3::ZERO);
            }
            (o + s * d, DVec3::Y, GROUND_ALBEDO, false)
        }
    };
    let albedo = albedo.as_dvec3();
    let (to_light, dist2, emission) = match &scene.light {
        Light::Spot(l) => {
            let to = l.position.as_dvec3() - p;
            let axis = l.direction.as_dvec3().normalize();
            let cos_cone = f64::from(l.cone_angle_deg).to_radians().cos();
            let off_axis = (-to.normalize()).dot(axis) - cos_cone;
            if off_axis.abs() < margin {
                return None;
            }
            if off_axis < 0.0 {
                return Some(ambient * albedo);
            }
            (to, to.length_squared(), f64::from(l.intensity))
        }
        Light::Directional(l) => (
            -l.direction.as_dvec3().normalize(),
            1.0,
            f64::from(l.irradiance),
        ),
    };
    let cos = n.dot(to_light.normalize());
    let direct = albedo / std::f64::consts::PI * emission * cos / dist2;
    if on_blocker {
        return Some(direct + ambient * albedo);
    }
    // Crossing the blocker's plane on the way to the light (spot: before reaching it).
    let (s, inside) = rectangle(p, to_light, h, [x0, x1, z0, z1])?;
    let reaches = match scene.light {
        Light::Spot(_) => s > 0.0 && s < 1.0,
        Light::Directional(_) => s > 0.0,
    };
    if reaches && inside.abs() < margin {
        return None;
    }
    Some(if reaches && inside > 0.0 {
        ambient * albedo
    } else {
        direct + ambient * albedo
    })
}

fn settings(method: Method, size: (u32, u32), spp: u32, seed: u32) -> RenderSettings {
    RenderSettings {
        width: size.0,
        height: size.1,
        spp,
        seed,
        method,
        ..RenderSettings::default()
    }
}

fn raytrace(scene: &Scene, size: (u32, u32), spp: u32, seed: u32) -> RenderResult {
    motion_shadows_app::raytrace::render(
        scene,
        &settings(Method::Raytrace, size, spp, seed),
        &mut |_| {},
    )
    .expect("raytrace")
}

/// On a static scene the traced radiance is the shading formula, sample by sample, to f32
/// rounding: for each pixel whose samples are all clear of edges, the mean over the same
/// samples (the library's mirror of the shaders' sampling, the renderer's camera rays) of the
/// closed-form answer.
#[test]
fn static_scene_matches_the_closed_form_shading() {
    const SIZE: (u32, u32) = (64, 48);
    const SPP: u32 = 16;
    const SEED: u32 = 7;
    for light in [spot(), directional()] {
        let scene = static_scene(light);
        let result = raytrace(&scene, SIZE, SPP, SEED);
        let view = LightingView {
            camera: camera_view(&scene, SIZE),
            seed: SEED,
            ambient: AMBIENT,
            estimator: Default::default(),
            filter: Default::default(),
        };
        let params = CameraParams::new(&view, SIZE, SPP);
        let origin = params.position.truncate().as_dvec3();
        let (mut checked, mut shadowed, mut lit) = (0, 0, 0);
        for y in 0..SIZE.1 {
            'pixel: for x in 0..SIZE.0 {
                let key = pixel_key(x, y, SEED);
                let mut sum = DVec3::ZERO;
                for k in 0..SPP {
                    let (_, offset) = pixel_sample(key, k, SPP);
                    let at = Vec2::new(x as f32, y as f32) + offset;
                    let dir = params.ray00.truncate()
                        + at.x * params.ray_dx.truncate()
                        + at.y * params.ray_dy.truncate();
                    match expected_sample(&scene, origin, dir.as_dvec3(), 1e-3) {
                        Some(radiance) => sum += radiance,
                        None => continue 'pixel,
                    }
                }
                let expected = sum / f64::from(SPP);
                let i = 3 * (y * SIZE.0 + x) as usize;
                let got = &result.image.rgb[i..i + 3];
                for c in 0..3 {
                    let (g, e) = (f64::from(got[c]), expected[c]);
                    assert!(
                        (g - e).abs() <= 1e-5 * e.abs().max(1e-3),
                        "pixel ({x},{y}) channel {c}: traced {g}, closed form {e}"
                    );
                }
                checked += 1;
                let ambient_only = expected.x <= f64::from(AMBIENT * GROUND_ALBEDO.x) * 1.000001;
                shadowed += usize::from(ambient_only && expected.x > 0.0);
                lit += usize::from(!ambient_only);
            }
        }
        eprintln!(
            "{checked} pixels checked: {shadowed} in shadow (or outside the cone), {lit} lit"
        );
        let pixels = (SIZE.0 * SIZE.1) as usize;
        assert!(
            checked > pixels / 2,
            "only {checked} of {pixels} pixels checked"
        );
        assert!(shadowed > 40 && lit > 500, "{shadowed} shadowed, {lit} lit");
    }
}

/// A ground and a box flying over it under a spot light: the scene every shadow method
/// handles, where the truth and the brute-force reference must agree.
fn moving_scene() -> Scene {
    let ground = plane_mesh(Vec2::splat(8.0), 16);
    let cube = box_mesh(Vec3::new(1.0, 0.6, 0.8), 2);
    let at = |by: Vec3| cube.iter().map(|p| *p + by).collect::<Vec<_>>();
    Scene {
        name: "moving".into(),
        camera: camera(),
        light: Light::Spot(SpotLight {
            position: Vec3::new(0.5, 6.0, 0.5),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 45.0,
            intensity: 60.0,
            near: 0.5,
            far: 50.0,
            t1: None,
        }),
        ambient: AMBIENT,
        meshes: vec![
            mesh("ground", GROUND_ALBEDO, ground.clone(), ground, false),
            mesh(
                "box",
                BLOCKER_ALBEDO,
                at(Vec3::new(-1.2, 1.2, 0.0)),
                at(Vec3::new(0.9, 1.6, 0.3)),
                true,
            ),
        ],
    }
}

/// The brute-force reference (many time slices, a large shadow map) and the ray tracer see the
/// same picture, to within the ray tracer's own sampling noise.
///
/// Tolerance: the RMSE between two traces that differ only in their seed measures that noise
/// (each has variance sigma^2 per value: their RMSE is sqrt(2) sigma). Against a reference with
/// 8 times the samples, an unbiased trace is off by about sqrt(1 + 1/8) sigma = 1.06 sigma
/// (its noise and the reference's): so its RMSE must stay below that of two traces, which
/// leaves room for a systematic difference of at most about 0.9 sigma. An ordinary shadow map frozen at mid-shutter
/// is far outside that (checked too, so the tolerance cannot pass anything).
#[test]
fn moving_blocker_agrees_with_the_brute_force_reference() {
    const SIZE: (u32, u32) = (64, 48);
    let scene = moving_scene();
    let ctx = Context::headless(&ContextOptions { validation: true })
        .expect("GPU tests need a Vulkan device and the validation layer");
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let gpu = |renderer: &mut Renderer, method| {
        let mut s = settings(method, SIZE, 16, 1);
        s.shadow_size = Some((2048, 2048));
        renderer.render(&scene, &s, &mut |_| {}).expect("render")
    };
    let reference = gpu(&mut renderer, Method::Reference { slices: 512 });
    let frozen = gpu(&mut renderer, Method::Plain { time: 0.5 });
    let traced = raytrace(&scene, SIZE, 64, 1);
    let other_seed = raytrace(&scene, SIZE, 64, 2);

    let noise = rmse(&traced.image, &other_seed.image, None).unwrap();
    let error = rmse(&traced.image, &reference.image, None).unwrap();
    let frozen_error = rmse(&frozen.image, &reference.image, None).unwrap();
    eprintln!(
        "RMSE: trace vs reference {error:.5}, trace vs trace (seeds 1, 2) {noise:.5}, \
         frozen map vs reference {frozen_error:.5}"
    );
    assert!(
        noise > 0.0,
        "two seeds gave the same image: the seed is ignored"
    );
    assert!(
        error < noise,
        "trace vs reference {error} >= the trace's noise {noise}"
    );
    assert!(
        frozen_error > 3.0 * noise,
        "the tolerance {noise} would pass a frozen map"
    );
    // The moving-object masks agree too (what compare's masked errors are computed over).
    let share = |r: &RenderResult| r.moving_coverage.iter().map(|&c| f64::from(c)).sum::<f64>();
    let (a, b) = (share(&traced), share(&reference));
    assert!(
        (a - b).abs() < 0.05 * b,
        "moving coverage: traced {a}, reference {b}"
    );
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "validation: {}", messages.join("\n"));
}
