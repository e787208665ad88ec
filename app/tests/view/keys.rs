//! Keys typed into the window (xdotool) switch the method and take a screenshot.

use crate::support::*;
use std::process::{Command, Stdio};
use std::time::Duration;

#[test]
fn view_keys_switch_the_method_and_take_a_screenshot_of_what_is_shown() {
    let dir = temp_dir("view-keys");
    let alone = one_renderer_at_a_time();
    let xvfb = Xvfb::start();
    let size = ["--width", "160", "--height", "90"];
    let mut viewer = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .arg("view")
        .args(size)
        .args(["--overlay", "off"])
        .current_dir(&dir)
        .env("DISPLAY", &xvfb.display)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the binary");
    // Generous: at 120 s this wait gave up twice in nine runs on a loaded machine (cause not
    // found); a bound for a hung viewer, not a timing assertion.
    let limit = Duration::from_secs(300);
    let window = wait_for("the viewer's window", limit, || {
        if let Ok(Some(status)) = viewer.try_wait() {
            // Ended before its window was found: its own words say why.
            let mut stderr = String::new();
            if let Some(mut pipe) = viewer.stderr.take() {
                std::io::Read::read_to_string(&mut pipe, &mut stderr).ok();
            }
            panic!("the viewer ended ({status}) before its window was found: {stderr}");
        }
        let found = xdotool(&xvfb.display, &["search", "--name", "motion-shadows"]);
        found.lines().next().map(str::to_owned)
    });
    xdotool(&xvfb.display, &["windowfocus", "--sync", &window]);
    // M three times: temporal -> temporal-exact -> TSM-8 -> plain; then P: a screenshot of
    // the next frame, as presented.
    for key in ["m", "m", "m", "p"] {
        xdotool(&xvfb.display, &["key", key]);
    }
    let shot = dir.join("motion-shadows-view-001.png");
    wait_for("the screenshot", limit, || shot.exists().then_some(()));
    // The viewer writes the file within one event, so Escape is handled after it is whole;
    // it is read once the viewer has exited.
    xdotool(&xvfb.display, &["key", "Escape"]);
    let status = wait_for("the viewer to close on Escape", limit, || {
        viewer.try_wait().expect("the viewer's status")
    });
    let output = viewer.wait_with_output().expect("the viewer's output");
    drop(xvfb);
    drop(alone);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(status.success(), "view failed: {stderr}");
    assert!(!stderr.contains("vulkan validation"), "{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("wrote motion-shadows-view-001.png"),
        "{stdout}"
    );
    let args: Vec<&str> = size.iter().chain(&["--method", "plain"]).copied().collect();
    let expected = offline(&args, &dir, "cubes-toward-light-deferred-plain.png");
    assert_same_frame(&rgb(&shot), &expected);
    std::fs::remove_dir_all(&dir).ok();
}
