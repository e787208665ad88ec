//! glTF 2.0 models as moving triangle meshes: the model is posed at shutter open
//! (`time`) and at shutter close (`time + shutter`), and each vertex moves linearly between
//! the two world-space positions, as every scene vertex does.
//!
//! Supported: `.gltf` (embedded or external buffers) and `.glb`; TRIANGLES, TRIANGLE_STRIP
//! and TRIANGLE_FAN primitives, indexed (u8/u16/u32) or not; sparse accessors and
//! normalised integer attributes; node hierarchies (TRS or matrix); skins (any number of
//! JOINTS_n/WEIGHTS_n sets, weights renormalised to sum 1); morph targets (POSITION deltas;
//! animated, node or mesh default weights); STEP, LINEAR (slerp for rotations) and
//! CUBICSPLINE samplers. Not supported: points and lines, required extensions (Draco,
//! meshopt, KHR_mesh_quantization, ...), remote URIs. Materials, normals, texture
//! coordinates, cameras and lights are ignored.

mod accessor;
mod animation;
mod evaluate;
mod geometry;
mod hierarchy;
mod options;
mod sampler;
mod skinning;
mod source;
#[cfg(test)]
mod tests;

use std::path::Path;

use glam::Vec3;

use super::limits::{MAX_GLTF_SUBDIVIDE, MAX_SCENE_TRIANGLES};
use super::subdivide::subdivide;
use super::{Mesh, SceneError};
pub use options::{AnimationRef, GltfOptions, shutter_seconds};

/// Albedo of the meshes `load_gltf_motion` returns; a scene file sets its own.
pub const DEFAULT_ALBEDO: Vec3 = Vec3::splat(0.8);

/// One mesh per drawn primitive (named after its node, else its mesh), in world space:
/// `t0` at `options.time`, `t1` at `options.time + options.shutter`, both subdivided
/// `options.subdivide` times. Meshes are not marked closed.
pub fn load_gltf_motion(path: &Path, options: &GltfOptions) -> Result<Vec<Mesh>, SceneError> {
    load_bounded(path, options, "", MAX_SCENE_TRIANGLES)
}

/// `load_gltf_motion` for a model in memory (a built-in scene's, compiled into the
/// binary); `name` stands for its path in error messages. Only the GLB chunk and `data:`
/// URIs can hold its buffers.
pub fn load_gltf_motion_from_bytes(
    name: &str,
    bytes: &[u8],
    options: &GltfOptions,
) -> Result<Vec<Mesh>, SceneError> {
    load_from(
        Path::new(name),
        || source::parse(bytes.to_vec(), None),
        options,
        "",
        MAX_SCENE_TRIANGLES,
    )
}

/// `load_gltf_motion` adding at most `budget` triangles; `context` (e.g. `object #2
/// ("man")`) prefixes error messages.
pub(crate) fn load_bounded(
    path: &Path,
    options: &GltfOptions,
    context: &str,
    budget: u64,
) -> Result<Vec<Mesh>, SceneError> {
    load_from(path, || source::load(path), options, context, budget)
}

/// The loader proper; `read` gives the parsed model once the options are known to be valid.
fn load_from(
    path: &Path,
    read: impl FnOnce() -> Result<source::Source, String>,
    options: &GltfOptions,
    context: &str,
    budget: u64,
) -> Result<Vec<Mesh>, SceneError> {
    let error = |message: String| SceneError::Gltf {
        path: path.to_owned(),
        message: if context.is_empty() {
            message
        } else {
            format!("{context}: {message}")
        },
    };
    if !(options.time.is_finite() && options.shutter.is_finite() && options.shutter >= 0.0) {
        return Err(error(format!(
            "time must be finite and shutter finite and >= 0, got time {} and shutter {}",
            options.time, options.shutter
        )));
    }
    if options.subdivide > MAX_GLTF_SUBDIVIDE {
        return Err(error(format!(
            "subdivide must be at most {MAX_GLTF_SUBDIVIDE}, got {}",
            options.subdivide
        )));
    }
    let source = read().map_err(error)?;
    // Counted from the accessors' sizes before any vertex is read.
    let triangles = evaluate::count_triangles(&source)
        .map_err(error)?
        .saturating_mul(4u64.pow(options.subdivide));
    if triangles > budget {
        return Err(error(format!(
            "{triangles} triangles would take the scene over its limit of \
             {MAX_SCENE_TRIANGLES} (docs/scene-format.md, \"Limits\")"
        )));
    }
    super::memory::check_triangles(triangles).map_err(error)?;
    let model = evaluate::Model::new(source, options).map_err(error)?;
    let open = model.posed(options.time);
    let close = model.posed(options.time + options.shutter);
    let mut meshes = Vec::new();
    for ((inst, (p0, mirrored)), (p1, _)) in model.instances.iter().zip(open).zip(close) {
        let mut t0 = Vec::with_capacity(inst.geometry.triangles.len());
        let mut t1 = Vec::with_capacity(inst.geometry.triangles.len());
        for tri in inst.geometry.triangles.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
            // Decided once, at shutter open, so t0 and t1 list the same corners in the
            // same order; a mirroring transform turns counter-clockwise into clockwise.
            let flips = [a, b, c].iter().filter(|&&v| mirrored[v]).count() >= 2;
            let order = if flips { [a, c, b] } else { [a, b, c] };
            t0.extend(order.map(|v| p0[v]));
            t1.extend(order.map(|v| p1[v]));
        }
        if t0.is_empty() {
            continue;
        }
        let mesh = Mesh {
            name: inst.name.clone(),
            albedo: DEFAULT_ALBEDO,
            closed: false,
            t0,
            t1,
        };
        meshes.push(subdivide(&mesh, options.subdivide));
    }
    if meshes.is_empty() {
        return Err(error("the model's scene draws no triangles".into()));
    }
    if let Some(bad) = meshes
        .iter()
        .flat_map(|m| m.t0.iter().chain(&m.t1))
        .find(|p| !p.is_finite())
    {
        return Err(error(format!("posed vertex {bad} is not finite")));
    }
    Ok(meshes)
}
