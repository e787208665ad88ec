//! A user's mistakes (issue 10's probes): one case per class of problem the probes found, each run through
//! the `motion-shadows` binary as a user would, with the validation layer on
//! (MOTION_SHADOWS_VALIDATION=1). Runs that must be refused are refused before a device is
//! made, in milliseconds; a few tiny renders (48x36) check what must still render.
//!
//! Every run has a time limit and a memory limit (ulimit -v), so a regression to reading or
//! building without bound fails here instead of taking the machine down.

mod closed_meshes;
mod coordinate_bound;
mod empty_shadow_map;
mod input_sizes;
mod option_values;
mod output_paths;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use motion_shadows_app::output::read_exr;

/// Virtual memory a run may use: enough for lavapipe, far less than the probes needed.
const MEMORY_LIMIT_KIB: u64 = 8 << 20;

struct Run {
    output: Output,
}

impl Run {
    fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    fn succeeded(&self) -> bool {
        self.output.status.success()
    }

    /// Asserts the run failed with a message containing every one of `needles`. (How fast is
    /// a bench's concern, not a test's: `run` only kills a run that hangs.)
    fn refused(&self, needles: &[&str]) -> String {
        let stderr = self.stderr();
        assert!(!self.succeeded(), "must fail; stderr: {stderr}");
        for needle in needles {
            assert!(
                stderr.contains(needle),
                "{needle:?} not in stderr: {stderr}"
            );
        }
        stderr
    }
}

/// Runs the binary with `args`, under the memory limit, killed after `limit` (a hang guard:
/// a run that needs it has failed anyway).
fn run_for(args: &[&str], limit: Duration) -> Run {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_LIMIT_KIB} && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the binary");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let output = child.wait_with_output().expect("collect");
            panic!(
                "{args:?} still ran after {limit:?} (killed); stderr: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().expect("collect");
    Run { output }
}

fn run(args: &[&str]) -> Run {
    run_for(args, Duration::from_secs(120))
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "motion-shadows-hardening-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// A scene file with the given name, spot light and objects (JSON fragments).
fn scene_json(name: &str, camera_near: f32, light_position: &str, objects: &[String]) -> String {
    format!(
        r#"{{
  "format": "motion-shadows-scene/1",
  "name": {name:?},
  "camera": {{ "position": [0, 4, 6], "target": [0, 0, 0], "fov_y_deg": 45, "near": {camera_near}, "far": 100 }},
  "light": {{ "type": "spot", "position": {light_position}, "direction": [0, -1, 0],
             "cone_angle_deg": 50, "intensity": 50, "near": 0.05, "far": 50 }},
  "objects": [{}]
}}"#,
        objects.join(",\n")
    )
}

/// A floor triangle with corners at +-`half` (so |coordinate| = half), facing +y.
fn floor(half: f64) -> String {
    format!(
        r#"{{ "name": "floor", "albedo": [0.8, 0.8, 0.8], "mesh": {{ "triangles": {{
             "t0": [[{m}, 0, {h}], [{h}, 0, {h}], [0, 0, {m}]] }} }} }}"#,
        h = half,
        m = -half
    )
}

fn write_scene(dir: &Path, file: &str, json: &str) -> PathBuf {
    let path = dir.join(file);
    std::fs::write(&path, json).unwrap();
    path
}

const SMALL: [&str; 6] = ["--width", "48", "--height", "36", "--spp", "2"];

fn render_file(scene: &Path, out: &Path, extra: &[&str]) -> Run {
    let mut args = vec!["render", "--scene-file", s(scene), "--out", s(out)];
    args.extend(SMALL);
    args.extend(extra);
    run(&args)
}

/// Mean and maximum luminance-ish (mean of RGB) of an EXR.
fn radiance_stats(path: &Path) -> (f32, f32) {
    let image = read_exr(path).expect("read the EXR");
    let values: Vec<f32> = image
        .rgb
        .chunks_exact(3)
        .map(|p| (p[0] + p[1] + p[2]) / 3.0)
        .collect();
    let mean = values.iter().sum::<f32>() / values.len() as f32;
    (mean, values.iter().copied().fold(0.0, f32::max))
}
