//! The presented frame is the offline renderer's (deferred after a resize, TSM, the
//! stochastic frame), and the frames after the first allocate nothing.

use crate::support::*;

#[test]
fn view_presents_the_offline_deferred_frame_and_allocates_nothing_after_the_first() {
    let dir = temp_dir("view");
    let (summary, presented) = view(
        &[
            "--frames",
            "3",
            "--width",
            "160",
            "--height",
            "90",
            "--shadow-size",
            "160x90",
            "--resize",
            "192x108",
        ],
        &dir,
    );
    assert_eq!(summary["width"], 192, "{summary}");
    assert_eq!(summary["height"], 108, "{summary}");
    assert!(summary["frames"].as_u64() >= Some(3), "{summary}");
    assert!(summary["swapchains_made"].as_u64() >= Some(2), "{summary}");
    assert_eq!(summary["incomplete_frames"], 0, "{summary}");
    let allocations = &summary["allocations"];
    assert_eq!(allocations["after_first_frame"], 0, "{summary}");
    // The counter sees the resize's new images and the screenshot's buffer.
    assert!(allocations["events"].as_u64() > Some(1), "{summary}");
    let expected = offline(
        &[
            "--width",
            "192",
            "--height",
            "108",
            "--shadow-size",
            "160x90",
        ],
        &dir,
        "cubes-toward-light-deferred-temporal.png",
    );
    assert_same_frame(&presented, &expected);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn view_presents_the_offline_tsm_frame() {
    let dir = temp_dir("view-tsm");
    let size = ["--width", "160", "--height", "90"];
    let method = ["--method", "tsm", "--tsm-maps", "4"];
    let args: Vec<&str> = ["--frames", "3"]
        .iter()
        .chain(&size)
        .chain(&method)
        .copied()
        .collect();
    let (summary, presented) = view(&args, &dir);
    assert_eq!(summary["method"], "tsm-4", "{summary}");
    assert_eq!(summary["allocations"]["after_first_frame"], 0, "{summary}");
    let args: Vec<&str> = size.iter().chain(&method).copied().collect();
    let expected = offline(&args, &dir, "cubes-toward-light-deferred-tsm-4.png");
    assert_same_frame(&presented, &expected);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn view_presents_the_offline_stochastic_frame() {
    let dir = temp_dir("view-forward");
    // The analytic estimator with the bilinear filter: the view's own options reach the
    // lighting pass as `render`'s do.
    let size = [
        "--width",
        "160",
        "--height",
        "90",
        "--spp",
        "2",
        "--shadow-estimator",
        "analytic",
        "--shadow-filter",
        "bilinear",
    ];
    let args: Vec<&str> = ["--frames", "3", "--frame", "forward"]
        .iter()
        .chain(&size)
        .copied()
        .collect();
    let (summary, presented) = view(&args, &dir);
    assert_eq!(summary["frame"], "forward", "{summary}");
    assert_eq!(summary["allocations"]["after_first_frame"], 0, "{summary}");
    // `render`'s forward frame: the same samples (seed 1), the temporal map.
    let expected = offline_frame(&size, &dir, "cubes-toward-light-temporal.png");
    assert_same_frame(&presented, &expected);
    std::fs::remove_dir_all(&dir).ok();
}
