//! `render --method raytrace` and `compare --truth raytrace` through the binary.

use super::*;

/// `render --method raytrace` runs without any Vulkan driver, reports itself in `--json` like
/// the other methods (no shadow map; its two CPU steps as passes) and is deterministic;
/// `compare --truth raytrace` measures every other method, the reference included, against it.
#[test]
fn raytrace_renders_without_a_device_and_compare_measures_against_it() {
    let dir = temp_dir("raytrace");
    let small = ["--width", "48", "--height", "36", "--spp", "4"];
    let render = |out: &Path| {
        let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
            .args([&["render", "--method", "raytrace", "--json"][..], &small].concat())
            .arg("--out")
            .arg(out)
            .env("VK_DRIVER_FILES", "/nonexistent/no_icd.json")
            .env("VK_ICD_FILENAMES", "/nonexistent/no_icd.json")
            .output()
            .expect("run the binary");
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&output.stdout).expect("one JSON object")
    };
    let json = render(&dir.join("a"));
    assert_eq!(json["method"], "raytrace");
    assert_eq!(json["scene"], "cubes-toward-light");
    assert_eq!(
        (json["width"].as_u64(), json["spp"].as_u64()),
        (Some(48), Some(4))
    );
    assert!(json["triangles"].as_u64().unwrap() > 10_000);
    for field in [
        "shadow_width",
        "fragments",
        "fragments_stored",
        "ranges",
        "shadow_map_bytes_allocated",
    ] {
        assert_eq!(json[field], 0, "{field}");
    }
    let passes: Vec<&str> = json["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["pass"].as_str().unwrap())
        .collect();
    assert_eq!(passes, ["bvh build", "raytrace"]);
    assert!(json["device"].as_str().unwrap().starts_with("CPU"));
    let files: Vec<&str> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(files.len(), 2);
    assert!(files.iter().all(|f| Path::new(f).is_file()), "{files:?}");
    render(&dir.join("b"));
    let exr = |d: &str| std::fs::read(dir.join(d).join("cubes-toward-light-raytrace.exr")).unwrap();
    assert!(exr("a") == exr("b"), "two runs differ");

    let out = motion_shadows(
        &[
            &["compare", "--json", "--truth", "raytrace", "--slices", "16"][..],
            &small,
        ]
        .concat(),
        &dir.join("compare"),
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["truth"], "raytrace");
    let methods = json["methods"].as_array().unwrap();
    let names: Vec<&str> = methods
        .iter()
        .map(|m| m["method"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["raytrace", "reference", "temporal", "tsm"]);
    assert!(methods[0]["errors"].is_null());
    for m in &methods[1..] {
        let rmse = m["errors"]["rmse"].as_f64().expect("rmse");
        assert!(rmse.is_finite() && rmse > 0.0, "{}: {rmse}", m["method"]);
    }
    let files = json["files"].as_array().unwrap();
    for name in [
        "cubes-toward-light-raytrace.exr",
        "cubes-toward-light-reference-error.png",
    ] {
        assert!(
            files.iter().any(|f| f.as_str().unwrap().ends_with(name)),
            "{name} not in {files:?}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
