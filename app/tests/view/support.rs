//! The viewer tests' helpers: a virtual X server, scripted runs of `view`, the offline
//! frames they are compared with, and the tolerance.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Read-held by each scripted viewer or offline render, write-held by the interactive viewer
/// of `keys`: that one renders until it is closed, and beside other renders its window took
/// minutes to appear (seven side by side). Scripted runs share the cores: each one's small
/// frames leave most of a second core idle (the binary took 51 s of wall for 29 s of CPU with
/// one run at a time), and the harness runs as many tests at once as there are cores.
static RENDERERS: std::sync::RwLock<()> = std::sync::RwLock::new(());

/// A scripted run's share of [`RENDERERS`] (a test that failed while holding it leaves it
/// usable).
pub fn beside_other_scripted_runs() -> std::sync::RwLockReadGuard<'static, ()> {
    RENDERERS
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The interactive viewer's hold of [`RENDERERS`]: no other render while it runs.
pub fn one_renderer_at_a_time() -> std::sync::RwLockWriteGuard<'static, ()> {
    RENDERERS
        .write()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A virtual X server on a free display, ended when dropped.
pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    pub fn start() -> Self {
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

pub fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("motion-shadows-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `view` scripted with `args` (and the screenshot, the JSON summary, no overlay) on
/// its own Xvfb; returns the summary and the screenshot.
pub fn view(args: &[&str], dir: &Path) -> (serde_json::Value, image::RgbImage) {
    let shot = dir.join("shot.png");
    let _shared = beside_other_scripted_runs();
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
pub fn offline(args: &[&str], dir: &Path, file: &str) -> image::RgbImage {
    let deferred: Vec<&str> = ["--frame", "deferred"]
        .iter()
        .chain(args)
        .copied()
        .collect();
    offline_frame(&deferred, dir, file)
}

/// The offline frame of `args` (`render ... --exposure 0`).
pub fn offline_frame(args: &[&str], dir: &Path, file: &str) -> image::RgbImage {
    let out = dir.join("offline");
    let _shared = beside_other_scripted_runs();
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
pub fn assert_same_frame(presented: &image::RgbImage, expected: &image::RgbImage) {
    let difference = FrameDifference::of(presented, expected);
    eprintln!("presented vs offline: {difference}");
    assert!(
        difference.within_tolerance(),
        "presented vs offline deferred frame: {difference}"
    );
    // Not a blank frame: lit surfaces.
    let lit = expected.pixels().filter(|p| p[0] > 100).count();
    assert!(lit > 100, "the frame shows lit surfaces ({lit} pixels)");
}

/// How two images of one size differ, channel by channel.
pub struct FrameDifference {
    /// The largest difference, in 8-bit levels.
    pub worst: i32,
    /// Channels that differ at all, of `channels`.
    pub off: usize,
    pub channels: usize,
}

impl FrameDifference {
    pub fn of(a: &image::RgbImage, b: &image::RgbImage) -> Self {
        assert_eq!(a.dimensions(), b.dimensions());
        let differences: Vec<i32> = a
            .as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(&a, &b)| (i32::from(a) - i32::from(b)).abs())
            .collect();
        Self {
            worst: differences.iter().copied().max().unwrap_or(0),
            off: differences.iter().filter(|&&d| d > 0).count(),
            channels: differences.len(),
        }
    }

    /// The tolerance of the same frame shaded on the device and on the host: one 8-bit level
    /// at a rounding boundary on at most 1% of the channels.
    pub fn within_tolerance(&self) -> bool {
        self.worst <= 1 && self.off * 100 <= self.channels
    }
}

impl std::fmt::Display for FrameDifference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "largest difference {} levels, {} of {} channels differ",
            self.worst, self.off, self.channels
        )
    }
}

/// Columns `from..to` of `image`.
pub fn columns(image: &image::RgbImage, from: u32, to: u32) -> image::RgbImage {
    image::imageops::crop_imm(image, from, 0, to - from, image.height()).to_image()
}

/// Runs `xdotool` with `args` on `display` (ended after 60 s, so that a window system that
/// never answers fails the test instead of hanging it); its stdout.
pub fn xdotool(display: &str, args: &[&str]) -> String {
    let output = Command::new("timeout")
        .args(["60", "xdotool"])
        .args(args)
        .env("DISPLAY", display)
        .output()
        .expect("xdotool must be installed (scripts/setup.sh installs it)");
    if !output.stderr.is_empty() || !output.status.success() {
        // Shown with a failing test's output.
        eprintln!(
            "xdotool {args:?} ({}): {}",
            output.status,
            String::from_utf8_lossy(&output.stderr)
        );
    }
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Polls `check` every 200 ms until it gives a value or `limit` passed (then panics with
/// `what`). A generous bound for a slow machine, not a timing assertion.
pub fn wait_for<T>(what: &str, limit: Duration, mut check: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = check() {
            return v;
        }
        assert!(start.elapsed() < limit, "gave up waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// `view` with `args` (without an X display when `display` is None): it must fail with a
/// message naming `expected`.
pub fn refused(args: &[&str], display: Option<&str>, expected: &str) {
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
