//! The static layer (the nearest static triangle per texel, in place of static triangles'
//! fragments and ranges) answers every lookup as the lists do: the same images, sampled and
//! analytic, filtered and not, with either receiver test, on built-in scenes whose receivers
//! and casters are both static and moving. The lists are the oracle (their construction is
//! checked against CPU models in exact_prisms.rs, generation.rs and analytic.rs).

use crate::support::gpu::{assert_no_validation_messages, context, render_with, renderer};
use crate::support::ray_traced::rmse_against_the_ray_tracer;
use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
use motion_shadows_app::render::{Method, ReceiverTest, RenderSettings};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

fn settings(static_layer: bool) -> RenderSettings {
    RenderSettings {
        width: 96,
        height: 72,
        spp: 4,
        seed: 3,
        shadow_size: Some((256, 256)),
        method: Method::Temporal,
        static_layer,
        ..RenderSettings::default()
    }
}

#[test]
fn the_static_layer_renders_what_the_lists_render() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    let variants = [
        (
            "sampled",
            ShadowEstimator::Sampled,
            ShadowFilter::None,
            ReceiverTest::Auto,
        ),
        (
            "analytic",
            ShadowEstimator::Analytic,
            ShadowFilter::None,
            ReceiverTest::Auto,
        ),
        (
            "footprint",
            ShadowEstimator::Analytic,
            ShadowFilter::Footprint,
            ReceiverTest::Auto,
        ),
        (
            "offset",
            ShadowEstimator::Sampled,
            ShadowFilter::Bilinear,
            ReceiverTest::Offset,
        ),
    ];
    let scenes = [
        "cubes-toward-light",
        "leg-toward-light",
        "game-level",
        "hard-grazing",
        "hard-static-silhouette",
    ];
    for name in scenes {
        let scene = builtin(name, &BuiltinOptions::default()).unwrap();
        for (what, estimator, filter, receiver) in variants {
            let at = |static_layer| RenderSettings {
                shadow_estimator: estimator,
                shadow_filter: filter,
                receiver,
                ..settings(static_layer)
            };
            let lists = render_with(&mut renderer, &scene, &at(false));
            let layer = render_with(&mut renderer, &scene, &at(true));
            assert_eq!(lists.stats.static_layer_bytes, 0);
            assert_eq!(layer.stats.static_layer_bytes, 256 * 256 * 8);
            assert!(
                layer.stats.fragments < lists.stats.fragments,
                "{name}: the static triangles' {} fragments stayed in the lists",
                lists.stats.fragments
            );
            let differing = (lists.image.rgb.iter())
                .zip(&layer.image.rgb)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(
                differing, 0,
                "{name}, {what}: {differing} channel values differ from the lists' image"
            );
            if what == "sampled" && name == "cubes-toward-light" {
                // The lists and the layer share the range lookup, so their agreement cannot
                // see it break: the layer's image must also be as near the ray tracer's (the
                // same samples, no shadow map) as texel-sized shadow edges allow. Measured
                // (lavapipe, 2026-12-07): RMSE 0.0060; with a range that shadows past its
                // end time (the mutant `lighting-lookup-range-past-its-end`, which the lists
                // share) 0.0164.
                let rmse = rmse_against_the_ray_tracer(&scene, &at(true), &layer.image);
                assert!(
                    rmse < 0.01,
                    "{name}, {what}: RMSE {rmse} against the ray tracer"
                );
            }
        }
    }
    assert_no_validation_messages(&ctx);
}
