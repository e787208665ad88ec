//! Clear errors instead of crashes or silent loss.

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::technique::TemporalShadowMap;
use motion_shadows_app::Error as AppError;
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

#[test]
fn buffers_beyond_the_device_limit_are_refused_with_figures() {
    let ctx = context();
    let err = TemporalShadowMap::new(&ctx, 64, 64, u32::MAX - 1, 16)
        .err()
        .expect("must fail");
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
