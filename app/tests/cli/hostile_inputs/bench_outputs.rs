//! Issue 36 item 6: `bench --preset engine` with a directory at `OUT/engine-results.csv` (or
//! `--preset frame` with a symbolic link at `frame-time.png`) ran the whole preset, wrote
//! its other files, then failed. Every file of every preset asked for is checked before the
//! device is made now, from the one list each preset declares (`Preset::outputs`).

use motion_shadows_app::bench::{PRESETS, Preset};

use super::{listing, run_env, s, temp_dir};

/// No Vulkan driver: a run that got past the check would fail at once, without rendering,
/// and its error would name the device, not the file in the way.
const NO_DEVICE: [(&str, &str); 2] = [
    (
        "VK_DRIVER_FILES",
        "/nonexistent/motion-shadows-no-driver.json",
    ),
    (
        "VK_ICD_FILENAMES",
        "/nonexistent/motion-shadows-no-driver.json",
    ),
];

/// Puts what an output may not replace at `out/name`: a directory at a CSV's place, a
/// symbolic link (to `elsewhere`) at a PNG's; returns the words the refusal must say.
fn obstruct(out: &std::path::Path, name: &str, elsewhere: &std::path::Path) -> &'static str {
    let target = out.join(name);
    if name.ends_with(".csv") {
        std::fs::create_dir(&target).unwrap();
        "is a directory"
    } else if name.ends_with(".png") {
        std::os::unix::fs::symlink(elsewhere, &target).unwrap();
        "symbolic link"
    } else {
        panic!("{name}: a preset file that is neither CSV nor PNG");
    }
}

#[test]
fn every_presets_files_that_cannot_be_replaced_are_refused_before_it_runs() {
    let root = temp_dir("bench-targets");
    let elsewhere = root.join("elsewhere.png");
    std::fs::write(&elsewhere, "not the bench's").unwrap();
    let mut cases = 0;
    for &preset in PRESETS {
        let outputs = preset.outputs();
        assert!(!outputs.is_empty(), "{} declares no file", preset.name());
        for name in outputs {
            let out = root.join(format!("case-{cases}"));
            std::fs::create_dir(&out).unwrap();
            let kind = obstruct(&out, &name, &elsewhere);
            let args = [
                "bench",
                "--quick",
                "--preset",
                preset.name(),
                "--out",
                s(&out),
            ];
            let r = run_env(&args, &NO_DEVICE);
            r.refused(&[s(&out.join(&name)), kind]);
            assert_eq!(listing(&out), [name.as_str()], "something was written");
            cases += 1;
        }
    }
    assert_eq!(
        std::fs::read_to_string(&elsewhere).unwrap(),
        "not the bench's"
    );

    // Several presets: the second's file is checked before the first runs.
    let out = root.join("two-presets");
    std::fs::create_dir(&out).unwrap();
    let engine_table = Preset::Engine.outputs()[0].clone();
    assert_eq!(engine_table, "engine-results.csv");
    let kind = obstruct(&out, &engine_table, &elsewhere);
    let args = [
        "bench",
        "--quick",
        "--preset",
        "frame",
        "--preset",
        "engine",
        "--out",
        s(&out),
    ];
    run_env(&args, &NO_DEVICE).refused(&[s(&out.join(&engine_table)), kind]);
    assert_eq!(listing(&out), [engine_table.as_str()]);
    std::fs::remove_dir_all(&root).ok();
}
