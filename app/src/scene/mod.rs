//! Scene description: runtime types (`Scene`, `Mesh`, lights, camera), the JSON scene
//! file format (docs/scene-format.md) and the built-in test scenes.
//!
//! Conventions shared by all of it: right-handed, y up, angles in degrees, shutter time t in
//! [0, 1] with every vertex moving linearly from its t0 to its t1 position, triangles
//! counter-clockwise seen from their front (outside). `builtin()` builds a `SceneFile` and
//! converts it exactly like a loaded file, so there is a single path to a `Scene`.

mod builtin;
mod camera_pan;
mod character;
mod clip;
mod culling;
mod error;
mod file;
mod fox;
mod frames;
mod game;
pub mod gltf;
mod hard;
mod leg;
pub mod limits;
pub mod memory;
mod moving_light;
mod name;
mod obj;
mod parts;
mod precision;
mod pretty;
mod primitives;
mod read;
pub(crate) mod rng;
mod subdivide;
mod types;
mod validate;
mod walker;

pub use builtin::{BUILTIN_NAMES, BuiltinOptions, builtin, builtin_animation_time, builtin_file};
pub use clip::{clip, quoted};
pub use culling::{
    CullingException, contains_during_shutter, culling_exceptions, effective_closed,
};
pub use error::SceneError;
pub use file::{
    BoxSpec, CameraFile, CameraPoseFile, DirectionalPoseFile, LightFile, MeshSpec, ObjectFile,
    PlaneSpec, SCENE_FORMAT, SceneFile, SceneSource, SpotPoseFile, TransformFile, TrianglesSpec,
    load_scene_file, parse_scene_json, read_scene_file, scene_to_json,
};
pub use frames::AnimatedScene;
pub use hard::HARD_NAMES;
pub use name::{name_from_file_stem, scene_name_problem};
pub use primitives::{RigidTransform, box_mesh, plane_mesh};
pub use subdivide::subdivide;
pub use types::{
    Camera, CameraPose, DirectionalLight, DirectionalPose, Light, Mesh, Scene, SpotLight, SpotPose,
};
