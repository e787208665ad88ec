//! `bench --quick --preset engine` (issue 35 item 6): per scene the exact mask's row beside
//! the depth-line mask and the TSM ladder over N and map sizes, and the equal-quality verdict
//! against the exact mask. The verdict is worked out here from the rows the CSV prints (the
//! cheapest TSM whose RMSE is at or below the exact mask's), and the exact mask's RMSE from
//! `compare --frame deferred --lookup exact` at the same settings: a separate run through
//! the command users compare masks with. Validation layer on.

use crate::common::temp_dir;
use std::path::Path;
use std::process::Command;

/// The quick preset's sizes (docs/src/cli.md): 480x270 images, maps 512x512 and 1024x1024,
/// TSM-1 to TSM-32.
const QUICK_SIZE: (&str, &str) = ("480", "270");
const QUICK_MAP: &str = "512x512";
const QUICK_MAP_SIZES: [&str; 2] = ["512x512", "1024x1024"];
const QUICK_MAPS: [u32; 6] = [1, 2, 4, 8, 16, 32];
/// The CSV's RMSEs have 7 decimals: each is within this of the figure it rounds (half the
/// last decimal, and a hair for binary fractions).
const ROUNDING: f64 = 5.01e-8;
const SCENES: [&str; 3] = ["game-level", "walker-toward-light", "cubes-toward-light"];

fn run(args: &[&str], out: &Path) -> std::process::Output {
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

/// One row of the engine table, the cells the test reads.
#[derive(Debug, Clone)]
struct Row {
    scene: String,
    method: String,
    maps: u32,
    map_size: String,
    ms: f64,
    rmse: f64,
    shadow_bytes: u64,
    tsm_vs_exact: String,
}

fn rows(csv: &str) -> Vec<Row> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let (scene, method, maps, map_size) =
        (col("scene"), col("method"), col("maps"), col("map_size"));
    let (ms, rmse) = (col("shadow_and_mask_ms"), col("rmse"));
    let (bytes, verdict) = (col("shadow_bytes"), col("tsm_vs_exact"));
    lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            assert_eq!(cells.len(), header.len(), "{line}");
            Row {
                scene: cells[scene].to_owned(),
                method: cells[method].to_owned(),
                maps: cells[maps].parse().unwrap(),
                map_size: cells[map_size].to_owned(),
                ms: cells[ms].parse().unwrap(),
                rmse: cells[rmse].parse().unwrap(),
                shadow_bytes: cells[bytes].parse().unwrap(),
                tsm_vs_exact: cells[verdict].to_owned(),
            }
        })
        .collect()
}

#[test]
fn quick_engine_preset_prints_the_exact_row_and_the_cheapest_matching_tsm() {
    let dir = temp_dir("bench-engine-exact");
    let bench = dir.join("bench");
    run(&["bench", "--quick", "--preset", "engine"], &bench);
    let csv = std::fs::read_to_string(bench.join("engine-results.csv")).unwrap();
    let all = rows(&csv);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(bench.join("bench-summary.json")).unwrap()).unwrap();
    let report = &summary["reports"][0];
    let ratio = |name: &str| {
        report["ratios"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"].as_str() == Some(name))
            .unwrap_or_else(|| panic!("no ratio {name:?}: {report}"))
            .clone()
    };
    let notes: Vec<&str> = report["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    let mut with_exact_rows = Vec::new();
    for scene in SCENES {
        let of = |method: &str| -> Vec<&Row> {
            all.iter()
                .filter(|r| r.scene == scene && r.method == method)
                .collect()
        };
        let exact = of("temporal-exact");
        // Every scene has it: cubes-toward-light's texels name up to hundreds of triangles,
        // and the exact walks stop within a texel's list on lavapipe (the loop limiter refused
        // its frame before).
        assert!(
            !exact.is_empty(),
            "{scene}: no exact row (notes: {notes:?}): {csv}"
        );
        assert_eq!(exact.len(), 1, "{scene}: one exact row: {csv}");
        with_exact_rows.push(scene);
        let exact = exact[0];
        let temporal = of("temporal")[0];
        assert_eq!((exact.map_size.as_str(), exact.maps), (QUICK_MAP, 0));
        assert!(exact.ms > 0.0 && exact.shadow_bytes > 0, "{csv}");
        // The exact mask has no texel-sized floor: below the depth-line mask's error.
        assert!(exact.rmse < temporal.rmse, "{scene}: {csv}");
        // The ladder: every N at every map size, each TSM's depth maps as allocated (the
        // static map and min(N, 8) working layers, 4 bytes a texel).
        let tsm = of("tsm");
        let ladder: Vec<(u32, &str)> = tsm.iter().map(|r| (r.maps, r.map_size.as_str())).collect();
        let expected: Vec<(u32, &str)> = QUICK_MAP_SIZES
            .iter()
            .flat_map(|m| QUICK_MAPS.iter().map(move |n| (*n, *m)))
            .collect();
        assert_eq!(ladder, expected, "{scene}: {csv}");
        for r in &tsm {
            let side: u64 = r.map_size.split('x').next().unwrap().parse().unwrap();
            let layers = u64::from(r.maps.min(8));
            assert_eq!(r.shadow_bytes, (1 + layers) * 4 * side * side, "{r:?}");
        }
        // The verdict, from the rows: the cheapest TSM at or below the exact mask's RMSE.
        let cheapest = tsm
            .iter()
            .filter(|r| r.rmse <= exact.rmse)
            .min_by(|a, b| a.ms.total_cmp(&b.ms));
        for r in &tsm {
            let expected = match cheapest {
                Some(c) if std::ptr::eq(*c, *r) => "cheapest match",
                _ if r.rmse <= exact.rmse => "matches",
                _ => "above",
            };
            assert_eq!(r.tsm_vs_exact, expected, "{r:?}: {csv}");
        }
        assert_eq!(exact.tsm_vs_exact, "", "{csv}");
        let exact_rmse = ratio(&format!("{scene}: exact mask RMSE vs the truth"));
        assert!((exact_rmse["value"].as_f64().unwrap() - exact.rmse).abs() <= ROUNDING);
        match cheapest {
            Some(c) => {
                let r = ratio(&format!(
                    "{scene}: equal quality vs the exact mask (TSM-{} at {} time / exact time)",
                    c.maps, c.map_size
                ));
                let expected = c.ms / exact.ms;
                let value = r["value"].as_f64().unwrap();
                assert!((value - expected).abs() <= 1e-3 * expected, "{r}: {csv}");
                assert_eq!(r["met"].as_bool(), Some(value >= 20.0));
            }
            None => {
                let best = tsm.iter().min_by(|a, b| a.rmse.total_cmp(&b.rmse)).unwrap();
                let r = ratio(&format!(
                    "{scene}: TSM's best RMSE / the exact mask's (none matches up to N=32, \
                     1024x1024; best TSM-{} at {})",
                    best.maps, best.map_size
                ));
                // value = B / E of the unrounded RMSEs; the CSV's b and e are each within
                // ROUNDING of them, so value * e - b is within ROUNDING * (value + 1).
                let value = r["value"].as_f64().unwrap();
                let off = (value * exact.rmse - best.rmse).abs();
                assert!(off <= ROUNDING * (value + 1.0), "{r}: {csv}");
                assert!(
                    notes.iter().any(|n| n.starts_with(&format!(
                        "{scene}: equal quality vs the exact mask: none up to N=32, 1024x1024"
                    ))),
                    "{notes:?}"
                );
            }
        }
    }
    assert_eq!(with_exact_rows, SCENES, "{csv}");
    // The exact mask's RMSE as `compare` measures it at the same settings.
    let compare = run(
        &[
            "compare",
            "--frame",
            "deferred",
            "--lookup",
            "exact",
            "--scene",
            "walker-toward-light",
            "--width",
            QUICK_SIZE.0,
            "--height",
            QUICK_SIZE.1,
            "--shadow-size",
            QUICK_MAP,
            "--tsm-maps",
            "1",
            "--json",
        ],
        &dir.join("compare"),
    );
    let compared: serde_json::Value = serde_json::from_slice(&compare.stdout).unwrap();
    let compared_rmse = compared["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["method"] == "temporal-exact")
        .unwrap()["rmse"]
        .as_f64()
        .unwrap();
    let benched = all
        .iter()
        .find(|r| r.scene == "walker-toward-light" && r.method == "temporal-exact")
        .unwrap();
    assert!(
        (benched.rmse - compared_rmse).abs() <= 1e-6,
        "bench {} vs compare {compared_rmse}",
        benched.rmse
    );
    std::fs::remove_dir_all(&dir).ok();
}
