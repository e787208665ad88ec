//! Issue 10, "Hardening": one case per class of problem the probes found, each run through
//! the `motion-shadows` binary as a user would, with the validation layer on
//! (MOTION_SHADOWS_VALIDATION=1). Runs that must be refused are refused before a device is
//! made, in milliseconds; a few tiny renders (48x36) check what must still render.
//!
//! Every run has a time limit and a memory limit (ulimit -v), so a regression to reading or
//! building without bound fails here instead of taking the machine down.

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

// ---------------------------------------------------------------------------------------
// Runaway memory: sizes are checked before anything of that size is read or built.

#[test]
fn endless_scene_file_and_obj_are_refused_without_reading_them_whole() {
    let dir = temp_dir("endless");
    let r = run(&["render", "--scene-file", "/dev/zero", "--out", s(&dir)]);
    r.refused(&["/dev/zero", "MiB"]);

    let obj = r#"{ "name": "zero", "albedo": [0.5, 0.5, 0.5], "mesh": { "obj": "/dev/zero" } }"#;
    let scene = write_scene(
        &dir,
        "obj.json",
        &scene_json("obj", 0.1, "[0, 5, 0]", &[floor(4.0), obj.into()]),
    );
    render_file(&scene, &dir, &[]).refused(&["/dev/zero", "not a regular file", "\"zero\""]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn absurd_triangle_counts_are_refused_before_building() {
    let dir = temp_dir("counts");
    for cubes in ["5000000", "50000000"] {
        let r = run(&[
            "render",
            "--scene",
            "random-cubes",
            "--cubes",
            cubes,
            "--out",
            s(&dir),
        ]);
        r.refused(&["cube count", "33554432"]);
    }
    // A box of 1024 x 1024 quads a face would need a 1.2 GB vertex buffer.
    let fine_box = r#"{ "name": "fine", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, 1, 1], "subdivisions": 1024 } } }"#;
    let scene = write_scene(
        &dir,
        "fine.json",
        &scene_json("fine", 0.1, "[0, 5, 0]", &[floor(4.0), fine_box.into()]),
    );
    render_file(&scene, &dir, &[]).refused(&["\"fine\"", "subdivisions", "256"]);
    // 200 boxes at the limit: each fits, together they do not.
    let many: Vec<String> = (0..200)
        .map(|i| {
            format!(
                r#"{{ "name": "b{i}", "albedo": [0.5, 0.5, 0.5],
                    "mesh": {{ "box": {{ "size": [1, 1, 1], "subdivisions": 256 }} }} }}"#
            )
        })
        .collect();
    let scene = write_scene(
        &dir,
        "many.json",
        &scene_json("many", 0.1, "[0, 5, 0]", &many),
    );
    render_file(&scene, &dir, &[]).refused(&["157286400 triangles", "limit"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------
// Writing outside --out: scene names are file names, so they are held to a safe set.

#[test]
fn scene_names_cannot_leave_the_output_directory_or_flood_the_error() {
    let root = temp_dir("names");
    let out = root.join("a").join("b");
    std::fs::create_dir_all(&out).unwrap();
    for name in ["../../escaped", "/tmp/motion-shadows-absolute", ".hidden"] {
        let scene = write_scene(
            &root,
            "named.json",
            &scene_json(name, 0.1, "[0, 5, 0]", &[floor(4.0)]),
        );
        render_file(&scene, &out, &[]).refused(&["scene name"]);
    }
    assert!(!root.join("escaped-temporal.png").exists());
    assert!(!Path::new("/tmp/motion-shadows-absolute-temporal.png").exists());
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        0,
        "nothing written"
    );

    let long = "n".repeat(1_000_000);
    let scene = write_scene(
        &root,
        "long.json",
        &scene_json(&long, 0.1, "[0, 5, 0]", &[floor(4.0)]),
    );
    let stderr = render_file(&scene, &out, &[]).refused(&["scene name", "1000000 bytes in all"]);
    assert!(stderr.len() < 2000, "{} bytes of stderr", stderr.len());
    std::fs::remove_dir_all(&root).unwrap();
}

// ---------------------------------------------------------------------------------------
// Good files destroyed: options and output paths are checked before rendering, and the files
// of a run replace the old ones only once all of them are complete.

#[test]
fn a_run_that_must_fail_leaves_previous_outputs_untouched() {
    let out = temp_dir("keep");
    let good = |name: &str| {
        let path = out.join(name);
        std::fs::write(&path, format!("good {name}")).unwrap();
        path
    };
    let exr = good("cubes-toward-light-tsm.exr");
    let png = good("cubes-toward-light-tsm.png");
    // TSM stores no ranges, so there is nothing to draw a heat map of.
    let mut args = vec!["render", "--method", "tsm", "--heatmaps", "--out", s(&out)];
    args.extend(SMALL);
    run(&args).refused(&["--heatmaps", "temporal or coverage"]);
    assert_eq!(
        std::fs::read_to_string(&exr).unwrap(),
        "good cubes-toward-light-tsm.exr"
    );
    assert_eq!(
        std::fs::read_to_string(&png).unwrap(),
        "good cubes-toward-light-tsm.png"
    );

    // The PNG's path is a directory: found before rendering, the EXR is not replaced.
    let exr = good("cubes-toward-light-temporal.exr");
    std::fs::create_dir(out.join("cubes-toward-light-temporal.png")).unwrap();
    let mut args = vec!["render", "--out", s(&out)];
    args.extend(SMALL);
    let r = run(&args);
    r.refused(&["cubes-toward-light-temporal.png", "is a directory"]);
    assert!(
        !r.stderr().contains("lighting pass"),
        "refused before rendering"
    );
    assert_eq!(
        std::fs::read_to_string(&exr).unwrap(),
        "good cubes-toward-light-temporal.exr"
    );
    // No temporary file is left behind either.
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            "cubes-toward-light-temporal.exr",
            "cubes-toward-light-temporal.png",
            "cubes-toward-light-tsm.exr",
            "cubes-toward-light-tsm.png"
        ]
    );
    std::fs::remove_dir_all(&out).unwrap();
}

// ---------------------------------------------------------------------------------------
// Values accepted that made nonsense: refused up front with messages naming the value.

#[test]
fn nonsense_values_are_refused_with_clear_messages() {
    let out = temp_dir("values");
    for exposure in ["NaN", "inf", "-inf", "1e39", "65"] {
        let r = run(&["render", "--exposure", exposure, "--out", s(&out)]);
        r.refused(&["--exposure", "finite number of stops in [-64, 64]"]);
    }
    let r = run(&[
        "render",
        "--scene",
        "random-cubes",
        "--speed-min",
        "1e30",
        "--speed-max",
        "1e30",
        "--out",
        s(&out),
    ]);
    assert!(!r.stderr().contains("parallel"), "{}", r.stderr());
    r.refused(&["speed_max <= 1000"]);
    let r = run(&[
        "render",
        "--scene",
        "random-cubes",
        "--cube-size",
        "1e20",
        "--out",
        s(&out),
    ]);
    assert!(!r.stderr().contains("parallel"), "{}", r.stderr());
    r.refused(&["cube size must be in [0.1, 1000]"]);

    let inside_out = r#"{ "name": "inside-out", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, -1, 1] } } }"#;
    let scene = write_scene(
        &out,
        "neg.json",
        &scene_json("neg", 0.1, "[0, 5, 0]", &[floor(4.0), inside_out.into()]),
    );
    render_file(&scene, &out, &[]).refused(&["\"inside-out\"", "box size", "> 0"]);
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        1,
        "only the scene file"
    );
    std::fs::remove_dir_all(&out).unwrap();
}

// ---------------------------------------------------------------------------------------
// Closed meshes: back-face culling is only right from outside.

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

#[test]
fn a_light_inside_a_closed_box_lights_nothing_and_the_box_is_named() {
    let dir = temp_dir("lamp");
    // The spot light sits in the middle of a closed box: no light gets out.
    let lamp = r#"{ "name": "lamp-housing", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [0.5, 0.5, 0.5] } }, "t0": { "translation": [0, 3, 0] } }"#;
    let plane = r#"{ "name": "ground", "albedo": [0.8, 0.8, 0.8],
        "mesh": { "plane": { "size": [10, 10], "subdivisions": 4 } } }"#;
    let scene = write_scene(
        &dir,
        "lamp.json",
        &scene_json("lamp", 0.1, "[0, 3, 0]", &[plane.into(), lamp.into()]),
    );
    let r = render_file(&scene, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    assert!(
        r.stderr()
            .contains("mesh #1 (\"lamp-housing\") is closed but contains the spot light"),
        "{}",
        r.stderr()
    );
    let (mean, max) = radiance_stats(&dir.join("lamp-temporal.exr"));
    // Lit, the floor under the light would be 0.8/pi * 50 / 9 = 1.4; enclosed, it is black
    // (a stray sample through the box's edges would still keep the mean near 0).
    assert!(
        mean < 1e-3,
        "light leaks out of the closed box: mean {mean}, max {max}"
    );

    // The camera inside a closed box: the box is drawn without culling too.
    let room = r#"{ "name": "room", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, 1, 1] } }, "t0": { "translation": [0, 4, 6] } }"#;
    let scene = write_scene(
        &dir,
        "room.json",
        &scene_json("room", 0.1, "[0, 3, 0]", &[plane.into(), room.into()]),
    );
    let r = render_file(&scene, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    assert!(
        r.stderr()
            .contains("mesh #1 (\"room\") is closed but contains the camera"),
        "{}",
        r.stderr()
    );
    // From inside the box the camera sees only its walls: no floor anywhere.
    let (mean, _) = radiance_stats(&dir.join("room-temporal.exr"));
    let (floor_mean, _) = {
        let scene = write_scene(
            &dir,
            "bare.json",
            &scene_json("bare", 0.1, "[0, 3, 0]", &[plane.into()]),
        );
        assert!(render_file(&scene, &dir, &[]).succeeded());
        radiance_stats(&dir.join("bare-temporal.exr"))
    };
    assert!(
        mean < 0.5 * floor_mean,
        "the camera sees through the closed box: mean {mean} vs floor alone {floor_mean}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------
// Large coordinates: rendered right up to the documented bound, refused beyond it.

#[test]
fn coordinates_just_inside_the_bound_render_lit_and_beyond_are_refused() {
    let dir = temp_dir("coordinates");
    // Camera near 0.1, bound 1e5 x near = 1e4.
    let inside = write_scene(
        &dir,
        "inside.json",
        &scene_json("inside", 0.1, "[0, 5, 0]", &[floor(0.99e4)]),
    );
    let r = render_file(&inside, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    let image = read_exr(&dir.join("inside-temporal.exr")).unwrap();
    // The camera looks at the origin, right below the light: the four centre pixels see the
    // floor there, lit at albedo/pi * I * cos / d^2 = 0.8/pi * 50 / 25.
    let expected = 0.8 / std::f32::consts::PI * 50.0 / 25.0;
    for (x, y) in [(23, 17), (24, 17), (23, 18), (24, 18)] {
        let [r, g, b] = image.pixel(x, y);
        for c in [r, g, b] {
            assert!(
                (c - expected).abs() < 0.03 * expected,
                "pixel ({x}, {y}) = {c}, expected {expected}"
            );
        }
    }
    let (mean, _) = radiance_stats(&dir.join("inside-temporal.exr"));
    assert!(mean > 0.05, "mostly black: mean {mean}");

    let beyond = write_scene(
        &dir,
        "beyond.json",
        &scene_json("beyond", 0.1, "[0, 5, 0]", &[floor(1.01e4)]),
    );
    render_file(&beyond, &dir, &[]).refused(&["mesh #0 (\"floor\")", "1e5 x near", "1e4"]);
    assert!(!dir.join("beyond-temporal.exr").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------
// Silent emptiness: a shadow map that receives no fragment at all is reported.

#[test]
fn a_shadow_map_that_receives_nothing_is_warned_about() {
    let dir = temp_dir("empty-map");
    // The spot light looks down from y = 10, but its depth range ends at 5: every triangle
    // lies beyond its far plane, which clips the papers' prisms (the exact ones are not
    // clipped by the near and far planes, so they would shadow it).
    let json = scene_json("beyond-far", 0.1, "[0, 10, 0]", &[floor(4.0)])
        .replace(r#""near": 0.05, "far": 50"#, r#""near": 0.05, "far": 5"#);
    let scene = write_scene(&dir, "beyond.json", &json);
    let out = dir.join("out");
    let run = render_file(&scene, &out, &["--json", "--prisms", "paper"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0);
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0]
            .as_str()
            .unwrap()
            .contains("no triangle reaches the shadow map")
    );
    assert!(
        run.stderr().contains("warning: no triangle reaches"),
        "{}",
        run.stderr()
    );

    // The exact prisms are not clipped by the far plane: the same scene has fragments in
    // the lists (static layer off), or the floor in the static layer (on, the default: no
    // fragment, and no warning either, since the layer is read when the lists are empty).
    let run = render_file(&scene, &out, &["--json", "--static-layer", "off"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert!(json["fragments"].as_u64().unwrap() > 0, "{json}");
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0), "{json}");
    let run = render_file(&scene, &out, &["--json"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0, "{json}");
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0), "{json}");

    // Within the depth range: fragments, no warning.
    let json = scene_json("within-far", 0.1, "[0, 10, 0]", &[floor(4.0)]);
    let scene = write_scene(&dir, "within.json", &json);
    let run = render_file(&scene, &out, &["--json", "--static-layer", "off"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert!(json["fragments"].as_u64().unwrap() > 0);
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0));

    // Outside the light's cone, static: an empty static layer and empty lists are warned
    // about.
    let json = scene_json("outside-cone", 0.1, "[100, 10, 0]", &[floor(4.0)]);
    let scene = write_scene(&dir, "outside.json", &json);
    let run = render_file(&scene, &out, &["--json"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0, "{json}");
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    std::fs::remove_dir_all(&dir).ok();
}
