//! Errors name what is wrong and, for a missing animation, what there is instead.

use super::super::{AnimationRef, GltfOptions, load_gltf_motion};
use super::builder::{asset, write_temp};
use crate::scene::SceneError;

fn message(path: &std::path::Path, animation: Option<AnimationRef>) -> String {
    let options = GltfOptions {
        animation,
        ..GltfOptions::default()
    };
    match load_gltf_motion(path, &options) {
        Err(e @ SceneError::Gltf { .. }) => e.to_string(),
        other => panic!("expected a glTF error, got {other:?}"),
    }
}

#[test]
fn an_unknown_animation_lists_the_available_ones() {
    let m = message(&asset("Fox.glb"), Some(AnimationRef::Name("Trot".into())));
    assert!(
        m.contains("\"Trot\" not found")
            && m.contains("\"Survey\"")
            && m.contains("\"Walk\"")
            && m.contains("\"Run\""),
        "{m}"
    );
    let m = message(&asset("CesiumMan.gltf"), Some(AnimationRef::Index(1)));
    assert!(
        m.contains("animation index 1 not found") && m.contains("#0 (unnamed)"),
        "{m}"
    );
}

#[test]
fn missing_unparseable_and_extension_requiring_files_are_refused() {
    let m = message(&asset("Absent.gltf"), None);
    assert!(
        m.contains("Absent.gltf") && m.contains("No such file"),
        "{m}"
    );
    let path = write_temp("junk.gltf", "{ not json");
    let m = message(&path, None);
    assert!(m.contains("not a glTF 2.0 file"), "{m}");
    std::fs::write(
        &path,
        r#"{"asset": {"version": "2.0"}, "extensionsRequired": ["KHR_draco_mesh_compression"],
            "extensionsUsed": ["KHR_draco_mesh_compression"]}"#,
    )
    .unwrap();
    let m = message(&path, None);
    assert!(
        m.contains("KHR_draco_mesh_compression") && m.contains("not support"),
        "{m}"
    );
    std::fs::write(&path, r#"{"asset": {"version": "2.0"}}"#).unwrap();
    let m = message(&path, None);
    assert!(m.contains("draws no triangles"), "{m}");
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}
