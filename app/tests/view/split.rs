//! The split view: the left half is the left method's frame, the right half the right
//! method's, of the same camera and time, each as the viewer shows it unsplit.

use crate::support::*;

/// Temporal on the left, TSM-2 on the right (two discrete shadows instead of the blur: the
/// halves differ measurably from the other method's, so swapped halves fail), against the
/// viewer's unsplit frames of each method. Tolerance: as the offline comparison's (one
/// level on at most 1% of the channels), though both come from the same device's passes.
#[test]
fn view_split_shows_each_methods_frame_on_its_half() {
    let dir = temp_dir("view-split");
    let run = |method: &[&str]| {
        let args: Vec<&str> = ["--frames", "3", "--width", "160", "--height", "90"]
            .iter()
            .chain(method)
            .copied()
            .collect();
        view(&args, &dir)
    };
    let (summary, split) = run(&["--method", "temporal", "--split", "tsm", "--tsm-maps", "2"]);
    assert_eq!(summary["method"], "temporal", "{summary}");
    assert_eq!(summary["split"], "tsm-2", "{summary}");
    assert_eq!(summary["allocations"]["after_first_frame"], 0, "{summary}");
    assert_eq!(summary["incomplete_frames"], 0, "{summary}");
    let passes: Vec<&str> = summary["gpu_ms_per_frame"]
        .as_array()
        .map(|a| a.iter().filter_map(|p| p["pass"].as_str()).collect())
        .unwrap_or_default();
    assert!(passes.contains(&"mask"), "{summary}");
    assert!(passes.contains(&"split tsm + mask"), "{summary}");
    let (_, left) = run(&["--method", "temporal"]);
    let (_, right) = run(&["--method", "tsm", "--tsm-maps", "2"]);
    let seam = split.width() / 2;
    let halves = [
        ("left", 0, seam, &left, &right),
        ("right", seam, split.width(), &right, &left),
    ];
    for (half, from, to, own, other) in halves {
        let shown = columns(&split, from, to);
        let same = FrameDifference::of(&shown, &columns(own, from, to));
        let swapped = FrameDifference::of(&shown, &columns(other, from, to));
        eprintln!("{half} half: its method's frame: {same}; the other method's: {swapped}");
        assert!(
            same.within_tolerance(),
            "the split's {half} half vs its method's frame: {same}"
        );
        assert!(
            !swapped.within_tolerance(),
            "the methods do not differ measurably on the {half} half: {swapped}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
