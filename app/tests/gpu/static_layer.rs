//! The static layer (the nearest static triangle per texel, in place of static triangles'
//! fragments and ranges) answers every lookup as the lists do: the same images, sampled and
//! analytic, filtered and not, with either receiver test, on built-in scenes whose receivers
//! and casters are both static and moving. The lists are the oracle (their construction is
//! checked against CPU models in exact_prisms.rs, generation.rs and analytic.rs).

use crate::support::gpu::{assert_no_validation_messages, context, render};
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
            let lists = render(&ctx, &scene, &at(false));
            let layer = render(&ctx, &scene, &at(true));
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
        }
    }
    assert_no_validation_messages(&ctx);
}
