//! `motion-shadows bench`: runs the presets and prints their ratios.

use super::args::BenchArgs;
use super::shared::progress_reporter;
use crate::bench::{PRESETS, Preset, Report, Scale, run_preset};
use crate::output::{StagedFiles, write_file_atomically};
use crate::render::Renderer;
use anyhow::Context as _;
use motion_shadows::gpu::{Context, ContextOptions};
use serde::Serialize;
use std::time::Instant;

const SUMMARY_FILE: &str = "bench-summary.json";

#[derive(Serialize)]
struct Summary<'a> {
    device: String,
    quick: bool,
    shadow_estimator: &'static str,
    prisms: &'static str,
    /// `--receiver`: auto, plane or offset.
    receiver: &'static str,
    /// `--shadow-filter`: none or bilinear.
    shadow_filter: &'static str,
    /// The default image size: presets that set their own say so (each report's
    /// `image_sizes`).
    width: u32,
    height: u32,
    wall_seconds: f64,
    reports: &'a [Report],
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let presets: Vec<Preset> = if args.presets.is_empty() {
        PRESETS.iter().copied().filter(|p| p.by_default()).collect()
    } else {
        args.presets
            .iter()
            .map(|name| {
                Preset::from_name(name).ok_or_else(|| {
                    let known: Vec<&str> = PRESETS.iter().map(|p| p.name()).collect();
                    anyhow::anyhow!("unknown preset {name:?}; known: {}", known.join(", "))
                })
            })
            .collect::<anyhow::Result<_>>()?
    };
    // The output directory and every file the presets will write are checked before the
    // device is made and hours are spent: the directory is created, a file can be made in
    // it, and no target is something an output may not replace (a directory, a link, ...;
    // the staging checks all three, naming the path). The presets declare their files in
    // the list their writers use, so none is missed.
    let mut names = vec![SUMMARY_FILE.to_owned()];
    for preset in &presets {
        for name in preset.outputs() {
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    StagedFiles::prepare(&args.out, &names)
        .with_context(|| format!("preparing the output directory {}", args.out.display()))?;
    let start = Instant::now();
    let (bar, mut report) = progress_reporter();
    let ctx = Context::headless(&ContextOptions::from_env())?;
    let device = format!("{} ({})", ctx.info().name, ctx.info().driver);
    let scale = Scale {
        shadow_estimator: args.shadow_estimator.estimator(),
        prisms: args.prisms.construction(),
        receiver: args.receiver.test(false),
        shadow_filter: args.shadow_filter.filter(),
        ..Scale::new(args.quick, args.out.clone())
    };
    let mut renderer = Renderer::new(&ctx)?;
    let mut reports = Vec::new();
    for preset in presets {
        reports.push(run_preset(&mut renderer, preset, &scale, &mut report)?);
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let summary = Summary {
        device,
        quick: args.quick,
        shadow_estimator: match args.shadow_estimator {
            super::args::EstimatorArg::Sampled => "sampled",
            super::args::EstimatorArg::Analytic => "analytic",
        },
        prisms: crate::render::stats::prisms_name(scale.prisms),
        receiver: scale.receiver.name(),
        shadow_filter: crate::render::stats::filter_name(scale.shadow_filter),
        width: scale.width,
        height: scale.height,
        wall_seconds: start.elapsed().as_secs_f64(),
        reports: &reports,
    };
    let json = serde_json::to_string_pretty(&summary)?;
    let summary_path = args.out.join(SUMMARY_FILE);
    write_file_atomically(&summary_path, json.as_bytes())?;
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        println!(
            "bench on {} (default size {}x{}{}), {:.0} s",
            summary.device,
            summary.width,
            summary.height,
            if args.quick { ", quick" } else { "" },
            summary.wall_seconds
        );
        for r in &reports {
            let sizes: Vec<String> = r
                .image_sizes
                .iter()
                .map(|[w, h]| format!("{w}x{h}"))
                .collect();
            println!("[{}] {}", r.preset, sizes.join(", "));
            for ratio in &r.ratios {
                let target = match (&ratio.target, ratio.met) {
                    (Some(t), Some(met)) => {
                        format!("  (target {t}: {})", if met { "met" } else { "MISSED" })
                    }
                    _ => String::new(),
                };
                println!("  {:<58} {:>10.3}{target}", ratio.name, ratio.value);
            }
            for note in &r.notes {
                println!("  note: {note}");
            }
            for f in &r.files {
                println!("  wrote {}", f.display());
            }
        }
        println!("wrote {}", summary_path.display());
    }
    super::validation_clean(&ctx)
}
