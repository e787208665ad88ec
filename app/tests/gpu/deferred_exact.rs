//! The deferred frame with the exact lookup (`--lookup exact`, `Lookup::Exact`) against the
//! exact truth (the CPU's lit share of each G-buffer point, `render_truth`): a still block and
//! ground, a cube flying past above them (moving caster, and moving receivers on its own
//! faces). The map's resolution should not matter: the error is measured at a fine and a
//! coarse map (lavapipe, validation on).

use glam::{Vec2, Vec3};
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::Lookup;
use motion_shadows_app::compare::{MaskError, mask_error};
use motion_shadows_app::raytrace::deferred::render_truth;
use motion_shadows_app::render::deferred::{DeferredMethod, DeferredResult, DeferredSettings};
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{
    Camera, DirectionalLight, Light, Mesh, Scene, SpotLight, box_mesh, plane_mesh,
};

const SIZE: (u32, u32) = (160, 120);
/// The exact mask's RMSE against the truth, at any map size (the brief's target; what is
/// left is f32 rounding at the G-buffer's shadow edges).
const EXACT_RMSE: f64 = 0.002;

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
/// height 2 and a plate sliding 1 along x at height 1.4, under a directional light 22 degrees
/// above the ground's plane.
fn block_and_flying_casters() -> Scene {
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
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(2.0, -1.0, 1.2),
            irradiance: 3.0,
            center: Vec3::ZERO,
            half_extent: 5.0,
            distance: 10.0,
            near: 0.5,
            far: 30.0,
            t1: None,
        }),
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

fn settings(shadow: u32) -> RenderSettings {
    RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        shadow_size: Some((shadow, shadow)),
        ..RenderSettings::default()
    }
}

fn deferred(method: DeferredMethod, lookup: Lookup) -> DeferredSettings {
    DeferredSettings {
        method,
        lookup,
        ..DeferredSettings::default()
    }
}

fn error(r: &DeferredResult, truth: &DeferredResult) -> MaskError {
    mask_error(&r.lit, &truth.lit, &truth.facing)
}

/// Any one pixel's lit share off the truth's by at most this (the truth's own per-pixel
/// visibility: f32 roots against f64 ones, a few ulps of the shutter).
const LARGEST_DIFFERENCE: f32 = 1e-3;

/// The largest difference of one pixel's lit share from the truth's, over the pixels the
/// light reaches.
fn largest_difference(r: &DeferredResult, truth: &DeferredResult) -> f32 {
    (0..truth.lit.len())
        .filter(|&i| truth.facing[i])
        .map(|i| (r.lit[i] - truth.lit[i]).abs())
        .fold(0.0, f32::max)
}

/// RMSE <= 0.002 at 512 x 512 and at 64 x 64 maps, where the depth-line mask is many times
/// that (printed for comparison, and asserted to be worse at the coarse map, so that the
/// scene's shadows are ones a texel can misplace).
#[test]
fn the_exact_mask_matches_the_truth_at_fine_and_coarse_maps() {
    let ctx = Context::headless(&ContextOptions { validation: true })
        .expect("GPU tests need a Vulkan device and the validation layer");
    let scene = block_and_flying_casters();
    let truth = render_truth(
        &scene,
        &settings(512),
        &deferred(DeferredMethod::Raytrace, Lookup::DepthLine),
        &mut |_| {},
    )
    .expect("truth");
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    for shadow in [512, 64] {
        let mut render = |lookup| {
            let r = renderer
                .render_deferred(
                    &scene,
                    &settings(shadow),
                    &deferred(DeferredMethod::Temporal, lookup),
                    &mut |_| {},
                )
                .expect("deferred frame");
            (error(&r, &truth), largest_difference(&r, &truth))
        };
        let (exact, exact_largest) = render(Lookup::Exact);
        let (depth, _) = render(Lookup::DepthLine);
        println!(
            "{shadow}x{shadow}: exact {exact:?} (largest pixel difference {exact_largest}), \
             depth line {depth:?}"
        );
        assert!(
            exact_largest <= LARGEST_DIFFERENCE,
            "{shadow}x{shadow}: a pixel {exact_largest} off the truth"
        );
        assert!(
            exact.pixels > 5000 && exact.shadowed_pixels > 500,
            "{exact:?}"
        );
        assert!(
            exact.rmse <= EXACT_RMSE,
            "{shadow}x{shadow}: exact {exact:?}"
        );
        if shadow == 64 {
            assert!(depth.rmse > 5.0 * EXACT_RMSE, "depth line {depth:?}");
        }
    }
    drop(renderer);
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "validation: {}", messages.join("\n"));
}

/// A plate sliding 1 along x at height 1.4 under a still square 1 above it, nothing else:
/// every shadowed pixel is a moving receiver shadowed, part of the shutter, by a still
/// triangle (the static names a moving receiver walks).
fn plate_under_a_still_square() -> Scene {
    let square = |x0: f32, z0: f32, side: f32, y: f32| {
        [
            (0.0, 0.0),
            (0.0, 1.0),
            (1.0, 1.0),
            (0.0, 0.0),
            (1.0, 1.0),
            (1.0, 0.0),
        ]
        .map(|(x, z)| Vec3::new(x0 + side * x, y, z0 + side * z))
        .to_vec()
    };
    let plate = square(-2.5, -1.0, 0.8, 1.4);
    // One unit above the plate along the light's travel (2, -1, 1.2): its shadow on the
    // plate's plane is x in [-1.9, -1.3], where the plate passes during the shutter.
    let roof = square(-3.9, -2.2, 0.6, 2.4);
    let mut scene = block_and_flying_casters();
    scene.name = "plate-under-a-still-square".into();
    scene.camera.position = Vec3::new(0.5, 4.5, 1.5);
    scene.camera.target = Vec3::new(-1.6, 1.4, -0.6);
    if let Light::Directional(light) = &mut scene.light {
        light.center = Vec3::new(-2.5, 1.8, -1.2);
        light.half_extent = 2.5;
    }
    scene.meshes = vec![
        mesh("roof", roof.clone(), roof, false),
        mesh("plate", plate.clone(), moved(&plate, Vec3::X), false),
    ];
    scene
}

/// Moving receivers shadowed by a still caster for part of the shutter, under the
/// directional light and under a spot light behind the square (whose range of s ends at the
/// light): each pixel's lit share within LARGEST_DIFFERENCE of the truth's, and enough of them
/// partly shadowed (so the still caster's shadow does fall on the moving plate during the
/// shutter).
#[test]
fn a_moving_receiver_under_a_still_caster_matches_the_truth() {
    let ctx = Context::headless(&ContextOptions { validation: true })
        .expect("GPU tests need a Vulkan device and the validation layer");
    let directional = plate_under_a_still_square();
    let mut spot = directional.clone();
    spot.light = Light::Spot(SpotLight {
        position: Vec3::new(-6.6, 3.9, -3.7),
        direction: Vec3::new(5.0, -2.5, 3.1),
        cone_angle_deg: 30.0,
        intensity: 40.0,
        near: 0.5,
        far: 20.0,
        t1: None,
    });
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    for scene in [directional, spot] {
        let truth = render_truth(
            &scene,
            &settings(256),
            &deferred(DeferredMethod::Raytrace, Lookup::DepthLine),
            &mut |_| {},
        )
        .expect("truth");
        let partly = (0..truth.lit.len())
            .filter(|&i| truth.facing[i] && truth.lit[i] > 0.05 && truth.lit[i] < 0.95)
            .count();
        let r = renderer
            .render_deferred(
                &scene,
                &settings(256),
                &deferred(DeferredMethod::Temporal, Lookup::Exact),
                &mut |_| {},
            )
            .expect("deferred frame");
        let largest = largest_difference(&r, &truth);
        println!(
            "{:?}: {partly} pixels partly shadowed; {:?}, largest {largest}",
            scene.light,
            error(&r, &truth)
        );
        assert!(partly > 300, "{partly} pixels of the plate partly shadowed");
        assert!(
            largest <= LARGEST_DIFFERENCE,
            "a pixel {largest} off the truth"
        );
    }
    drop(renderer);
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "validation: {}", messages.join("\n"));
}
