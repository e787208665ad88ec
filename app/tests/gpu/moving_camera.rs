//! The GPU's forward frame under a moving camera (issue 38 item 3): each vertex's clip
//! position made with the camera at t = 0 and at t = 1 and blended linearly (McGuire et al.
//! 2010), the raster's hull, time bounds and ray tests at each sample's time. Two
//! expectations independent of the lighting pass's camera code: still renders along the
//! camera's path (the old, still-camera arithmetic) and the ray tracer (each sample's ray shot
//! from the camera at its time).

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::gpu::Context;
use motion_shadows_app::compare::error_stats;
use motion_shadows_app::output::RadianceImage;
use motion_shadows_app::render::{Method, RenderResult, RenderSettings, Renderer};
use motion_shadows_app::scene::{BuiltinOptions, Scene, builtin};

const WIDTH: u32 = 48;
const HEIGHT: u32 = 36;
const SPP: u32 = 64;
/// Still poses along the path, at the midpoints of equal time slices.
const POSES: u32 = 32;
/// Block means compared (BLOCK x BLOCK pixels), so that a block's noise is small next to
/// what a wrong camera time moves across it.
const BLOCK: u32 = 6;

/// `camera-pan` with its cubes held at t = 0 and the pan widened to a quarter of the image,
/// so that only the camera moves and a camera seen at the wrong time shows.
fn panning_over_still_scene() -> Scene {
    let mut scene = builtin("camera-pan", &BuiltinOptions::default()).unwrap();
    for mesh in &mut scene.meshes {
        mesh.t1 = mesh.t0.clone();
    }
    let end = scene.camera.t1.as_mut().unwrap();
    end.position = scene.camera.position + glam::Vec3::X * 5.0;
    end.target = scene.camera.target + glam::Vec3::X * 5.0;
    scene
}

fn small(method: Method) -> RenderSettings {
    RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: SPP,
        seed: 3,
        shadow_size: Some((512, 512)),
        method,
        ..RenderSettings::default()
    }
}

fn render_with(renderer: &mut Renderer, scene: &Scene, settings: &RenderSettings) -> RenderResult {
    motion_shadows_app::frame::render(Some(renderer), scene, settings, &mut |_| {}).expect("render")
}

/// The sum of a block's channels, averaged over its pixels.
fn block_means(rgb: &[f32]) -> Vec<f64> {
    let (bw, bh) = (WIDTH / BLOCK, HEIGHT / BLOCK);
    let mut means = vec![0.0; (bw * bh) as usize];
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = 3 * (y * WIDTH + x) as usize;
            let sum: f32 = rgb[i..i + 3].iter().sum();
            means[((y / BLOCK) * bw + x / BLOCK) as usize] += f64::from(sum);
        }
    }
    means.iter().map(|m| m / f64::from(BLOCK * BLOCK)).collect()
}

fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The bound (as the ray tracer's own test of its moving camera,
/// `raytrace::tests::moving_camera`): a block mean averages B = BLOCK^2 x SPP independent
/// samples, each a channel sum in [0, L], so its standard deviation is at most
/// L / (2 sqrt B); the still poses' average is no noisier than one still render, so the
/// difference's deviation is at most sqrt 2 times that, and 5 of those over the 48 blocks
/// leaves a chance of a false failure below 3e-5 even at this worst-case variance. L is the
/// brightest pixel of any still render times 1.25. The midpoint rule over POSES poses adds at
/// most (pan in pixels / POSES) / BLOCK of an edge's contrast per block, the pan being under
/// 13 pixels: 13 / 32 / 6 of L, counted in. A pan is a translation of the camera, for which
/// the linear blend of clip positions is the camera's own projection at every time, so no
/// term is added for it. Shadows come from the one temporal map every render shares (the
/// scene is still; the map does not depend on the camera).
#[test]
fn a_moving_camera_over_a_still_scene_averages_the_still_renders_along_its_path() {
    let ctx = context();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let scene = panning_over_still_scene();
    let settings = small(Method::Temporal);
    let result = render_with(&mut renderer, &scene, &settings);
    assert!(result.stats.camera_moves);
    let moving = block_means(&result.image.rgb);
    let mut average = vec![0.0; moving.len()];
    let mut brightest: f32 = 0.0;
    let mut at_start = Vec::new();
    for i in 0..POSES {
        let t = (i as f32 + 0.5) / POSES as f32;
        let mut still = scene.clone();
        still.camera = scene.camera.at(t);
        let image = render_with(&mut renderer, &still, &settings).image;
        brightest = image
            .rgb
            .chunks(3)
            .map(|p| p.iter().sum::<f32>())
            .fold(brightest, f32::max);
        for (a, m) in average.iter_mut().zip(block_means(&image.rgb)) {
            *a += m / f64::from(POSES);
        }
        if i == 0 {
            at_start = block_means(&image.rgb);
        }
    }
    let range = 1.25 * f64::from(brightest);
    let samples = f64::from(BLOCK * BLOCK * SPP);
    let noise = 5.0 * 2f64.sqrt() * range / (2.0 * samples.sqrt());
    let quadrature = range * 13.0 / f64::from(POSES * BLOCK);
    let bound = noise + quadrature;
    let worst = worst_difference(&moving, &average);
    let off = worst_difference(&at_start, &average);
    eprintln!(
        "worst block difference {worst:.4}, bound {bound:.4} (L {range:.3}); the camera at \
         its first pose: {off:.4}"
    );
    assert!(worst <= bound, "worst block {worst} > bound {bound}");
    // The test can see a camera seen at one time only.
    assert!(off > 2.0 * bound, "the first pose is only {off} off");
    assert_no_validation_messages(&ctx);
}

/// Every method of the forward frame on `camera-pan` against the ray tracer on the same
/// samples, next to the same method on the same scene with the camera held still
/// (`cubes-toward-light`, camera-pan's meshes, light and t = 0 camera) against its own truth:
/// a pan is exact in the linear blend of clip positions, so the moving camera must agree
/// about as well as the still one (the method's own error: texels, time strata, slices): its
/// RMSE within 1.5 times the still one's. A frame that ignored the camera's motion (the still
/// camera's image against the moving camera's truth) must fail that check by a factor of 2
/// at least, so that the check can tell (measured: about 0.056 whatever the method, each
/// method's own error at most 0.016).
#[test]
fn every_forward_method_renders_camera_pan_like_the_ray_tracer() {
    let ctx = context();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let options = BuiltinOptions::default();
    let moving = builtin("camera-pan", &options).unwrap();
    let still = builtin("cubes-toward-light", &options).unwrap();
    let settings = |method| RenderSettings {
        width: 96,
        height: 72,
        spp: 8,
        ..small(method)
    };
    let truth = |scene: &Scene| -> RadianceImage {
        motion_shadows_app::raytrace::render(scene, &settings(Method::Raytrace), &mut |_| {})
            .unwrap()
            .image
    };
    let (moving_truth, still_truth) = (truth(&moving), truth(&still));
    let rmse = |image: &RadianceImage, truth: &RadianceImage| {
        error_stats(image, truth, None).unwrap().rmse
    };
    for method in [
        Method::Temporal,
        Method::Tsm,
        Method::Plain { time: 0.5 },
        Method::Reference { slices: 16 },
    ] {
        let moving_image = render_with(&mut renderer, &moving, &settings(method)).image;
        let still_image = render_with(&mut renderer, &still, &settings(method)).image;
        let moving_error = rmse(&moving_image, &moving_truth);
        let still_error = rmse(&still_image, &still_truth);
        let ignored = rmse(&still_image, &moving_truth);
        eprintln!(
            "{}: RMSE against the ray tracer: panning camera {moving_error:.5}, still camera \
             {still_error:.5}, the camera's motion ignored {ignored:.5}",
            method.name()
        );
        let agreement = 1.5 * still_error.max(1e-3);
        assert!(
            moving_error < agreement,
            "{}: {moving_error} vs {still_error}",
            method.name()
        );
        assert!(
            ignored > 2.0 * agreement,
            "{}: {ignored} vs {moving_error}",
            method.name()
        );
    }
    assert_no_validation_messages(&ctx);
}

/// The settings whose shading takes the camera as still are refused by name, by the app and
/// by the library itself (a host that builds its own `LightingView`).
#[test]
fn the_settings_that_take_the_camera_as_still_are_refused_by_name() {
    use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
    let ctx: Context = context();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let scene = builtin("camera-pan", &BuiltinOptions::default()).unwrap();
    let tiny = RenderSettings {
        width: 16,
        height: 12,
        spp: 2,
        ..small(Method::Temporal)
    };
    for (settings, named) in [
        (
            RenderSettings {
                shadow_estimator: ShadowEstimator::Analytic,
                ..tiny.clone()
            },
            "--shadow-estimator analytic",
        ),
        (
            RenderSettings {
                shadow_filter: ShadowFilter::Footprint,
                ..tiny.clone()
            },
            "--shadow-filter footprint",
        ),
    ] {
        let error =
            motion_shadows_app::frame::render(Some(&mut renderer), &scene, &settings, &mut |_| {})
                .err()
                .expect("refused")
                .to_string();
        assert!(
            error.contains("camera moves") && error.contains(named),
            "{error}"
        );
    }
    assert_no_validation_messages(&ctx);
}

/// A host driving the library's lighting pass itself (no app checks in between) gets the
/// same refusals from the pass, naming the setting and what to use, and nothing recorded.
#[test]
fn the_lighting_pass_refuses_the_still_camera_settings_for_a_moving_camera() {
    use crate::support::frame::render_draws;
    use motion_shadows::technique::{LightingView, ShadowEstimator, ShadowFilter};
    use motion_shadows_app::render::upload::{SceneGeometry, camera_view, light_view};
    let ctx = context();
    let scene = builtin("camera-pan", &BuiltinOptions::default()).unwrap();
    let geometry = SceneGeometry::upload(&ctx, &scene).expect("upload");
    let size = (16, 12);
    let end = scene.camera.t1.unwrap();
    let camera = camera_view(&scene, size)
        .moving_to(end.position, end.target, end.up)
        .unwrap();
    let view = |estimator, filter| LightingView {
        camera,
        seed: 1,
        ambient: scene.ambient,
        estimator,
        filter,
    };
    let light = light_view(&scene, (64, 64));
    let frame = |estimator, filter| {
        render_draws(
            &ctx,
            &geometry.draws,
            &light,
            &view(estimator, filter),
            size,
            (64, 64),
            1,
        )
    };
    frame(ShadowEstimator::Sampled, ShadowFilter::Bilinear).expect("a moving camera is lit");
    for (estimator, filter, named) in [
        (
            ShadowEstimator::Analytic,
            ShadowFilter::None,
            "ShadowEstimator::Analytic",
        ),
        (
            ShadowEstimator::Sampled,
            ShadowFilter::Footprint,
            "ShadowFilter::Footprint",
        ),
    ] {
        let refused = frame(estimator, filter).err().expect("refused").to_string();
        assert!(
            refused.contains(named) && refused.contains("CameraView::end"),
            "{refused}"
        );
    }
    drop(geometry);
    assert_no_validation_messages(&ctx);
}
