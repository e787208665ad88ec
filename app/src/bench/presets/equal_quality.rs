//! The time each method needs to get within a given RMSE of a high-slice reference.

use super::{Bench, RESULTS, bench_error, builtin_scene, chart, ratio, series, target};
use crate::chart::{LineChart, Table, fmt_num};
use crate::compare::rmse;
use crate::error::Result;
use crate::render::{Method, RenderSettings};
use crate::scene::{BuiltinOptions, Scene};
use glam::Vec3;
use motion_shadows::technique::ShadowEstimator::{self, Analytic, Sampled};
use motion_shadows::technique::ShadowFilter;

/// (GPU ms, RMSE, samples per pixel or slices) of each configuration of one method.
type Curve = Vec<(f64, f64, u32)>;

const RMSE_CHART: &str = "rmse-vs-time.png";
/// The prefix of the ground view's files, before the shared names.
const GROUND: &str = "ground-";

/// The files it writes (see `Preset::outputs`): one table and chart per view.
pub(super) fn outputs() -> Vec<String> {
    ["", GROUND]
        .into_iter()
        .flat_map(|view| [RESULTS, RMSE_CHART].map(|file| format!("{view}{file}")))
        .collect()
}

pub(super) fn equal_quality(b: &mut Bench) -> Result<()> {
    let scene = builtin_scene("cubes-toward-light", &BuiltinOptions::default())?;
    sweep(b, &scene, "", "")?;
    // The same scene seen from the ground under the left cube (docs/examples/
    // cubes-ground-view.json): static receivers only, what the analytic estimator is for.
    let mut ground = scene.clone();
    ground.name = "cubes-ground-view".into();
    ground.camera.position = Vec3::new(-1.0, 2.0, 2.0);
    ground.camera.target = Vec3::new(-3.0, 0.0, -0.25);
    sweep(b, &ground, "ground view: ", GROUND)
}

/// The sweep on one scene; `label` prefixes its ratios and notes, `files` its files' names
/// (`{files}results.csv`, `{files}rmse-vs-time.png`).
fn sweep(b: &mut Bench, scene: &Scene, label: &str, files: &str) -> Result<()> {
    let (width, height) = b.scale.pick((128, 96), (320, 240));
    let (prisms, receiver) = (b.scale.prisms, b.scale.receiver);
    let at = |method, spp, seed, shadow_estimator, shadow_filter| RenderSettings {
        width,
        height,
        spp,
        seed,
        method,
        shadow_estimator,
        shadow_filter,
        prisms,
        receiver,
        ..RenderSettings::default()
    };
    let reference_slices = b.scale.pick(128, 2048);
    // Another seed than the measured renders, so the reference's noise is independent. Its
    // image is what counts (the same bytes every run), not its time: rendered once.
    let reference = b
        .measure_once(
            &format!("{label}reference, {reference_slices} slices"),
            scene,
            &at(
                Method::Reference {
                    slices: reference_slices,
                },
                1,
                1000,
                ShadowEstimator::Sampled,
                ShadowFilter::None,
            ),
        )
        .ok_or_else(|| bench_error("the reference could not be rendered"))?;
    let mut table = Table::new(
        ["method", "samples", "rmse", "frame_ms"]
            .map(String::from)
            .to_vec(),
    );
    let mut curves: Vec<(&str, Curve)> = Vec::new();
    let sweeps: [(&str, Vec<u32>); 5] = [
        (
            "temporal",
            b.scale.pick(vec![1, 4, 16], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "temporal analytic",
            b.scale.pick(vec![1, 4, 16], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "temporal analytic footprint",
            b.scale.pick(vec![1, 4, 16], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "tsm",
            b.scale.pick(vec![1, 4, 16], vec![1, 2, 4, 8, 16, 32, 64]),
        ),
        (
            "reference",
            b.scale
                .pick(vec![4, 16, 64], vec![4, 8, 16, 32, 64, 128, 256, 512]),
        ),
    ];
    for (name, samples) in sweeps {
        let mut curve = Vec::new();
        for n in samples {
            let (method, spp, estimator, filter) = match name {
                "temporal" => (Method::Temporal, n, Sampled, ShadowFilter::None),
                "temporal analytic" => (Method::Temporal, n, Analytic, ShadowFilter::None),
                "temporal analytic footprint" => {
                    (Method::Temporal, n, Analytic, ShadowFilter::Footprint)
                }
                "tsm" => (Method::Tsm, n, Sampled, ShadowFilter::None),
                _ => (
                    Method::Reference { slices: n },
                    1,
                    Sampled,
                    ShadowFilter::None,
                ),
            };
            let settings = at(method, spp, 1, estimator, filter);
            let Some(m) = b.measure(&format!("{label}{name} {n}"), scene, &settings) else {
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
    b.write_table(&format!("{files}{RESULTS}"), &table)?;
    let as_series = |(name, curve): &(&str, Curve)| {
        // Short: the legend gets at most half the plot's width.
        let label = match *name {
            "reference" => "brute force (slices)",
            "temporal" => "sampled (spp)",
            "temporal analytic" => "analytic (spp)",
            "temporal analytic footprint" => "analytic+footpr. (spp)",
            _ => "TSM (spp)",
        };
        series(label, curve.iter().map(|(t, e, _)| (*t, *e)).collect())
    };
    b.write_chart(
        &format!("{files}{RMSE_CHART}"),
        &LineChart {
            log_x: true,
            log_y: true,
            ..chart(
                &format!("{label}RMSE against the reference vs GPU time"),
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
        b.report.notes.push(format!(
            "{label}no temporal 16 spp measurement: no equal-quality ratio"
        ));
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
    b.report.ratios.push(ratio(
        format!("{label}equal-quality RMSE (temporal at 16 spp)"),
        goal,
    ));
    for (name, curve) in &curves[1..] {
        let t = time_to(curve);
        let what = format!("{label}equal-quality time {name} / temporal");
        if t.is_finite() {
            b.report.ratios.push(if *name == "reference" {
                target(what, t / t_temporal, 20.0, false)
            } else {
                ratio(what, t / t_temporal)
            });
        } else {
            b.report.notes.push(format!(
                "{label}{name} never reached RMSE {} in the sweep",
                fmt_num(goal)
            ));
        }
    }
    // The analytic estimators against brute force at the same goal (issue target: >= 20).
    let curve = |wanted: &str| {
        curves
            .iter()
            .find(|(name, _)| *name == wanted)
            .map(|(_, c)| time_to(c))
            .unwrap_or(f64::INFINITY)
    };
    let t_reference = curve("reference");
    for name in ["temporal analytic", "temporal analytic footprint"] {
        let t = curve(name);
        if t.is_finite() && t_reference.is_finite() {
            b.report.ratios.push(target(
                format!("{label}equal-quality time reference / {name}"),
                t_reference / t,
                20.0,
                false,
            ));
        }
    }
    Ok(())
}
