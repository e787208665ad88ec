//! The light's `t1` pose in the scene file: fields it leaves out taken from t = 0, no `t1` a
//! still light, unknown fields and too large a turn refused by name.

use std::path::Path;

use glam::Vec3;

use super::{parse_scene_json, scene_to_json};
use crate::scene::{DirectionalPose, Light, Scene, SceneError, SpotPose};

fn scene(light: &str) -> Result<Scene, SceneError> {
    let text = format!(
        r#"{{"format": "motion-shadows-scene/1",
            "camera": {{"position": [0, 4, 6], "target": [0, 0, 0], "fov_y_deg": 45, "near": 0.1, "far": 50}},
            "light": {light},
            "objects": [{{"albedo": [0.5, 0.5, 0.5], "mesh": {{"plane": {{"size": [4, 4]}}}}}}]}}"#
    );
    parse_scene_json(&text, Path::new("."), "light.json")
}

const SPOT: &str = r#""type": "spot", "position": [0, 5, 0], "direction": [0, -2, 0],
    "cone_angle_deg": 40, "intensity": 10, "near": 0.5, "far": 20"#;
const DIRECTIONAL: &str = r#""type": "directional", "direction": [0, -1, 0], "irradiance": 2,
    "center": [0, 0, 0], "half_extent": 5, "distance": 10, "near": 0.1, "far": 20"#;

#[test]
fn a_light_without_t1_is_still() {
    let s = scene(&format!("{{{SPOT}}}")).unwrap();
    assert!(!s.light.moves());
    let Light::Spot(spot) = &s.light else {
        panic!("spot expected")
    };
    assert_eq!(spot.t1, None);
}

#[test]
fn a_spot_t1_takes_what_it_leaves_out_from_t0() {
    let s = scene(&format!("{{{SPOT}, \"t1\": {{\"position\": [3, 5, 0]}}}}")).unwrap();
    let Light::Spot(spot) = &s.light else {
        panic!("spot expected")
    };
    let end = SpotPose {
        position: Vec3::new(3.0, 5.0, 0.0),
        direction: Vec3::NEG_Y,
    };
    assert_eq!(spot.t1, Some(end));
    assert!(s.light.moves());
}

#[test]
fn a_directional_t1_turns_and_keeps_its_centre() {
    let s = scene(&format!(
        "{{{DIRECTIONAL}, \"t1\": {{\"direction\": [1, -1, 0]}}}}"
    ))
    .unwrap();
    let Light::Directional(light) = &s.light else {
        panic!("directional expected")
    };
    let end = DirectionalPose {
        direction: Vec3::new(1.0, -1.0, 0.0).normalize(),
        center: Vec3::ZERO,
    };
    assert_eq!(light.t1, Some(end));
    // Its shadow camera sits `distance` back along the t = 1 direction.
    let expected = -end.direction * 10.0;
    assert!(
        light.eye_t1().abs_diff_eq(expected, 1e-6),
        "{}",
        light.eye_t1()
    );
}

#[test]
fn unknown_fields_and_right_angle_turns_are_refused_by_name() {
    let typo = scene(&format!("{{{SPOT}, \"t1\": {{\"positon\": [3, 5, 0]}}}}"));
    let message = typo.unwrap_err().to_string();
    assert!(message.contains("positon"), "{message}");
    let turned = scene(&format!("{{{SPOT}, \"t1\": {{\"direction\": [1, 0, 0]}}}}"));
    let message = turned.unwrap_err().to_string();
    assert!(
        message.contains("t1 direction") && message.contains("90"),
        "{message}"
    );
    let zero = scene(&format!(
        "{{{DIRECTIONAL}, \"t1\": {{\"direction\": [0, 0, 0]}}}}"
    ));
    let message = zero.unwrap_err().to_string();
    assert!(message.contains("t1 direction"), "{message}");
}

#[test]
fn the_moving_light_built_in_round_trips_through_json() {
    let options = crate::scene::BuiltinOptions::default();
    let file = crate::scene::builtin_file("moving-light", &options).unwrap();
    let text = scene_to_json(&file);
    assert!(text.contains("\"t1\""), "{text}");
    let back = parse_scene_json(&text, Path::new("."), "moving-light.json").unwrap();
    assert_eq!(
        back,
        crate::scene::builtin("moving-light", &options).unwrap()
    );
    assert!(back.light.moves());
}
