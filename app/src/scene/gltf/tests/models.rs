//! The shipped models against the figures of assets/models/README.md (computed there with
//! an independent numpy parser and the Khronos validator).

use glam::Vec3;

use super::super::{AnimationRef, GltfOptions, load_gltf_motion};
use super::builder::asset;
use crate::scene::Mesh;

fn bounds(points: impl Iterator<Item = Vec3>) -> (Vec3, Vec3) {
    points.fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)))
}

fn near(got: (Vec3, Vec3), want: ([f32; 3], [f32; 3]), tol: f32) -> bool {
    (got.0 - Vec3::from(want.0)).abs().max_element() < tol
        && (got.1 - Vec3::from(want.1)).abs().max_element() < tol
}

fn posed(name: &str, animation: Option<AnimationRef>, time: f32, shutter: f32) -> Vec<Mesh> {
    let options = GltfOptions {
        animation,
        time,
        shutter,
        subdivide: 0,
    };
    load_gltf_motion(&asset(name), &options).unwrap()
}

/// Bounds over the clip's keys (every 1/24 s from 0 to `keys - 1` twenty-fourths).
fn key_bounds(name: &str, animation: AnimationRef, keys: usize) -> (Vec3, Vec3) {
    let all: Vec<Vec3> = (0..keys)
        .flat_map(|k| posed(name, Some(animation.clone()), k as f32 / 24.0, 0.0))
        .flat_map(|m| m.t0)
        .collect();
    bounds(all.into_iter())
}

#[test]
fn cesium_man_has_its_triangles_and_bounds() {
    let rest = posed("CesiumMan.gltf", None, 0.0, 0.0);
    assert_eq!(rest.iter().map(Mesh::triangle_count).sum::<usize>(), 4672);
    let b = bounds(rest.iter().flat_map(|m| m.t0.iter().copied()));
    assert!(
        near(b, ([-0.131, 0.0, -0.5691], [0.181, 1.5065, 0.5691]), 1e-3),
        "{b:?}"
    );
    // Its 49 keys are 1/24 s apart over 2 s. (The 210 vertices with weight sums below 1 do
    // not reach these extremes, so weight renormalisation is checked by the bar model.)
    let b = key_bounds("CesiumMan.gltf", AnimationRef::Index(0), 49);
    assert!(
        near(
            b,
            ([-0.5083, -0.0258, -0.247], [0.4789, 1.52, 0.3414]),
            1e-3
        ),
        "{b:?}"
    );
}

#[test]
fn cesium_man_moves_most_at_the_feet_and_not_at_all_without_a_shutter() {
    let walk = Some(AnimationRef::Index(0));
    let frozen = posed("CesiumMan.gltf", walk.clone(), 0.5, 0.0);
    assert!(frozen.iter().all(|m| m.t0 == m.t1));
    // Half a frame at 24 fps.
    let m = &posed("CesiumMan.gltf", walk, 0.5, 1.0 / 48.0)[0];
    let (moved, at) =
        m.t0.iter()
            .zip(&m.t1)
            .map(|(a, b)| ((*b - *a).length(), *a))
            .fold(
                (0.0f32, Vec3::ZERO),
                |best, x| if x.0 > best.0 { x } else { best },
            );
    println!("CesiumMan at 0.5 s, shutter 1/48 s: max displacement {moved} m at {at}");
    // A walker's swinging foot outruns every other part: the fastest vertex is in the
    // lowest tenth of the 1.5 m figure.
    assert!(moved > 0.01 && at.y < 0.15, "{moved} at {at}");
}

#[test]
fn fox_has_its_triangles_and_each_clip_by_name() {
    let rest = posed("Fox.glb", None, 0.0, 0.0);
    assert_eq!(rest.iter().map(Mesh::triangle_count).sum::<usize>(), 576);
    let b = bounds(rest.iter().flat_map(|m| m.t0.iter().copied()));
    assert!(
        near(
            b,
            ([-12.5927, -0.1217, -88.095], [12.5927, 78.9072, 66.6249]),
            1e-2
        ),
        "{b:?}"
    );
    for clip in ["Survey", "Walk", "Run"] {
        let m = &posed("Fox.glb", Some(AnimationRef::Name(clip.into())), 0.3, 0.05)[0];
        assert_eq!(m.triangle_count(), 576);
        assert!(m.t0 != m.t1, "{clip} moves");
    }
    let walk = key_bounds("Fox.glb", AnimationRef::Name("Walk".into()), 18);
    assert!(
        near(
            walk,
            ([-12.8148, -1.9672, -97.5011], [13.4389, 77.3126, 70.1812]),
            1e-2
        ),
        "{walk:?}"
    );
    let survey = key_bounds("Fox.glb", AnimationRef::Name("Survey".into()), 83);
    assert!(
        near(
            survey,
            ([-29.8998, -0.131, -85.8977], [26.5595, 79.7752, 68.8215]),
            1e-2
        ),
        "{survey:?}"
    );
}

#[test]
fn subdivided_cesium_man_reaches_the_papers_sizes() {
    let options = GltfOptions {
        animation: Some(AnimationRef::Index(0)),
        time: 0.5,
        shutter: 1.0 / 48.0,
        subdivide: 2,
    };
    let m = load_gltf_motion(&asset("CesiumMan.gltf"), &options).unwrap();
    assert_eq!(m.iter().map(Mesh::triangle_count).sum::<usize>(), 4672 * 16);
}
