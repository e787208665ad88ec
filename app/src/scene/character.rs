//! Animated characters for the built-in scenes: a glTF model compiled into the binary,
//! posed at shutter open and close and written into the scene file as explicit `triangles`
//! (t0/t1), so `scene export` gives a file that renders the same without the asset.

use glam::Vec3;

use super::SceneError;
use super::file::{MeshSpec, ObjectFile, SCENE_FORMAT, SceneFile, TransformFile, TrianglesSpec};
use super::gltf::{GltfOptions, load_gltf_motion_from_bytes};
use super::parts::object;

pub(super) const CESIUM_MAN: (&str, &[u8]) = (
    "assets/models/CesiumMan.gltf",
    include_bytes!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/models/CesiumMan.gltf"
    )),
);

pub(super) const FOX: (&str, &[u8]) = (
    "assets/models/Fox.glb",
    include_bytes!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/models/Fox.glb"
    )),
);

/// A film camera's half-open shutter, 180 degrees at 24 fps, in seconds.
pub(crate) const SHUTTER_180_AT_24: f32 = 1.0 / 48.0;

/// `model` (name, bytes) posed as `options` say, as one object of explicit moving
/// triangles placed by `transform` (the same at both ends of the shutter: the motion is the
/// animation's).
pub(super) fn animated_object(
    name: &str,
    albedo: Vec3,
    model: (&str, &[u8]),
    options: &GltfOptions,
    transform: TransformFile,
) -> Result<ObjectFile, SceneError> {
    let meshes = load_gltf_motion_from_bytes(model.0, model.1, options)?;
    let t0 = meshes.iter().flat_map(|m| m.t0.iter().copied()).collect();
    let t1 = meshes.iter().flat_map(|m| m.t1.iter().copied()).collect();
    let mesh = MeshSpec::Triangles(TrianglesSpec { t0, t1: Some(t1) });
    Ok(object(name, albedo, false, mesh, transform, None))
}

/// A character on `leg-toward-light`'s stage (ground, back wall, side camera, front spot
/// light): the scene file of every character built-in.
pub(super) fn staged_scene(name: &str, character: ObjectFile) -> SceneFile {
    let mut objects = super::leg::backdrop();
    objects.push(character);
    SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some(name.to_owned()),
        camera: super::leg::side_camera(),
        light: super::leg::front_spot(),
        ambient: 0.0,
        objects,
    }
}

/// What the tests of the scenes on `leg-toward-light`'s stage share.
#[cfg(test)]
pub(super) mod test_support {
    use super::super::{Light, Mesh, Scene};
    use glam::Vec3;

    /// The names of the meshes that move during the shutter, in scene order.
    pub fn moving_meshes(s: &Scene) -> Vec<&str> {
        s.meshes
            .iter()
            .filter(|m| m.t0 != m.t1)
            .map(|m| m.name.as_str())
            .collect()
    }

    /// The fastest vertex over the shutter: (displacement, position at shutter open).
    pub fn fastest(m: &Mesh) -> (f32, Vec3) {
        m.t0.iter()
            .zip(&m.t1)
            .map(|(a, b)| ((*b - *a).length(), *a))
            .fold(
                (0.0, Vec3::ZERO),
                |best, x| if x.0 > best.0 { x } else { best },
            )
    }

    /// Every vertex of `m`, at both ends of the shutter (so at every time: the cone is
    /// convex and vertices move on straight lines), is inside the scene's spot light cone
    /// and between its near and far distances.
    pub fn assert_inside_spot_cone(s: &Scene, m: &Mesh) {
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let cos_cone = light.cone_angle_deg.to_radians().cos();
        for &p in m.t0.iter().chain(&m.t1) {
            let d = p - light.position;
            assert!(
                d.normalize().dot(light.direction) > cos_cone + 0.02,
                "{} outside the cone at {p}",
                m.name
            );
            assert!(d.length() > light.near * 2.0 && d.length() < light.far);
        }
    }
}
