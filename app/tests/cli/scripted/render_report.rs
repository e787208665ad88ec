//! `render --json` and `compare` report what ran: the frame, its runs, the static layer and the
//! shadow estimator, with the files written.

use super::*;

#[test]
fn render_json_reports_the_frame_and_writes_the_files() {
    let dir = temp_dir("json");
    let out = motion_shadows(
        &[
            "render", "--width", "64", "--height", "48", "--spp", "2", "--json",
        ],
        &dir,
    );
    let json: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(json["scene"], "cubes-toward-light");
    assert_eq!(json["method"], "temporal");
    assert_eq!(json["width"], 64);
    let (nf, nr) = (
        json["fragments"].as_u64().unwrap(),
        json["ranges"].as_u64().unwrap(),
    );
    assert!(nf > 0 && nr > 0 && nr <= nf, "N_f {nf}, N_r {nr}");
    // The default (exact construction, static layer) stores each run as its range: two
    // fragments per range, none stored as a node.
    assert_eq!(nf, 2 * nr);
    assert_eq!(json["fragments_stored"], 0);
    // Equation (2), by hand, for the sorted ranges (the default): 24 bytes per range, one
    // 4-byte index per pixel; the collection's lists and counts held besides until the sort.
    assert_eq!(json["range_storage"], "sorted");
    assert_eq!(
        json["shadow_map_bytes_eq2"].as_u64().unwrap(),
        nr * 24 + 64 * 48 * 4
    );
    assert_eq!(
        json["shadow_map_bytes_transient"].as_u64().unwrap(),
        nr * 24 + 64 * 48 * 4
    );
    let passes: Vec<&str> = json["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["pass"].as_str().unwrap())
        .collect();
    assert_eq!(
        passes,
        [
            "collection",
            "generation",
            "lighting raster",
            "lighting shade"
        ]
    );
    for file in json["files"].as_array().unwrap() {
        assert!(Path::new(file.as_str().unwrap()).is_file(), "{file}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--runs 2`: the JSON says so and its frame figures are the sums of its counted passes
/// (every pass: a temporal frame has no copy-out); `--static-layer off`: no static layer,
/// the ground's fragments back in the lists, and the same image bytes; `--static-layer kept`:
/// said so, and the same image bytes; `compare --static-layer`: the same errors.
#[test]
fn render_runs_and_static_layer_are_reported() {
    let dir = temp_dir("runs");
    let small = [
        "render", "--width", "48", "--height", "36", "--spp", "2", "--json",
    ];
    let render = |extra: &[&str], sub: &str| -> (serde_json::Value, Vec<u8>) {
        let out = dir.join(sub);
        let output = motion_shadows(&[&small[..], extra].concat(), &out);
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        let png = std::fs::read(out.join("cubes-toward-light-temporal.png")).unwrap();
        (json, png)
    };
    let (layer, layer_png) = render(&["--runs", "2"], "layer");
    assert_eq!(layer["runs"], 2);
    let passes = layer["passes"].as_array().unwrap();
    let sum = |keep: &dyn Fn(&str) -> bool| -> f64 {
        passes
            .iter()
            .filter(|p| keep(p["pass"].as_str().unwrap()))
            .map(|p| p["gpu_ms"].as_f64().unwrap())
            .sum()
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
    assert!(close(layer["frame_ms"].as_f64().unwrap(), sum(&|_| true)));
    assert!(close(
        layer["lighting_pass_ms"].as_f64().unwrap(),
        sum(&|p| p.starts_with("lighting"))
    ));
    assert_eq!(layer["static_layer_bytes"], 48 * 36 * 8);
    let (lists, lists_png) = render(&["--static-layer", "off"], "lists");
    assert_eq!(lists["runs"], 1);
    assert_eq!(lists["static_layer_bytes"], 0);
    assert!(lists["fragments"].as_u64() > layer["fragments"].as_u64());
    // The lists store their fragments as nodes (the generation pass pairs them).
    assert_eq!(lists["fragments_stored"], lists["fragments"]);
    assert!(lists_png == layer_png, "the static layer changed the image");
    // `--range-storage lists`: the collection's lists as they are, equation (2) with both
    // heads per pixel, the same image.
    let (linked, linked_png) = render(&["--range-storage", "lists"], "linked");
    assert_eq!(linked["range_storage"], "lists");
    assert_eq!(layer["range_storage"], "sorted");
    let nr = linked["ranges"].as_u64().unwrap();
    assert_eq!(linked["ranges"], layer["ranges"]);
    assert_eq!(linked["shadow_map_bytes_eq2"], nr * 24 + 2 * 48 * 36 * 4);
    assert_eq!(linked["shadow_map_bytes_transient"], 0);
    assert!(
        linked_png == layer_png,
        "the range storage changed the image"
    );
    // `--pruning cover`: said so where the frame sorts (none otherwise), the same image.
    let (cover, cover_png) = render(&["--pruning", "cover"], "cover");
    assert_eq!(cover["pruning"], "cover");
    assert_eq!(layer["pruning"], "static-layer");
    assert_eq!(linked["pruning"], "none");
    assert_eq!(cover["ranges"], layer["ranges"]);
    assert!(cover_png == layer_png, "the cover rule changed the image");
    assert_eq!(layer["static_layer_kept"], false);
    // Kept from a pass before the timed one: the same image, and the timed collection draws
    // only what moves.
    let (kept, kept_png) = render(&["--static-layer", "kept"], "kept");
    assert_eq!(kept["static_layer_kept"], true);
    assert_eq!(kept["static_layer_bytes"], 48 * 36 * 8);
    assert_eq!(kept["fragments"], layer["fragments"]);
    assert!(
        kept_png == layer_png,
        "keeping the static layer changed the image"
    );
    // compare takes the same switch for its temporal row, and its errors do not change.
    let compare = |layer: &str| -> serde_json::Value {
        let args = [
            "compare",
            "--width",
            "48",
            "--height",
            "36",
            "--spp",
            "2",
            "--slices",
            "8",
            "--json",
            "--static-layer",
            layer,
        ];
        let output = motion_shadows(&args, &dir.join(format!("compare-{layer}")));
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        let methods = json["methods"].as_array().unwrap();
        methods
            .iter()
            .find(|m| m["method"] == "temporal")
            .unwrap()
            .clone()
    };
    let (on, off) = (compare("on"), compare("off"));
    assert_eq!(on["stats"]["static_layer_bytes"], 48 * 36 * 8);
    assert_eq!(off["stats"]["static_layer_bytes"], 0);
    assert_eq!(on["errors"]["rmse"], off["errors"]["rmse"]);
    // TSM: its maps' copy into the lookups' buffers is listed but not counted.
    let out = dir.join("tsm");
    let output = motion_shadows(&[&small[..], &["--method", "tsm"]].concat(), &out);
    let tsm: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let passes = tsm["passes"].as_array().unwrap();
    let ms = |name: &str| {
        passes
            .iter()
            .filter(|p| p["pass"] == name)
            .map(|p| p["gpu_ms"].as_f64().unwrap())
            .sum::<f64>()
    };
    let all: f64 = passes.iter().map(|p| p["gpu_ms"].as_f64().unwrap()).sum();
    assert!(ms("map copy-out") > 0.0, "{passes:?}");
    assert!(close(
        tsm["frame_ms"].as_f64().unwrap(),
        all - ms("map copy-out")
    ));
    assert!(close(
        tsm["shadow_pass_ms"].as_f64().unwrap(),
        ms("tsm shadow maps")
    ));
    std::fs::remove_dir_all(&dir).ok();
}

/// `--shadow-estimator` reaches the renderer and `--json`, and `compare` reports the RMSE on
/// static receivers for each method.
#[test]
fn shadow_estimator_is_reported_and_compare_measures_static_receivers() {
    let dir = temp_dir("estimator");
    let small = ["--width", "48", "--height", "36", "--spp", "1"];
    let out = motion_shadows(
        &[
            &["render", "--json", "--shadow-estimator", "analytic"][..],
            &small,
        ]
        .concat(),
        &dir,
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["shadow_estimator"], "analytic");
    let out = motion_shadows(
        &[
            &[
                "compare",
                "--json",
                "--slices",
                "16",
                "--shadow-estimator",
                "analytic",
            ][..],
            &small,
        ]
        .concat(),
        &dir,
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["truth"], "reference", "the default truth");
    let methods = json["methods"].as_array().unwrap();
    let temporal = methods.iter().find(|m| m["method"] == "temporal").unwrap();
    assert_eq!(temporal["stats"]["shadow_estimator"], "analytic");
    let rmse_static = temporal["rmse_static"].as_f64().expect("rmse_static");
    // Worked out here from the images it wrote: the squared error over every pixel, less the
    // moving-object mask's share (its pixels and RMSE, from the JSON), over the other pixels.
    let scene = json["scene"].as_str().unwrap();
    let image = |method: &str| {
        motion_shadows_app::output::read_exr(&dir.join(format!("{scene}-{method}.exr")))
            .expect("the EXR compare wrote")
    };
    let (reference, analytic) = (image("reference"), image("temporal"));
    let squared: f64 = (reference.rgb.iter())
        .zip(&analytic.rgb)
        .map(|(a, b)| (f64::from(*a) - f64::from(*b)).powi(2))
        .sum();
    let pixels = f64::from(reference.width * reference.height);
    let masked = json["moving_mask_pixels"].as_f64().unwrap();
    let rmse_masked = temporal["errors"]["rmse_masked"].as_f64().unwrap();
    assert!(
        masked > 0.0 && masked < pixels,
        "{masked} of {pixels} pixels masked"
    );
    let expected =
        ((squared - 3.0 * masked * rmse_masked.powi(2)) / (3.0 * (pixels - masked))).sqrt();
    assert!(
        expected > 0.0 && (rmse_static - expected).abs() <= 1e-6 * expected,
        "rmse_static {rmse_static}, the images outside the mask give {expected}"
    );
    let bench = dir.join("bench");
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "shadow-pass"])
        .args(["--shadow-estimator", "analytic", "--out"])
        .arg(&bench)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(bench.join("bench-summary.json")).unwrap()).unwrap();
    assert_eq!(summary["shadow_estimator"], "analytic");
    std::fs::remove_dir_all(&dir).ok();
}
