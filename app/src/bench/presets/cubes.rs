//! 2017 paper Figs. 9-12: memory and time with and without the coverage map, against the
//! number of random cubes or their speed; and against the cubes' size, which the paper does
//! not give and on which the coverage map's saving depends most.

use super::{
    Bench, MIB, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series, target,
};
use crate::bench::measure::Measurement;
use crate::chart::{Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

const MEMORY_CHART: &str = "memory.png";
/// Drawn by the cube-size sweep only.
const REDUCTION_CHART: &str = "reduction.png";

/// The files the preset of `sweep` writes (see `Preset::outputs`).
pub(super) fn outputs(sweep: Sweep) -> Vec<String> {
    let mut files = vec![RESULTS, MEMORY_CHART, TIME_CHART];
    if sweep == Sweep::Size {
        files.push(REDUCTION_CHART);
    }
    files.into_iter().map(String::from).collect()
}

/// What a random-cubes preset varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sweep {
    Count,
    Speed,
    Size,
}

impl Sweep {
    /// (x value, options) per configuration.
    fn configs(self, b: &Bench) -> Vec<(f64, BuiltinOptions)> {
        match self {
            Sweep::Speed => {
                let cubes = b.scale.pick(1000, 5000);
                let speeds = b.scale.pick(
                    vec![(0.0, 1.0), (2.0, 4.0), (8.0, 16.0)],
                    vec![(0.0, 1.0), (1.0, 2.0), (2.0, 4.0), (4.0, 8.0), (8.0, 16.0)],
                );
                speeds
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
            }
            Sweep::Count => b
                .scale
                .pick(
                    vec![250, 500, 1000, 2000],
                    vec![1000, 2000, 3000, 4000, 5000],
                )
                .into_iter()
                .map(|n| {
                    let o = BuiltinOptions {
                        cube_count: n,
                        ..BuiltinOptions::default()
                    };
                    (n as f64, o)
                })
                .collect(),
            Sweep::Size => {
                let cubes = b.scale.pick(1000, 4000);
                b.scale
                    .pick(
                        vec![1.0, 16.0, 64.0],
                        vec![1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0],
                    )
                    .into_iter()
                    .map(|size: f32| {
                        let o = BuiltinOptions {
                            cube_count: cubes,
                            cube_size: size,
                            ..BuiltinOptions::default()
                        };
                        (size as f64, o)
                    })
                    .collect()
            }
        }
    }

    fn x_name(self) -> &'static str {
        match self {
            Sweep::Count => "cubes",
            Sweep::Speed => "cube speed (mid of range)",
            Sweep::Size => "cube size (speeds 4 to 8)",
        }
    }

    /// The two leading CSV columns and their values for one configuration.
    fn columns(self) -> [&'static str; 2] {
        match self {
            Sweep::Count => ["cubes", "triangles"],
            Sweep::Speed => ["speed_min", "speed_max"],
            Sweep::Size => ["cube_size", "cubes"],
        }
    }

    fn values(self, o: &BuiltinOptions, triangles: u64) -> [String; 2] {
        match self {
            Sweep::Count => [o.cube_count.to_string(), triangles.to_string()],
            Sweep::Speed => [fmt_num(o.speed_min as f64), fmt_num(o.speed_max as f64)],
            Sweep::Size => [fmt_num(o.cube_size as f64), o.cube_count.to_string()],
        }
    }
}

pub(super) fn random_cubes(b: &mut Bench, sweep: Sweep) -> Result<()> {
    let configs = sweep.configs(b);
    let x_name = sweep.x_name();
    let mut table = Table::new(
        [
            sweep.columns()[0],
            sweep.columns()[1],
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
            "{} cubes of size {}, speeds [{}, {}]",
            options.cube_count, options.cube_size, options.speed_min, options.speed_max
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
            let [first, second] = sweep.values(options, s.triangles as u64);
            table
                .push(vec![
                    first,
                    second,
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
    b.write_table(RESULTS, &table)?;
    // Cube sizes double from one configuration to the next.
    let chart = |title: &str, x: &str, y: &str, series| crate::chart::LineChart {
        log_x: sweep == Sweep::Size,
        ..chart(title, x, y, series)
    };
    let pick = |f: &dyn Fn(&Measurement, &Measurement) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|(x, t, c)| (*x, f(t, c))).collect()
    };
    b.write_chart(
        MEMORY_CHART,
        &chart(
            "Memory, eq. (2), with and without the coverage map (CM)",
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
        TIME_CHART,
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
    let fewer =
        |c: &Measurement| c.stats.ranges_without_coverage as f64 / c.stats.ranges.max(1) as f64;
    let time = |t: &Measurement, c: &Measurement| c.frame_ms() / t.frame_ms();
    if sweep == Sweep::Size {
        b.write_chart(
            REDUCTION_CHART,
            &chart(
                "Ranges stored without / with the coverage map",
                x_name,
                "ranges without CM / with CM",
                vec![series("reduction", pick(&|_, c| fewer(c)))],
            ),
        )?;
        for (x, t, c) in &points {
            b.report.ratios.push(ratio(
                format!("ranges without / with CM, cube size {x}"),
                fewer(c),
            ));
            b.report.ratios.push(ratio(
                format!("frame time with / without CM, cube size {x}"),
                time(t, c),
            ));
        }
    } else if let Some((x, t, c)) = points.last() {
        let what = if sweep == Sweep::Speed {
            format!("speed {x}")
        } else {
            format!("{x} cubes")
        };
        if sweep == Sweep::Count && *x >= 4000.0 {
            b.report.ratios.push(target(
                format!("ranges without / with CM, {what}"),
                fewer(c),
                5.0,
                false,
            ));
            b.report.ratios.push(target(
                format!("frame time with / without CM, {what}"),
                time(t, c),
                1.2,
                true,
            ));
        } else {
            b.report
                .ratios
                .push(ratio(format!("ranges without / with CM, {what}"), fewer(c)));
            b.report.ratios.push(ratio(
                format!("frame time with / without CM, {what}"),
                time(t, c),
            ));
        }
    }
    Ok(())
}
