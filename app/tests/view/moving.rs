//! A moving light and a moving camera in the viewer's deferred frame (issue 38): the camera
//! where it is at the G-buffer's time, the mask with the light moving over the shutter, the
//! shading with the light where it is at that time. The presented frame must be the offline
//! deferred frame of the same scene and time (`render --frame deferred`), itself checked
//! against the exact truth (app/tests/gpu: `moving_light`, `moving_light_deferred_tsm`,
//! `moving_camera_deferred`). A viewer that drew the camera or the light at t = 0 is off by
//! far more than the tolerance (the pan moves the image 1.5 units; the light 2).

use crate::support::*;

const SIZE: [&str; 6] = [
    "--width",
    "160",
    "--height",
    "90",
    "--shadow-size",
    "512x512",
];

/// `view` of `scene` with `extra` (scripted, 4 frames: the first may overflow a moving
/// light's map, which grows after) against `render --frame deferred` of the same.
fn presents_the_offline_frame(name: &str, scene: &str, extra: &[&str], file: &str) {
    let dir = temp_dir(name);
    let common: Vec<&str> = ["--scene", scene]
        .iter()
        .chain(&SIZE)
        .chain(extra)
        .copied()
        .collect();
    let args: Vec<&str> = ["--frames", "4"].iter().chain(&common).copied().collect();
    let (summary, presented) = view(&args, &dir);
    eprintln!("{scene}: {summary}");
    let expected = offline(&common, &dir, file);
    assert_same_frame(&presented, &expected);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn view_presents_the_offline_frame_under_a_moving_light() {
    presents_the_offline_frame(
        "view-moving-light",
        "moving-light",
        &[],
        "moving-light-deferred-temporal.png",
    );
}

#[test]
fn view_presents_the_offline_tsm_frame_under_a_moving_light() {
    presents_the_offline_frame(
        "view-moving-light-tsm",
        "moving-light",
        &["--method", "tsm", "--tsm-maps", "4"],
        "moving-light-deferred-tsm-4.png",
    );
}

#[test]
fn view_presents_the_offline_frame_of_a_moving_camera() {
    presents_the_offline_frame(
        "view-camera-pan",
        "camera-pan",
        &["--camera-time", "0.5"],
        "camera-pan-deferred-temporal.png",
    );
}
