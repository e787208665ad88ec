//! Item 1: the deferred truth at 16384x16384 took about 13 GiB in one go and aborted
//! (`memory allocation of 3221225472 bytes failed`, SIGABRT), leaving `animate`'s
//! `.gif.partial`. Now its memory is estimated from the image size before anything is
//! traced and the run is refused with the figures, naming the options to lower.

use super::{listing, run, s, scene_json, square, temp_dir};

/// Refused with status 1 and the figures, nothing left in `out`.
fn assert_refused(args: &[&str], out: &std::path::Path) {
    let r = run(args);
    r.refused(&["16384x16384", "would need about", "GiB", "--width"]);
    assert!(listing(out).is_empty(), "left behind: {:?}", listing(out));
}

#[test]
fn the_deferred_truth_past_what_the_process_can_use_is_refused_with_figures() {
    let dir = temp_dir("memory");
    let out = dir.join("out");
    let scene = dir.join("floor.json");
    std::fs::write(
        &scene,
        scene_json(
            "floor",
            &[square("floor", 8.0, 0.0, ""), square("roof", 1.0, 2.0, "")],
        ),
    )
    .unwrap();
    let huge = ["--width", "16384", "--height", "16384", "--out", s(&out)];
    let deferred = ["--frame", "deferred", "--scene-file", s(&scene)];
    assert_refused(
        &[
            &["render", "--method", "raytrace"],
            &deferred[..],
            &huge[..],
        ]
        .concat(),
        &out,
    );
    assert_refused(&[&["compare"], &deferred[..], &huge[..]].concat(), &out);
    // animate needs an animated scene: the built-in walker (its frames are rendered one by
    // one, the GIF written as they come: nothing of it may stay).
    assert_refused(
        &[
            &[
                "animate", "--frames", "2", "--frame", "deferred", "--method", "raytrace",
            ][..],
            &huge[..],
        ]
        .concat(),
        &out,
    );
    std::fs::remove_dir_all(&dir).ok();
}
