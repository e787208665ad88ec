//! Issue 36, "Hardening, round 3" (the CLI's items): what the deferred frame and `compare`
//! take and refuse, run through the `motion-shadows` binary with the validation layer on
//! (MOTION_SHADOWS_VALIDATION=1), under an address-space limit (ulimit -v) so that a run that
//! would take more memory than it may is refused, not left to abort.

mod device_limit;
mod forward_lookup;
mod lookup;
mod memory;
mod preset;
mod receivers;
mod runs;
mod unread;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Virtual memory a run may use: enough for lavapipe and a small frame.
const MEMORY_LIMIT_KIB: u64 = 8 << 20;

pub struct Run {
    pub output: Output,
}

impl Run {
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    pub fn json(&self) -> serde_json::Value {
        assert!(self.output.status.success(), "failed: {}", self.stderr());
        serde_json::from_slice(&self.output.stdout).expect("stdout is one JSON object")
    }

    /// Asserts the run failed with exit status 1 (an error, not a signal or a panic), with a
    /// message containing every one of `needles`; returns the message.
    pub fn refused(&self, needles: &[&str]) -> String {
        let stderr = self.stderr();
        assert_eq!(
            self.output.status.code(),
            Some(1),
            "must fail with status 1 (not abort); status {:?}, stderr: {stderr}",
            self.output.status
        );
        assert!(!stderr.contains("panicked"), "a panic: {stderr}");
        for needle in needles {
            assert!(
                stderr.contains(needle),
                "{needle:?} not in stderr: {stderr}"
            );
        }
        stderr
    }
}

/// Runs the binary with `args` under the memory limit.
pub fn run(args: &[&str]) -> Run {
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_LIMIT_KIB} && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    Run { output }
}

pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "motion-shadows-frame-options-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// Every name in `dir` (recursively none expected deeper), sorted; empty if it is missing.
pub fn listing(dir: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A scene file: a camera above and in front of the origin, a light straight down, and
/// `objects` (JSON fragments).
pub fn scene_json(name: &str, objects: &[String]) -> String {
    format!(
        r#"{{
  "format": "motion-shadows-scene/1",
  "name": {name:?},
  "camera": {{ "position": [0, 8, 6], "target": [0, 0, 0], "fov_y_deg": 40, "near": 0.1, "far": 100 }},
  "light": {{ "type": "directional", "direction": [0, -1, 0], "irradiance": 3,
             "center": [0, 0, 0], "half_extent": 8, "distance": 12, "near": 0.1, "far": 30 }},
  "ambient": 0.05,
  "objects": [{}]
}}"#,
        objects.join(",\n")
    )
}

/// A square of side `side` at height `y`, centred on the x and z axes.
pub fn square(name: &str, side: f32, y: f32, motion: &str) -> String {
    let a = side / 2.0;
    format!(
        r#"{{ "name": {name:?}, "albedo": [0.8, 0.8, 0.8],
             "mesh": {{ "triangles": {{ "t0": [[-{a}, {y}, {a}], [{a}, {y}, {a}], [{a}, {y}, -{a}],
                                             [-{a}, {y}, {a}], [{a}, {y}, -{a}], [-{a}, {y}, -{a}]] }} }}
             {motion} }}"#
    )
}
