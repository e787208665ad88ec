//! The presets: what each sweeps, what it writes, which ratios it reports.

use super::Scale;
use super::measure::{Measurement, measure};
use crate::chart::{LineChart, Series, Table, fmt_num, write_chart};
use crate::compare::rmse;
use crate::error::{Error, Result};
use crate::render::{Method, RenderSettings, Renderer};
use crate::scene::{BuiltinOptions, Scene, builtin};
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// 2018 paper Figs. 11-12: time per step and memory, temporal vs TSM, as spp grows.
    Spp,
    /// 2017 paper Figs. 9-10: memory and time vs number of random cubes, with/without the
    /// coverage map.
    RandomCubes,
    /// 2017 paper Figs. 11-12: the same vs cube speed.
    Speed,
    /// Time each method needs to get within a given RMSE of a high-slice reference.
    EqualQuality,
    /// The temporal shadow pass against an ordinary depth-only shadow map of the same scene.
    ShadowPass,
    /// Frame time against triangle count.
    Scaling,
}

pub const PRESETS: &[Preset] = &[
    Preset::Spp,
    Preset::RandomCubes,
    Preset::Speed,
    Preset::EqualQuality,
    Preset::ShadowPass,
    Preset::Scaling,
];

impl Preset {
    pub fn name(self) -> &'static str {
        match self {
            Preset::Spp => "spp",
            Preset::RandomCubes => "random-cubes",
            Preset::Speed => "speed",
            Preset::EqualQuality => "equal-quality",
            Preset::ShadowPass => "shadow-pass",
            Preset::Scaling => "scaling",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        PRESETS.iter().copied().find(|p| p.name() == name)
    }
}

/// A key figure of a preset and, where the project set one, its target.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    pub name: String,
    pub value: f64,
    pub target: Option<String>,
    pub met: Option<bool>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub preset: &'static str,
    pub files: Vec<PathBuf>,
    pub ratios: Vec<Ratio>,
    /// Configurations that could not be measured, and why.
    pub notes: Vec<String>,
}

const MIB: f64 = 1024.0 * 1024.0;
const CHART_SIZE: (u32, u32) = (800, 500);

fn ratio(name: impl Into<String>, value: f64) -> Ratio {
    Ratio {
        name: name.into(),
        value,
        target: None,
        met: None,
    }
}

/// A ratio with a target: `at_most` (the value must not exceed it) or at least.
fn target(name: impl Into<String>, value: f64, bound: f64, at_most: bool) -> Ratio {
    Ratio {
        name: name.into(),
        value,
        target: Some(format!(
            "{} {}",
            if at_most { "<=" } else { ">=" },
            fmt_num(bound)
        )),
        met: Some(if at_most {
            value <= bound
        } else {
            value >= bound
        }),
    }
}

fn bench_error(e: impl std::fmt::Display) -> Error {
    Error::Bench(e.to_string())
}

struct Bench<'a, 'r> {
    renderer: &'a mut Renderer<'r>,
    scale: &'a Scale,
    progress: &'a mut dyn FnMut(&str),
    report: Report,
}

impl Bench<'_, '_> {
    fn settings(&self, method: Method, spp: u32) -> RenderSettings {
        RenderSettings {
            width: self.scale.width,
            height: self.scale.height,
            spp,
            seed: 1,
            method,
            ..RenderSettings::default()
        }
    }

    fn measure(
        &mut self,
        what: &str,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Option<Measurement> {
        (self.progress)(&format!("bench {}: {what}", self.report.preset));
        match measure(self.renderer, scene, settings, self.scale.runs) {
            Ok(m) => Some(m),
            Err(e) => {
                self.report.notes.push(format!("{what}: {e}"));
                None
            }
        }
    }

    fn write_table(&mut self, name: &str, table: &Table) -> Result<()> {
        let path = self
            .scale
            .out
            .join(format!("{}-{name}.csv", self.report.preset));
        table.write(&path).map_err(bench_error)?;
        self.report.files.push(path);
        Ok(())
    }

    fn write_chart(&mut self, name: &str, chart: &LineChart) -> Result<()> {
        let path = self
            .scale
            .out
            .join(format!("{}-{name}.png", self.report.preset));
        write_chart(&path, chart, CHART_SIZE.0, CHART_SIZE.1).map_err(bench_error)?;
        self.report.files.push(path);
        Ok(())
    }
}

fn chart(title: &str, x: &str, y: &str, series: Vec<Series>) -> LineChart {
    LineChart {
        title: title.into(),
        x_label: x.into(),
        y_label: y.into(),
        series,
        log_x: false,
        log_y: false,
    }
}

fn series(label: &str, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.into(),
        points,
    }
}

fn builtin_scene(name: &str, options: &BuiltinOptions) -> Result<Scene> {
    Ok(builtin(name, options)?)
}

/// Runs one preset; its files go to `scale.out`.
pub fn run_preset(
    renderer: &mut Renderer<'_>,
    preset: Preset,
    scale: &Scale,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    std::fs::create_dir_all(&scale.out).map_err(bench_error)?;
    let mut bench = Bench {
        renderer,
        scale,
        progress,
        report: Report {
            preset: preset.name(),
            files: Vec::new(),
            ratios: Vec::new(),
            notes: Vec::new(),
        },
    };
    match preset {
        Preset::Spp => spp(&mut bench)?,
        Preset::RandomCubes => random_cubes(&mut bench, false)?,
        Preset::Speed => random_cubes(&mut bench, true)?,
        Preset::EqualQuality => equal_quality(&mut bench)?,
        Preset::ShadowPass => shadow_pass(&mut bench)?,
        Preset::Scaling => scaling(&mut bench)?,
    }
    Ok(bench.report)
}

fn spp(b: &mut Bench) -> Result<()> {
    let scene = builtin_scene("cubes-toward-light", &BuiltinOptions::default())?;
    let spps: Vec<u32> = b.scale.pick(vec![1, 2, 4, 8, 16], vec![1, 2, 4, 8, 16, 32]);
    let mut table = Table::new(
        [
            "spp",
            "method",
            "shadow_ms",
            "lighting_ms",
            "frame_ms",
            "shadow_map_bytes",
        ]
        .map(String::from)
        .to_vec(),
    );
    let mut rows: Vec<(u32, Measurement, Measurement)> = Vec::new();
    for &spp in &spps {
        let temporal = b.measure(
            &format!("temporal {spp} spp"),
            &scene,
            &b.settings(Method::Temporal, spp),
        );
        let tsm = b.measure(
            &format!("tsm {spp} spp"),
            &scene,
            &b.settings(Method::Tsm, spp),
        );
        for m in [&temporal, &tsm].into_iter().flatten() {
            table
                .push(vec![
                    spp.to_string(),
                    m.stats.method.clone(),
                    fmt_num(m.shadow_ms()),
                    fmt_num(m.lighting_ms()),
                    fmt_num(m.frame_ms()),
                    m.shadow_bytes().to_string(),
                ])
                .map_err(bench_error)?;
        }
        if let (Some(t), Some(s)) = (temporal, tsm) {
            rows.push((spp, t, s));
        }
    }
    b.write_table("results", &table)?;
    let line = |f: &dyn Fn(&Measurement) -> f64, tsm: bool| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|(spp, t, s)| (*spp as f64, f(if tsm { s } else { t })))
            .collect()
    };
    let time = chart(
        "GPU time per frame and per step (cubes-toward-light)",
        "samples per pixel",
        "GPU ms",
        vec![
            series("temporal: frame", line(&|m| m.frame_ms(), false)),
            series("temporal: shadow pass", line(&|m| m.shadow_ms(), false)),
            series("temporal: lighting", line(&|m| m.lighting_ms(), false)),
            series("TSM: frame", line(&|m| m.frame_ms(), true)),
            series("TSM: shadow maps", line(&|m| m.shadow_ms(), true)),
            series("TSM: lighting", line(&|m| m.lighting_ms(), true)),
        ],
    );
    b.write_chart(
        "time",
        &LineChart {
            log_x: true,
            ..time
        },
    )?;
    let memory = chart(
        "Shadow-map memory (temporal: equation (2); TSM: spp x 4 B x pixels)",
        "samples per pixel",
        "MiB",
        vec![
            series("temporal", line(&|m| m.shadow_bytes() as f64 / MIB, false)),
            series("TSM", line(&|m| m.shadow_bytes() as f64 / MIB, true)),
        ],
    );
    b.write_chart(
        "memory",
        &LineChart {
            log_x: true,
            ..memory
        },
    )?;
    for (spp, t, s) in &rows {
        let r = t.frame_ms() / s.frame_ms();
        let name = format!("temporal / TSM frame time at {spp} spp");
        b.report.ratios.push(match spp {
            8 => target(name, r, 1.0, true),
            16 => target(name, r, 0.5, true),
            _ => ratio(name, r),
        });
    }
    if let Some((_, t, _)) = rows.iter().find(|(spp, _, _)| *spp == 8) {
        let ms = t.frame_ms();
        let name = format!(
            "temporal frame GPU ms at 8 spp, {}x{}",
            b.scale.width, b.scale.height
        );
        b.report.ratios.push(if b.scale.quick {
            ratio(name, ms)
        } else {
            target(name, ms, 1000.0, true)
        });
    }
    Ok(())
}

fn random_cubes(b: &mut Bench, by_speed: bool) -> Result<()> {
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

/// (GPU ms, RMSE, samples per pixel or slices) of each configuration of one method.
type Curve = Vec<(f64, f64, u32)>;

fn equal_quality(b: &mut Bench) -> Result<()> {
    let scene = builtin_scene("cubes-toward-light", &BuiltinOptions::default())?;
    let (width, height) = b.scale.pick((128, 96), (320, 240));
    let at = |method, spp, seed| RenderSettings {
        width,
        height,
        spp,
        seed,
        method,
        ..RenderSettings::default()
    };
    let reference_slices = b.scale.pick(512, 2048);
    // Another seed than the measured renders, so the reference's noise is independent.
    let reference = b
        .measure(
            &format!("reference, {reference_slices} slices"),
            &scene,
            &at(
                Method::Reference {
                    slices: reference_slices,
                },
                1,
                1000,
            ),
        )
        .ok_or_else(|| bench_error("the reference could not be rendered"))?;
    let mut table = Table::new(
        ["method", "samples", "rmse", "frame_ms"]
            .map(String::from)
            .to_vec(),
    );
    let mut curves: Vec<(&str, Curve)> = Vec::new();
    let sweeps: [(&str, Vec<u32>); 3] = [
        (
            "temporal",
            b.scale
                .pick(vec![1, 2, 4, 8, 16, 32], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "tsm",
            b.scale
                .pick(vec![1, 2, 4, 8, 16, 32], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "reference",
            b.scale.pick(
                vec![4, 8, 16, 32, 64, 128],
                vec![4, 8, 16, 32, 64, 128, 256, 512],
            ),
        ),
    ];
    for (name, samples) in sweeps {
        let mut curve = Vec::new();
        for n in samples {
            let (method, spp) = match name {
                "temporal" => (Method::Temporal, n),
                "tsm" => (Method::Tsm, n),
                _ => (Method::Reference { slices: n }, 1),
            };
            let Some(m) = b.measure(&format!("{name} {n}"), &scene, &at(method, spp, 1)) else {
                continue;
            };
            let e = rmse(&m.image, &reference.image, None).map_err(bench_error)?;
            table
                .push(vec![
                    name.into(),
                    n.to_string(),
                    fmt_num(e),
                    fmt_num(m.frame_ms()),
                ])
                .map_err(bench_error)?;
            curve.push((m.frame_ms(), e, n));
        }
        curves.push((name, curve));
    }
    b.write_table("results", &table)?;
    let as_series = |(name, curve): &(&str, Curve)| {
        let label = match *name {
            "reference" => "brute force (slices)".to_string(),
            n => format!("{n} (spp)"),
        };
        series(&label, curve.iter().map(|(t, e, _)| (*t, *e)).collect())
    };
    b.write_chart(
        "rmse-vs-time",
        &LineChart {
            log_x: true,
            log_y: true,
            ..chart(
                "RMSE against the reference vs GPU time",
                "GPU ms per frame",
                "RMSE",
                curves.iter().map(as_series).collect(),
            )
        },
    )?;
    // Equal quality: the temporal method's error at 16 spp; each method's time is the fastest
    // configuration that is at least as good.
    let temporal = &curves[0].1;
    let Some(&(_, goal, _)) = temporal.iter().find(|(_, _, n)| *n == 16) else {
        b.report
            .notes
            .push("no temporal 16 spp measurement: no equal-quality ratio".into());
        return Ok(());
    };
    let time_to = |curve: &[(f64, f64, u32)]| {
        curve
            .iter()
            .filter(|(_, e, _)| *e <= goal)
            .map(|(t, _, _)| *t)
            .fold(f64::INFINITY, f64::min)
    };
    let t_temporal = time_to(temporal);
    b.report
        .ratios
        .push(ratio("equal-quality RMSE (temporal at 16 spp)", goal));
    for (name, curve) in &curves[1..] {
        let t = time_to(curve);
        let what = format!("equal-quality time {name} / temporal");
        if t.is_finite() {
            b.report.ratios.push(if *name == "reference" {
                target(what, t / t_temporal, 20.0, false)
            } else {
                ratio(what, t / t_temporal)
            });
        } else {
            b.report.notes.push(format!(
                "{name} never reached RMSE {} in the sweep",
                fmt_num(goal)
            ));
        }
    }
    Ok(())
}

fn shadow_pass(b: &mut Bench) -> Result<()> {
    let mut table = Table::new(
        [
            "scene",
            "temporal_shadow_ms",
            "collection_ms",
            "generation_ms",
            "plain_depth_map_ms",
            "ratio",
        ]
        .map(String::from)
        .to_vec(),
    );
    let cubes = b.scale.pick(1000, 4000);
    let scenes = [
        builtin_scene("cubes-toward-light", &BuiltinOptions::default())?,
        builtin_scene(
            "random-cubes",
            &BuiltinOptions {
                cube_count: cubes,
                ..BuiltinOptions::default()
            },
        )?,
    ];
    let mut bars = Vec::new();
    for scene in &scenes {
        let temporal = b.measure(
            &format!("{} temporal", scene.name),
            scene,
            &b.settings(Method::Temporal, 1),
        );
        let plain = b.measure(
            &format!("{} plain", scene.name),
            scene,
            &b.settings(Method::Plain { time: 0.5 }, 1),
        );
        let (Some(t), Some(p)) = (temporal, plain) else {
            continue;
        };
        let (shadow, floor) = (t.shadow_ms(), p.shadow_ms());
        table
            .push(vec![
                scene.name.clone(),
                fmt_num(shadow),
                fmt_num(t.gpu_ms_where(|n| n == "collection")),
                fmt_num(t.gpu_ms_where(|n| n == "generation")),
                fmt_num(floor),
                fmt_num(shadow / floor),
            ])
            .map_err(bench_error)?;
        bars.push((scene.name.clone(), shadow, floor));
        b.report.ratios.push(target(
            format!("{}: shadow pass / plain shadow map", scene.name),
            shadow / floor,
            3.0,
            true,
        ));
    }
    b.write_table("results", &table)?;
    let points = |f: &dyn Fn(&(String, f64, f64)) -> f64| {
        bars.iter()
            .enumerate()
            .map(|(i, v)| (i as f64 + 1.0, f(v)))
            .collect()
    };
    b.write_chart(
        "time",
        &chart(
            "Shadow pass vs an ordinary shadow map (1 = cubes-toward-light, 2 = random cubes)",
            "scene",
            "GPU ms",
            vec![
                series("temporal: collection + generation", points(&|v| v.1)),
                series("plain shadow map", points(&|v| v.2)),
            ],
        ),
    )?;
    b.report.notes.push(
        "the plain shadow map is this project's ordinary map (nearest depth and id per texel by 64-bit atomics, no depth attachment)".into(),
    );
    Ok(())
}

fn scaling(b: &mut Bench) -> Result<()> {
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
    b.write_table("results", &table)?;
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
        "time",
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
