//! The `motion-shadows` binary as users script it: `--json` output, scene export and
//! re-import, bench output files, and a clear error without a Vulkan device. Every run has the
//! validation layer on (MOTION_SHADOWS_VALIDATION=1) and fails if it reports anything.

use motion_shadows_app::scene::{BuiltinOptions, builtin};
use std::path::Path;
use std::process::Command;

fn motion_shadows(args: &[&str], out: &Path) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .arg("--out")
        .arg(out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    assert!(
        output.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("motion-shadows-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Whether a figure a bench wrote (six significant digits) agrees with `expected`, worked
/// out here from other figures it wrote: within the rounding of a quotient of two of them.
fn agrees(written: f64, expected: f64) -> bool {
    written.is_finite() && (written - expected).abs() <= 1e-4 * expected.abs()
}

/// One row of a bench CSV, its cells by column name.
struct CsvRow<'a> {
    header: &'a [&'a str],
    cells: Vec<&'a str>,
}

impl CsvRow<'_> {
    fn cell(&self, column: &str) -> &str {
        let i = (self.header.iter().position(|h| *h == column))
            .unwrap_or_else(|| panic!("no column {column} in {:?}", self.header));
        self.cells[i]
    }

    fn num(&self, column: &str) -> f64 {
        let cell = self.cell(column);
        cell.parse()
            .unwrap_or_else(|_| panic!("{column}: {cell:?} is not a number"))
    }
}

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

/// A built-in scene exported as a file renders to the same bytes as the built-in; for
/// `walker-toward-light` the file holds the posed model as triangles and needs no asset.
#[test]
fn exported_scene_file_renders_like_the_builtin() {
    let dir = temp_dir("export");
    for name in ["cubes-toward-light", "walker-toward-light"] {
        let scene_file = dir.join(format!("{name}.json"));
        let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
            .args(["scene", "export", name, "--out"])
            .arg(&scene_file)
            .status()
            .unwrap();
        assert!(status.success());
        let small = ["--width", "48", "--height", "36", "--spp", "2"];
        let a = dir.join(format!("{name}-builtin"));
        let b = dir.join(format!("{name}-file"));
        motion_shadows(&[&["render", "--scene", name][..], &small].concat(), &a);
        let file_arg = scene_file.to_str().unwrap();
        motion_shadows(
            &[&["render", "--scene-file", file_arg][..], &small].concat(),
            &b,
        );
        let exr = |d: &Path| std::fs::read(d.join(format!("{name}-temporal.exr"))).unwrap();
        assert!(
            exr(&a) == exr(&b),
            "the exported {name} renders differently"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn quick_bench_preset_writes_csv_and_png() {
    let out = std::env::temp_dir().join(format!("motion-shadows-bench-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "shadow-pass", "--out"])
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let csv = std::fs::read_to_string(out.join("shadow-pass-results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 4, "header and three scenes: {csv}");
    let columns = lines[0].split(',').count();
    assert!(
        lines.iter().all(|l| l.split(',').count() == columns),
        "{csv}"
    );
    let png = image::open(out.join("shadow-pass-time.png")).expect("a decodable PNG");
    assert_eq!((png.width(), png.height()), (800, 500));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reports"][0]["preset"], "shadow-pass");
    // Per scene: the shadow pass against one depth-only map, the same with the static layer
    // kept (both with the scene's target), and the lists against the static layer.
    let ratios = summary["reports"][0]["ratios"].as_array().unwrap();
    assert_eq!(ratios.len(), 9, "{ratios:?}");
    // Each row: the scene's own triangle count (the quick preset's 1,000 cubes), and its
    // ratios the quotients of the times the row prints, in the CSV and the summary alike.
    let quick = BuiltinOptions {
        cube_count: 1000,
        ..BuiltinOptions::default()
    };
    let header: Vec<&str> = lines[0].split(',').collect();
    for (line, scene) in lines[1..].iter().zip(ratios.chunks(3)) {
        let row = CsvRow {
            header: &header,
            cells: line.split(',').collect(),
        };
        let name = row.cell("scene");
        let triangles = builtin(name, &quick).unwrap().triangle_count();
        assert_eq!(row.cell("triangles"), triangles.to_string(), "{line}");
        let (shadow, floor) = (row.num("temporal_shadow_ms"), row.num("depth_only_map_ms"));
        assert!(shadow > 0.0 && floor > 0.0, "{line}");
        let summary_value = |k: usize| {
            let name = scene[k]["name"].as_str().unwrap().to_owned();
            (name, scene[k]["value"].as_f64().unwrap())
        };
        let expected = [
            (
                ("the CSV's ratio".to_owned(), row.num("ratio")),
                shadow / floor,
            ),
            (summary_value(0), shadow / floor),
            (summary_value(1), row.num("temporal_kept_shadow_ms") / floor),
            (
                summary_value(2),
                row.num("temporal_lists_shadow_ms") / shadow,
            ),
        ];
        for ((what, written), expected) in expected {
            assert!(
                agrees(written, expected),
                "{what}: {written}, the row's times give {expected}: {line}"
            );
        }
        assert!(scene[0]["target"].is_string() && scene[1]["target"].is_string());
        assert!(scene[2]["target"].is_null(), "{scene:?}");
        for r in &scene[..2] {
            let bound: f64 = r["target"].as_str().unwrap()[3..].parse().unwrap();
            let met = r["value"].as_f64().unwrap() <= bound;
            assert_eq!(r["met"].as_bool(), Some(met), "{r:?}");
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

/// `bench --quick --preset frame`: the default frame for temporal, TSM and plain at 1, 8 and
/// 16 spp, every pass of each, under the validation layer; each frame row is the sum of its
/// passes; the ratios against TSM carry their targets at 8 and 16 spp.
#[test]
fn quick_frame_preset_measures_every_pass_of_three_methods() {
    let out = std::env::temp_dir().join(format!("motion-shadows-frame-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "frame", "--out"])
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let csv = std::fs::read_to_string(out.join("frame-results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    for spp in ["1", "8", "16"] {
        for (method, passes) in [
            (
                "temporal",
                &[
                    "collection",
                    "generation",
                    "lighting raster",
                    "lighting shade",
                ][..],
            ),
            (
                "tsm",
                &["tsm shadow maps", "lighting raster", "lighting shade"][..],
            ),
            (
                "plain",
                &["plain shadow map", "lighting raster", "lighting shade"][..],
            ),
        ] {
            let of = |pass: &str| -> f64 {
                let row = rows
                    .iter()
                    .find(|r| r[0] == spp && r[1] == method && r[2] == pass)
                    .unwrap_or_else(|| panic!("no {method} {spp} spp {pass} in {csv}"));
                row[3].parse().unwrap()
            };
            let sum: f64 = passes.iter().map(|p| of(p)).sum();
            let frame = of("frame");
            assert!(
                frame > 0.0 && (frame - sum).abs() <= 1e-3 * frame,
                "{method} {spp}: {csv}"
            );
        }
    }
    let png = image::open(out.join("frame-time.png")).expect("a decodable PNG");
    assert_eq!((png.width(), png.height()), (800, 500));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    let ratios = summary["reports"][0]["ratios"].as_array().unwrap();
    let target = |name: &str| {
        ratios
            .iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("no ratio {name} in {ratios:?}"))["target"]
            .clone()
    };
    assert_eq!(target("temporal / TSM frame time at 8 spp"), "<= 1");
    assert_eq!(target("temporal / TSM frame time at 16 spp"), "<= 0.8");
    assert!(target("temporal / plain frame time at 8 spp").is_null());
    std::fs::remove_dir_all(&out).ok();
}

/// `bench --quick --preset characters`: the walker at its own size and subdivided once (each
/// triangle into four), both methods, under the validation layer; the triangle counts are the
/// model's (4,672 x 4^n) plus the stage's 1,024.
#[test]
fn quick_characters_preset_measures_the_walker_at_two_sizes() {
    let out = std::env::temp_dir().join(format!("motion-shadows-chars-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "characters", "--out"])
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let csv = std::fs::read_to_string(out.join("characters-results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let got: Vec<(&str, &str)> = rows.iter().map(|r| (r[1], r[2])).collect();
    assert_eq!(
        got,
        [
            ("5696", "temporal"),
            ("5696", "tsm"),
            ("19712", "temporal"),
            ("19712", "tsm")
        ],
        "{csv}"
    );
    for r in &rows {
        let ms: f64 = r[3].parse().unwrap();
        assert!(ms.is_finite() && ms > 0.0, "{csv}");
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reports"][0]["ratios"].as_array().unwrap().len(), 2);
    std::fs::remove_dir_all(&out).ok();
}

/// `bench --quick --preset game`: game-level measured by temporal, TSM, plain and temporal
/// with the static layer kept, each row with the whole scene's triangles and a positive time,
/// then one depth-only map (its shadow pass alone), and the four ratios (the two temporal
/// shadow passes against the depth-only map, with their targets; the two temporal frames
/// against TSM's).
#[test]
fn quick_game_preset_measures_three_methods_on_the_game_level() {
    let out = temp_dir("bench-game");
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "game", "--out"])
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let csv = std::fs::read_to_string(out.join("game-results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "method,shadow_ms,lighting_ms,frame_ms,shadow_map_mib,triangles"
    );
    let methods: Vec<&str> = lines[1..]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(
        methods,
        [
            "temporal",
            "tsm",
            "plain",
            "temporal (static layer kept)",
            "one depth-only map"
        ],
        "{csv}"
    );
    // The whole level's triangles, counted here from the scene itself.
    let level = builtin("game-level", &BuiltinOptions::default()).unwrap();
    let triangles = level.triangle_count().to_string();
    for (i, line) in lines[1..].iter().enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[5], triangles, "{csv}");
        let timed = if i < 4 { &cells[1..4] } else { &cells[1..2] };
        for ms in timed {
            let ms: f64 = ms.parse().unwrap();
            assert!(ms.is_finite() && ms > 0.0, "{line}");
        }
    }
    image::open(out.join("game-time.png")).expect("the chart");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    // The size the preset renders at (docs/src/cli.md: game-level at 480x270 in a quick
    // run), not the quick run's default 256x192 (the summary said so for every preset).
    assert_eq!(
        summary["reports"][0]["image_sizes"],
        serde_json::json!([[480, 270]]),
        "{summary}"
    );
    let ratios = summary["reports"][0]["ratios"].as_array().unwrap();
    assert_eq!(ratios.len(), 4);
    assert_eq!(ratios[0]["target"], "<= 3");
    assert_eq!(ratios[1]["target"], "<= 3");
    assert!(ratios[2]["target"].is_null() && ratios[3]["target"].is_null());
    // The ratios are the quotients of the rows' times (temporal, TSM, temporal with the layer
    // kept, the depth-only map), and a target is met exactly when its value is within it.
    let header: Vec<&str> = lines[0].split(',').collect();
    let row = |i: usize| CsvRow {
        header: &header,
        cells: lines[i].split(',').collect(),
    };
    let (temporal, tsm, kept, floor) = (row(1), row(2), row(4), row(5));
    let expected = [
        temporal.num("shadow_ms") / floor.num("shadow_ms"),
        kept.num("shadow_ms") / floor.num("shadow_ms"),
        temporal.num("frame_ms") / tsm.num("frame_ms"),
        kept.num("frame_ms") / tsm.num("frame_ms"),
    ];
    for (r, expected) in ratios.iter().zip(expected) {
        let value = r["value"].as_f64().unwrap();
        assert!(
            agrees(value, expected),
            "{}: {value}, the rows give {expected}: {csv}",
            r["name"]
        );
    }
    for r in &ratios[..2] {
        assert_eq!(
            r["met"].as_bool(),
            Some(r["value"].as_f64().unwrap() <= 3.0)
        );
    }
    std::fs::remove_dir_all(&out).ok();
}

/// `bench --quick --preset hard`: every hard scene, each method's RMSE against the truth in
/// the CSV (finite, and zero for no method: each differs from the truth somewhere; the
/// temporal method's no worse than a plain map's, and small), one side-by-side image per
/// scene, and the temporal method's RMSE per scene as a ratio.
#[test]
fn quick_hard_preset_measures_every_method_on_every_hard_scene() {
    let out = temp_dir("bench-hard");
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["bench", "--quick", "--preset", "hard", "--out"])
        .arg(&out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .status()
        .expect("run the binary");
    assert!(status.success());
    let scenes = [
        "rotating-triangle",
        "hinged-limb",
        "propeller",
        "near-plane",
        "grazing",
        "thin-fast",
        "deforming",
        "small-cubes",
        "static-silhouette",
    ];
    let methods = [
        "temporal",
        "temporal-paper-prisms",
        "temporal-exact",
        "coverage",
        "tsm",
        "plain",
        "reference",
    ];
    let csv = std::fs::read_to_string(out.join("hard-results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "scene,method,rmse,rmse_moving,rmse_static,frame_ms"
    );
    // The truth is the ray tracer: every method (and the papers' prisms) is measured.
    assert_eq!(lines.len(), 1 + scenes.len() * methods.len(), "{csv}");
    for scene in scenes {
        let name = format!("hard-{scene}");
        for method in &methods {
            let row = lines
                .iter()
                .find(|l| l.starts_with(&format!("{name},{method},")))
                .unwrap_or_else(|| panic!("no row for {name} {method}: {csv}"));
            let rmse: f64 = row.split(',').nth(2).unwrap().parse().unwrap();
            // The exact lookup may match the ray tracer on every sample.
            let least = if *method == "temporal-exact" {
                0.0
            } else {
                f64::MIN_POSITIVE
            };
            assert!(rmse.is_finite() && rmse >= least, "{row}");
        }
        // Against the same truth (the ray tracer, the same samples), the temporal map is
        // never worse than one plain map drawn at a single time (the same map where nothing
        // moves), and within 0.03 RMSE everywhere (at most 0.0234, on small-cubes; lavapipe,
        // 2026-12-07).
        let rmse = |method: &str| -> f64 {
            let row = (lines.iter())
                .find(|l| l.starts_with(&format!("{name},{method},")))
                .unwrap();
            row.split(',').nth(2).unwrap().parse().unwrap()
        };
        let (temporal, plain) = (rmse("temporal"), rmse("plain"));
        assert!(
            temporal <= plain && temporal < 0.03,
            "{name}: temporal RMSE {temporal}, plain {plain}: {csv}"
        );
        // The exact lookup tests each sample's ray as the ray tracer does (issue 35's target).
        let exact = rmse("temporal-exact");
        assert!(
            exact <= 0.0005,
            "{name}: temporal-exact RMSE {exact}: {csv}"
        );
        let png = image::open(out.join(format!("hard-{scene}.png"))).expect("a decodable PNG");
        assert!(png.width() >= 4 * 64, "{scene}: {}", png.width());
    }
    image::open(out.join("hard-rmse.png")).expect("the chart");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    let report = &summary["reports"][0];
    assert_eq!(report["preset"], "hard");
    // Against an exact truth, three targets per scene: the temporal RMSE <= 0.005 and <= the
    // reference's, the exact lookup's <= 0.0005.
    assert_eq!(report["ratios"].as_array().unwrap().len(), 3 * scenes.len());
    std::fs::remove_dir_all(&out).ok();
}

/// With no Vulkan driver the binary fails with a message that says what is missing and how
/// to install lavapipe.
#[test]
fn no_device_gives_a_clear_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["render", "--width", "8", "--height", "8", "--spp", "1"])
        .env("VK_DRIVER_FILES", "/nonexistent/no_icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/no_icd.json")
        .env("MOTION_SHADOWS_VALIDATION", "0")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("run the binary");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success(),
        "must fail without a driver; stderr: {stderr}"
    );
    assert!(stderr.contains("no Vulkan device"), "stderr: {stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers"), "stderr: {stderr}");
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

/// `animate`: one PNG per frame and a GIF with as many frames of the same size, the walker
/// moving between them, and the `--json` summary's counts and times.
#[test]
fn animate_writes_each_frame_and_a_gif_of_them() {
    use image::AnimationDecoder as _;
    let dir = temp_dir("animate");
    let out = motion_shadows(
        &[
            "animate", "--frames", "3", "--width", "64", "--height", "48", "--spp", "1", "--json",
        ],
        &dir,
    );
    let json: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(json["scene"], "walker-toward-light");
    assert_eq!(json["frames"], 3);
    // Frame i's shutter opens i / 24 s after frame 0's (f32 printed in shortest form).
    let offsets: Vec<f32> = json["frame_offsets_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() as f32)
        .collect();
    assert_eq!(offsets, [0.0, 1.0 / 24.0, 2.0 / 24.0]);
    let gpu_ms = json["frame_gpu_ms"].as_array().unwrap();
    assert_eq!(gpu_ms.len(), 3);
    assert!(gpu_ms.iter().all(|ms| ms.as_f64().unwrap() > 0.0));
    let names: Vec<String> = (0..3)
        .map(|i| format!("walker-toward-light-frame-000{i}.png"))
        .chain(["walker-toward-light.gif".to_owned()])
        .collect();
    let files: Vec<String> = names
        .iter()
        .map(|n| dir.join(n).display().to_string())
        .collect();
    assert_eq!(json["files"], serde_json::json!(files));
    assert_eq!(json["gif"], serde_json::json!(files[3]));

    let pngs: Vec<image::RgbImage> = files[..3]
        .iter()
        .map(|f| image::open(f).unwrap().to_rgb8())
        .collect();
    for png in &pngs {
        assert_eq!(png.dimensions(), (64, 48));
    }
    // The walker moves between consecutive frames (everything else is static).
    assert_ne!(pngs[0], pngs[1]);
    assert_ne!(pngs[1], pngs[2]);
    let gif = std::io::BufReader::new(std::fs::File::open(&files[3]).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(gif)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 3);
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (64, 48));
    }
    assert_ne!(frames[0].buffer(), frames[1].buffer());
    std::fs::remove_dir_all(&dir).ok();
}

/// `animate` refuses, before rendering or writing anything, a scene in which nothing is
/// animated, frame counts and rates out of range, and heat maps.
#[test]
fn animate_refuses_bad_requests_before_rendering() {
    let dir = temp_dir("animate-errors");
    let out = dir.join("out");
    for (args, needle) in [
        (&["--scene", "leg-toward-light"][..], "has no animation"),
        (&["--frames", "0"][..], "--frames"),
        (&["--frames", "601"][..], "--frames"),
        (&["--fps", "0"][..], "--fps"),
        (&["--fps", "NaN"][..], "--fps"),
        (&["--start", "inf"][..], "--start"),
        (&["--heatmaps"][..], "--heatmaps"),
        (&["--runs", "2"][..], "--runs"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
            .arg("animate")
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} created the output directory");
    }
    // A frame's path is a directory: refused before rendering, the old GIF kept, and no
    // temporary file left.
    std::fs::create_dir_all(out.join("walker-toward-light-frame-0001.png")).unwrap();
    std::fs::write(out.join("walker-toward-light.gif"), "old").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args([
            "animate", "--frames", "2", "--width", "16", "--height", "16",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("is a directory"), "{stderr}");
    assert!(
        !stderr.contains("lighting pass"),
        "rendered first: {stderr}"
    );
    let gif = std::fs::read_to_string(out.join("walker-toward-light.gif")).unwrap();
    assert_eq!(gif, "old");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 2);
    std::fs::remove_dir_all(&dir).ok();
}

/// `animate --frame deferred` renders the engine's frame: frame 0 (the scene's own time) is
/// the PNG `render --frame deferred` writes for the same scene and settings, byte for byte,
/// and the summary names the frame and the deferred method. (Before, animate ignored
/// `--frame` and rendered the forward frame.)
#[test]
fn animate_renders_the_deferred_frame() {
    let out = temp_dir("animate-deferred");
    let common = [
        "--scene",
        "game-level",
        "--frame",
        "deferred",
        "--method",
        "tsm",
        "--tsm-maps",
        "4",
        "--width",
        "160",
        "--height",
        "90",
        "--shadow-size",
        "256x256",
        "--exposure",
        "0",
        "--json",
    ];
    let animate = motion_shadows(
        &[&["animate", "--frames", "2"], &common[..]].concat(),
        &out.join("animate"),
    );
    let summary: serde_json::Value = serde_json::from_slice(&animate.stdout).unwrap();
    assert_eq!(summary["frame"], "deferred");
    assert_eq!(summary["method"], "tsm-4");
    let render = motion_shadows(&[&["render"], &common[..]].concat(), &out.join("render"));
    let rendered: serde_json::Value = serde_json::from_slice(&render.stdout).unwrap();
    let png = |v: &serde_json::Value| {
        v["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap().to_owned())
            .find(|f| f.ends_with(".png") && !f.ends_with("-mask.png"))
            .unwrap()
    };
    let first = std::fs::read(png(&summary)).unwrap();
    assert_eq!(first, std::fs::read(png(&rendered)).unwrap());
    let second = std::fs::read(summary["files"][1].as_str().unwrap()).unwrap();
    assert_ne!(first, second, "game-level moves between frames");
    std::fs::remove_dir_all(&out).ok();
}
