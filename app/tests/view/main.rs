//! `motion-shadows view` in a real window: a virtual X server (Xvfb, started here; the test
//! fails without it, or without a Vulkan device that presents to it), scripted runs of a few
//! frames, the validation layer and synchronization validation on. The presented frame, read
//! back from the swapchain image, must be the offline renderer's deferred frame of the same
//! camera, time and method (`render --frame deferred`), also after a resize, and the frames
//! after the first must allocate nothing.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A virtual X server on a free display, ended when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Self {
        // -displayfd: the server picks a free display and writes its number to stdout once
        // it accepts connections.
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb must be installed (scripts/setup.sh installs xvfb)");
        let stdout = child.stdout.take().expect("Xvfb's stdout");
        let mut line = String::new();
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("Xvfb's display number");
        let number: u32 = line
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("Xvfb did not start: printed {line:?}"));
        Self {
            child,
            display: format!(":{number}"),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("motion-shadows-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `view` scripted with `args` (and the screenshot, the JSON summary, no overlay) on
/// its own Xvfb; returns the summary and the screenshot.
fn view(args: &[&str], dir: &Path) -> (serde_json::Value, image::RgbImage) {
    let shot = dir.join("shot.png");
    let xvfb = Xvfb::start();
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .arg("view")
        .args(args)
        // The overlay's text is not in the offline frame.
        .args(["--overlay", "off", "--json", "--screenshot"])
        .arg(&shot)
        .env("DISPLAY", &xvfb.display)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    drop(xvfb);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "view {args:?} failed: {stderr}");
    // The run fails on any validation message; none may even be printed.
    assert!(!stderr.contains("vulkan validation"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("view --json prints one JSON object");
    (summary, rgb(&shot))
}

/// The offline deferred frame of `args` (`render --frame deferred ... --exposure 0`).
fn offline(args: &[&str], dir: &Path, file: &str) -> image::RgbImage {
    let deferred: Vec<&str> = ["--frame", "deferred"]
        .iter()
        .chain(args)
        .copied()
        .collect();
    offline_frame(&deferred, dir, file)
}

/// The offline frame of `args` (`render ... --exposure 0`).
fn offline_frame(args: &[&str], dir: &Path, file: &str) -> image::RgbImage {
    let out = dir.join("offline");
    let render = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["render", "--exposure", "0"])
        .args(args)
        .arg("--out")
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    assert!(
        render.status.success(),
        "render failed: {}",
        String::from_utf8_lossy(&render.stderr)
    );
    rgb(&out.join(file))
}

/// Tolerance: the same G-buffer and lit shares, shaded in f32 on the device instead of f64
/// on the host: one 8-bit level at a rounding boundary on at most 1% of the channels.
fn assert_same_frame(presented: &image::RgbImage, expected: &image::RgbImage) {
    assert_eq!(presented.dimensions(), expected.dimensions());
    let differences: Vec<i32> = presented
        .as_raw()
        .iter()
        .zip(expected.as_raw())
        .map(|(&a, &b)| (i32::from(a) - i32::from(b)).abs())
        .collect();
    let worst = differences.iter().copied().max().unwrap_or(0);
    let off = differences.iter().filter(|&&d| d > 0).count();
    eprintln!(
        "presented vs offline: largest difference {worst} levels, {off} of {} channels differ",
        differences.len()
    );
    assert!(
        worst <= 1 && off * 100 <= differences.len(),
        "presented vs offline deferred frame: largest difference {worst} levels, {off} of {} \
         channels differ",
        differences.len()
    );
    // Not a blank frame: lit surfaces.
    let lit = expected.pixels().filter(|p| p[0] > 100).count();
    assert!(lit > 100, "the frame shows lit surfaces ({lit} pixels)");
}

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

/// Runs `xdotool` with `args` on `display` (ended after 60 s, so that a window system that
/// never answers fails the test instead of hanging it); its stdout.
fn xdotool(display: &str, args: &[&str]) -> String {
    let output = Command::new("timeout")
        .args(["60", "xdotool"])
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("xdotool must be installed (scripts/setup.sh installs it)");
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Polls `check` every 200 ms until it gives a value or `limit` passed (then panics with
/// `what`). A generous bound for a slow machine, not a timing assertion.
fn wait_for<T>(what: &str, limit: Duration, mut check: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = check() {
            return v;
        }
        assert!(start.elapsed() < limit, "gave up waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

#[test]
fn view_keys_switch_the_method_and_take_a_screenshot_of_what_is_shown() {
    let dir = temp_dir("view-keys");
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
    let limit = Duration::from_secs(120);
    let window = wait_for("the viewer's window", limit, || {
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

/// `view` with `args` (without an X display when `display` is None): it must fail with a
/// message naming `expected`.
fn refused(args: &[&str], display: Option<&str>, expected: &str) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_motion-shadows"));
    command.arg("view").args(args);
    match display {
        Some(d) => command.env("DISPLAY", d),
        None => command.env_remove("DISPLAY"),
    };
    let output = command.output().expect("run the binary");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "view {args:?} was accepted");
    assert!(
        stderr.contains(expected),
        "view {args:?}: the error does not name {expected:?}: {stderr}"
    );
}

#[test]
fn view_refuses_what_it_cannot_do_by_name() {
    // Without a display: it says so before opening anything.
    refused(&["--frames", "1"], None, "DISPLAY");
    // Scripted-only options without --frames.
    refused(&["--screenshot", "x.png"], Some(":0"), "--frames");
    refused(&["--resize", "64x64"], Some(":0"), "--frames");
    refused(
        &["--tsm-maps", "0", "--frames", "1"],
        Some(":0"),
        "--tsm-maps",
    );
    refused(
        &["--camera-time", "2", "--frames", "1"],
        Some(":0"),
        "--camera-time",
    );
    refused(
        &["--resize", "0x64", "--frames", "1"],
        Some(":0"),
        "--resize",
    );
    refused(&["--spp", "0", "--frames", "1"], Some(":0"), "--spp");
    refused(
        &[
            "--method",
            "temporal-exact",
            "--shadow-filter",
            "bilinear",
            "--frames",
            "1",
        ],
        Some(":0"),
        "--shadow-filter bilinear",
    );
    refused(
        &["--frame", "forward", "--method", "tsm", "--frames", "1"],
        Some(":0"),
        "--frame forward",
    );
}
