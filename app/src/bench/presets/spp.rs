//! 2018 paper Figs. 11-12: time per step and memory, temporal vs TSM, as spp grows.

use super::{
    Bench, MIB, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series, target,
};
use crate::bench::measure::Measurement;
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

const MEMORY_CHART: &str = "memory.png";

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, TIME_CHART, MEMORY_CHART]
        .map(String::from)
        .to_vec()
}

pub(super) fn spp(b: &mut Bench) -> Result<()> {
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
    b.write_table(RESULTS, &table)?;
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
        TIME_CHART,
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
        MEMORY_CHART,
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
