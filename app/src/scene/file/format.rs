//! The file's serde types, field by field as docs/scene-format.md documents them, with
//! their defaults. Every field name is checked (`deny_unknown_fields`): a typo is an error,
//! not a default.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::scene::gltf::AnimationRef;

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
    /// The camera's pose at t = 1 (docs/scene-format.md, "A moving camera"); fields left
    /// out keep their t = 0 value, no `t1` at all: a still camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t1: Option<CameraPoseFile>,
}

/// The camera's `t1`: its position, target and up at t = 1, each defaulting to t = 0's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPoseFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3>,
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
        /// The light's pose at t = 1 (docs/scene-format.md, "A moving light"); fields left
        /// out keep their t = 0 value, no `t1` at all: a still light.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        t1: Option<SpotPoseFile>,
    },
    Directional {
        direction: Vec3,
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
        /// As the spot's `t1`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        t1: Option<DirectionalPoseFile>,
    },
}

/// A spot light's `t1`: its position and direction at t = 1, each defaulting to t = 0's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpotPoseFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<Vec3>,
}

/// A directional light's `t1`: its direction and its shadow box's centre at t = 1, each
/// defaulting to t = 0's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalPoseFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec3>,
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
