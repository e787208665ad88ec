//! glTF keyframe values: refused where they are read, like every other number.

use base64::Engine as _;
use serde_json::json;

use super::{SMALL, run, s, scene_json, temp_dir};

/// A glTF model of one triangle whose node is rotated by a LINEAR channel with `keys`
/// (x, y, z, w per key, at times 0 and 1).
fn rotated_triangle(keys: [[f32; 4]; 2]) -> String {
    let mut bin = Vec::new();
    let positions: [f32; 9] = [-0.5, 1.0, -0.5, 0.5, 1.0, -0.5, 0.0, 1.0, 0.5];
    let times: [f32; 2] = [0.0, 1.0];
    for v in positions.iter().chain(&times).chain(keys.iter().flatten()) {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "buffers": [{ "byteLength": bin.len(),
                      "uri": format!("data:application/octet-stream;base64,{data}") }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 8 },
            { "buffer": 0, "byteOffset": 44, "byteLength": 32 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [-0.5, 1.0, -0.5], "max": [0.5, 1.0, 0.5] },
            { "bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR",
              "min": [0.0], "max": [1.0] },
            { "bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC4" }
        ],
        "animations": [{
            "samplers": [{ "input": 1, "output": 2, "interpolation": "LINEAR" }],
            "channels": [{ "sampler": 0, "target": { "node": 0, "path": "rotation" } }]
        }]
    })
    .to_string()
}

/// Case 4: a NaN rotation key was normalised into the identity, so the model rendered
/// unrotated without a word, while a NaN translation was refused. Every key value is
/// checked as it is read now, and a rotation of length 0 (no direction) too.
#[test]
fn non_finite_and_zero_rotation_keys_are_refused() {
    let dir = temp_dir("rotation-keys");
    let identity = [0.0, 0.0, 0.0, 1.0];
    let cases = [
        (
            "nan",
            [identity, [f32::NAN, 0.0, 0.0, 1.0]],
            "not a finite number",
        ),
        ("zero", [identity, [0.0; 4]], "length 0"),
    ];
    for (name, keys, needle) in cases {
        let model = dir.join(format!("{name}.gltf"));
        std::fs::write(&model, rotated_triangle(keys)).unwrap();
        let object = format!(
            r#"{{ "name": "blade", "albedo": [0.5, 0.5, 0.5], "mesh": {{ "gltf": {{
                 "path": {:?}, "animation": 0, "time": 0.4, "shutter": 0.2 }} }} }}"#,
            s(&model)
        );
        let scene = dir.join(format!("{name}.json"));
        std::fs::write(&scene, scene_json(name, &[object])).unwrap();
        let mut args = vec![
            "render",
            "--scene-file",
            s(&scene),
            "--method",
            "raytrace",
            "--out",
            s(&dir),
        ];
        args.extend(SMALL);
        run(&args).refused(&["animation 0 channel 0", "rotation", needle]);
    }
    // The same model with good keys renders.
    let model = dir.join("good.gltf");
    std::fs::write(
        &model,
        rotated_triangle([identity, [0.0, 0.38268343, 0.0, 0.9238795]]),
    )
    .unwrap();
    let object = format!(
        r#"{{ "name": "blade", "albedo": [0.5, 0.5, 0.5], "mesh": {{ "gltf": {{
             "path": {:?}, "animation": 0, "time": 0.4, "shutter": 0.2 }} }} }}"#,
        s(&model)
    );
    let scene = dir.join("good.json");
    std::fs::write(&scene, scene_json("good", &[object])).unwrap();
    let mut args = vec![
        "render",
        "--scene-file",
        s(&scene),
        "--method",
        "raytrace",
        "--out",
        s(&dir),
    ];
    args.extend(SMALL);
    let r = run(&args);
    assert!(r.succeeded(), "{}", r.stderr());
    std::fs::remove_dir_all(&dir).ok();
}
