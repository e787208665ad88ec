//! Wavefront OBJ loading for scene objects: every model in the file is merged into one
//! triangle list (positions only; materials and normals are ignored because the scene
//! gives each object a single albedo).

use std::path::Path;

use glam::Vec3;

use super::SceneError;
use super::limits::{MAX_OBJ_BYTES, MAX_SCENE_TRIANGLES};
use super::read::read_bounded;

/// Reads `path` and returns its triangles (polygons are triangulated by tobj).
/// `context` (e.g. `object #2 ("bunny")`) prefixes error messages. The file must be a
/// regular file of at most `MAX_OBJ_BYTES` (a scene file names it, so it must not be able to
/// point at a device or a pipe), and may add at most `budget` triangles to the scene.
pub(crate) fn load_obj_triangles(
    path: &Path,
    context: &str,
    budget: u64,
) -> Result<Vec<Vec3>, SceneError> {
    let obj_error = |message: String| SceneError::Obj {
        path: path.to_owned(),
        message: format!("{context}: {message}"),
    };
    // Read it ourselves: tobj's own open error drops the OS reason, and tobj reads without
    // a bound.
    let bytes = read_bounded(path, MAX_OBJ_BYTES, false).map_err(|e| obj_error(e.to_string()))?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    // Material libraries are not needed; refusing them keeps a missing .mtl harmless.
    let (models, _materials) = tobj::load_obj_buf(&mut bytes.as_slice(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| obj_error(e.to_string()))?;
    drop(bytes);

    // Counted before the positions are copied out, so the copy is bounded too.
    let triangles: u64 = models.iter().map(|m| m.mesh.indices.len() as u64 / 3).sum();
    if triangles > budget {
        return Err(obj_error(format!(
            "{triangles} triangles would take the scene over its limit of \
             {MAX_SCENE_TRIANGLES} (docs/scene-format.md, \"Limits\")"
        )));
    }
    super::memory::check_triangles(triangles).map_err(obj_error)?;
    let mut out = Vec::with_capacity(triangles as usize * 3);
    for model in &models {
        let mesh = &model.mesh;
        for &index in &mesh.indices {
            let i = index as usize * 3;
            let p = mesh.positions.get(i..i + 3).ok_or_else(|| {
                obj_error(format!(
                    "model {:?}: vertex index {index} out of range",
                    model.name
                ))
            })?;
            out.push(Vec3::new(p[0], p[1], p[2]));
        }
    }
    if out.is_empty() {
        return Err(obj_error("contains no faces".into()));
    }
    Ok(out)
}
