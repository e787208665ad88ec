//! The default frame, pass by pass: temporal, TSM and plain on the default scene at 1, 8 and
//! 16 spp, with the frame ratios against TSM. What a reader of the papers or an engine
//! developer looks at first; the README's frame table is this preset's.

use super::{Bench, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series, target};
use crate::bench::measure::Measurement;
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::{MAP_COPY_PASS, Method};
use crate::scene::BuiltinOptions;

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, TIME_CHART].map(String::from).to_vec()
}

// The plain map at mid-shutter, as the `plain` method renders by default.
const PLAIN: Method = Method::Plain { time: 0.5 };
const METHODS: [Method; 3] = [Method::Temporal, Method::Tsm, PLAIN];
const SPPS: [u32; 3] = [1, 8, 16];

pub(super) fn frame(b: &mut Bench) -> Result<()> {
    let scene = builtin_scene("cubes-toward-light", &BuiltinOptions::default())?;
    let mut table = Table::new(
        ["spp", "method", "pass", "gpu_ms"]
            .map(String::from)
            .to_vec(),
    );
    // (spp, method, measurement) of every frame that could be measured.
    let mut frames: Vec<(u32, Method, Measurement)> = Vec::new();
    for spp in SPPS {
        for method in METHODS {
            let what = format!("{} {spp} spp", method.name());
            let Some(m) = b.measure(&what, &scene, &b.settings(method, spp)) else {
                continue;
            };
            for pass in &m.stats.passes {
                // Our copy of an ordinary map out of its attachment is plumbing, not counted
                // in any frame figure (see the JSON's `passes`).
                if pass.pass != MAP_COPY_PASS {
                    table
                        .push(vec![
                            spp.to_string(),
                            method.name().to_owned(),
                            pass.pass.clone(),
                            fmt_num(pass.gpu_ms),
                        ])
                        .map_err(bench_error)?;
                }
            }
            table
                .push(vec![
                    spp.to_string(),
                    method.name().to_owned(),
                    "frame".to_owned(),
                    fmt_num(m.frame_ms()),
                ])
                .map_err(bench_error)?;
            frames.push((spp, method, m));
        }
    }
    b.write_table(RESULTS, &table)?;

    let frame_of = |spp: u32, method: Method| {
        frames
            .iter()
            .find(|(s, m, _)| *s == spp && *m == method)
            .map(|(_, _, m)| m.frame_ms())
    };
    let line = |method: Method| -> Vec<(f64, f64)> {
        SPPS.iter()
            .filter_map(|&spp| frame_of(spp, method).map(|ms| (spp as f64, ms)))
            .collect()
    };
    let time = chart(
        &format!(
            "Frame GPU time, cubes-toward-light, {}x{}",
            b.scale.width, b.scale.height
        ),
        "samples per pixel",
        "GPU ms",
        METHODS.iter().map(|&m| series(m.name(), line(m))).collect(),
    );
    b.write_chart(
        TIME_CHART,
        &LineChart {
            log_x: true,
            ..time
        },
    )?;

    for spp in SPPS {
        let (Some(temporal), Some(tsm)) =
            (frame_of(spp, Method::Temporal), frame_of(spp, Method::Tsm))
        else {
            continue;
        };
        let name = format!("temporal / TSM frame time at {spp} spp");
        let r = temporal / tsm;
        b.report.ratios.push(match spp {
            8 => target(name, r, 1.0, true),
            16 => target(name, r, 0.8, true),
            _ => ratio(name, r),
        });
        if let Some(plain) = frame_of(spp, PLAIN) {
            b.report.ratios.push(ratio(
                format!("temporal / plain frame time at {spp} spp"),
                temporal / plain,
            ));
        }
    }
    if let Some(ms) = frame_of(8, Method::Temporal) {
        b.report.ratios.push(ratio(
            format!(
                "temporal frame GPU ms at 8 spp, {}x{}",
                b.scale.width, b.scale.height
            ),
            ms,
        ));
    }
    Ok(())
}
