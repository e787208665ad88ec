//! From the file's types to the runtime [`Scene`]: meshes built or loaded, transforms
//! resolved (t1 inheriting from t0), lights' directions normalised, and each refusal naming
//! the object it concerns.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::format::{
    GltfSpec, LightFile, MeshSpec, ObjectFile, SCENE_FORMAT, SceneFile, TransformFile,
};
use crate::scene::clip::quoted;
use crate::scene::gltf::{GltfOptions, load_bounded as load_gltf, shutter_seconds};
use crate::scene::limits::MAX_SCENE_TRIANGLES;
use crate::scene::name::scene_name_problem;
use crate::scene::obj::load_obj_triangles;
use crate::scene::primitives::{RigidTransform, box_mesh, plane_mesh};
use crate::scene::{
    Camera, CameraPose, DirectionalLight, DirectionalPose, Light, Mesh, Scene, SceneError,
    SpotLight, SpotPose,
};

impl SceneFile {
    /// Converts to the runtime scene and validates it. `fallback_name` is used when
    /// `name` is absent; relative OBJ paths are resolved against `base_dir`.
    pub fn to_scene(&self, base_dir: &Path, fallback_name: &str) -> Result<Scene, SceneError> {
        if self.format != SCENE_FORMAT {
            return Err(SceneError::Invalid(format!(
                "unsupported format {:?}, expected {SCENE_FORMAT:?}",
                self.format
            )));
        }
        let name = self
            .name
            .clone()
            .unwrap_or_else(|| fallback_name.to_owned());
        if let Some(problem) = scene_name_problem(&name) {
            return Err(SceneError::Invalid(problem));
        }
        self.check_triangle_budget()?;
        let c = &self.camera;
        let camera = Camera {
            position: c.position,
            target: c.target,
            up: c.up,
            fov_y_deg: c.fov_y_deg,
            near: c.near,
            far: c.far,
            t1: c.t1.map(|end| CameraPose {
                position: end.position.unwrap_or(c.position),
                target: end.target.unwrap_or(c.target),
                up: end.up.unwrap_or(c.up),
            }),
        };
        // OBJ and glTF models are counted as they load: each may use what the others left.
        let mut budget = MAX_SCENE_TRIANGLES - self.known_triangles().unwrap_or(0);
        let meshes = self
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| o.to_mesh(i, base_dir, &mut budget))
            .collect::<Result<Vec<_>, _>>()?;
        let scene = Scene {
            name,
            camera,
            light: self.light.to_light(),
            ambient: self.ambient,
            meshes,
        };
        scene.validate()?;
        Ok(scene)
    }
}

/// How errors name object `index`: `object #2 ("bunny")`, the name clipped.
pub(super) fn object_context(index: usize, name: &str) -> String {
    if name.is_empty() {
        format!("object #{index} (\"object-{index}\")")
    } else {
        format!("object #{index} ({:?})", quoted(name))
    }
}

/// Directions are normalised here so the renderer gets unit vectors (a zero vector stays
/// zero and is reported by `Scene::validate`).
impl LightFile {
    fn to_light(&self) -> Light {
        match *self {
            LightFile::Spot {
                position,
                direction,
                cone_angle_deg,
                intensity,
                near,
                far,
                t1,
            } => Light::Spot(SpotLight {
                position,
                direction: direction.normalize_or_zero(),
                cone_angle_deg,
                intensity,
                near,
                far,
                t1: t1.map(|end| SpotPose {
                    position: end.position.unwrap_or(position),
                    direction: end.direction.unwrap_or(direction).normalize_or_zero(),
                }),
            }),
            LightFile::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
                t1,
            } => Light::Directional(DirectionalLight {
                direction: direction.normalize_or_zero(),
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
                t1: t1.map(|end| DirectionalPose {
                    direction: end.direction.unwrap_or(direction).normalize_or_zero(),
                    center: end.center.unwrap_or(center),
                }),
            }),
        }
    }
}

impl ObjectFile {
    /// `budget`: triangles OBJ and glTF models may still add to the scene; each takes its
    /// share.
    fn to_mesh(&self, index: usize, base_dir: &Path, budget: &mut u64) -> Result<Mesh, SceneError> {
        let name = if self.name.is_empty() {
            format!("object-{index}")
        } else {
            self.name.clone()
        };
        let context = object_context(index, &self.name);
        let invalid = |msg: String| SceneError::Invalid(format!("{context}: {msg}"));
        // A negative or zero size would turn the faces inside out or collapse them, as a
        // negative scale would (which is refused below for the same reason).
        let positive = |what: &str, v: &[f32]| {
            if v.iter().all(|&x| x.is_finite() && x > 0.0) {
                Ok(())
            } else {
                Err(invalid(format!(
                    "{what} size components must be finite and > 0, got {v:?}"
                )))
            }
        };

        let (local0, local1) = match &self.mesh {
            MeshSpec::Box(b) => {
                positive("box", &b.size.to_array())?;
                let tris = box_mesh(b.size, b.subdivisions);
                (tris.clone(), tris)
            }
            MeshSpec::Plane(p) => {
                positive("plane", &p.size.to_array())?;
                let tris = plane_mesh(p.size, p.subdivisions);
                (tris.clone(), tris)
            }
            MeshSpec::Obj(rel) => {
                let path: PathBuf = base_dir.join(rel);
                let tris = load_obj_triangles(&path, &context, *budget)?;
                *budget -= tris.len() as u64 / 3;
                (tris.clone(), tris)
            }
            MeshSpec::Gltf(g) => {
                let options = g.options().map_err(&invalid)?;
                let path: PathBuf = base_dir.join(&g.path);
                let meshes = load_gltf(&path, &options, &context, *budget)?;
                let t0: Vec<Vec3> = meshes.iter().flat_map(|m| m.t0.iter().copied()).collect();
                let t1: Vec<Vec3> = meshes.iter().flat_map(|m| m.t1.iter().copied()).collect();
                *budget -= t0.len() as u64 / 3;
                (t0, t1)
            }
            MeshSpec::Triangles(t) => {
                let t1 = t.t1.clone().unwrap_or_else(|| t.t0.clone());
                if t1.len() != t.t0.len() {
                    let msg = format!(
                        "triangles: t0 has {} vertices but t1 has {}",
                        t.t0.len(),
                        t1.len()
                    );
                    return Err(invalid(msg));
                }
                (t.t0.clone(), t1)
            }
        };

        let none = TransformFile::default();
        let t0_file = self.t0.as_ref().unwrap_or(&none);
        let xf0 = t0_file.resolve(&none);
        let xf1 = self.t1.as_ref().unwrap_or(t0_file).resolve(t0_file);
        for (label, xf) in [("t0", &xf0), ("t1", &xf1)] {
            // Mirroring would flip the triangle winding and so the outward normals.
            if xf.scale.min_element() <= 0.0 {
                return Err(invalid(format!(
                    "{label}.scale components must be > 0, got {}",
                    xf.scale
                )));
            }
            if xf.rotation_deg != 0.0 && xf.rotation_axis.length_squared() == 0.0 {
                return Err(invalid(format!("{label}.rotation_axis must be non-zero")));
            }
        }
        Ok(Mesh {
            name,
            albedo: self.albedo,
            closed: self.closed,
            t0: xf0.apply(&local0),
            t1: xf1.apply(&local1),
        })
    }
}

impl GltfSpec {
    /// The loader's options; the shutter must be given one way exactly when an animation
    /// is chosen (without one there is no motion, and a shutter would mean nothing).
    fn options(&self) -> Result<GltfOptions, String> {
        let shutter = match (self.shutter, self.shutter_angle_deg, self.fps) {
            (Some(s), None, None) => s,
            (None, Some(angle), Some(fps)) => {
                if !(angle.is_finite() && angle >= 0.0 && fps.is_finite() && fps > 0.0) {
                    return Err(format!(
                        "gltf: shutter_angle_deg must be >= 0 and fps > 0, got {angle} and {fps}"
                    ));
                }
                shutter_seconds(angle, fps)
            }
            (None, None, None) if self.animation.is_none() => 0.0,
            (None, None, None) => {
                return Err("gltf: an animation needs \"shutter\" (seconds) or \
                            \"shutter_angle_deg\" and \"fps\""
                    .into());
            }
            _ => {
                return Err(
                    "gltf: give either \"shutter\" or both \"shutter_angle_deg\" \
                            and \"fps\""
                        .into(),
                );
            }
        };
        Ok(GltfOptions {
            animation: self.animation.clone(),
            time: self.time,
            shutter,
            subdivide: self.subdivide,
        })
    }
}

impl TransformFile {
    /// Fields missing here come from `base`, then from the identity.
    fn resolve(&self, base: &TransformFile) -> RigidTransform {
        let id = RigidTransform::default();
        RigidTransform {
            translation: self
                .translation
                .or(base.translation)
                .unwrap_or(id.translation),
            rotation_axis: self
                .rotation_axis
                .or(base.rotation_axis)
                .unwrap_or(id.rotation_axis),
            rotation_deg: self
                .rotation_deg
                .or(base.rotation_deg)
                .unwrap_or(id.rotation_deg),
            scale: self.scale.or(base.scale).unwrap_or(id.scale),
        }
    }
}
