//! The engine's frame (`render --frame deferred`): a G-buffer at shutter close lit by each
//! pixel's lit share of the shutter, on game-level, walker-toward-light and
//! cubes-toward-light. The temporal mask (receivers moving) against engine TSM-N for N = 1,
//! 2, 4, ... (the static depth map kept on both sides, as the static layer is), each mask's
//! RMSE against the exact truth (the CPU's lit share of each pixel's moving point) and the GPU
//! time of the shadow pass plus the mask. The equal-quality ratio: the time of the smallest N
//! whose RMSE is at or below the temporal mask's (plus [`EQUAL_RMSE_SLACK`]), over the
//! temporal frame's time.
//!
//! Both methods look up hard-edged depth maps, so both share a spatial error at shadow edges
//! (a texel's worth of misplaced edge) that no number of maps removes: TSM-N converges to the
//! temporal mask's RMSE, not to 0 (the results table shows it). So the preset also measures
//! the error in time alone: each mask against the converged TSM (the most maps measured),
//! which shares the maps' spatial error, and the time-only equal-quality ratio from it.
//!
//! The exact mask (`Lookup::Exact`, method `temporal-exact`) has no such floor: it tests each
//! receiver's shadow ray against the triangles the map names. The preset measures it beside
//! the depth-line mask (RMSE, time, the temporal map's memory), runs TSM's ladder at the
//! preset's map and at finer ones (up to 4096x4096 at full scale), and gives the verdict
//! against it: the cheapest TSM (N, map) at or below the exact mask's RMSE
//! ([`super::engine_verdict`]), or TSM's best where none is.

use super::engine_ghosting::write_ghosting;
use super::engine_verdict::{TsmPoint, Verdict, row_label, verdict};
use super::{Bench, MIB, RESULTS, bench_error, builtin_scene, chart, ratio, series, target};
use crate::chart::{LineChart, Table, fmt_num};
use crate::compare::{MaskError, mask_error};
use crate::error::Result;
use crate::raytrace::deferred::render_truth;
use crate::render::deferred::{
    DeferredMethod, DeferredResult, DeferredSettings, deferred_tsm_bytes,
};
use crate::render::{Method, RenderSettings};
use crate::scene::BuiltinOptions;
use motion_shadows::technique::Lookup;

/// The scenes and their equal-quality targets (the issue's).
const SCENES: [(&str, f64); 3] = [
    ("game-level", 20.0),
    ("walker-toward-light", 10.0),
    ("cubes-toward-light", 4.0),
];
/// The temporal mask's RMSE target against the truth (at 2048x2048 maps).
const MASK_RMSE_TARGET: f64 = 0.005;
/// TSM-N matches the temporal mask's quality when its RMSE is within this of it: TSM converges
/// to the same spatial floor from above, and the last digits are noise of the edge pixels.
const EQUAL_RMSE_SLACK: f64 = 1e-4;
/// The target against the exact mask: TSM matches its RMSE only at this many times
/// its time, if at all.
const EXACT_RATIO_TARGET: f64 = 20.0;
/// The TSM whose ghosts the picture shows.
pub(super) const GHOSTING_MAPS: u32 = 8;

/// The files it writes (see `Preset::outputs`): the table, and per scene its chart and
/// the ghosting picture.
pub(super) fn outputs() -> Vec<String> {
    let per_scene = SCENES
        .iter()
        .flat_map(|(name, _)| [rmse_chart(name), ghosting_picture(name)]);
    std::iter::once(RESULTS.to_owned())
        .chain(per_scene)
        .collect()
}

fn rmse_chart(scene: &str) -> String {
    format!("{scene}-rmse-time.png")
}

pub(super) fn ghosting_picture(scene: &str) -> String {
    format!("{scene}-ghosting.png")
}

/// One measured mask: a row of the table.
struct Measured {
    method: &'static str,
    maps: u32,
    /// The side of the square shadow maps.
    map: u32,
    result: DeferredResult,
    error: MaskError,
}

pub(super) fn engine(b: &mut Bench) -> Result<()> {
    let ((width, height), map, max_maps, max_map) = b
        .scale
        .pick(((480, 270), 512, 32, 1024), ((1920, 1080), 2048, 256, 4096));
    // TSM's ladder: N = 1, 2, 4, ... at the preset's map, then at maps twice as fine, up to
    // the largest (4096x4096 at full scale), to show what TSM needs to approach the exact
    // mask, which has no texel-sized floor.
    let map_sizes: Vec<u32> = std::iter::successors(Some(map), |m| Some(m * 2))
        .take_while(|m| *m <= max_map)
        .collect();
    let mut table = Table::new(
        [
            "scene",
            "method",
            "maps",
            "shadow_and_mask_ms",
            "rmse",
            "rmse_shadowed",
            "pixels",
            "shadowed_pixels",
            "rmse_vs_converged_tsm",
            "map_size",
            "shadow_bytes",
            "tsm_vs_exact",
        ]
        .map(String::from)
        .to_vec(),
    );
    let mut charts = Vec::new();
    for (name, ratio_target) in SCENES {
        let scene = builtin_scene(name, &BuiltinOptions::default())?;
        let base = b.settings(Method::Temporal, 1);
        let at_map = |m: u32| RenderSettings {
            width,
            height,
            shadow_size: Some((m, m)),
            ..base.clone()
        };
        let settings = at_map(map);
        b.record_size(width, height);
        (b.progress)(&format!("bench engine: {name}, the truth (CPU)"));
        let truth = match render_truth(
            &scene,
            &settings,
            &deferred(DeferredMethod::Raytrace),
            &mut |_| {},
        ) {
            Ok(t) => t,
            Err(e) => {
                b.report.notes.push(format!("{name}: the truth: {e}"));
                continue;
            }
        };
        let measure = |b: &mut Bench, settings: &RenderSettings, method: DeferredSettings| {
            let what = format!("{} at {}", method.name(), map_name(settings));
            (b.progress)(&format!("bench engine: {name}, {what}"));
            let mut best: Option<DeferredResult> = None;
            for _ in 0..b.scale.runs {
                match b
                    .renderer
                    .render_deferred(&scene, settings, &method, &mut |_| {})
                {
                    Ok(r) => {
                        if best
                            .as_ref()
                            .is_none_or(|m| r.shadow_and_mask_ms < m.shadow_and_mask_ms)
                        {
                            best = Some(r);
                        }
                    }
                    Err(e) => {
                        b.report.notes.push(format!("{name} {what}: {e}"));
                        return None;
                    }
                }
            }
            let r = best?;
            let error = mask_error(&r.lit, &truth.lit, &truth.facing);
            Some((r, error))
        };
        // Each mask on its own: where one is refused (the loop limiter, memory: a note says
        // why), the others are still measured.
        let temporal = measure(b, &settings, deferred(DeferredMethod::Temporal));
        let exact = measure(b, &settings, exact_lookup());
        let mut rows = Vec::new();
        for (method, measured) in [("temporal", temporal), ("temporal-exact", exact)] {
            if let Some((result, error)) = measured {
                rows.push(Measured {
                    method,
                    maps: 0,
                    map,
                    result,
                    error,
                });
            }
        }
        for &m in &map_sizes {
            let mut maps = 1;
            while maps <= max_maps {
                if let Some(reason) = tsm_memory_refusal(m, maps) {
                    let note = format!("{name}: TSM-{maps} at {m}x{m} skipped: {reason}");
                    (b.progress)(&format!("bench engine: {note}"));
                    b.report.notes.push(note);
                } else if let Some((result, error)) =
                    measure(b, &at_map(m), deferred(DeferredMethod::Tsm { maps }))
                {
                    rows.push(Measured {
                        method: "tsm",
                        maps,
                        map: m,
                        result,
                        error,
                    });
                }
                maps *= 2;
            }
        }
        let exact_row = rows.iter().find(|r| r.method == "temporal-exact");
        let points: Vec<TsmPoint> = rows.iter().filter_map(tsm_point).collect();
        let against_exact = exact_row.map(|e| (e.error.rmse, verdict(&points, e.error.rmse)));
        // The error in time alone: against the converged TSM at the same map size (the most
        // maps measured there: same maps, same spatial error). Not for the exact mask, whose
        // spatial error is not the maps'.
        let converged = |m: u32| {
            rows.iter()
                .filter(|r| r.method == "tsm" && r.map == m)
                .max_by_key(|r| r.maps)
                .map(|r| &r.result.lit)
        };
        let in_time = |r: &Measured| -> Option<f64> {
            if r.method == "temporal-exact" {
                return None;
            }
            let lit = converged(r.map)?;
            Some(mask_error(&r.result.lit, lit, &truth.facing).rmse)
        };
        for row in &rows {
            let vs_exact = match (tsm_point(row), &against_exact) {
                (Some(p), Some((exact_rmse, v))) => row_label(&p, *exact_rmse, v),
                _ => "",
            };
            push_row(&mut table, name, row, in_time(row), vs_exact)?;
        }

        // The ratios against the depth-line temporal mask: TSM at the preset's map, as before
        // the ladder grew map sizes (both share that map's spatial floor).
        let tsm: Vec<&Measured> = rows
            .iter()
            .filter(|r| r.method == "tsm" && r.map == map)
            .collect();
        if let Some(temporal) = rows.iter().find(|r| r.method == "temporal") {
            report_depth_line(b, name, ratio_target, temporal, &tsm, &in_time);
            if let Some(tsm8) = tsm.iter().find(|r| r.maps == GHOSTING_MAPS) {
                write_ghosting(b, name, &truth, &tsm8.result, &temporal.result)?;
            }
        }
        if let (Some(exact), Some((_, v))) = (exact_row, &against_exact) {
            report_exact(b, name, exact, v, (max_maps, max_map));
        }
        charts.push((name, chart_series(&rows, &map_sizes)));
    }
    b.write_table(RESULTS, &table)?;
    for (name, series) in charts {
        let c = chart(
            &format!("Deferred mask: RMSE vs GPU time, {name}, {width}x{height}"),
            "shadow pass + mask, GPU ms",
            "mask RMSE vs the truth",
            series,
        );
        b.write_chart(
            &rmse_chart(name),
            &LineChart {
                log_x: true,
                log_y: true,
                ..c
            },
        )?;
    }
    Ok(())
}

/// The depth-line temporal mask's ratios (as before the exact mask): its RMSE and time, the
/// equal-quality ratio of TSM at the same map (`tsm`, N ascending) against it, and the same
/// in time alone (errors against the converged TSM, `in_time`).
fn report_depth_line(
    b: &mut Bench,
    name: &str,
    ratio_target: f64,
    temporal: &Measured,
    tsm: &[&Measured],
    in_time: &dyn Fn(&Measured) -> Option<f64>,
) {
    let temporal_ms = temporal.result.shadow_and_mask_ms;
    let temporal_in_time = in_time(temporal).unwrap_or(f64::NAN);
    let tsm_in_time: Vec<(u32, f64, f64)> = tsm
        .iter()
        .map(|r| {
            (
                r.maps,
                r.result.shadow_and_mask_ms,
                in_time(r).unwrap_or(f64::NAN),
            )
        })
        .collect();
    // The converged TSM itself (its error against itself is 0) is left out.
    let below_converged = &tsm_in_time[..tsm_in_time.len().saturating_sub(1)];
    match below_converged
        .iter()
        .find(|(_, _, e)| *e <= temporal_in_time + EQUAL_RMSE_SLACK)
    {
        Some((maps, ms, _)) => b.report.ratios.push(ratio(
            format!(
                "{name}: time-only equal-quality ratio (TSM-{maps} time / temporal time; \
                 errors against the converged TSM)"
            ),
            ms / temporal_ms,
        )),
        None => {
            if let Some((maps, ms, e)) = below_converged.last() {
                b.report.notes.push(format!(
                    "{name}: in time alone (against the converged TSM), TSM-{maps} is still \
                     {} off where the temporal mask is {} off: the time-only ratio is \
                     above {}",
                    fmt_num(*e),
                    fmt_num(temporal_in_time),
                    fmt_num(ms / temporal_ms)
                ));
            }
        }
    }
    b.report.ratios.push(target(
        format!("{name}: temporal mask RMSE vs the truth"),
        temporal.error.rmse,
        MASK_RMSE_TARGET,
        true,
    ));
    b.report.ratios.push(ratio(
        format!("{name}: temporal shadow pass + mask GPU ms"),
        temporal_ms,
    ));
    let equal = tsm
        .iter()
        .find(|r| r.error.rmse <= temporal.error.rmse + EQUAL_RMSE_SLACK);
    match equal {
        Some(r) => {
            b.report.ratios.push(target(
                format!(
                    "{name}: equal-quality ratio (TSM-{} time / temporal time)",
                    r.maps
                ),
                r.result.shadow_and_mask_ms / temporal_ms,
                ratio_target,
                false,
            ));
        }
        None => {
            if let Some(r) = tsm.last() {
                b.report.notes.push(format!(
                    "{name}: no TSM up to {} maps reaches the temporal mask's RMSE \
                     ({} vs {}); the ratio is above {}",
                    r.maps,
                    fmt_num(r.error.rmse),
                    fmt_num(temporal.error.rmse),
                    fmt_num(r.result.shadow_and_mask_ms / temporal_ms)
                ));
            }
        }
    }
}

/// A TSM row as the verdict reads it; `None` for the temporal masks.
fn tsm_point(r: &Measured) -> Option<TsmPoint> {
    (r.method == "tsm").then_some(TsmPoint {
        maps: r.maps,
        map: r.map,
        ms: r.result.shadow_and_mask_ms,
        rmse: r.error.rmse,
    })
}

/// The exact mask's figures and the verdict of TSM against it (the target: TSM's
/// best stays above the exact mask's RMSE, or matches it only at >= 20x its time).
fn report_exact(
    b: &mut Bench,
    name: &str,
    exact: &Measured,
    v: &Verdict,
    (max_maps, max_map): (u32, u32),
) {
    let exact_ms = exact.result.shadow_and_mask_ms;
    b.report.ratios.push(ratio(
        format!("{name}: exact mask RMSE vs the truth"),
        exact.error.rmse,
    ));
    b.report.ratios.push(ratio(
        format!("{name}: exact shadow pass + mask GPU ms"),
        exact_ms,
    ));
    b.report.ratios.push(ratio(
        format!("{name}: exact mask's temporal map MiB"),
        exact.result.shadow_bytes as f64 / MIB,
    ));
    match v {
        Verdict::Matches(p) => b.report.ratios.push(target(
            format!(
                "{name}: equal quality vs the exact mask (TSM-{} at {m}x{m} time / exact time)",
                p.maps,
                m = p.map
            ),
            p.ms / exact_ms,
            EXACT_RATIO_TARGET,
            false,
        )),
        Verdict::Above { best } => {
            let Some(best) = best else {
                return;
            };
            b.report.ratios.push(ratio(
                format!(
                    "{name}: TSM's best RMSE / the exact mask's (none matches up to \
                     N={max_maps}, {max_map}x{max_map}; best TSM-{} at {m}x{m})",
                    best.maps,
                    m = best.map
                ),
                best.rmse / exact.error.rmse,
            ));
            b.report.notes.push(format!(
                "{name}: equal quality vs the exact mask: none up to N={max_maps}, \
                 {max_map}x{max_map}: TSM's best RMSE is {} (TSM-{} at {m}x{m}, {} ms) where \
                 the exact mask's is {} ({} ms)",
                fmt_num(best.rmse),
                best.maps,
                fmt_num(best.ms),
                fmt_num(exact.error.rmse),
                fmt_num(exact_ms),
                m = best.map
            ));
        }
    }
}

/// Why TSM-`maps` at `map` x `map` cannot be drawn on this machine (its depth maps would not
/// fit in the memory the process can still use), or `None`.
fn tsm_memory_refusal(map: u32, maps: u32) -> Option<String> {
    crate::scene::memory::check_bytes(
        deferred_tsm_bytes((map, map), maps),
        &format!("TSM-{maps}'s depth maps at {map}x{map}"),
        "the static map and min(N, 8) working layers, 4 bytes a texel",
        "drawing them; the ladder goes on without this configuration",
    )
    .err()
}

/// The chart's series: TSM-N per map size, the temporal mask and the exact mask.
fn chart_series(rows: &[Measured], map_sizes: &[u32]) -> Vec<crate::chart::Series> {
    let point = |r: &Measured| (r.result.shadow_and_mask_ms, r.error.rmse.max(1e-6));
    let of = |method: &str| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.method == method)
            .map(point)
            .collect()
    };
    let mut all: Vec<_> = map_sizes
        .iter()
        .map(|&m| {
            let points = rows
                .iter()
                .filter(|r| r.method == "tsm" && r.map == m)
                .map(point)
                .collect();
            series(&format!("TSM-N, {m}x{m}"), points)
        })
        .collect();
    all.push(series("temporal", of("temporal")));
    all.push(series("exact", of("temporal-exact")));
    all
}

fn deferred(method: DeferredMethod) -> DeferredSettings {
    DeferredSettings {
        method,
        ..DeferredSettings::default()
    }
}

fn exact_lookup() -> DeferredSettings {
    DeferredSettings {
        lookup: Lookup::Exact,
        ..deferred(DeferredMethod::Temporal)
    }
}

fn map_name(settings: &RenderSettings) -> String {
    let (w, h) = settings.shadow_size();
    format!("{w}x{h}")
}

fn push_row(
    table: &mut Table,
    scene: &str,
    row: &Measured,
    in_time: Option<f64>,
    vs_exact: &str,
) -> Result<()> {
    let e = &row.error;
    table
        .push(vec![
            scene.to_owned(),
            row.method.to_owned(),
            row.maps.to_string(),
            fmt_num(row.result.shadow_and_mask_ms),
            format!("{:.7}", e.rmse),
            format!("{:.7}", e.rmse_shadowed),
            e.pixels.to_string(),
            e.shadowed_pixels.to_string(),
            in_time.map_or_else(String::new, |t| format!("{t:.7}")),
            format!("{m}x{m}", m = row.map),
            row.result.shadow_bytes.to_string(),
            vs_exact.to_owned(),
        ])
        .map_err(bench_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ladder step whose depth maps cannot fit (36 TiB: the static map and 8 working
    /// layers of 2^20 x 2^20 texels, 4 bytes each) is refused with a reason that names it,
    /// which the preset prints as a note; a small one is drawn.
    #[test]
    fn a_tsm_step_too_big_for_memory_is_refused_by_name() {
        let reason = tsm_memory_refusal(1 << 20, 256).expect("36 TiB of depth maps");
        assert!(
            reason.contains("TSM-256's depth maps at 1048576x1048576"),
            "{reason}"
        );
        assert_eq!(tsm_memory_refusal(64, 256), None);
    }
}
