//! Issue 25, "Hardening, round 2": the newer inputs (glTF, animate, export, concurrency) as a
//! hostile user would try them, one case per problem the probes found, each run through the
//! `motion-shadows` binary with the validation layer on (MOTION_SHADOWS_VALIDATION=1).
//!
//! Every run has a time limit (a hang guard only: no test asserts how fast anything is) and
//! a memory limit (ulimit -v), so a regression to building without bound fails here instead
//! of taking the machine down.

mod animate;
mod bench_outputs;
mod commit_recovery;
mod gltf_keys;
mod memory;
mod messages;
mod outputs;
mod partial_sweep;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Virtual memory a run may use: enough for lavapipe, far less than the probes needed.
pub const MEMORY_LIMIT_KIB: u64 = 8 << 20;

pub struct Run {
    pub output: Output,
}

impl Run {
    pub fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }

    pub fn succeeded(&self) -> bool {
        self.output.status.success()
    }

    /// Asserts the run failed, without a panic, with a message containing every one of
    /// `needles`.
    pub fn refused(&self, needles: &[&str]) -> String {
        let stderr = self.stderr();
        assert!(!self.succeeded(), "must fail; stderr: {stderr}");
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

/// The binary with `args` under the memory limit, stdout and stderr piped.
pub fn spawn(args: &[&str]) -> Child {
    spawn_env(args, &[])
}

/// [`spawn`], with the environment variables `env` set too.
pub fn spawn_env(args: &[&str], env: &[(&str, &str)]) -> Child {
    Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_LIMIT_KIB} && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the binary")
}

/// Runs the binary with `args`, killed after 300 s (a hang guard: a run that needs it has
/// failed anyway).
pub fn run(args: &[&str]) -> Run {
    run_env(args, &[])
}

/// [`run`], with the environment variables `env` set too.
pub fn run_env(args: &[&str], env: &[(&str, &str)]) -> Run {
    let limit = Duration::from_secs(300);
    let mut child = spawn_env(args, env);
    let start = Instant::now();
    // Drained while it runs, so a chatty run cannot fill the pipe and stall.
    let stdout = drain(child.stdout.take().unwrap());
    let stderr = drain(child.stderr.take().unwrap());
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{args:?} still ran after {limit:?} (killed); stderr: {}",
                String::from_utf8_lossy(&stderr.join().unwrap())
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Run {
        output: Output {
            status,
            stdout: stdout.join().unwrap(),
            stderr: stderr.join().unwrap(),
        },
    }
}

fn drain(mut from: impl std::io::Read + Send + 'static) -> std::thread::JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = from.read_to_end(&mut bytes);
        bytes
    })
}

pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "motion-shadows-hardening2-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// The names in `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A scene file with a spot light over a floor, and `objects` (JSON fragments) on it.
pub fn scene_json(name: &str, objects: &[String]) -> String {
    let mut all = vec![
        r#"{ "name": "floor", "albedo": [0.8, 0.8, 0.8],
             "mesh": { "plane": { "size": [8, 8], "subdivisions": 1 } } }"#
            .to_owned(),
    ];
    all.extend_from_slice(objects);
    format!(
        r#"{{
  "format": "motion-shadows-scene/1",
  "name": {name:?},
  "camera": {{ "position": [0, 4, 6], "target": [0, 0, 0], "fov_y_deg": 45, "near": 0.1, "far": 100 }},
  "light": {{ "type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
             "cone_angle_deg": 50, "intensity": 50, "near": 0.05, "far": 50 }},
  "objects": [{}]
}}"#,
        all.join(",\n")
    )
}

/// A tiny image: what is tested here is what is refused or written, not the picture.
pub const SMALL: [&str; 6] = ["--width", "48", "--height", "36", "--spp", "2"];
