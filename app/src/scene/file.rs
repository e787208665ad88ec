//! The JSON scene file (`motion-shadows-scene/1`, documented in docs/scene-format.md).
//! These serde types are the public, scriptable interface; they are kept separate from the
//! runtime types so the file format can stay stable while the renderer's data changes.
//! Every field name is checked (`deny_unknown_fields`): a typo is an error, not a default.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use super::clip::quoted;
use super::gltf::{AnimationRef, GltfOptions, load_bounded as load_gltf, shutter_seconds};
use super::limits::{MAX_SCENE_FILE_BYTES, MAX_SCENE_TRIANGLES, MAX_SUBDIVISIONS};
use super::name::{name_from_file_stem, scene_name_problem};
use super::obj::load_obj_triangles;
use super::pretty::pretty_json;
use super::primitives::{RigidTransform, box_mesh, plane_mesh};
use super::read::read_bounded;
use super::{Camera, DirectionalLight, Light, Mesh, Scene, SceneError, SpotLight};

/// The value the required `"format"` field must have.
pub const SCENE_FORMAT: &str = "motion-shadows-scene/1";

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub format: String,
    /// Defaults to the file name without extension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub camera: CameraFile,
    pub light: LightFile,
    #[serde(default)]
    pub ambient: f32,
    pub objects: Vec<ObjectFile>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    pub position: Vec3,
    pub target: Vec3,
    #[serde(default = "up_y")]
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

fn up_y() -> Vec3 {
    Vec3::Y
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum LightFile {
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_angle_deg: f32,
        intensity: f32,
        near: f32,
        far: f32,
    },
    Directional {
        direction: Vec3,
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
    },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectFile {
    /// Defaults to `object-<index>`.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    pub albedo: Vec3,
    #[serde(default)]
    pub closed: bool,
    pub mesh: MeshSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t0: Option<TransformFile>,
    /// Fields left out here take their value from `t0`; no `t1` at all means static.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t1: Option<TransformFile>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum MeshSpec {
    Box(BoxSpec),
    Plane(PlaneSpec),
    /// Path to a Wavefront OBJ, relative to the scene file's directory. A String rather
    /// than a PathBuf so that serialising can never fail on a non-UTF-8 path.
    Obj(String),
    Triangles(TrianglesSpec),
    /// A glTF 2.0 model posed at shutter open and close (docs/scene-format.md).
    Gltf(GltfSpec),
}

/// `"gltf"` mesh: the model at `time` (t0) and at `time` plus the shutter (t1), in the
/// model's world space; the object's transforms apply on top. The shutter is given either
/// in seconds (`shutter`) or as a film camera's `shutter_angle_deg` at `fps`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GltfSpec {
    /// Relative to the scene file's directory, like an OBJ path.
    pub path: String,
    /// Index or name; omitted: the rest pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationRef>,
    /// Seconds into the animation at shutter open.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub time: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shutter: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shutter_angle_deg: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fps: Option<f32>,
    /// Levels of midpoint subdivision (each multiplies the triangles by 4).
    #[serde(default, skip_serializing_if = "is_zero_u32")]
    pub subdivide: u32,
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

fn is_zero_u32(v: &u32) -> bool {
    *v == 0
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

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    pub size: Vec3,
    #[serde(default = "one")]
    pub subdivisions: u32,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    pub size: Vec2,
    #[serde(default = "one")]
    pub subdivisions: u32,
}

fn one() -> u32 {
    1
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrianglesSpec {
    pub t0: Vec<Vec3>,
    /// Omitted: the triangles do not deform (they may still move by the transforms).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t1: Option<Vec<Vec3>>,
}

/// Every field optional; see `ObjectFile::t1` for how t1 inherits from t0.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translation: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation_axis: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation_deg: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Vec3>,
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

/// Only checks the version, ignoring everything else, so a file from another format
/// version reports that rather than a confusing unknown-field error.
#[derive(Deserialize)]
struct FormatProbe {
    format: Option<serde_json::Value>,
}

/// Reads and converts a scene file; OBJ paths are resolved against its directory. The file
/// may be a pipe; either way at most `MAX_SCENE_FILE_BYTES` are read.
pub fn load_scene_file(path: &Path) -> Result<Scene, SceneError> {
    read_scene_file(path)?.to_scene()
}

/// A scene file read and parsed but not yet converted, so it can be changed first
/// (`animate` poses its glTF models at each frame's time).
#[derive(Debug, Clone)]
pub struct SceneSource {
    pub file: SceneFile,
    /// Where relative model paths are resolved.
    pub base_dir: PathBuf,
    /// The scene's name when the file has no `"name"`.
    pub fallback_name: String,
}

impl SceneSource {
    pub fn to_scene(&self) -> Result<Scene, SceneError> {
        self.file.to_scene(&self.base_dir, &self.fallback_name)
    }
}

/// `load_scene_file` without the conversion.
pub fn read_scene_file(path: &Path) -> Result<SceneSource, SceneError> {
    let io_error = |source| SceneError::Io {
        path: path.to_owned(),
        source,
    };
    let bytes = read_bounded(path, MAX_SCENE_FILE_BYTES, true).map_err(|e| {
        io_error(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            e.to_string(),
        ))
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let message = format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to());
        io_error(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ))
    })?;
    let base_dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let (file, fallback_name) = parse_file(&text, path)?;
    Ok(SceneSource {
        file,
        base_dir: base_dir.to_owned(),
        fallback_name,
    })
}

/// Parses scene JSON. `name` labels the source in error messages (e.g. a file name) and,
/// minus any extension, names the scene when the JSON has no `"name"`. OBJ paths are
/// resolved against `base_dir`.
pub fn parse_scene_json(text: &str, base_dir: &Path, name: &str) -> Result<Scene, SceneError> {
    parse(text, base_dir, Path::new(name))
}

fn parse(text: &str, base_dir: &Path, source: &Path) -> Result<Scene, SceneError> {
    let (file, fallback_name) = parse_file(text, source)?;
    file.to_scene(base_dir, &fallback_name)
}

/// The file's contents and the name its source gives a scene without `"name"`.
fn parse_file(text: &str, source: &Path) -> Result<(SceneFile, String), SceneError> {
    let json_error = |e| SceneError::Json {
        path: source.to_owned(),
        source: e,
    };
    let probe: FormatProbe = serde_json::from_str(text).map_err(json_error)?;
    match probe.format {
        Some(serde_json::Value::String(f)) if f == SCENE_FORMAT => {}
        Some(other) => {
            return Err(SceneError::Invalid(format!(
                "{}: unsupported \"format\" {other}, expected {SCENE_FORMAT:?}",
                source.display()
            )));
        }
        None => {
            return Err(SceneError::Invalid(format!(
                "{}: missing field \"format\" (expected {SCENE_FORMAT:?})",
                source.display()
            )));
        }
    }
    let file: SceneFile = serde_json::from_str(text).map_err(json_error)?;
    let stem = source
        .file_stem()
        .map_or_else(|| source.to_string_lossy(), |s| s.to_string_lossy());
    Ok((file, name_from_file_stem(&stem)))
}

/// Pretty JSON that `parse_scene_json` reads back to an equal scene (f32 values are
/// written in their shortest exact form).
pub fn scene_to_json(scene_file: &SceneFile) -> String {
    // Cannot fail: every map key is a string and every value is plain data.
    let compact = serde_json::to_string(scene_file).expect("SceneFile serialises to JSON");
    let mut text = pretty_json(&compact);
    text.push('\n');
    text
}

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

impl SceneFile {
    /// Triangles of every object whose count is known without building it (all but OBJ and glTF
    /// models); `None` when the sum overflows. Subdivisions are checked first, so each term
    /// is small.
    fn known_triangles(&self) -> Option<u64> {
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
    fn check_triangle_budget(&self) -> Result<(), SceneError> {
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
            Some(n) if n <= MAX_SCENE_TRIANGLES => super::memory::check_triangles(n)
                .map_err(|e| SceneError::Invalid(format!("the scene's objects: {e}"))),
            n => Err(SceneError::Invalid(format!(
                "the objects would have {} triangles, more than the limit of {MAX_SCENE_TRIANGLES} \
                 (docs/scene-format.md, \"Limits\")",
                n.map_or_else(|| "too many".to_owned(), |n| n.to_string())
            ))),
        }
    }
}

/// How errors name object `index`: `object #2 ("bunny")`, the name clipped.
fn object_context(index: usize, name: &str) -> String {
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
            } => Light::Spot(SpotLight {
                position,
                direction: direction.normalize_or_zero(),
                cone_angle_deg,
                intensity,
                near,
                far,
            }),
            LightFile::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            } => Light::Directional(DirectionalLight {
                direction: direction.normalize_or_zero(),
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
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

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = include_str!("../../../docs/examples/two-triangles.json");
    const DOC: &str = include_str!("../../../docs/scene-format.md");

    fn parse_str(text: &str) -> Result<Scene, SceneError> {
        parse_scene_json(text, Path::new("."), "test.json")
    }

    fn invalid_message(text: &str) -> String {
        match parse_str(text) {
            Err(SceneError::Invalid(m)) => m,
            other => panic!("expected Invalid, got {other:?}"),
        }
    }

    fn json_message(text: &str) -> String {
        match parse_str(text) {
            Err(e @ SceneError::Json { .. }) => e.to_string(),
            other => panic!("expected Json error, got {other:?}"),
        }
    }

    #[test]
    fn documented_example_parses_and_is_in_the_doc() {
        assert!(
            DOC.contains(EXAMPLE.trim()),
            "docs/scene-format.md must show the example verbatim"
        );
        let s = parse_str(EXAMPLE).unwrap();
        assert_eq!(s.name, "two-triangles");
        assert_eq!(s.triangle_count(), 2);
        assert_eq!(s.ambient, 0.05);
        assert_eq!(s.camera.up, Vec3::Y);
        let blade = &s.meshes[1];
        // t1 inherits nothing it overrides: moved by +2 in x, spun 90 degrees about +Y.
        assert_eq!(centre(&blade.t0), Vec3::new(-1.0, 1.0, 1.0 / 6.0));
        assert!(
            (blade.t1[0] - Vec3::new(1.5, 1.0, 0.5)).length() < 1e-5,
            "{}",
            blade.t1[0]
        );
        let Light::Directional(d) = &s.light else {
            panic!("directional expected")
        };
        assert!((d.direction.length() - 1.0).abs() < 1e-6);
    }

    fn centre(points: &[Vec3]) -> Vec3 {
        points.iter().sum::<Vec3>() / points.len() as f32
    }

    #[test]
    fn name_falls_back_to_the_source_stem() {
        let text = EXAMPLE.replace("\"name\": \"two-triangles\",", "");
        let s = parse_scene_json(&text, Path::new("."), "dir/my-scene.json").unwrap();
        assert_eq!(s.name, "my-scene");
    }

    #[test]
    fn unknown_fields_are_errors_naming_the_field() {
        let m = json_message(&EXAMPLE.replace("\"fov_y_deg\"", "\"fov_y_degs\""));
        assert!(m.contains("fov_y_degs") && m.contains("line"), "{m}");
        let m = json_message(&EXAMPLE.replace("\"irradiance\"", "\"irradience\""));
        assert!(m.contains("irradience"), "{m}");
        let m = json_message(&EXAMPLE.replace("\"translation\": [1", "\"translate\": [1"));
        assert!(m.contains("translate"), "{m}");
    }

    #[test]
    fn format_is_required_and_checked() {
        let m = invalid_message(&EXAMPLE.replace("\"format\": \"motion-shadows-scene/1\",", ""));
        assert!(m.contains("missing field \"format\""), "{m}");
        let m = invalid_message(&EXAMPLE.replace("scene/1", "scene/2"));
        assert!(m.contains("scene/2"), "{m}");
        let m = json_message("{ \"format\": ");
        assert!(m.contains("test.json") && m.contains("line 1"), "{m}");
    }

    #[test]
    fn bad_values_name_the_object() {
        let m = invalid_message(&EXAMPLE.replace("\"fov_y_deg\": 45", "\"fov_y_deg\": -45"));
        assert!(m.contains("camera") && m.contains("fov_y_deg"), "{m}");

        let short_t1 = EXAMPLE.replace(
            "{ \"t0\": [[-0.5, 0, 0.5], [0.5, 0, 0.5], [0, 0, -0.5]] }",
            "{ \"t0\": [[-0.5, 0, 0.5], [0.5, 0, 0.5], [0, 0, -0.5]], \"t1\": [[0, 0, 0]] }",
        );
        let m = invalid_message(&short_t1);
        assert!(
            m.contains("object #1") && m.contains("\"blade\"") && m.contains("t1 has 1"),
            "{m}"
        );

        let m = invalid_message(&EXAMPLE.replace("[0.9, 0.3, 0.2]", "[1.9, 0.3, 0.2]"));
        assert!(
            m.contains("mesh #1") && m.contains("blade") && m.contains("albedo"),
            "{m}"
        );

        let m = invalid_message(&EXAMPLE.replace(
            "\"rotation_deg\": 90",
            "\"rotation_deg\": 90, \"scale\": [1, -1, 1]",
        ));
        assert!(m.contains("blade") && m.contains("t1.scale"), "{m}");
    }

    #[test]
    fn gltf_objects_load_relative_to_the_scene_file() {
        let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models");
        let scene = |spec: &str| {
            EXAMPLE.replace(
                "{ \"triangles\": { \"t0\": [[-4, 0, 3], [4, 0, 3], [0, 0, -4]] } }",
                &format!("{{ \"gltf\": {spec} }}"),
            )
        };
        let load = |spec: &str| parse_scene_json(&scene(spec), &models, "test.json");
        let seconds = load(
            r#"{ "path": "CesiumMan.gltf", "animation": 0, "time": 0.5, "shutter": 0.0208333333 }"#,
        )
        .unwrap();
        assert_eq!(seconds.meshes[0].triangle_count(), 4672);
        assert_ne!(seconds.meshes[0].t0, seconds.meshes[0].t1);
        // 180 degrees at 24 fps is the same 1/48 s.
        let angle = load(
            r#"{ "path": "CesiumMan.gltf", "animation": 0, "time": 0.5, "shutter_angle_deg": 180, "fps": 24 }"#,
        )
        .unwrap();
        let (a, b) = (&seconds.meshes[0], &angle.meshes[0]);
        assert!(
            a.t1.iter()
                .zip(&b.t1)
                .all(|(p, q)| (*p - *q).length() < 1e-6)
        );
        let fox =
            load(r#"{ "path": "Fox.glb", "animation": "Walk", "shutter": 0.02, "subdivide": 1 }"#)
                .unwrap();
        assert_eq!(fox.meshes[0].triangle_count(), 4 * 576);

        let m = invalid_message(&scene(r#"{ "path": "Fox.glb", "animation": "Walk" }"#));
        assert!(m.contains("floor") && m.contains("shutter"), "{m}");
        let m = json_message(&scene(r#"{ "path": "Fox.glb", "shuter": 0.1 }"#));
        assert!(m.contains("shuter"), "{m}");
        match load(r#"{ "path": "Fox.glb", "animation": "Trot", "shutter": 0.1 }"#) {
            Err(e @ SceneError::Gltf { .. }) => {
                let m = e.to_string();
                assert!(m.contains("floor") && m.contains("Survey"), "{m}");
            }
            other => panic!("expected a glTF error, got {other:?}"),
        }
    }

    #[test]
    fn obj_objects_load_relative_to_the_scene_file() {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let dir = std::env::temp_dir().join(format!(
            "motion-shadows-scene-test-{}-{nanos}",
            std::process::id()
        ));
        std::fs::create_dir_all(dir.join("models")).unwrap();
        // Two models (a quad and a triangle) and a missing material library, which is ignored.
        let obj = "mtllib missing.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nf 1 2 3 4\n\
                   o tri\nv 0 1 0\nv 1 1 0\nv 0 1 -1\nf 5 6 7\n";
        std::fs::write(dir.join("models/tiny.obj"), obj).unwrap();
        let scene = |mesh: &str| {
            EXAMPLE.replace(
                "{ \"triangles\": { \"t0\": [[-4, 0, 3], [4, 0, 3], [0, 0, -4]] } }",
                &format!("{{ \"obj\": {mesh:?} }}"),
            )
        };
        let path = dir.join("scene.json");
        std::fs::write(&path, scene("models/tiny.obj")).unwrap();
        let s = load_scene_file(&path).unwrap();
        let floor = &s.meshes[0];
        assert_eq!(floor.triangle_count(), 3);
        assert_eq!(floor.t0, floor.t1);
        let normal = (floor.t0[1] - floor.t0[0]).cross(floor.t0[2] - floor.t0[0]);
        assert!(normal.y > 0.0, "OBJ winding must be kept");

        std::fs::write(&path, scene("models/absent.obj")).unwrap();
        match load_scene_file(&path) {
            Err(e @ SceneError::Obj { .. }) => {
                let m = e.to_string();
                assert!(
                    m.contains("absent.obj") && m.contains("object #0") && m.contains("floor"),
                    "{m}"
                );
            }
            other => panic!("expected Obj error, got {other:?}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();

        assert!(matches!(
            load_scene_file(&dir.join("scene.json")),
            Err(SceneError::Io { .. })
        ));
    }
}
