//! Scenes posed at any time of their glTF animations: the frames of `animate`. A built-in
//! with a character is rebuilt with its `frame_time`; a scene file has every animated glTF
//! model's `time` moved. Scenes with nothing animated are refused: every frame would be
//! the same image.

use std::path::Path;

use super::builtin::{BUILTIN_NAMES, BuiltinOptions, builtin, builtin_animation_time};
use super::file::{MeshSpec, SceneSource, read_scene_file};
use super::{Scene, SceneError};

/// A scene whose animated models can be posed at any time.
#[derive(Debug, Clone)]
pub struct AnimatedScene {
    source: Source,
}

#[derive(Debug, Clone)]
enum Source {
    Builtin {
        name: String,
        options: BuiltinOptions,
        time: f64,
    },
    /// Boxed: a scene file is far larger than a built-in's name and options.
    File(Box<SceneSource>),
}

impl AnimatedScene {
    pub fn builtin(name: &str, options: &BuiltinOptions) -> Result<Self, SceneError> {
        let Some(time) = builtin_animation_time(name) else {
            if !BUILTIN_NAMES.contains(&name) {
                // The loader's own error, which lists the names.
                builtin(name, options)?;
            }
            let animated: Vec<&str> = BUILTIN_NAMES
                .iter()
                .copied()
                .filter(|n| builtin_animation_time(n).is_some())
                .collect();
            return Err(SceneError::Invalid(format!(
                "the built-in scene {name} has no animation, so its frames would all be the \
                 same; the animated ones are {}",
                animated.join(", ")
            )));
        };
        Ok(Self {
            source: Source::Builtin {
                name: name.to_owned(),
                options: options.clone(),
                time: f64::from(time),
            },
        })
    }

    pub fn file(path: &Path) -> Result<Self, SceneError> {
        let source = read_scene_file(path)?;
        let animated = source
            .file
            .objects
            .iter()
            .any(|o| matches!(&o.mesh, MeshSpec::Gltf(g) if g.animation.is_some()));
        if !animated {
            return Err(SceneError::Invalid(format!(
                "{}: no object is a glTF model with an \"animation\", so its frames would all \
                 be the same",
                super::clip::quoted(&path.display().to_string())
            )));
        }
        Ok(Self {
            source: Source::File(Box::new(source)),
        })
    }

    /// The scene with each animated model's shutter opening `offset` seconds after `start`,
    /// or after the model's own time (the built-in's, or the file's `time`) without one.
    /// Times are f64 until each scene reduces them modulo its loops (`game-level`) or
    /// clamps them to its keys (glTF models): in f32, `start` 1e8 plus a frame's offset
    /// rounded to the same time for every frame.
    pub fn at(&self, start: Option<f64>, offset: f64) -> Result<Scene, SceneError> {
        match &self.source {
            Source::Builtin {
                name,
                options,
                time,
            } => {
                let options = BuiltinOptions {
                    frame_time: Some(start.unwrap_or(*time) + offset),
                    ..options.clone()
                };
                builtin(name, &options)
            }
            Source::File(source) => {
                let mut source = SceneSource::clone(source);
                for object in &mut source.file.objects {
                    if let MeshSpec::Gltf(g) = &mut object.mesh
                        && g.animation.is_some()
                    {
                        g.time = (start.unwrap_or(f64::from(g.time)) + offset) as f32;
                    }
                }
                source.to_scene()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walker_at(time: f64) -> Scene {
        let options = BuiltinOptions {
            frame_time: Some(time),
            ..Default::default()
        };
        builtin("walker-toward-light", &options).unwrap()
    }

    #[test]
    fn builtin_frames_are_the_scene_at_later_times() {
        let a = AnimatedScene::builtin("walker-toward-light", &BuiltinOptions::default()).unwrap();
        let own = builtin("walker-toward-light", &BuiltinOptions::default()).unwrap();
        assert_eq!(a.at(None, 0.0).unwrap(), own);
        assert_eq!(a.at(Some(0.25), 0.5).unwrap(), walker_at(0.75));
        assert_ne!(a.at(None, 1.0 / 24.0).unwrap(), own);
    }

    #[test]
    fn scenes_without_animation_are_refused() {
        for name in ["cubes-toward-light", "leg-toward-light"] {
            match AnimatedScene::builtin(name, &BuiltinOptions::default()) {
                Err(SceneError::Invalid(m)) => {
                    assert!(m.contains("no animation") && m.contains("fox-run"), "{m}")
                }
                other => panic!("{other:?}"),
            }
        }
        assert!(matches!(
            AnimatedScene::builtin("nope", &BuiltinOptions::default()),
            Err(SceneError::UnknownBuiltin { .. })
        ));
    }

    /// A scene file's glTF model moves its `time` by the offset, or to `start`: the same
    /// as writing that time in the file.
    #[test]
    fn file_frames_move_the_models_time() {
        let dir = std::env::temp_dir().join(format!("ms-frames-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models/Fox.glb");
        let write = |name: &str, time: f32, animation: &str| {
            let text = format!(
                r#"{{"format": "motion-shadows-scene/1",
                "camera": {{"position": [0, 50, 300], "target": [0, 40, 0], "fov_y_deg": 45,
                            "near": 1, "far": 1000}},
                "light": {{"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                           "center": [0, 0, 0], "half_extent": 200, "distance": 200,
                           "near": 1, "far": 400}},
                "objects": [{{"albedo": [1, 1, 1], "mesh": {{"gltf": {{"path": {:?},
                    {animation} "time": {time}, "shutter": 0.02}}}}}}]}}"#,
                model.display().to_string()
            );
            let path = dir.join(name);
            std::fs::write(&path, text).unwrap();
            path
        };
        let a = AnimatedScene::file(&write("a.json", 0.1, r#""animation": "Run","#)).unwrap();
        let at_03 = read_scene_file(&write("b.json", 0.3, r#""animation": "Run","#)).unwrap();
        let mut expected = at_03.to_scene().unwrap();
        expected.name = "a".into();
        assert_eq!(a.at(None, 0.2).unwrap(), expected);
        assert_eq!(a.at(Some(0.25), 0.05).unwrap(), expected);
        let still = write("still.json", 0.0, "");
        match AnimatedScene::file(&still) {
            Err(SceneError::Invalid(m)) => assert!(m.contains("no object"), "{m}"),
            other => panic!("{other:?}"),
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
