//! The scene file end to end: the documented example, names, unknown fields, the format
//! field, refusals naming their object, and models loaded relative to the file.

use std::path::Path;

use glam::Vec3;

use super::{load_scene_file, parse_scene_json};
use crate::scene::{Light, Scene, SceneError};

const EXAMPLE: &str = include_str!("../../../../docs/examples/two-triangles.json");
const DOC: &str = include_str!("../../../../docs/scene-format.md");

fn parse_str(text: &str) -> Result<Scene, SceneError> {
    parse_scene_json(text, Path::new("."), "test.json")
}

fn invalid_message(text: &str) -> String {
    match parse_str(text) {
        Err(SceneError::Invalid(m)) => m,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

fn json_message(text: &str) -> String {
    match parse_str(text) {
        Err(e @ SceneError::Json { .. }) => e.to_string(),
        other => panic!("expected Json error, got {other:?}"),
    }
}

#[test]
fn documented_example_parses_and_is_in_the_doc() {
    assert!(
        DOC.contains(EXAMPLE.trim()),
        "docs/scene-format.md must show the example verbatim"
    );
    let s = parse_str(EXAMPLE).unwrap();
    assert_eq!(s.name, "two-triangles");
    assert_eq!(s.triangle_count(), 2);
    assert_eq!(s.ambient, 0.05);
    assert_eq!(s.camera.up, Vec3::Y);
    let blade = &s.meshes[1];
    // t1 inherits nothing it overrides: moved by +2 in x, spun 90 degrees about +Y.
    assert_eq!(centre(&blade.t0), Vec3::new(-1.0, 1.0, 1.0 / 6.0));
    assert!(
        (blade.t1[0] - Vec3::new(1.5, 1.0, 0.5)).length() < 1e-5,
        "{}",
        blade.t1[0]
    );
    let Light::Directional(d) = &s.light else {
        panic!("directional expected")
    };
    assert!((d.direction.length() - 1.0).abs() < 1e-6);
}

fn centre(points: &[Vec3]) -> Vec3 {
    points.iter().sum::<Vec3>() / points.len() as f32
}

#[test]
fn name_falls_back_to_the_source_stem() {
    let text = EXAMPLE.replace("\"name\": \"two-triangles\",", "");
    let s = parse_scene_json(&text, Path::new("."), "dir/my-scene.json").unwrap();
    assert_eq!(s.name, "my-scene");
}

#[test]
fn unknown_fields_are_errors_naming_the_field() {
    let m = json_message(&EXAMPLE.replace("\"fov_y_deg\"", "\"fov_y_degs\""));
    assert!(m.contains("fov_y_degs") && m.contains("line"), "{m}");
    let m = json_message(&EXAMPLE.replace("\"irradiance\"", "\"irradience\""));
    assert!(m.contains("irradience"), "{m}");
    let m = json_message(&EXAMPLE.replace("\"translation\": [1", "\"translate\": [1"));
    assert!(m.contains("translate"), "{m}");
}

#[test]
fn format_is_required_and_checked() {
    let m = invalid_message(&EXAMPLE.replace("\"format\": \"motion-shadows-scene/1\",", ""));
    assert!(m.contains("missing field \"format\""), "{m}");
    let m = invalid_message(&EXAMPLE.replace("scene/1", "scene/2"));
    assert!(m.contains("scene/2"), "{m}");
    let m = json_message("{ \"format\": ");
    assert!(m.contains("test.json") && m.contains("line 1"), "{m}");
}

#[test]
fn bad_values_name_the_object() {
    let m = invalid_message(&EXAMPLE.replace("\"fov_y_deg\": 45", "\"fov_y_deg\": -45"));
    assert!(m.contains("camera") && m.contains("fov_y_deg"), "{m}");

    let short_t1 = EXAMPLE.replace(
        "{ \"t0\": [[-0.5, 0, 0.5], [0.5, 0, 0.5], [0, 0, -0.5]] }",
        "{ \"t0\": [[-0.5, 0, 0.5], [0.5, 0, 0.5], [0, 0, -0.5]], \"t1\": [[0, 0, 0]] }",
    );
    let m = invalid_message(&short_t1);
    assert!(
        m.contains("object #1") && m.contains("\"blade\"") && m.contains("t1 has 1"),
        "{m}"
    );

    let m = invalid_message(&EXAMPLE.replace("[0.9, 0.3, 0.2]", "[1.9, 0.3, 0.2]"));
    assert!(
        m.contains("mesh #1") && m.contains("blade") && m.contains("albedo"),
        "{m}"
    );

    let m = invalid_message(&EXAMPLE.replace(
        "\"rotation_deg\": 90",
        "\"rotation_deg\": 90, \"scale\": [1, -1, 1]",
    ));
    assert!(m.contains("blade") && m.contains("t1.scale"), "{m}");
}

#[test]
fn gltf_objects_load_relative_to_the_scene_file() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models");
    let scene = |spec: &str| {
        EXAMPLE.replace(
            "{ \"triangles\": { \"t0\": [[-4, 0, 3], [4, 0, 3], [0, 0, -4]] } }",
            &format!("{{ \"gltf\": {spec} }}"),
        )
    };
    let load = |spec: &str| parse_scene_json(&scene(spec), &models, "test.json");
    let seconds = load(
        r#"{ "path": "CesiumMan.gltf", "animation": 0, "time": 0.5, "shutter": 0.0208333333 }"#,
    )
    .unwrap();
    assert_eq!(seconds.meshes[0].triangle_count(), 4672);
    assert_ne!(seconds.meshes[0].t0, seconds.meshes[0].t1);
    // 180 degrees at 24 fps is the same 1/48 s.
    let angle = load(
        r#"{ "path": "CesiumMan.gltf", "animation": 0, "time": 0.5, "shutter_angle_deg": 180, "fps": 24 }"#,
    )
    .unwrap();
    let (a, b) = (&seconds.meshes[0], &angle.meshes[0]);
    assert!(
        a.t1.iter()
            .zip(&b.t1)
            .all(|(p, q)| (*p - *q).length() < 1e-6)
    );
    let fox =
        load(r#"{ "path": "Fox.glb", "animation": "Walk", "shutter": 0.02, "subdivide": 1 }"#)
            .unwrap();
    assert_eq!(fox.meshes[0].triangle_count(), 4 * 576);

    let m = invalid_message(&scene(r#"{ "path": "Fox.glb", "animation": "Walk" }"#));
    assert!(m.contains("floor") && m.contains("shutter"), "{m}");
    let m = json_message(&scene(r#"{ "path": "Fox.glb", "shuter": 0.1 }"#));
    assert!(m.contains("shuter"), "{m}");
    match load(r#"{ "path": "Fox.glb", "animation": "Trot", "shutter": 0.1 }"#) {
        Err(e @ SceneError::Gltf { .. }) => {
            let m = e.to_string();
            assert!(m.contains("floor") && m.contains("Survey"), "{m}");
        }
        other => panic!("expected a glTF error, got {other:?}"),
    }
}

#[test]
fn obj_objects_load_relative_to_the_scene_file() {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!(
        "motion-shadows-scene-test-{}-{nanos}",
        std::process::id()
    ));
    std::fs::create_dir_all(dir.join("models")).unwrap();
    // Two models (a quad and a triangle) and a missing material library, which is ignored.
    let obj = "mtllib missing.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nf 1 2 3 4\n\
               o tri\nv 0 1 0\nv 1 1 0\nv 0 1 -1\nf 5 6 7\n";
    std::fs::write(dir.join("models/tiny.obj"), obj).unwrap();
    let scene = |mesh: &str| {
        EXAMPLE.replace(
            "{ \"triangles\": { \"t0\": [[-4, 0, 3], [4, 0, 3], [0, 0, -4]] } }",
            &format!("{{ \"obj\": {mesh:?} }}"),
        )
    };
    let path = dir.join("scene.json");
    std::fs::write(&path, scene("models/tiny.obj")).unwrap();
    let s = load_scene_file(&path).unwrap();
    let floor = &s.meshes[0];
    assert_eq!(floor.triangle_count(), 3);
    assert_eq!(floor.t0, floor.t1);
    let normal = (floor.t0[1] - floor.t0[0]).cross(floor.t0[2] - floor.t0[0]);
    assert!(normal.y > 0.0, "OBJ winding must be kept");

    std::fs::write(&path, scene("models/absent.obj")).unwrap();
    match load_scene_file(&path) {
        Err(e @ SceneError::Obj { .. }) => {
            let m = e.to_string();
            assert!(
                m.contains("absent.obj") && m.contains("object #0") && m.contains("floor"),
                "{m}"
            );
        }
        other => panic!("expected Obj error, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();

    assert!(matches!(
        load_scene_file(&dir.join("scene.json")),
        Err(SceneError::Io { .. })
    ));
}
