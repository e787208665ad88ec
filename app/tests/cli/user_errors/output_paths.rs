//! What a run may write: scene names held to safe file names, and earlier outputs kept when a
//! run fails.

use super::*;

// ---------------------------------------------------------------------------------------
// Writing outside --out: scene names are file names, so they are held to a safe set.

#[test]
fn scene_names_cannot_leave_the_output_directory_or_flood_the_error() {
    let root = temp_dir("names");
    let out = root.join("a").join("b");
    std::fs::create_dir_all(&out).unwrap();
    for name in ["../../escaped", "/tmp/motion-shadows-absolute", ".hidden"] {
        let scene = write_scene(
            &root,
            "named.json",
            &scene_json(name, 0.1, "[0, 5, 0]", &[floor(4.0)]),
        );
        render_file(&scene, &out, &[]).refused(&["scene name"]);
    }
    assert!(!root.join("escaped-temporal.png").exists());
    assert!(!Path::new("/tmp/motion-shadows-absolute-temporal.png").exists());
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        0,
        "nothing written"
    );

    let long = "n".repeat(1_000_000);
    let scene = write_scene(
        &root,
        "long.json",
        &scene_json(&long, 0.1, "[0, 5, 0]", &[floor(4.0)]),
    );
    let stderr = render_file(&scene, &out, &[]).refused(&["scene name", "1000000 bytes in all"]);
    assert!(stderr.len() < 2000, "{} bytes of stderr", stderr.len());
    std::fs::remove_dir_all(&root).unwrap();
}

// ---------------------------------------------------------------------------------------
// Good files destroyed: options and output paths are checked before rendering, and the files
// of a run replace the old ones only once all of them are complete.

#[test]
fn a_run_that_must_fail_leaves_previous_outputs_untouched() {
    let out = temp_dir("keep");
    let good = |name: &str| {
        let path = out.join(name);
        std::fs::write(&path, format!("good {name}")).unwrap();
        path
    };
    let exr = good("cubes-toward-light-tsm.exr");
    let png = good("cubes-toward-light-tsm.png");
    // TSM stores no ranges, so there is nothing to draw a heat map of.
    let mut args = vec!["render", "--method", "tsm", "--heatmaps", "--out", s(&out)];
    args.extend(SMALL);
    run(&args).refused(&["--heatmaps", "temporal or coverage"]);
    assert_eq!(
        std::fs::read_to_string(&exr).unwrap(),
        "good cubes-toward-light-tsm.exr"
    );
    assert_eq!(
        std::fs::read_to_string(&png).unwrap(),
        "good cubes-toward-light-tsm.png"
    );

    // The PNG's path is a directory: found before rendering, the EXR is not replaced.
    let exr = good("cubes-toward-light-temporal.exr");
    std::fs::create_dir(out.join("cubes-toward-light-temporal.png")).unwrap();
    let mut args = vec!["render", "--out", s(&out)];
    args.extend(SMALL);
    let r = run(&args);
    r.refused(&["cubes-toward-light-temporal.png", "is a directory"]);
    assert!(
        !r.stderr().contains("lighting pass"),
        "refused before rendering"
    );
    assert_eq!(
        std::fs::read_to_string(&exr).unwrap(),
        "good cubes-toward-light-temporal.exr"
    );
    // No temporary file is left behind either.
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            "cubes-toward-light-temporal.exr",
            "cubes-toward-light-temporal.png",
            "cubes-toward-light-tsm.exr",
            "cubes-toward-light-tsm.png"
        ]
    );
    std::fs::remove_dir_all(&out).unwrap();
}
