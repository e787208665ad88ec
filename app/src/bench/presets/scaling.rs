//! Frame time against triangle count.

use super::{Bench, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series};
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, TIME_CHART].map(String::from).to_vec()
}

pub(super) fn scaling(b: &mut Bench) -> Result<()> {
    let counts: Vec<usize> = b
        .scale
        .pick(vec![125, 250, 500, 1000], vec![500, 1000, 2000, 4000, 8000]);
    let mut table = Table::new(
        [
            "cubes",
            "triangles",
            "fragments",
            "shadow_ms",
            "lighting_ms",
            "frame_ms",
        ]
        .map(String::from)
        .to_vec(),
    );
    let mut frame = Vec::new();
    let mut shadow = Vec::new();
    let mut lighting = Vec::new();
    for n in counts {
        // Slow cubes: the sweep isolates the triangle count from the motion.
        let options = BuiltinOptions {
            cube_count: n,
            speed_min: 0.5,
            speed_max: 1.0,
            ..BuiltinOptions::default()
        };
        let scene = builtin_scene("random-cubes", &options)?;
        let Some(m) = b.measure(
            &format!("{n} slow cubes"),
            &scene,
            &b.settings(Method::Temporal, 8),
        ) else {
            continue;
        };
        let triangles = m.stats.triangles as f64;
        table
            .push(vec![
                n.to_string(),
                m.stats.triangles.to_string(),
                m.stats.fragments.to_string(),
                fmt_num(m.shadow_ms()),
                fmt_num(m.lighting_ms()),
                fmt_num(m.frame_ms()),
            ])
            .map_err(bench_error)?;
        frame.push((triangles, m.frame_ms()));
        shadow.push((triangles, m.shadow_ms()));
        lighting.push((triangles, m.lighting_ms()));
    }
    b.write_table(RESULTS, &table)?;
    if let (Some(first), Some(last)) = (frame.first(), frame.last()) {
        b.report.ratios.push(ratio(
            format!(
                "frame time growth for {}x the triangles",
                fmt_num(last.0 / first.0)
            ),
            last.1 / first.1,
        ));
    }
    b.write_chart(
        TIME_CHART,
        &LineChart {
            log_x: true,
            log_y: true,
            ..chart(
                "GPU time vs triangles (temporal, random cubes moving 0.5-1 units)",
                "triangles",
                "GPU ms",
                vec![
                    series("frame", frame),
                    series("shadow pass", shadow),
                    series("lighting", lighting),
                ],
            )
        },
    )?;
    Ok(())
}
