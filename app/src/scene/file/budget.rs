//! The scene's triangle budget, checked before anything is built: a file cannot make the
//! renderer allocate more than `MAX_SCENE_TRIANGLES` triangles' worth of meshes.

use super::convert::object_context;
use super::format::{MeshSpec, SceneFile};
use crate::scene::SceneError;
use crate::scene::limits::{MAX_SCENE_TRIANGLES, MAX_SUBDIVISIONS};

impl SceneFile {
    /// Triangles of every object whose count is known without building it (all but OBJ and glTF
    /// models); `None` when the sum overflows. Subdivisions are checked first, so each term
    /// is small.
    pub(super) fn known_triangles(&self) -> Option<u64> {
        self.objects.iter().try_fold(0u64, |sum, o| {
            let n = match &o.mesh {
                MeshSpec::Box(b) => 12 * u64::from(b.subdivisions.max(1)).pow(2),
                MeshSpec::Plane(p) => 2 * u64::from(p.subdivisions.max(1)).pow(2),
                MeshSpec::Triangles(t) => t.t0.len() as u64 / 3,
                MeshSpec::Obj(_) | MeshSpec::Gltf(_) => 0,
            };
            sum.checked_add(n)
        })
    }

    /// Refuses a scene whose boxes, planes and triangle lists add up to more than
    /// `MAX_SCENE_TRIANGLES`, before any of them is built.
    pub(super) fn check_triangle_budget(&self) -> Result<(), SceneError> {
        for (i, o) in self.objects.iter().enumerate() {
            let n = match &o.mesh {
                MeshSpec::Box(b) => b.subdivisions,
                MeshSpec::Plane(p) => p.subdivisions,
                _ => continue,
            };
            if !(1..=MAX_SUBDIVISIONS).contains(&n) {
                return Err(SceneError::Invalid(format!(
                    "{}: subdivisions must be in 1..={MAX_SUBDIVISIONS}, got {n}",
                    object_context(i, &o.name)
                )));
            }
        }
        match self.known_triangles() {
            Some(n) if n <= MAX_SCENE_TRIANGLES => crate::scene::memory::check_triangles(n)
                .map_err(|e| SceneError::Invalid(format!("the scene's objects: {e}"))),
            n => Err(SceneError::Invalid(format!(
                "the objects would have {} triangles, more than the limit of {MAX_SCENE_TRIANGLES} \
                 (docs/scene-format.md, \"Limits\")",
                n.map_or_else(|| "too many".to_owned(), |n| n.to_string())
            ))),
        }
    }
}
