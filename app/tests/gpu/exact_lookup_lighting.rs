//! The lighting pass reads the temporal map's depth lines; a map built for the exact lookup
//! (`Lookup::Exact`: ranges over the whole shutter at the triangles' depth bounds) holds none,
//! so the pass refuses it by name instead of shading from them.

use crate::support::frame::render_draws;
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::technique::{LightView, LightingView, Lookup};
use motion_shadows_app::render::upload::{SceneGeometry, camera_view, light_view};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

const SIZE: (u32, u32) = (32, 24);

#[test]
fn the_lighting_pass_refuses_a_map_built_for_the_exact_lookup() {
    let ctx = context();
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).expect("scene");
    let geometry = SceneGeometry::upload(&ctx, &scene).expect("upload");
    let view = LightingView {
        camera: camera_view(&scene, SIZE),
        seed: 1,
        ambient: scene.ambient,
        estimator: Default::default(),
        filter: Default::default(),
    };
    let depth_line = light_view(&scene, SIZE);
    render_draws(&ctx, &geometry.draws, &depth_line, &view, SIZE, SIZE, 1)
        .expect("the depth-line map lights the frame");
    let exact = LightView {
        lookup: Lookup::Exact,
        ..depth_line
    };
    let refused = render_draws(&ctx, &geometry.draws, &exact, &view, SIZE, SIZE, 1)
        .err()
        .expect("an exact map is refused by the lighting pass");
    assert!(refused.to_string().contains("Lookup::Exact"), "{refused}");
    drop(geometry);
    assert_no_validation_messages(&ctx);
}
