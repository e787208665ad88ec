//! 2017 paper Figs. 9-12: memory and time with and without the coverage map, against the
//! number of random cubes or their speed.

use super::{Bench, MIB, bench_error, builtin_scene, chart, ratio, series, target};
use crate::bench::measure::Measurement;
use crate::chart::{Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

pub(super) fn random_cubes(b: &mut Bench, by_speed: bool) -> Result<()> {
    // (x value, options) per configuration.
    let configs: Vec<(f64, BuiltinOptions)> = if by_speed {
        let cubes = b.scale.pick(1000, 5000);
        [(0.0, 1.0), (1.0, 2.0), (2.0, 4.0), (4.0, 8.0), (8.0, 16.0)]
            .into_iter()
            .map(|(lo, hi)| {
                let o = BuiltinOptions {
                    cube_count: cubes,
                    speed_min: lo,
                    speed_max: hi,
                    ..BuiltinOptions::default()
                };
                ((lo + hi) as f64 / 2.0, o)
            })
            .collect()
    } else {
        let counts: Vec<usize> = b.scale.pick(
            vec![250, 500, 1000, 2000],
            vec![1000, 2000, 3000, 4000, 5000],
        );
        counts
            .into_iter()
            .map(|n| {
                let o = BuiltinOptions {
                    cube_count: n,
                    ..BuiltinOptions::default()
                };
                (n as f64, o)
            })
            .collect()
    };
    let x_name = if by_speed {
        "cube speed (mid of range)"
    } else {
        "cubes"
    };
    let mut table = Table::new(
        [
            if by_speed { "speed_min" } else { "cubes" },
            if by_speed { "speed_max" } else { "triangles" },
            "method",
            "fragments",
            "ranges",
            "ranges_without_coverage",
            "eq2_bytes",
            "eq2_bytes_without_coverage",
            "coverage_map_bytes",
            "frame_ms",
        ]
        .map(String::from)
        .to_vec(),
    );
    let mut points: Vec<(f64, Measurement, Measurement)> = Vec::new();
    for (x, options) in &configs {
        let scene = builtin_scene("random-cubes", options)?;
        let label = format!(
            "{} cubes, speeds [{}, {}]",
            options.cube_count, options.speed_min, options.speed_max
        );
        let temporal = b.measure(
            &format!("{label}, temporal"),
            &scene,
            &b.settings(Method::Temporal, 8),
        );
        let coverage = b.measure(
            &format!("{label}, coverage"),
            &scene,
            &b.settings(Method::Coverage, 8),
        );
        for m in [&temporal, &coverage].into_iter().flatten() {
            let s = &m.stats;
            table
                .push(vec![
                    if by_speed {
                        fmt_num(options.speed_min as f64)
                    } else {
                        options.cube_count.to_string()
                    },
                    if by_speed {
                        fmt_num(options.speed_max as f64)
                    } else {
                        s.triangles.to_string()
                    },
                    s.method.clone(),
                    s.fragments.to_string(),
                    s.ranges.to_string(),
                    s.ranges_without_coverage.to_string(),
                    s.shadow_map_bytes_eq2.to_string(),
                    s.shadow_map_bytes_eq2_without_coverage.to_string(),
                    s.coverage_map_bytes.to_string(),
                    fmt_num(m.frame_ms()),
                ])
                .map_err(bench_error)?;
        }
        if let (Some(t), Some(c)) = (temporal, coverage) {
            points.push((*x, t, c));
        }
    }
    b.write_table("results", &table)?;
    let pick = |f: &dyn Fn(&Measurement, &Measurement) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|(x, t, c)| (*x, f(t, c))).collect()
    };
    b.write_chart(
        "memory",
        &chart(
            "Temporal shadow map memory, equation (2), with and without the coverage map (CM)",
            x_name,
            "MiB",
            vec![
                series(
                    "without CM",
                    pick(&|t, _| t.stats.shadow_map_bytes_eq2 as f64 / MIB),
                ),
                series(
                    "with CM (incl. its maps)",
                    pick(&|_, c| {
                        (c.stats.shadow_map_bytes_eq2 + c.stats.coverage_map_bytes) as f64 / MIB
                    }),
                ),
            ],
        ),
    )?;
    b.write_chart(
        "time",
        &chart(
            "GPU time per frame, with and without the coverage map (CM)",
            x_name,
            "GPU ms",
            vec![
                series("without CM", pick(&|t, _| t.frame_ms())),
                series("with CM", pick(&|_, c| c.frame_ms())),
            ],
        ),
    )?;
    if let Some((x, t, c)) = points.last() {
        let what = if by_speed {
            format!("speed {x}")
        } else {
            format!("{x} cubes")
        };
        let fewer = c.stats.ranges_without_coverage as f64 / c.stats.ranges.max(1) as f64;
        let time = c.frame_ms() / t.frame_ms();
        if !by_speed && *x >= 4000.0 {
            b.report.ratios.push(target(
                format!("ranges without / with CM, {what}"),
                fewer,
                5.0,
                false,
            ));
            b.report.ratios.push(target(
                format!("frame time with / without CM, {what}"),
                time,
                1.2,
                true,
            ));
        } else {
            b.report
                .ratios
                .push(ratio(format!("ranges without / with CM, {what}"), fewer));
            b.report
                .ratios
                .push(ratio(format!("frame time with / without CM, {what}"), time));
        }
    }
    Ok(())
}
