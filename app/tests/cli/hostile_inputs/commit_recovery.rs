//! Issue 36 item 7: a run's PNG and EXR are committed by two renames; a run killed between
//! them left the new EXR beside the old PNG (and the PNG's `.partial`), and nothing ever put
//! the pair right. A run records the commit before its first rename now, and the next run
//! into the directory finishes a commit whose process is gone.
//!
//! The kill lands between the renames through `MOTION_SHADOWS_TEST_ABORT=between-renames`
//! (test-only: the process aborts there, as a kill would, no destructor running).

use super::{listing, run, run_env, s, temp_dir};

/// A raytraced frame (no device needed), its PNG at a fixed exposure so that it depends only
/// on the image; `seed` changes the image, so the two runs' files differ in every byte set.
fn render_args<'a>(out: &'a str, seed: &'a str) -> Vec<&'a str> {
    vec![
        "render",
        "--method",
        "raytrace",
        "--width",
        "48",
        "--height",
        "36",
        "--spp",
        "2",
        "--exposure",
        "0",
        "--seed",
        seed,
        "--out",
        out,
    ]
}

#[test]
fn a_pair_whose_commit_was_killed_between_its_renames_is_completed_by_the_next_run() {
    let out = temp_dir("commit-killed");
    let (png, exr) = (
        out.join("cubes-toward-light-raytrace.png"),
        out.join("cubes-toward-light-raytrace.exr"),
    );
    let first = run(&render_args(s(&out), "1"));
    assert!(first.succeeded(), "{}", first.stderr());
    let (old_png, old_exr) = (std::fs::read(&png).unwrap(), std::fs::read(&exr).unwrap());

    let killed = run_env(
        &render_args(s(&out), "2"),
        &[("MOTION_SHADOWS_TEST_ABORT", "between-renames")],
    );
    assert!(!killed.succeeded(), "the run was not aborted");
    assert!(
        killed.stderr().contains("between-renames: aborting here"),
        "{}",
        killed.stderr()
    );
    // The window the test is about: exactly one of the pair is new.
    let exr_new = std::fs::read(&exr).unwrap() != old_exr;
    let png_new = std::fs::read(&png).unwrap() != old_png;
    assert!(exr_new != png_new, "exr new {exr_new}, png new {png_new}");

    // Any later run into the directory, whatever it writes, puts the pair right.
    let json = out.join("scene.json");
    let next = run(&["scene", "export", "cubes-toward-light", "--out", s(&json)]);
    assert!(next.succeeded(), "{}", next.stderr());
    let exr_new = std::fs::read(&exr).unwrap() != old_exr;
    let png_new = std::fs::read(&png).unwrap() != old_png;
    assert!(
        exr_new && png_new,
        "the pair is mixed or old: exr new {exr_new}, png new {png_new}; {}",
        next.stderr()
    );
    assert!(
        next.stderr()
            .contains(&format!("note: completed {}", s(&png))),
        "{}",
        next.stderr()
    );
    assert_eq!(
        listing(&out),
        [
            "cubes-toward-light-raytrace.exr",
            "cubes-toward-light-raytrace.png",
            "scene.json"
        ]
    );
    std::fs::remove_dir_all(&out).ok();
}

/// A run killed after its files were complete but before the first rename: the next run
/// removes them and the old pair stays, both old.
#[test]
fn a_pair_whose_run_was_killed_before_its_commit_stays_old() {
    let out = temp_dir("commit-not-begun");
    let (png, exr) = (
        out.join("cubes-toward-light-raytrace.png"),
        out.join("cubes-toward-light-raytrace.exr"),
    );
    assert!(run(&render_args(s(&out), "1")).succeeded());
    let (old_png, old_exr) = (std::fs::read(&png).unwrap(), std::fs::read(&exr).unwrap());
    let killed = run_env(
        &render_args(s(&out), "2"),
        &[("MOTION_SHADOWS_TEST_ABORT", "before-commit")],
    );
    assert!(!killed.succeeded());
    let json = out.join("scene.json");
    let next = run(&["scene", "export", "cubes-toward-light", "--out", s(&json)]);
    assert!(next.succeeded(), "{}", next.stderr());
    assert_eq!(std::fs::read(&png).unwrap(), old_png);
    assert_eq!(std::fs::read(&exr).unwrap(), old_exr);
    assert_eq!(
        listing(&out),
        [
            "cubes-toward-light-raytrace.exr",
            "cubes-toward-light-raytrace.png",
            "scene.json"
        ]
    );
    std::fs::remove_dir_all(&out).ok();
}
