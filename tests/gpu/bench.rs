//! The measurement plumbing: the counters agree with the lists they count, and a quick bench
//! preset writes well-formed CSV and PNG.

use crate::support::gpu::{assert_no_validation_messages, context, temporal_map};
use motion_shadows::render::equation_2_bytes;
use motion_shadows::scene::{BuiltinOptions, builtin};
use std::process::Command;

/// N_f from the atomic counter equals the fragments found by walking every pixel's list (the
/// numbers a heat map would sum), and N_r likewise; equation (2) by hand on those figures.
#[test]
fn counters_equal_the_lists_they_count() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let map = temporal_map(&ctx, &s, (48, 36));
    let (mut fragments, mut ranges) = (0usize, 0usize);
    for y in 0..map.height {
        for x in 0..map.width {
            fragments += map.nodes_at(x, y).len();
            ranges += map.ranges_at(x, y).len();
        }
    }
    assert_eq!(fragments, map.nodes.len(), "fragments linked vs counted");
    assert_eq!(ranges, map.ranges.len(), "ranges linked vs counted");
    assert!(fragments > 1000);
    let pixels = 48 * 36;
    assert_eq!(
        equation_2_bytes(fragments as u64, ranges as u64, pixels),
        fragments as u64 * 16 + ranges as u64 * 24 + 2 * pixels * 4
    );
    assert_no_validation_messages(&ctx);
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
    assert_eq!(lines.len(), 3, "header and two scenes: {csv}");
    let columns = lines[0].split(',').count();
    assert!(
        lines.iter().all(|l| l.split(',').count() == columns),
        "{csv}"
    );
    for line in &lines[1..] {
        let ratio: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
        assert!(ratio.is_finite() && ratio > 0.0, "{line}");
    }
    let png = image::open(out.join("shadow-pass-time.png")).expect("a decodable PNG");
    assert_eq!((png.width(), png.height()), (800, 500));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench-summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reports"][0]["preset"], "shadow-pass");
    std::fs::remove_dir_all(&out).ok();
}
