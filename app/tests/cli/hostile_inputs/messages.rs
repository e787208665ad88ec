//! Messages that must name the real cause, and limits checked before the work.

use super::{SMALL, listing, run, s, temp_dir};

/// Case 7: `scene export walker-toward-light --subdivide 4` wrote 346 MiB that `render
/// --scene-file` then refused (256 MiB limit). The export checks the loader's limit first
/// and writes nothing.
#[test]
fn export_refuses_a_file_the_loader_would_refuse() {
    let dir = temp_dir("export-limit");
    let out = dir.join("walker.json");
    let r = run(&[
        "scene",
        "export",
        "walker-toward-light",
        "--subdivide",
        "4",
        "--out",
        s(&out),
    ]);
    r.refused(&["MiB", "256 MiB", "--subdivide", "nothing was written"]);
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // One level less fits, and is written.
    let r = run(&[
        "scene",
        "export",
        "walker-toward-light",
        "--subdivide",
        "3",
        "--out",
        s(&out),
    ]);
    assert!(r.succeeded(), "{}", r.stderr());
    assert_eq!(listing(&dir), ["walker.json"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// Case 9: a one-row map (`--shadow-size 256x1`) whose texel centres miss every triangle
/// was reported as "all outside the light's cone or box", though the geometry is inside it.
/// The warning names the map's resolution now.
#[test]
fn an_empty_map_too_coarse_to_hit_anything_says_so() {
    let dir = temp_dir("coarse-map");
    let mut args = vec![
        "render",
        "--shadow-size",
        "256x1",
        "--json",
        "--out",
        s(&dir),
    ];
    args.extend(SMALL);
    let r = run(&args);
    assert!(r.succeeded(), "{}", r.stderr());
    let json: serde_json::Value = serde_json::from_slice(&r.output.stdout).unwrap();
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let warning = warnings[0].as_str().unwrap();
    for needle in [
        "256x1",
        "too coarse",
        "--shadow-size",
        "inside the light's view",
    ] {
        assert!(warning.contains(needle), "{needle:?} not in {warning:?}");
    }
    assert!(!warning.contains("all outside"), "{warning}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Case 10: `render --method reference --shadow-filter footprint` filtered the reference,
/// which the documentation says stays unfiltered (`compare` and `bench` force `none`). It
/// is refused now, before a device is made.
#[test]
fn the_reference_is_never_filtered() {
    let dir = temp_dir("reference-filter");
    for filter in ["bilinear", "footprint"] {
        let mut args = vec![
            "render",
            "--method",
            "reference",
            "--slices",
            "4",
            "--shadow-filter",
            filter,
            "--out",
            s(&dir),
        ];
        args.extend(SMALL);
        let r = run(&args);
        r.refused(&[&format!("--shadow-filter {filter}"), "unfiltered"]);
        assert!(
            !r.stderr().contains("creating the Vulkan device"),
            "{}",
            r.stderr()
        );
    }
    assert!(listing(&dir).is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

/// A vertical quad around (0, `y`, 0) whose plane sweeps along x from -0.5 to 0.5.
fn sweeping_quad(y: f32) -> String {
    let (lo, hi) = (y - 1.0, y + 1.0);
    let corners = |x: f32| {
        format!(
            "[[{x}, {lo}, -1], [{x}, {lo}, 1], [{x}, {hi}, 1], \
              [{x}, {lo}, -1], [{x}, {hi}, 1], [{x}, {hi}, -1]]"
        )
    };
    format!(
        r#"{{ "name": "sweeper", "albedo": [0.5, 0.5, 0.5],
             "mesh": {{ "triangles": {{ "t0": {}, "t1": {} }} }} }}"#,
        corners(-0.5),
        corners(0.5)
    )
}

/// Case 6: a quad that sweeps through the spot light itself got a straight-edged shadow
/// split the ray tracer does not have, and was then warned about as approximate. The exact
/// prisms cut at the times the plane passes the light now, so the image is exact
/// (app/tests/gpu/through_light.rs checks it against the ray tracer, and the library's
/// tests/gpu/exact_prisms.rs every texel against the f64 oracle): no warning remains, for
/// the quad through the light or below it.
#[test]
fn a_quad_sweeping_through_the_light_is_rendered_without_a_warning() {
    let dir = temp_dir("through-light");
    for y in [5.0, 2.5] {
        let scene = dir.join(format!("sweep-{y}.json"));
        std::fs::write(&scene, super::scene_json("sweep", &[sweeping_quad(y)])).unwrap();
        let mut args = vec![
            "render",
            "--scene-file",
            s(&scene),
            "--json",
            "--out",
            s(&dir),
        ];
        args.extend(SMALL);
        let r = run(&args);
        assert!(r.succeeded(), "{}", r.stderr());
        let json: serde_json::Value = serde_json::from_slice(&r.output.stdout).unwrap();
        let warnings = json["warnings"].as_array().expect("a warnings array");
        assert!(warnings.is_empty(), "quad at y = {y}: {json}");
        assert!(!r.stderr().contains("warning"), "{}", r.stderr());
    }
    std::fs::remove_dir_all(&dir).ok();
}
