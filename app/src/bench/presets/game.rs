//! `game-level` at a game's frame size: a static level of ~50k triangles with a tenth of
//! them moving. The temporal shadow pass against one depth-only shadow map of the same scene
//! (the floor any shadow pass is measured against), and the temporal frame against TSM's and
//! the plain map's, all at 8 spp.

use super::{
    Bench, MIB, Measurement, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series,
    target,
};
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::{Method, RenderSettings};
use crate::scene::BuiltinOptions;

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, TIME_CHART].map(String::from).to_vec()
}

const SPP: u32 = 8;
/// The plain map's scene is frozen at mid-shutter.
const PLAIN: Method = Method::Plain { time: 0.5 };

pub(super) fn game(b: &mut Bench) -> Result<()> {
    // Full: a 1080p frame with a 2048^2 map, as a game would render; quick: a sixteenth of
    // the pixels and a quarter of the map's texels.
    let ((width, height), map) = b.scale.pick(((480, 270), 1024), ((1920, 1080), 2048));
    let scene = builtin_scene("game-level", &BuiltinOptions::default())?;
    let mut table = Table::new(
        [
            "method",
            "shadow_ms",
            "lighting_ms",
            "frame_ms",
            "shadow_map_mib",
            "triangles",
        ]
        .map(String::from)
        .to_vec(),
    );
    // (chart position, method, shadow pass, frame) of each method measured.
    let mut measured = Vec::new();
    for (i, method) in [Method::Temporal, Method::Tsm, PLAIN]
        .into_iter()
        .enumerate()
    {
        let settings = RenderSettings {
            width,
            height,
            shadow_size: Some((map, map)),
            ..b.settings(method, SPP)
        };
        let what = format!("game-level {width}x{height}, {}", method.name());
        let Some(m) = b.measure(&what, &scene, &settings) else {
            continue;
        };
        push_row(&mut table, method.name(), &m)?;
        measured.push((i as f64 + 1.0, method, m.shadow_ms(), m.frame_ms()));
    }
    // An engine keeps the level's static layer from frame to frame (the light stays put).
    let kept_settings = RenderSettings {
        width,
        height,
        shadow_size: Some((map, map)),
        keep_static_layer: true,
        ..b.settings(Method::Temporal, SPP)
    };
    let kept = b.measure(
        &format!("game-level {width}x{height}, temporal, static layer kept"),
        &scene,
        &kept_settings,
    );
    if let Some(m) = &kept {
        push_row(&mut table, "temporal (static layer kept)", m)?;
    }
    // Plotted fourth; `of` below finds the redrawn temporal row first.
    let kept_point = kept
        .as_ref()
        .map(|m| (4.0, Method::Temporal, m.shadow_ms(), m.frame_ms()));
    let depth_only = b.depth_only_map_ms(&scene, (map, map));
    if let Some(floor) = depth_only {
        table
            .push(vec![
                "one depth-only map".to_owned(),
                fmt_num(floor),
                String::new(),
                String::new(),
                fmt_num((map as u64 * map as u64 * 4) as f64 / MIB),
                scene.triangle_count().to_string(),
            ])
            .map_err(bench_error)?;
    }
    let of = |wanted: Method| measured.iter().find(|(_, m, ..)| *m == wanted);
    if let (Some(t), Some(floor)) = (of(Method::Temporal), depth_only) {
        b.report.ratios.push(target(
            "shadow pass temporal / one depth-only map, game-level",
            t.2 / floor,
            3.0,
            true,
        ));
    }
    if let (Some(k), Some(floor)) = (&kept, depth_only) {
        b.report.ratios.push(target(
            "shadow pass temporal with the static layer kept / one depth-only map, game-level",
            k.shadow_ms() / floor,
            3.0,
            true,
        ));
    }
    if let (Some(t), Some(s)) = (of(Method::Temporal), of(Method::Tsm)) {
        b.report
            .ratios
            .push(ratio("frame temporal / TSM, game-level", t.3 / s.3));
        if let Some(k) = &kept {
            b.report.ratios.push(ratio(
                "frame temporal with the static layer kept / TSM, game-level",
                k.frame_ms() / s.3,
            ));
        }
    }
    b.write_table(RESULTS, &table)?;
    let plotted: Vec<_> = measured.iter().copied().chain(kept_point).collect();
    let points = |pick: fn(&(f64, Method, f64, f64)) -> f64| {
        plotted.iter().map(|m| (m.0, pick(m))).collect()
    };
    b.write_chart(
        TIME_CHART,
        &LineChart {
            log_y: true,
            ..chart(
                &format!(
                    "game-level {width}x{height}, {SPP} spp: 1 temporal, 2 TSM, 3 plain, 4 kept"
                ),
                "method",
                "GPU ms",
                vec![
                    series("shadow pass", points(|m| m.2)),
                    series("frame", points(|m| m.3)),
                ],
            )
        },
    )?;
    b.report.notes.push(format!(
        "game-level: {width}x{height} image, {map}x{map} shadow maps, {SPP} spp; plain is one \
         ordinary map (depth and id) of the scene at mid-shutter; the depth-only map is TSM's \
         map alone (one map, 1 spp)"
    ));
    Ok(())
}

/// One measured row of the results table.
fn push_row(table: &mut Table, method: &str, m: &Measurement) -> Result<()> {
    table
        .push(vec![
            method.to_owned(),
            fmt_num(m.shadow_ms()),
            fmt_num(m.lighting_ms()),
            fmt_num(m.frame_ms()),
            fmt_num(m.shadow_bytes() as f64 / MIB),
            m.stats.triangles.to_string(),
        ])
        .map_err(bench_error)
}
