//! One triangle with one morph target: position = base + w x delta, with w from the mesh's
//! default weights at rest and from a LINEAR weight channel when animated.

use glam::Vec3;
use serde_json::json;

use super::super::{AnimationRef, GltfOptions, load_gltf_motion};
use super::builder::{Builder, write_temp};

const BASE: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];
const DELTA: [Vec3; 3] = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 2.0), Vec3::X];

fn model() -> String {
    let mut b = Builder::default();
    let flat = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
    let position = b.floats(&flat(&BASE), "VEC3");
    let delta = b.floats(&flat(&DELTA), "VEC3");
    let times = b.floats(&[0.0, 2.0], "SCALAR");
    let weights = b.floats(&[0.0, 1.0], "SCALAR");
    b.finish(json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "translation": [0.0, 10.0, 0.0] }],
        "meshes": [{
            "primitives": [{ "attributes": { "POSITION": position }, "targets": [{ "POSITION": delta }] }],
            "weights": [0.25]
        }],
        "animations": [{
            "name": "grow",
            "samplers": [{ "input": times, "output": weights }],
            "channels": [{ "sampler": 0, "target": { "node": 0, "path": "weights" } }]
        }]
    }))
}

fn posed(w: f32) -> Vec<Vec3> {
    (0..3)
        .map(|i| BASE[i] + w * DELTA[i] + Vec3::new(0.0, 10.0, 0.0))
        .collect()
}

#[test]
fn morph_weights_move_positions_along_the_target_deltas() {
    let path = write_temp("morph.gltf", &model());
    let rest = load_gltf_motion(&path, &GltfOptions::default()).unwrap();
    assert_eq!(rest[0].t0, posed(0.25), "mesh default weights at rest");
    assert_eq!(rest[0].t1, posed(0.25));
    // Weight w(t) = t / 2: 0.25 at 0.5 s, 0.75 at 1.5 s.
    let options = GltfOptions {
        animation: Some(AnimationRef::Name("grow".into())),
        time: 0.5,
        shutter: 1.0,
        subdivide: 0,
    };
    let m = &load_gltf_motion(&path, &options).unwrap()[0];
    for (got, want) in
        m.t0.iter()
            .zip(posed(0.25))
            .chain(m.t1.iter().zip(posed(0.75)))
    {
        assert!((*got - want).length() < 1e-6, "{got} != {want}");
    }
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}
