//! Animated characters for the built-in scenes: a glTF model compiled into the binary,
//! posed at shutter open and close and written into the scene file as explicit `triangles`
//! (t0/t1), so `scene export` gives a file that renders the same without the asset.

use glam::Vec3;

use super::SceneError;
use super::builtin::object;
use super::file::{MeshSpec, ObjectFile, TransformFile, TrianglesSpec};
use super::gltf::{GltfOptions, load_gltf_motion_from_bytes};

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
