//! A moving camera on the command line: the forward frame takes it, the ray tracer's (its
//! test against still renders along the path: `raytrace::tests::moving_camera`) and the
//! GPU's (the gpu binary's `moving_camera`), and so does the deferred frame (the camera at
//! the camera time: `moving_camera_deferred`); `--json` says the camera moves, and what does
//! not take it (the viewer, the forward frame's settings that take the camera as still)
//! refuses it by name rather than render the camera at t = 0 only.

use crate::common::{run_with_out as motion_shadows, temp_dir};
use std::process::Command;

const SMALL: [&str; 6] = ["--width", "32", "--height", "24", "--spp", "2"];

#[test]
fn json_says_whether_the_camera_moves() {
    let dir = temp_dir("camera-moves");
    for method in ["raytrace", "temporal"] {
        for (scene, moves) in [("camera-pan", true), ("cubes-toward-light", false)] {
            let mut args = vec!["render", "--scene", scene, "--method", method, "--json"];
            args.extend(SMALL);
            let out = motion_shadows(&args, &dir);
            assert!(
                out.status.success(),
                "{args:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            assert_eq!(json["camera_moves"], moves, "{scene} {method}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn what_does_not_take_a_moving_camera_refuses_it_by_name() {
    let dir = temp_dir("camera-refused");
    let forward = |option: &'static str, value: &'static str| {
        let mut args = vec!["render", "--scene", "camera-pan", "--method", "temporal"];
        args.extend([option, value]);
        args.extend(SMALL);
        args
    };
    for (args, named) in [
        (
            forward("--shadow-estimator", "analytic"),
            "--shadow-estimator analytic (use --shadow-estimator sampled)",
        ),
        (
            forward("--shadow-filter", "footprint"),
            "--shadow-filter footprint (use --shadow-filter none or bilinear)",
        ),
    ] {
        let out = motion_shadows(&args, &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} ran");
        assert!(
            stderr.contains("camera moves") && stderr.contains("\"t1\"") && stderr.contains(named),
            "{args:?}: {stderr}"
        );
    }
    // The viewer, before it opens a window.
    let out = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["view", "--frame", "forward", "--scene", "camera-pan"])
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "view ran");
    assert!(
        stderr.contains("camera moves") && stderr.contains("the viewer's stochastic frame"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_deferred_frame_takes_a_moving_camera() {
    let dir = temp_dir("camera-deferred");
    for method in ["temporal", "raytrace"] {
        // `--spp` is the forward frame's only.
        let mut args = vec!["render", "--frame", "deferred", "--scene", "camera-pan"];
        args.extend(["--method", method, "--json"]);
        args.extend(&SMALL[..4]);
        let out = motion_shadows(&args, &dir);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
