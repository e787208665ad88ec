//! The animated character scene (`walker-toward-light`: CesiumMan, skinned, posed at shutter
//! open and close by the glTF loader) at 256x192 under the validation layer, against the
//! ray tracer on the same samples (no shadow map, no shared assumption).

use crate::support::gpu::{assert_no_validation_messages, context, render};
use motion_shadows_app::compare::error_stats;
use motion_shadows_app::render::{Method, RenderSettings};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

#[test]
fn walker_renders_like_the_ray_tracer() {
    let ctx = context();
    let scene = builtin("walker-toward-light", &BuiltinOptions::default()).unwrap();
    let settings = |method| RenderSettings {
        width: 256,
        height: 192,
        spp: 4,
        seed: 3,
        shadow_size: Some((1024, 1024)),
        method,
        ..RenderSettings::default()
    };
    let truth =
        motion_shadows_app::raytrace::render(&scene, &settings(Method::Raytrace), &mut |_| {})
            .unwrap();
    let temporal = render(&ctx, &scene, &settings(Method::Temporal));
    let moving = temporal
        .moving_coverage
        .iter()
        .filter(|&&m| m > 0.0)
        .count();
    let e = error_stats(&temporal.image, &truth.image, None).unwrap();
    eprintln!(
        "walker, 256x192, 4 spp: {} triangles, {moving} pixels see the walker move, RMSE \
         against the ray tracer {:.5}",
        temporal.stats.triangles, e.rmse
    );
    assert_eq!(temporal.stats.triangles, 4672 + 1024);
    assert!(moving > 200, "{moving} pixels see the walker");
    // Same samples: what differs is the shadow test at texel resolution along shadow edges.
    assert!(e.rmse < 0.01, "RMSE {}", e.rmse);
    assert_no_validation_messages(&ctx);
}
