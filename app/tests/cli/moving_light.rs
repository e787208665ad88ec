//! A moving light on the command line: the ray tracer, the exact deferred truth and the
//! temporal map (forward frame and deferred mask) take it (their tests against closed forms
//! and the truth: `raytrace::tests::moving_light`, `tests/gpu/moving_light.rs`), `--json` says
//! the light moves, what does not take it yet refuses it by name, and a light whose t = 1
//! pose is its t = 0 pose renders bit for bit as the still light in the tracer.

use crate::common::{run_with_out as motion_shadows, temp_dir};
use motion_shadows_app::raytrace::deferred::deferred_truth;
use motion_shadows_app::render::{Method, RenderSettings};
use motion_shadows_app::scene::{
    BuiltinOptions, Light, LightFile, Scene, SpotPose, builtin, builtin_file, scene_to_json,
};
use std::process::Command;

const SMALL: [&str; 6] = ["--width", "32", "--height", "24", "--spp", "2"];

#[test]
fn json_says_whether_the_light_moves() {
    let dir = temp_dir("light-moves");
    for (scene, method, moves) in [
        ("moving-light", "raytrace", true),
        ("moving-light", "temporal", true),
        ("moving-light", "tsm", true),
        ("cubes-toward-light", "raytrace", false),
    ] {
        let mut args = vec!["render", "--scene", scene, "--method", method, "--json"];
        args.extend(SMALL);
        let out = motion_shadows(&args, &dir);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["light_moves"], moves, "{scene}");
        if method == "temporal" {
            // Nothing stands still relative to a moving light: no static layer.
            assert_eq!(json["static_layer_bytes"], 0, "{scene}");
        }
    }
    // The deferred frame's masks (temporal with either lookup, TSM's, plain's) and its exact
    // truth take the moving light too.
    for (method, lookup) in [
        ("temporal", &["--lookup", "depth"][..]),
        ("temporal", &["--lookup", "exact"]),
        ("tsm", &["--tsm-maps", "4"]),
        ("plain", &[]),
        ("raytrace", &[]),
    ] {
        let mut args = vec![
            "render",
            "--frame",
            "deferred",
            "--scene",
            "moving-light",
            "--method",
            method,
            "--width",
            "32",
            "--height",
            "24",
        ];
        args.extend(lookup);
        let out = motion_shadows(&args, &dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `compare --frame deferred` on `moving-light`: the truth, the temporal mask, TSM-N and
/// plain, all under the carried light (their accuracy: `tests/gpu/moving_light*.rs`).
#[test]
fn the_deferred_comparison_takes_a_moving_light() {
    let dir = temp_dir("light-compare");
    let args = [
        "compare",
        "--frame",
        "deferred",
        "--scene",
        "moving-light",
        "--tsm-maps",
        "2",
        "--width",
        "32",
        "--height",
        "24",
    ];
    let run = motion_shadows(&args, &dir);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for method in ["temporal", "tsm-2", "plain"] {
        assert!(stdout.contains(method), "{method}: {stdout}");
    }
    assert!(dir.join("moving-light-deferred-compare-masks.png").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn what_does_not_take_a_moving_light_refuses_it_by_name() {
    let dir = temp_dir("light-refused");
    let forward = |extra: &[&'static str]| {
        let mut args = vec!["render", "--scene", "moving-light"];
        args.extend(extra);
        args.extend(SMALL);
        args
    };
    // `--spp` is the forward frame's only.
    let deferred = |extra: &[&'static str]| {
        let mut args = vec!["render", "--frame", "deferred", "--scene", "moving-light"];
        args.extend(extra);
        args.extend(&SMALL[..4]);
        args
    };
    for (args, named) in [
        (forward(&["--method", "coverage"]), "--method coverage"),
        (
            forward(&["--shadow-estimator", "analytic"]),
            "--shadow-estimator analytic",
        ),
        (
            deferred(&["--method", "tsm", "--static-receivers"]),
            "--static-receivers",
        ),
        (deferred(&["--static-receivers"]), "--static-receivers"),
    ] {
        let out = motion_shadows(&args, &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} ran");
        assert!(
            stderr.contains("light moves") && stderr.contains("\"t1\"") && stderr.contains(named),
            "{args:?}: {stderr}"
        );
    }
    // The deferred mask with a light that turns.
    let mut file = builtin_file("moving-light", &BuiltinOptions::default()).unwrap();
    if let LightFile::Spot { t1: Some(end), .. } = &mut file.light {
        end.direction = Some(glam::Vec3::new(0.3, -1.0, 0.9));
    }
    let path = dir.join("turning.json");
    std::fs::write(&path, scene_to_json(&file)).unwrap();
    // (TSM's and plain's masks take it: `moving_light_deferred_tsm` in the gpu binary.) The
    // viewer, whose method key reaches the exact mask, refuses it from any method.
    let out = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["view", "--method", "tsm", "--scene-file"])
        .arg(&path)
        .output()
        .expect("run the binary");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "view ran");
    assert!(stderr.contains("a turning light"), "{stderr}");
    // The temporal deferred mask: not with the light carried and the box sliding across the
    // turn (the map's blend of the two ends misplaces them), nor under a turning sun with the
    // depth-line lookup; under a spot turning in place over still geometry with both lookups
    // (the depth line's receivers' normals turned with the light's frame:
    // `moving_light_deferred_turn` in the gpu binary; the exact lookup's rays:
    // `moving_light_exact`), but with the exact lookup not over geometry that moves.
    fn deferred_args(path: &std::path::Path) -> Vec<&str> {
        let mut args = vec!["render", "--frame", "deferred", "--scene-file"];
        args.push(path.to_str().unwrap());
        args.extend(&SMALL[..4]);
        args
    }
    let args = deferred_args(&path);
    let out = motion_shadows(&args, &dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} ran");
    assert!(
        stderr.contains("a turning light") && stderr.contains("across the turn"),
        "{stderr}"
    );
    for object in &mut file.objects {
        object.t1 = None;
    }
    if let LightFile::Spot { t1: Some(end), .. } = &mut file.light {
        end.position = None;
    }
    let still_path = dir.join("turning-over-still.json");
    std::fs::write(&still_path, scene_to_json(&file)).unwrap();
    let mut args = deferred_args(&still_path);
    let out = motion_shadows(&args, &dir);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    args.extend(["--lookup", "exact"]);
    let out = motion_shadows(&args, &dir);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut box_slides = file.clone();
    let sliding = box_slides
        .objects
        .iter_mut()
        .find(|o| o.name.contains("box"))
        .expect("moving-light has a box");
    let mut slid = sliding.t0.clone().expect("the box is placed");
    slid.translation = slid.translation.map(|at| at + glam::Vec3::X);
    sliding.t1 = Some(slid);
    let sliding_path = dir.join("turning-over-a-sliding-box.json");
    std::fs::write(&sliding_path, scene_to_json(&box_slides)).unwrap();
    let mut args = deferred_args(&sliding_path);
    args.extend(["--lookup", "exact"]);
    let out = motion_shadows(&args, &dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} ran");
    assert!(
        stderr.contains("over geometry that moves") && stderr.contains("--lookup exact"),
        "{stderr}"
    );
    let mut args = vec![
        "render",
        "--frame",
        "deferred",
        "--scene",
        "hard-turning-light",
    ];
    args.extend(&SMALL[..4]);
    let out = motion_shadows(&args, &dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} ran");
    assert!(stderr.contains("a turning directional light"), "{stderr}");
    // The forward frame's exact lookup with a spot that turns and is carried (a translating
    // one it takes, and one turning in place over still geometry).
    let mut args = vec!["render", "--lookup", "exact", "--scene-file"];
    args.push(path.to_str().unwrap());
    args.extend(SMALL);
    let out = motion_shadows(&args, &dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} ran");
    assert!(
        stderr.contains("a turning spot light carried") && stderr.contains("--lookup exact"),
        "{stderr}"
    );
    // The viewer's stochastic frame, before it opens a window (its deferred frame takes the
    // light: the view binary's `moving`).
    let out = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["view", "--frame", "forward", "--scene", "moving-light"])
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "view ran");
    assert!(
        stderr.contains("light moves") && stderr.contains("the viewer's stochastic frame"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `compare --frame deferred --lookup exact` on `hard-turning-light` (a sun turning 20
/// degrees over still posts): the depth-line mask refuses the turning sun and is reported as
/// refused, with its reason, while the exact mask, TSM and plain are measured against the
/// truth; the exact mask matches it (its accuracy in detail: `moving_light_exact` in the gpu
/// binary).
#[test]
fn the_deferred_comparison_reports_a_refused_method_and_measures_the_others() {
    let dir = temp_dir("turning-compare");
    let args = [
        "compare",
        "--frame",
        "deferred",
        "--scene",
        "hard-turning-light",
        "--lookup",
        "exact",
        "--tsm-maps",
        "2",
        "--width",
        "48",
        "--height",
        "36",
        "--shadow-size",
        "256x256",
        "--json",
    ];
    let run = motion_shadows(&args, &dir);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).expect("json");
    let row = |name: &str| {
        json["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["method"] == name)
            .unwrap_or_else(|| panic!("no {name} row: {json}"))
            .clone()
    };
    let temporal = row("temporal");
    assert!(
        temporal["refused"]
            .as_str()
            .is_some_and(|r| r.contains("a turning directional light")),
        "{temporal}"
    );
    assert!(temporal["rmse"].is_null(), "{temporal}");
    let exact = row("temporal-exact");
    assert!(exact["refused"].is_null(), "{exact}");
    let rmse = exact["rmse"].as_f64().unwrap();
    assert!(
        rmse <= 1e-3,
        "the exact mask's RMSE against the truth: {rmse}"
    );
    assert!(row("tsm-2")["rmse"].as_f64().is_some(), "{json}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `moving-light` with its light held at the t = 0 pose: once without `t1`, once with a
/// `t1` equal to t = 0 (the moving light's arithmetic, no motion).
fn held_still(with_t1: bool) -> Scene {
    let mut scene = builtin("moving-light", &BuiltinOptions::default()).unwrap();
    let Light::Spot(light) = &mut scene.light else {
        panic!("spot expected")
    };
    light.t1 = with_t1.then_some(SpotPose {
        position: light.position,
        direction: light.direction,
    });
    scene
}

#[test]
fn a_light_whose_t1_is_its_t0_renders_as_the_still_light_to_the_bit() {
    let settings = RenderSettings {
        width: 32,
        height: 24,
        spp: 2,
        method: Method::Raytrace,
        ..RenderSettings::default()
    };
    let [still, same] = [false, true].map(|with_t1| {
        motion_shadows_app::raytrace::render(&held_still(with_t1), &settings, &mut |_| {}).unwrap()
    });
    assert!(!still.stats.light_moves && same.stats.light_moves);
    let bits = |rgb: &[f32]| rgb.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&still.image.rgb), bits(&same.image.rgb));
    let [still, same] = [false, true].map(|with_t1| {
        deferred_truth(&held_still(with_t1), 32, 24, 0.5, (64, 64), &mut |_| {}).unwrap()
    });
    assert_eq!(bits(&still.rgb), bits(&same.rgb));
    assert_eq!(bits(&still.lit), bits(&same.lit));
    // Not a vacuous comparison: the scene has shadows.
    assert!(still.lit.iter().any(|&l| l < 0.5), "no shadow in view");
}
