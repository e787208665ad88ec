//! The animated character (`walker-toward-light`, CesiumMan) at its own size and subdivided
//! to the papers' character sizes (2018 Fig. 10: 265k triangles; 2017 Figs. 5-6: 70k and
//! 268k): temporal vs TSM, per-pass time and memory.

use super::{Bench, MIB, RESULTS, bench_error, builtin_scene, chart, ratio, series};
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

const SHADOW_PASS_CHART: &str = "shadow-pass.png";

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, SHADOW_PASS_CHART].map(String::from).to_vec()
}

pub(super) fn characters(b: &mut Bench) -> Result<()> {
    // Levels of midpoint subdivision: 4,672 x 4^n character triangles (2: ~75k, 3: ~300k).
    let levels: Vec<u32> = b.scale.pick(vec![0, 1], vec![0, 2, 3]);
    let mut table = Table::new(
        [
            "subdivide",
            "triangles",
            "method",
            "shadow_ms",
            "lighting_ms",
            "frame_ms",
            "shadow_map_mib",
        ]
        .map(String::from)
        .to_vec(),
    );
    let (mut temporal, mut tsm) = (Vec::new(), Vec::new());
    for level in levels {
        let options = BuiltinOptions {
            subdivide: level,
            ..BuiltinOptions::default()
        };
        let scene = builtin_scene("walker-toward-light", &options)?;
        let mut shadow = [0.0; 2];
        for (i, method) in [Method::Temporal, Method::Tsm].into_iter().enumerate() {
            let what = format!("walker, subdivided {level}x, {}", method.name());
            let Some(m) = b.measure(&what, &scene, &b.settings(method, 8)) else {
                continue;
            };
            let triangles = f64::from(m.stats.triangles);
            table
                .push(vec![
                    level.to_string(),
                    m.stats.triangles.to_string(),
                    method.name().to_owned(),
                    fmt_num(m.shadow_ms()),
                    fmt_num(m.lighting_ms()),
                    fmt_num(m.frame_ms()),
                    fmt_num(m.shadow_bytes() as f64 / MIB),
                ])
                .map_err(bench_error)?;
            shadow[i] = m.shadow_ms();
            [&mut temporal, &mut tsm][i].push((triangles, m.shadow_ms()));
        }
        if shadow.iter().all(|&s| s > 0.0) {
            b.report.ratios.push(ratio(
                format!("shadow pass temporal / TSM (8 maps), walker subdivided {level}x",),
                shadow[0] / shadow[1],
            ));
        }
    }
    b.write_table(RESULTS, &table)?;
    b.write_chart(
        SHADOW_PASS_CHART,
        &LineChart {
            log_x: true,
            log_y: true,
            ..chart(
                "Shadow pass vs triangles, walker-toward-light, 8 spp",
                "triangles",
                "GPU ms",
                vec![series("temporal", temporal), series("TSM (8 maps)", tsm)],
            )
        },
    )?;
    Ok(())
}
