//! `render --frame deferred --method raytrace --runs N` rendered the truth once (the loop over
//! the runs was the device methods' only), dropping `--runs` silently.

use super::{run, s, scene_json, square, temp_dir};

#[test]
fn the_deferred_truth_renders_each_run() {
    let dir = temp_dir("runs");
    let scene = dir.join("floor.json");
    std::fs::write(
        &scene,
        scene_json(
            "floor",
            &[square("floor", 8.0, 0.0, ""), square("roof", 1.0, 2.0, "")],
        ),
    )
    .unwrap();
    let r = run(&[
        "render",
        "--frame",
        "deferred",
        "--method",
        "raytrace",
        "--scene-file",
        s(&scene),
        "--width",
        "32",
        "--height",
        "24",
        "--runs",
        "3",
        "--out",
        s(&dir.join("out")),
    ]);
    assert!(r.output.status.success(), "{}", r.stderr());
    // Progress goes to stderr, one line a step, where it is not a terminal: each run after
    // the first is announced as it starts.
    let stderr = r.stderr();
    for run in ["run 2 of 3", "run 3 of 3"] {
        assert!(stderr.contains(run), "{run:?} not in {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
