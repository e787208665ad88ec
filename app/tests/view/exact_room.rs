//! The exact lookup's map room is reserved before each frame from the host's positions, as
//! the depth-line lookup's is: no frame overflows, is grown after and misses casters.

use crate::support::*;

/// Frames with the exact lookup: none incomplete (grown after it overflowed), nothing
/// allocated after the first, and the frame is still the offline exact frame.
#[test]
fn view_reserves_the_exact_lookups_room_before_each_frame() {
    let dir = temp_dir("view-exact");
    let size = ["--width", "160", "--height", "90"];
    let args: Vec<&str> = ["--frames", "4", "--method", "temporal-exact"]
        .iter()
        .chain(&size)
        .copied()
        .collect();
    let (summary, presented) = view(&args, &dir);
    assert_eq!(summary["method"], "temporal-exact", "{summary}");
    assert_eq!(summary["incomplete_frames"], 0, "{summary}");
    assert_eq!(summary["allocations"]["after_first_frame"], 0, "{summary}");
    let args: Vec<&str> = size
        .iter()
        .chain(&["--method", "temporal", "--lookup", "exact"])
        .copied()
        .collect();
    let expected = offline(
        &args,
        &dir,
        "cubes-toward-light-deferred-temporal-exact.png",
    );
    assert_same_frame(&presented, &expected);
    std::fs::remove_dir_all(&dir).ok();
}
