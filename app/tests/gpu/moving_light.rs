//! The temporal map under a moving light (issue 38): built in the light's moving frame and
//! looked up with the light at each sample's time, against the ray tracer on the same samples
//! (the light at each sample's time, exact; nothing shared with the map).
//!
//! The bound: the same scene with its light held still, whose error against its own truth is
//! the map's discretisation alone (texels, normal offset, bias). The translating light is the
//! exact case of the moving frame, so the moving light must agree about as well; a map that
//! ignored the light's motion (the still light's image against the moving light's truth) is
//! far off, so the bound can tell.

use crate::support::gpu::{assert_no_validation_messages, context, render, render_with, renderer};
use motion_shadows_app::compare::error_stats;
use motion_shadows_app::render::{Method, RenderResult, RenderSettings};
use motion_shadows_app::scene::{BuiltinOptions, Light, Scene, SpotPose, builtin};

fn settings(method: Method) -> RenderSettings {
    RenderSettings {
        width: 96,
        height: 72,
        spp: 8,
        seed: 1,
        shadow_size: Some((1024, 1024)),
        method,
        ..RenderSettings::default()
    }
}

/// `moving-light`, its light as built (`Some`: carried), held still (`None`), or with a t = 1
/// pose equal to t = 0's (`Some(Vec3::ZERO)`: moving by nothing).
fn scene(carried: Option<glam::Vec3>) -> Scene {
    let mut scene = builtin("moving-light", &BuiltinOptions::default()).unwrap();
    let Light::Spot(light) = &mut scene.light else {
        panic!("spot expected")
    };
    let built = light.t1.unwrap();
    light.t1 = carried.map(|by| SpotPose {
        position: if by == glam::Vec3::ZERO {
            light.position
        } else {
            built.position
        },
        direction: light.direction,
    });
    scene
}

fn truth(scene: &Scene) -> RenderResult {
    motion_shadows_app::raytrace::render(scene, &settings(Method::Raytrace), &mut |_| {}).unwrap()
}

#[test]
fn a_carried_light_renders_like_the_ray_tracer() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    let moving = scene(Some(glam::Vec3::X));
    let still = scene(None);
    let (moving_truth, still_truth) = (truth(&moving), truth(&still));
    let moving_map = render_with(&mut renderer, &moving, &settings(Method::Temporal));
    let still_map = render_with(&mut renderer, &still, &settings(Method::Temporal));
    let rmse = |image, truth| error_stats(image, truth, None).unwrap().rmse;
    let moving_error = rmse(&moving_map.image, &moving_truth.image);
    let still_error = rmse(&still_map.image, &still_truth.image);
    let ignored = rmse(&still_map.image, &moving_truth.image);
    eprintln!(
        "RMSE against the ray tracer: carried light {moving_error:.5}, still light \
         {still_error:.5}, the light's motion ignored {ignored:.5}"
    );
    assert!(moving_map.stats.light_moves && !still_map.stats.light_moves);
    // Every draw is collected as moving: no static layer.
    assert_eq!(moving_map.stats.static_layer_bytes, 0);
    assert!(still_map.stats.static_layer_bytes > 0);
    assert!(
        moving_error < 1.5 * still_error.max(1e-3),
        "{moving_error} vs {still_error}"
    );
    assert!(ignored > 4.0 * moving_error, "{ignored} vs {moving_error}");
    // A light moving by nothing: the moving frame's arithmetic leaves the still light's view
    // as it is, and the still draws collected as moving store the same shadow the static
    // layer does: the same image, to the bit.
    let unmoved = render(
        &ctx,
        &scene(Some(glam::Vec3::ZERO)),
        &settings(Method::Temporal),
    );
    let differs = (unmoved.image.rgb.iter().zip(&still_map.image.rgb))
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differs, 0, "a light moving by nothing changed the image");
    assert_no_validation_messages(&ctx);
}

/// The deferred frame's mask under the carried light: every receiver walked along its path
/// in the light's moving frame (still pixels too), against the exact lit share of the
/// shutter, on the pixels the light's cone holds all shutter. The still light is no bound
/// here (its sharp edges put whole pixels off by a texel: RMSE 0.048 measured against 0.0013
/// for the carried light, lavapipe, 2026-12-07): the bound is the target, 0.005,
/// about four times the measured error (a texel's misplacement of a shadow blurred over a
/// unit or so is ~0.01 at its edge pixels, few of them); ignoring the light's motion is far
/// off (0.39).
#[test]
fn the_mask_under_a_carried_light_agrees_with_the_exact_truth() {
    use motion_shadows_app::compare::mask_error;
    use motion_shadows_app::raytrace::deferred::{deferred_truth, render_truth};
    use motion_shadows_app::render::Renderer;
    use motion_shadows_app::render::deferred::{DeferredMethod, DeferredSettings};
    let ctx = context();
    let settings = RenderSettings {
        spp: 1,
        ..settings(Method::Temporal)
    };
    let deferred = |method| DeferredSettings {
        method,
        camera_time: 0.5,
        ..DeferredSettings::default()
    };
    let (moving, still) = (scene(Some(glam::Vec3::X)), scene(None));
    let truth = |s: &Scene| {
        render_truth(
            s,
            &settings,
            &deferred(DeferredMethod::Raytrace),
            &mut |_| {},
        )
        .unwrap()
    };
    let (moving_truth, still_truth) = (truth(&moving), truth(&still));
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let mut mask = |s: &Scene| {
        let frame = deferred(DeferredMethod::Temporal);
        renderer
            .render_deferred(s, &settings, &frame, &mut |_| {})
            .unwrap()
    };
    let (moving_mask, still_mask) = (mask(&moving), mask(&still));
    drop(renderer);
    // Where the light's cone holds the point all shutter (at both ends: for a translating
    // light then at every time): elsewhere the truth counts shadows the light's cone never
    // lights, the map (a square around the cone) counts time outside its view lit.
    let points = deferred_truth(&moving, 96, 72, 0.5, (1024, 1024), &mut |_| {}).unwrap();
    let Light::Spot(light) = &moving.light else {
        panic!("spot expected")
    };
    let cos_cone = light.cone_angle_deg.to_radians().cos();
    let in_cone =
        |p: glam::Vec3, at: glam::Vec3| (p - at).normalize().dot(light.direction) > cos_cone;
    let ends = [light.position, light.t1.unwrap().position];
    let held: Vec<bool> = (0..points.hit.len())
        .map(|i| {
            let p = glam::Vec3::from(points.position[i]);
            moving_truth.facing[i] && points.hit[i] && ends.iter().all(|&at| in_cone(p, at))
        })
        .collect();
    let error = |r: &[f32], truth: &motion_shadows_app::render::deferred::DeferredResult| {
        mask_error(r, &truth.lit, &held)
    };
    let moving_error = error(&moving_mask.lit, &moving_truth);
    let still_error = mask_error(&still_mask.lit, &still_truth.lit, &still_truth.facing);
    let ignored = error(&still_mask.lit, &moving_truth);
    eprintln!(
        "mask RMSE against the exact truth: carried light {:.5}, still light {:.5}, the \
         light's motion ignored {:.5}",
        moving_error.rmse, still_error.rmse, ignored.rmse
    );
    assert!(moving_error.pixels > 2000 && moving_error.shadowed_pixels > 200);
    assert!(
        moving_error.rmse < 0.005,
        "{moving_error:?} ({still_error:?} still)"
    );
    assert!(ignored.rmse > 4.0 * moving_error.rmse, "{ignored:?}");
    assert_no_validation_messages(&ctx);
}

/// The ordinary maps under the carried light, each layer drawn and read with the light at
/// its time: the brute-force reference (one map per time slice, 32 slices) agrees with the
/// ray tracer about as well as under the still light, and TSM-8 keeps about its own
/// (time-mismatch) error, not the far larger one of maps that ignore the light's motion.
#[test]
fn ordinary_maps_take_the_light_at_each_layer_s_time() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    let (moving, still) = (scene(Some(glam::Vec3::X)), scene(None));
    let (moving_truth, still_truth) = (truth(&moving), truth(&still));
    let rmse = |image: &_, truth: &_| error_stats(image, truth, None).unwrap().rmse;
    for method in [Method::Reference { slices: 32 }, Method::Tsm] {
        let moving_map = render_with(&mut renderer, &moving, &settings(method));
        let still_map = render_with(&mut renderer, &still, &settings(method));
        let moving_error = rmse(&moving_map.image, &moving_truth.image);
        let still_error = rmse(&still_map.image, &still_truth.image);
        let ignored = rmse(&still_map.image, &moving_truth.image);
        eprintln!(
            "{}: RMSE against the ray tracer: carried light {moving_error:.5}, still light \
             {still_error:.5}, the light's motion ignored {ignored:.5}",
            method.name()
        );
        // Measured (lavapipe, 2026-12-07): the reference 0.0111 against 0.0073 (its own
        // sampling noise either way: twice allows it); TSM-8 0.0037 against 0.0019: its time
        // mismatch (a sample tested in its stratum's map, drawn at another time) now moves
        // every post's shadow too, not only the box's: three times allows it. Ignoring the
        // light's motion: 0.050, over three times either.
        let factor = if method == Method::Tsm { 3.0 } else { 2.0 };
        assert!(
            moving_error < factor * still_error,
            "{method:?}: {moving_error} vs {still_error}"
        );
        assert!(ignored > 3.0 * moving_error, "{method:?}: {ignored}");
    }
    assert_no_validation_messages(&ctx);
}
