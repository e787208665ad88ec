//! A built-in scene exported as a file and imported again.

use super::*;

/// A built-in scene exported as a file renders to the same bytes as the built-in; for
/// `walker-toward-light` the file holds the posed model as triangles and needs no asset.
#[test]
fn exported_scene_file_renders_like_the_builtin() {
    let dir = temp_dir("export");
    for name in ["cubes-toward-light", "walker-toward-light"] {
        let scene_file = dir.join(format!("{name}.json"));
        let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
            .args(["scene", "export", name, "--out"])
            .arg(&scene_file)
            .status()
            .unwrap();
        assert!(status.success());
        let small = ["--width", "48", "--height", "36", "--spp", "2"];
        let a = dir.join(format!("{name}-builtin"));
        let b = dir.join(format!("{name}-file"));
        motion_shadows(&[&["render", "--scene", name][..], &small].concat(), &a);
        let file_arg = scene_file.to_str().unwrap();
        motion_shadows(
            &[&["render", "--scene-file", file_arg][..], &small].concat(),
            &b,
        );
        let exr = |d: &Path| std::fs::read(d.join(format!("{name}-temporal.exr"))).unwrap();
        assert!(
            exr(&a) == exr(&b),
            "the exported {name} renders differently"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
