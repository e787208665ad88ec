//! Clear errors instead of crashes or silent loss.

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::glam::Vec3;
use motion_shadows::technique::{LightView, TemporalShadowMap};
use motion_shadows_app::Error as AppError;
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

/// (The node buffer is made for a path that stores fragments, here the static layer off.)
#[test]
fn buffers_beyond_the_device_limit_are_refused_with_figures() {
    let ctx = context();
    let mut map = TemporalShadowMap::new(&ctx, 64, 64, u32::MAX - 1, 16).expect("map");
    let light = LightView {
        static_layer: false,
        ..LightView::spot(Vec3::Y, Vec3::NEG_Y, 30.0, 1.0, 0.1, 10.0, (64, 64))
    };
    let err = map.prepare_for(&ctx, &light, None).expect_err("must fail");
    match &err {
        Error::DeviceLimit {
            count,
            element_bytes,
            limit_bytes,
            ..
        } => {
            assert_eq!(*count, (u32::MAX - 1) as u64);
            assert_eq!(*element_bytes, 16);
            assert_eq!(*limit_bytes, ctx.max_addressed_buffer_bytes());
        }
        other => panic!("expected DeviceLimit, got {other}"),
    }
    assert!(err.to_string().contains("bytes"));
    assert_no_validation_messages(&ctx);
}

#[test]
fn out_of_range_settings_are_rejected() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let mut renderer = Renderer::new(&ctx).unwrap();
    for bad in [
        RenderSettings {
            spp: 0,
            ..RenderSettings::default()
        },
        RenderSettings {
            spp: 65,
            ..RenderSettings::default()
        },
        RenderSettings {
            width: 0,
            ..RenderSettings::default()
        },
        RenderSettings {
            shadow_size: Some((0, 4)),
            ..RenderSettings::default()
        },
    ] {
        match renderer.render(&s, &bad, &mut |_| {}) {
            Err(AppError::InvalidArgument(message)) => assert!(!message.is_empty()),
            Err(other) => panic!("expected InvalidArgument, got {other}"),
            Ok(_) => panic!("{bad:?} must be rejected"),
        }
    }
    assert_no_validation_messages(&ctx);
}

/// A frame whose 32-bit fragment counter wrapped (2^32 fragments or more) is refused, never
/// sized or used from its meaningless figures. (The collection shader sets `wrapped` when it
/// hands out the count 2^32 - 1; producing 2^32 fragments is beyond a test's time.)
#[test]
fn a_wrapped_fragment_counter_is_an_error() {
    let ctx = context();
    let mut map = TemporalShadowMap::new(&ctx, 8, 8, 16, 16).unwrap();
    let counts = motion_shadows::technique::Counters {
        node_count: 5,
        node_capacity: 16,
        wrapped: 1,
        ..Default::default()
    };
    assert!(map.needs_more_room(&counts), "a wrapped count never fits");
    assert!(matches!(
        map.check_complete(&counts),
        Err(Error::FragmentCountOverflow)
    ));
    assert!(matches!(
        map.grow_to_fit(&ctx, &counts),
        Err(Error::FragmentCountOverflow)
    ));
    assert_no_validation_messages(&ctx);
}
