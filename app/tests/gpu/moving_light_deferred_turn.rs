//! The temporal deferred mask under a turning light (issue 38): `moving-light`'s flashlight
//! turned during the shutter, against the exact lit share of the shutter
//! (`raytrace::deferred`, which shares nothing with the map), over the pixels the cone holds
//! at both ends.
//!
//! The map is built in the light's moving frame: the world each receiver's t = 1 end is taken
//! into (`ms_light_frame_end`) is the real one turned with the light, so a receiver's plane
//! turns there too. A mask that kept the G-buffer's normal as it is for the normal offset and
//! the plane test (as it did before this test) tests a plane the receiver is not on: 0.0133
//! with the flashlight carried and tipped 20 degrees, 0.0011 with the normal turned
//! (lavapipe, 2026-12-07).
//!
//! The flashlight tips about x, the axis the box slides along: a caster moving across the
//! turn's axis leaves the map's blend of its two ends' clip positions by
//! `t (1 - t) P (V1 - V0) (p1 - p0)` (docs/src/scene-format.md#a-moving-light), an error of
//! the map, not of the mask, measured in docs/src/deferred-frame.md#a-turning-light.

use crate::moving_light_deferred_tsm::{deferred, held_in_cone, scene, settings};
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows_app::compare::mask_error;
use motion_shadows_app::raytrace::deferred::render_truth;
use motion_shadows_app::render::Renderer;
use motion_shadows_app::render::deferred::DeferredMethod;
use motion_shadows_app::scene::{Light, Scene};

/// `moving-light`'s flashlight carried 2 units and tipped by
/// `turn_deg` about x: its cone sweeps along the floor, whose plane turns in the light's
/// moving frame.
fn turning_flashlight(turn_deg: f32) -> Scene {
    let mut scene = scene(true);
    let Light::Spot(light) = &mut scene.light else {
        panic!("spot expected")
    };
    let direction = glam::Quat::from_rotation_x(turn_deg.to_radians()) * light.direction;
    let end = light.t1.as_mut().expect("moving-light's light moves");
    end.direction = direction;
    scene
}

/// The target, 0.005, for the flashlight carried 2 units and tipped 20 degrees, with
/// the mask's own receiver test (`--receiver auto`: the offset where a pixel moves, the plane
/// test where it stands still, both with the normal turned with the light's frame).
#[test]
fn the_temporal_mask_takes_a_turning_light() {
    let ctx = context();
    let settings = settings();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let turning = turning_flashlight(20.0);
    let truth = render_truth(
        &turning,
        &settings,
        &deferred(DeferredMethod::Raytrace),
        &mut |_| {},
    )
    .unwrap();
    let held = held_in_cone(&turning, &truth);
    let mask = renderer
        .render_deferred(
            &turning,
            &settings,
            &deferred(DeferredMethod::Temporal),
            &mut |_| {},
        )
        .unwrap_or_else(|e| panic!("the temporal mask under a turning light: {e}"));
    let error = mask_error(&mask.lit, &truth.lit, &held);
    eprintln!(
        "temporal mask, flashlight carried and tipped 20 degrees: RMSE {:.5} against the \
         exact truth ({} pixels, {} shadowed)",
        error.rmse, error.pixels, error.shadowed_pixels
    );
    assert!(
        error.pixels > 1000 && error.shadowed_pixels > 100,
        "{error:?}"
    );
    assert!(error.rmse < 0.005, "{error:?}");
    drop(renderer);
    assert_no_validation_messages(&ctx);
}
