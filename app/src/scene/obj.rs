//! Wavefront OBJ loading for scene objects: every model in the file is merged into one
//! triangle list (positions only; materials and normals are ignored because the scene
//! gives each object a single albedo).

use std::io::BufReader;
use std::path::Path;

use glam::Vec3;

use super::SceneError;

/// Reads `path` and returns its triangles (polygons are triangulated by tobj).
/// `context` (e.g. `object #2 ("bunny")`) prefixes error messages.
pub(crate) fn load_obj_triangles(path: &Path, context: &str) -> Result<Vec<Vec3>, SceneError> {
    let obj_error = |message: String| SceneError::Obj {
        path: path.to_owned(),
        message: format!("{context}: {message}"),
    };
    // Open it ourselves: tobj's own open error drops the OS reason.
    let file = std::fs::File::open(path).map_err(|e| obj_error(e.to_string()))?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    // Material libraries are not needed; refusing them keeps a missing .mtl harmless.
    let (models, _materials) = tobj::load_obj_buf(&mut BufReader::new(file), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| obj_error(e.to_string()))?;

    let mut out = Vec::new();
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
