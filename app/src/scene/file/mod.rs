//! The JSON scene file (`motion-shadows-scene/1`, documented in docs/scene-format.md): its
//! serde types (`format`), reading and parsing it (`load`), the triangle budget checked before
//! anything is built (`budget`) and the conversion to the runtime scene (`convert`). The serde
//! types are the public, scriptable interface; they are kept separate from the runtime types
//! so the file format can stay stable while the renderer's data changes.

mod budget;
#[cfg(test)]
mod camera_motion_tests;
mod convert;
mod format;
#[cfg(test)]
mod light_motion_tests;
mod load;
#[cfg(test)]
mod tests;

pub use format::{
    BoxSpec, CameraFile, CameraPoseFile, DirectionalPoseFile, LightFile, MeshSpec, ObjectFile,
    PlaneSpec, SCENE_FORMAT, SceneFile, SpotPoseFile, TransformFile, TrianglesSpec,
};
pub use load::{SceneSource, load_scene_file, parse_scene_json, read_scene_file, scene_to_json};
