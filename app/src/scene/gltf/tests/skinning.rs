//! A two-segment bar skinned to two joints; the second joint turns about z (and moves in
//! y) by keyframes. Every skinned vertex is then a blend of itself (joint 0, at rest) and
//! its rotation about the second joint's pivot, known in closed form.

use glam::{Quat, Vec3};
use serde_json::json;

use super::super::{AnimationRef, GltfOptions, load_gltf_motion};
use super::builder::{Builder, write_temp};

/// The bar: x in {0, 1, 2}, y in {0, 0.2}, counter-clockwise from +z.
const POSITIONS: [[f32; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [0.0, 0.2, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 0.2, 0.0],
    [2.0, 0.0, 0.0],
    [2.0, 0.2, 0.0],
];
const INDICES: [u32; 12] = [0, 2, 3, 0, 3, 1, 2, 4, 5, 2, 5, 3];
/// Normalised weight of joint 1 per vertex. The far end's file weights are (0.5, 0): a sum
/// of 0.5, which the loader must scale to 1.
const JOINT1: [f32; 6] = [0.0, 0.0, 0.5, 0.5, 1.0, 1.0];

fn z_quat(deg: f32) -> [f32; 4] {
    Quat::from_rotation_z(deg.to_radians()).to_array()
}

/// Joint 1's keys at 0, 0.5 and 1 s: angles 0, 45, 90 degrees; translation y 0, 0.2, 0.4
/// (CUBICSPLINE: y stays 0 but leaves the first key with slope 1, see `cubic`).
fn model(interpolation: &str) -> String {
    let mut b = Builder::default();
    let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
    let position = b.floats(&flat(&POSITIONS), "VEC3");
    let indices = b.integers(&INDICES, "SCALAR", 2);
    let joints = b.integers(
        &[
            0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0,
        ],
        "VEC4",
        1,
    );
    let weights = b.floats(
        &[
            1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.5,
            0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0,
        ],
        "VEC4",
    );
    let mut ibm = glam::Mat4::IDENTITY.to_cols_array().to_vec();
    ibm.extend(glam::Mat4::from_translation(Vec3::new(-1.0, 0.0, 0.0)).to_cols_array());
    let ibm = b.floats(&ibm, "MAT4");
    let times = b.floats(&[0.0, 0.5, 1.0], "SCALAR");
    let q = [z_quat(0.0), z_quat(45.0), z_quat(90.0)];
    let (rotations, translations): (Vec<f32>, Vec<f32>) = if interpolation == "CUBICSPLINE" {
        // Per key: in-tangent, value, out-tangent. Rotation tangents are each segment's
        // chord over its 0.5 s, so the Hermite curve is the straight line between the
        // keys' quaternions (normalised afterwards): a normalised lerp, not a slerp.
        let chord =
            |a: [f32; 4], b: [f32; 4]| -> [f32; 4] { std::array::from_fn(|i| (b[i] - a[i]) / 0.5) };
        let zero = [0.0; 4];
        let (c01, c12) = (chord(q[0], q[1]), chord(q[1], q[2]));
        let r = [zero, q[0], c01, c01, q[1], c12, c12, q[2], zero].concat();
        let one = [1.0, 0.0, 0.0];
        let z3 = [0.0; 3];
        let t = [z3, one, [0.0, 1.0, 0.0], z3, one, z3, z3, one, z3].concat();
        (r, t)
    } else {
        let t = [1.0, 0.0, 0.0, 1.0, 0.2, 0.0, 1.0, 0.4, 0.0];
        (q.concat(), t.to_vec())
    };
    let rotations = b.floats(&rotations, "VEC4");
    let translations = b.floats(&translations, "VEC3");
    b.finish(json!({
        "scene": 0,
        "scenes": [{ "nodes": [0, 2] }],
        "nodes": [
            { "children": [1] },
            { "translation": [1.0, 0.0, 0.0] },
            // A skinned mesh's own node transform must not apply.
            { "mesh": 0, "skin": 0, "translation": [5.0, 0.0, 0.0] }
        ],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weights },
            "indices": indices
        }] }],
        "skins": [{ "joints": [0, 1], "inverseBindMatrices": ibm }],
        "animations": [{
            "samplers": [
                { "input": times, "output": rotations, "interpolation": interpolation },
                { "input": times, "output": translations, "interpolation": interpolation }
            ],
            "channels": [
                { "sampler": 0, "target": { "node": 1, "path": "rotation" } },
                { "sampler": 1, "target": { "node": 1, "path": "translation" } }
            ]
        }]
    }))
}

/// Where vertex `v` goes with joint 1 turned by `deg` about z and its pivot at (1, dy, 0).
fn expected(v: usize, deg: f32, dy: f32) -> Vec3 {
    let p = Vec3::from(POSITIONS[v]);
    let (s, c) = deg.to_radians().sin_cos();
    let r = p - Vec3::X;
    let turned = Vec3::new(c * r.x - s * r.y, s * r.x + c * r.y, r.z) + Vec3::new(1.0, dy, 0.0);
    p * (1.0 - JOINT1[v]) + turned * JOINT1[v]
}

/// Shutter from 0.1 s to 0.75 s.
fn check(interpolation: &str, open: (f32, f32), close: (f32, f32)) {
    let path = write_temp("bar.gltf", &model(interpolation));
    let options = GltfOptions {
        animation: Some(AnimationRef::Index(0)),
        time: 0.1,
        shutter: 0.65,
        subdivide: 0,
    };
    let meshes = load_gltf_motion(&path, &options).unwrap();
    assert_eq!(meshes.len(), 1);
    let m = &meshes[0];
    assert_eq!(m.triangle_count(), 4);
    for (slot, &v) in INDICES.iter().enumerate() {
        let v = v as usize;
        for (got, (deg, dy), when) in [(m.t0[slot], open, "t0"), (m.t1[slot], close, "t1")] {
            let want = expected(v, deg, dy);
            assert!(
                (got - want).length() < 1e-5,
                "{interpolation} {when} vertex {v}: {got} != {want}"
            );
        }
    }
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn linear_keys_turn_the_second_segment_about_its_joint() {
    // 0.1 s: a fifth of the way to 45 degrees and to y 0.2; 0.75 s: halfway from 45 to 90
    // and from 0.2 to 0.4.
    check("LINEAR", (9.0, 0.04), (67.5, 0.3));
}

#[test]
fn step_keys_hold_the_previous_key() {
    check("STEP", (0.0, 0.0), (45.0, 0.2));
}

#[test]
fn cubic_spline_keys_follow_the_hermite_curve() {
    // 0.1 s is s = 0.2 of the first segment. Rotation: the normalised quaternion
    // (1 - s) q(0) + s q(45), whose angle is 2 atan2(s sin 22.5, (1 - s) + s cos 22.5)
    // (8.97 degrees, not the slerp's 9). Translation y: values 0, out-tangent 1, so
    // dt (s^3 - 2 s^2 + s) = 0.5 x 0.128 = 0.064. At 0.75 s (s = 0.5 of the second segment)
    // the normalised midpoint of q(45) and q(90) is q(67.5), and y stays 0.
    let s = 0.2f32;
    let half = 22.5f32.to_radians();
    let open_deg = 2.0 * (s * half.sin()).atan2((1.0 - s) + s * half.cos());
    check("CUBICSPLINE", (open_deg.to_degrees(), 0.064), (67.5, 0.0));
}

#[test]
fn rest_pose_is_the_bind_pose_and_zero_shutter_does_not_move() {
    let path = write_temp("bar.gltf", &model("LINEAR"));
    let rest = load_gltf_motion(&path, &GltfOptions::default()).unwrap();
    let flat: Vec<Vec3> = INDICES
        .iter()
        .map(|&v| Vec3::from(POSITIONS[v as usize]))
        .collect();
    assert_eq!(rest[0].t0, flat);
    assert_eq!(rest[0].t1, flat);
    let frozen = GltfOptions {
        animation: Some(AnimationRef::Index(0)),
        time: 0.3,
        ..GltfOptions::default()
    };
    let m = &load_gltf_motion(&path, &frozen).unwrap()[0];
    assert_eq!(m.t0, m.t1);
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}
