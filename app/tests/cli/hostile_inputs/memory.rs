//! Case 2: scenes inside the documented limits that no process here could build. They
//! aborted (`memory allocation of 3-6 GB failed`) mid-build under an address-space cap,
//! leaving `.partial-PID` files; now what they need is estimated from counts known before
//! building (accessor counts, cubes, subdivision) and they are refused with the figures.

use base64::Engine as _;
use serde_json::json;

use super::{listing, run, s, scene_json, temp_dir};

/// A glTF of a few hundred bytes whose index accessor has no buffer view (all zeros) but
/// for one sparse entry: 33 million triangles once expanded.
fn sparse_model() -> String {
    let mut bin = Vec::new();
    for v in [0.0f32, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.0] {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    bin.extend_from_slice(&0u32.to_le_bytes()); // the sparse index
    bin.extend_from_slice(&1u32.to_le_bytes()); // its value
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "buffers": [{ "byteLength": bin.len(),
                      "uri": format!("data:application/octet-stream;base64,{data}") }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 4 },
            { "buffer": 0, "byteOffset": 40, "byteLength": 4 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [0.0, 1.0, 0.0], "max": [1.0, 1.0, 1.0] },
            { "componentType": 5125, "count": 99_000_000, "type": "SCALAR",
              "sparse": { "count": 1,
                          "indices": { "bufferView": 1, "componentType": 5125 },
                          "values": { "bufferView": 2 } } }
        ]
    })
    .to_string()
}

/// Refused cleanly (exit status 1, no panic, no abort), naming the figures, with nothing
/// left in the output directory.
fn assert_refused_for_memory(args: &[&str], out: &std::path::Path) {
    let r = run(args);
    r.refused(&["triangles would need about", "GiB", "ulimit -v"]);
    assert_eq!(r.output.status.code(), Some(1), "{}", r.stderr());
    assert!(
        !out.exists() || listing(out).is_empty(),
        "{:?}",
        listing(out)
    );
}

#[test]
fn scenes_no_process_here_could_build_are_refused_with_figures() {
    let dir = temp_dir("memory");
    let out = dir.join("out");
    let model = dir.join("sparse.gltf");
    std::fs::write(&model, sparse_model()).unwrap();
    let object = format!(
        r#"{{ "name": "sparse", "albedo": [0.5, 0.5, 0.5],
             "mesh": {{ "gltf": {{ "path": {:?} }} }} }}"#,
        s(&model)
    );
    let scene = dir.join("sparse.json");
    std::fs::write(&scene, scene_json("sparse", &[object])).unwrap();
    for method in ["temporal", "raytrace"] {
        assert_refused_for_memory(
            &[
                "render",
                "--scene-file",
                s(&scene),
                "--method",
                method,
                "--out",
                s(&out),
            ],
            &out,
        );
    }
    // The documented largest cube count, and a character subdivided 6 times, ray traced.
    assert_refused_for_memory(
        &[
            "render",
            "--scene",
            "random-cubes",
            "--cubes",
            "2796192",
            "--out",
            s(&out),
        ],
        &out,
    );
    assert_refused_for_memory(
        &[
            "render",
            "--scene",
            "walker-toward-light",
            "--subdivide",
            "6",
            "--method",
            "raytrace",
            "--out",
            s(&out),
        ],
        &out,
    );
    std::fs::remove_dir_all(&dir).ok();
}
