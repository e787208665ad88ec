//! The camera's `t1` pose in the scene file: fields it leaves out taken from t = 0, no `t1` a
//! still camera, unknown fields and degenerate poses refused by name; the camera between the
//! two poses against closed forms.

use std::path::Path;

use glam::Vec3;

use super::{parse_scene_json, scene_to_json};
use crate::scene::{CameraPose, Scene, SceneError};

const CAMERA: &str =
    r#""position": [0, 4, 6], "target": [0, 0, 0], "fov_y_deg": 45, "near": 0.1, "far": 50"#;

fn scene(camera: &str) -> Result<Scene, SceneError> {
    let text = format!(
        r#"{{"format": "motion-shadows-scene/1",
            "camera": {camera},
            "light": {{"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                "cone_angle_deg": 40, "intensity": 10, "near": 0.5, "far": 20}},
            "objects": [{{"albedo": [0.5, 0.5, 0.5], "mesh": {{"plane": {{"size": [4, 4]}}}}}}]}}"#
    );
    parse_scene_json(&text, Path::new("."), "camera.json")
}

#[test]
fn a_camera_without_t1_is_still_and_is_its_own_pose_at_every_time() {
    let s = scene(&format!("{{{CAMERA}}}")).unwrap();
    assert!(!s.camera.moves());
    assert_eq!(s.camera.t1, None);
    assert_eq!(s.camera.at(0.7), s.camera);
}

#[test]
fn a_camera_t1_takes_what_it_leaves_out_from_t0_and_blends_linearly() {
    let s = scene(&format!(
        "{{{CAMERA}, \"t1\": {{\"position\": [4, 4, 6], \"target\": [2, 0, 0]}}}}"
    ))
    .unwrap();
    let end = CameraPose {
        position: Vec3::new(4.0, 4.0, 6.0),
        target: Vec3::new(2.0, 0.0, 0.0),
        up: Vec3::Y,
    };
    assert_eq!(s.camera.t1, Some(end));
    assert!(s.camera.moves());
    // A quarter of the way: position and target a quarter of their paths along, by hand.
    let quarter = s.camera.at(0.25);
    assert_eq!(quarter.position, Vec3::new(1.0, 4.0, 6.0));
    assert_eq!(quarter.target, Vec3::new(0.5, 0.0, 0.0));
    assert_eq!((quarter.up, quarter.t1), (Vec3::Y, None));
    assert_eq!(
        (quarter.fov_y_deg, quarter.near, quarter.far),
        (45.0, 0.1, 50.0)
    );
}

#[test]
fn unknown_fields_and_degenerate_camera_poses_are_refused_by_name() {
    let typo = scene(&format!("{{{CAMERA}, \"t1\": {{\"postion\": [3, 5, 0]}}}}"));
    let message = typo.unwrap_err().to_string();
    assert!(message.contains("postion"), "{message}");
    // Looking at itself at t = 1.
    let onto = scene(&format!(
        "{{{CAMERA}, \"t1\": {{\"position\": [0, 0, 0]}}}}"
    ));
    let message = onto.unwrap_err().to_string();
    assert!(message.contains("camera t1"), "{message}");
    // Fine at both ends, but the target passes through the eye a third of the way along.
    let through = scene(&format!(
        "{{{CAMERA}, \"t1\": {{\"position\": [0, 4, 6], \"target\": [0, 12, 18]}}}}"
    ));
    let message = through.unwrap_err().to_string();
    assert!(
        message.contains("camera t1") && message.contains("90 degrees"),
        "{message}"
    );
    // Up turned through the view direction half way (valid at both ends).
    let up_through = scene(&format!(
        "{{{CAMERA}, \"up\": [1, -2, -3], \"t1\": {{\"up\": [-1, -2, -3]}}}}"
    ));
    let message = up_through.unwrap_err().to_string();
    assert!(message.contains("camera at t = 0.5"), "{message}");
    let nan_up = scene(&format!("{{{CAMERA}, \"t1\": {{\"up\": [0, 0, 0]}}}}"));
    let message = nan_up.unwrap_err().to_string();
    assert!(message.contains("camera t1"), "{message}");
}

#[test]
fn the_camera_pan_built_in_round_trips_through_json_and_pans() {
    let options = crate::scene::BuiltinOptions::default();
    let file = crate::scene::builtin_file("camera-pan", &options).unwrap();
    let text = scene_to_json(&file);
    assert!(text.contains("\"t1\""), "{text}");
    let back = parse_scene_json(&text, Path::new("."), "camera-pan.json").unwrap();
    let built = crate::scene::builtin("camera-pan", &options).unwrap();
    assert_eq!(back, built);
    // The default scene's meshes, light and camera at t = 0; carried, not turned.
    let default = crate::scene::builtin("cubes-toward-light", &options).unwrap();
    assert_eq!(built.meshes, default.meshes);
    assert_eq!(built.light, default.light);
    assert_eq!(built.camera.at(0.0), default.camera);
    let end = built.camera.t1.unwrap();
    assert_eq!(
        end.position - built.camera.position,
        end.target - built.camera.target
    );
    assert!(end.position.x > built.camera.position.x);
}
