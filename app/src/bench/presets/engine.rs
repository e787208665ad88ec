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

use super::{Bench, RESULTS, bench_error, builtin_scene, chart, ratio, series, target};
use crate::chart::{LineChart, Table, fmt_num};
use crate::compare::{MaskError, Rgb8Image, mask_error, side_by_side};
use crate::error::Result;
use crate::raytrace::deferred::render_truth;
use crate::render::deferred::{DeferredMethod, DeferredResult, DeferredSettings};
use crate::render::{Method, RenderSettings};
use crate::scene::BuiltinOptions;

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
/// The TSM whose ghosts the picture shows.
const GHOSTING_MAPS: u32 = 8;

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

fn ghosting_picture(scene: &str) -> String {
    format!("{scene}-ghosting.png")
}

pub(super) fn engine(b: &mut Bench) -> Result<()> {
    let ((width, height), map, max_maps) = b
        .scale
        .pick(((480, 270), 512, 32), ((1920, 1080), 2048, 256));
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
        ]
        .map(String::from)
        .to_vec(),
    );
    let mut lines = Vec::new();
    for (name, ratio_target) in SCENES {
        let scene = builtin_scene(name, &BuiltinOptions::default())?;
        let settings = RenderSettings {
            width,
            height,
            shadow_size: Some((map, map)),
            ..b.settings(Method::Temporal, 1)
        };
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
        let measure = |b: &mut Bench, method: DeferredMethod| {
            (b.progress)(&format!("bench engine: {name}, {}", method.name()));
            let mut best: Option<DeferredResult> = None;
            for _ in 0..b.scale.runs {
                match b
                    .renderer
                    .render_deferred(&scene, &settings, &deferred(method), &mut |_| {})
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
                        b.report
                            .notes
                            .push(format!("{name} {}: {e}", method.name()));
                        return None;
                    }
                }
            }
            let r = best?;
            let error = mask_error(&r.lit, &truth.lit, &truth.facing);
            Some((r, error))
        };
        let Some((temporal, temporal_error)) = measure(b, DeferredMethod::Temporal) else {
            continue;
        };
        let mut rows = vec![("temporal", 0, temporal.shadow_and_mask_ms, temporal_error)];
        let mut tsm = Vec::new();
        let mut tsm_lits = Vec::new();
        let mut ghosting = None;
        let mut maps = 1;
        while maps <= max_maps {
            if let Some((r, error)) = measure(b, DeferredMethod::Tsm { maps }) {
                rows.push(("tsm", maps, r.shadow_and_mask_ms, error));
                tsm.push((maps, r.shadow_and_mask_ms, error));
                tsm_lits.push(r.lit.clone());
                if maps == GHOSTING_MAPS {
                    ghosting = Some(r);
                }
            }
            maps *= 2;
        }
        // The error in time alone: against the converged TSM (same maps, same spatial error).
        let converged = tsm_lits.last().cloned().unwrap_or_default();
        let in_time = |lit: &[f32]| mask_error(lit, &converged, &truth.facing).rmse;
        let temporal_in_time = in_time(&temporal.lit);
        let mut lits = std::iter::once(&temporal.lit).chain(&tsm_lits);
        for (method, maps, ms, error) in &rows {
            let lit = lits.next().expect("one mask per row");
            push_row(&mut table, name, method, *maps, *ms, error, in_time(lit))?;
        }
        let tsm_in_time: Vec<(u32, f64, f64)> = tsm
            .iter()
            .zip(&tsm_lits)
            .map(|((maps, ms, _), lit)| (*maps, *ms, in_time(lit)))
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
                ms / temporal.shadow_and_mask_ms,
            )),
            None => {
                if let Some((maps, ms, e)) = below_converged.last() {
                    b.report.notes.push(format!(
                        "{name}: in time alone (against the converged TSM), TSM-{maps} is still \
                         {} off where the temporal mask is {} off: the time-only ratio is \
                         above {}",
                        fmt_num(*e),
                        fmt_num(temporal_in_time),
                        fmt_num(ms / temporal.shadow_and_mask_ms)
                    ));
                }
            }
        }
        lines.push((
            name,
            temporal.shadow_and_mask_ms,
            temporal_error,
            tsm.clone(),
        ));

        b.report.ratios.push(target(
            format!("{name}: temporal mask RMSE vs the truth"),
            temporal_error.rmse,
            MASK_RMSE_TARGET,
            true,
        ));
        b.report.ratios.push(ratio(
            format!("{name}: temporal shadow pass + mask GPU ms"),
            temporal.shadow_and_mask_ms,
        ));
        let equal = tsm
            .iter()
            .find(|(_, _, e)| e.rmse <= temporal_error.rmse + EQUAL_RMSE_SLACK);
        match equal {
            Some((maps, ms, _)) => {
                let r = ms / temporal.shadow_and_mask_ms;
                b.report.ratios.push(target(
                    format!("{name}: equal-quality ratio (TSM-{maps} time / temporal time)"),
                    r,
                    ratio_target,
                    false,
                ));
            }
            None => {
                if let Some((maps, ms, e)) = tsm.last() {
                    b.report.notes.push(format!(
                        "{name}: no TSM up to {maps} maps reaches the temporal mask's RMSE \
                         ({} vs {}); the ratio is above {}",
                        fmt_num(e.rmse),
                        fmt_num(temporal_error.rmse),
                        fmt_num(ms / temporal.shadow_and_mask_ms)
                    ));
                }
            }
        }
        if let Some(tsm8) = ghosting {
            write_ghosting(b, name, &truth, &tsm8, &temporal)?;
        }
    }
    b.write_table(RESULTS, &table)?;
    for (name, temporal_ms, temporal_error, tsm) in lines {
        let points = tsm
            .iter()
            .map(|(_, ms, e)| (*ms, e.rmse.max(1e-6)))
            .collect();
        let c = chart(
            &format!("Deferred mask: RMSE vs GPU time, {name}, {width}x{height}"),
            "shadow pass + mask, GPU ms",
            "mask RMSE vs the truth",
            vec![
                series("TSM-N (N = 1, 2, 4, ...)", points),
                series(
                    "temporal",
                    vec![(temporal_ms, temporal_error.rmse.max(1e-6))],
                ),
            ],
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

fn deferred(method: DeferredMethod) -> DeferredSettings {
    DeferredSettings {
        method,
        ..DeferredSettings::default()
    }
}

fn push_row(
    table: &mut Table,
    scene: &str,
    method: &str,
    maps: u32,
    ms: f64,
    e: &MaskError,
    in_time: f64,
) -> Result<()> {
    table
        .push(vec![
            scene.to_owned(),
            method.to_owned(),
            maps.to_string(),
            fmt_num(ms),
            format!("{:.5}", e.rmse),
            format!("{:.5}", e.rmse_shadowed),
            e.pixels.to_string(),
            e.shadowed_pixels.to_string(),
            format!("{in_time:.5}"),
        ])
        .map_err(bench_error)
}

/// The masks of TSM-8, the temporal map and the truth side by side, cropped to the window
/// (a third of the image each way) where TSM-8 is farthest from the truth: its ghosts.
fn write_ghosting(
    b: &mut Bench,
    name: &str,
    truth: &DeferredResult,
    tsm: &DeferredResult,
    temporal: &DeferredResult,
) -> Result<()> {
    let (w, h) = (truth.image.width as usize, truth.image.height as usize);
    let (cw, ch) = (w / 3, h / 3);
    // The error summed over each window, by a summed-area table.
    let mut sat = vec![0.0f64; (w + 1) * (h + 1)];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let e = if truth.facing[i] {
                (f64::from(tsm.lit[i]) - f64::from(truth.lit[i])).abs()
            } else {
                0.0
            };
            sat[(y + 1) * (w + 1) + x + 1] =
                e + sat[y * (w + 1) + x + 1] + sat[(y + 1) * (w + 1) + x] - sat[y * (w + 1) + x];
        }
    }
    let window = |x: usize, y: usize| {
        sat[(y + ch) * (w + 1) + x + cw] - sat[y * (w + 1) + x + cw] - sat[(y + ch) * (w + 1) + x]
            + sat[y * (w + 1) + x]
    };
    let step = (cw / 8).max(1);
    let (mut best, mut at) = (-1.0, (0, 0));
    for y in (0..=h - ch).step_by(step) {
        for x in (0..=w - cw).step_by(step) {
            if window(x, y) > best {
                best = window(x, y);
                at = (x, y);
            }
        }
    }
    // Scaled up so that the crop reads at the chart's size.
    let zoom = (800 / (3 * cw)).max(1);
    let crop = |lit: &[f32]| {
        let mut img = Rgb8Image::new((cw * zoom) as u32, (ch * zoom) as u32);
        for y in 0..ch * zoom {
            for x in 0..cw * zoom {
                let v = lit[(at.1 + y / zoom) * w + at.0 + x / zoom];
                let g = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
                img.put(x as u32, y as u32, [g, g, g]);
            }
        }
        img
    };
    let panels = [
        (format!("TSM-{GHOSTING_MAPS}"), crop(&tsm.lit)),
        ("temporal".to_owned(), crop(&temporal.lit)),
        ("truth".to_owned(), crop(&truth.lit)),
    ];
    let refs: Vec<(&str, &Rgb8Image)> = panels.iter().map(|(l, i)| (l.as_str(), i)).collect();
    let picture = side_by_side(&refs, [32, 32, 32]);
    b.write_picture(
        &ghosting_picture(name),
        picture.width,
        picture.height,
        &picture.data,
    )
}
