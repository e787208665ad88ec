//! Index types, primitive modes and mirroring nodes, checked on a unit square in the xy
//! plane facing +z.

use glam::Vec3;
use serde_json::{Value, json};

use super::super::{GltfOptions, load_gltf_motion};
use super::builder::{Builder, write_temp};
use crate::scene::{Mesh, SceneError};

/// Corners of the unit square, counter-clockwise from +z.
const SQUARE: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// A one-node model of the square's corners; `indices`: (values, bytes per index) or none.
fn model(mode: u32, indices: Option<(&[u32], usize)>, node: Value) -> String {
    let mut b = Builder::default();
    let flat: Vec<f32> = SQUARE.iter().flatten().copied().collect();
    let position = b.floats(&flat, "VEC3");
    let mut primitive = json!({ "attributes": { "POSITION": position }, "mode": mode });
    if let Some((values, bytes)) = indices {
        primitive["indices"] = json!(b.integers(values, "SCALAR", bytes));
    }
    let mut node = node;
    node["mesh"] = json!(0);
    b.finish(json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [node],
        "meshes": [{ "primitives": [primitive] }]
    }))
}

fn load(text: &str) -> Result<Vec<Mesh>, SceneError> {
    let path = write_temp("square.gltf", text);
    let result = load_gltf_motion(&path, &GltfOptions::default());
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    result
}

/// Total area and whether every triangle faces `facing`.
fn area_facing(m: &Mesh, facing: Vec3) -> (f32, bool) {
    m.t0.chunks_exact(3).fold((0.0, true), |(area, all), t| {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        (area + n.length() / 2.0, all && n.dot(facing) > 0.0)
    })
}

#[test]
fn every_index_type_strips_and_fans_give_the_square_facing_forward() {
    let quad: &[u32] = &[0, 1, 2, 0, 2, 3];
    let cases: Vec<(&str, String)> = vec![
        ("u8", model(4, Some((quad, 1)), json!({}))),
        ("u16", model(4, Some((quad, 2)), json!({}))),
        ("u32", model(4, Some((quad, 4)), json!({}))),
        // Strip 0 1 3 2: triangles (0 1 3) and, reversed as the second, (1 2 3).
        ("strip", model(5, Some((&[0, 1, 3, 2], 2)), json!({}))),
        // Fan around 0 through 1 2 3.
        ("fan", model(6, None, json!({}))),
    ];
    for (label, text) in cases {
        let meshes = load(&text).unwrap();
        assert_eq!(meshes[0].triangle_count(), 2, "{label}");
        let (area, forward) = area_facing(&meshes[0], Vec3::Z);
        assert!((area - 1.0).abs() < 1e-6 && forward, "{label}: area {area}");
    }
    // Not indexed: the first three corners only.
    let meshes = load(&model(4, None, json!({}))).unwrap();
    assert_eq!(meshes[0].triangle_count(), 1);
}

#[test]
fn a_mirroring_node_keeps_the_triangles_facing_out() {
    // Mirrored in x the square lies in x in [-1, 0], still in the plane z = 0 and still
    // seen from +z as its front; listed as is, its corners would turn clockwise.
    let text = model(
        4,
        Some((&[0, 1, 2, 0, 2, 3], 2)),
        json!({ "scale": [-1.0, 1.0, 1.0] }),
    );
    let m = &load(&text).unwrap()[0];
    assert!(m.t0.iter().all(|p| p.x <= 0.0));
    let (area, forward) = area_facing(m, Vec3::Z);
    assert!((area - 1.0).abs() < 1e-6 && forward);
}

#[test]
fn points_lines_and_bad_indices_are_refused() {
    let points = load(&model(0, None, json!({}))).unwrap_err().to_string();
    assert!(
        points.contains("Points") && points.contains("not supported"),
        "{points}"
    );
    let bad = load(&model(4, Some((&[0, 1, 9], 1)), json!({})))
        .unwrap_err()
        .to_string();
    assert!(bad.contains("vertex index 9 out of range"), "{bad}");
}
