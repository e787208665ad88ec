//! `motion-shadows render`: scene -> renderer -> EXR + PNG -> summary.

use super::args::{MethodArg, RandomCubesArgs, RenderArgs};
use super::summary::summary_text;
use crate::output::{auto_exposure, write_exr, write_png};
use crate::render::{Method, RenderSettings, Renderer};
use crate::scene::{BuiltinOptions, Scene, builtin, load_scene_file};
use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use motion_shadows::gpu::{Context, ContextOptions};
use std::io::IsTerminal;
use std::time::Duration;

pub fn builtin_options(random: &RandomCubesArgs) -> BuiltinOptions {
    BuiltinOptions {
        cube_count: random.cubes,
        speed_min: random.speed_min,
        speed_max: random.speed_max,
        cube_size: random.cube_size,
        seed: random.scene_seed,
    }
}

pub fn load_scene(args: &RenderArgs) -> anyhow::Result<Scene> {
    Ok(match &args.scene_file {
        Some(path) => load_scene_file(path)?,
        None => builtin(&args.scene, &builtin_options(&args.random))?,
    })
}

/// Progress on stderr: a spinner on a terminal, plain lines otherwise (logs, CI).
pub fn progress_reporter() -> (Option<ProgressBar>, impl FnMut(&str)) {
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed}] {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(Duration::from_millis(120));
        bar
    });
    let handle = bar.clone();
    let report = move |msg: &str| match &handle {
        Some(bar) => bar.set_message(msg.to_owned()),
        None => eprintln!("{msg}"),
    };
    (bar, report)
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let (bar, mut report) = progress_reporter();
    report("loading the scene");
    let scene = load_scene(args)?;
    report("creating the Vulkan device");
    let ctx = Context::headless(&ContextOptions::from_env())?;
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp,
        seed: args.seed,
        shadow_size: args.shadow_size,
        method: match args.method {
            MethodArg::Temporal => Method::Temporal,
            MethodArg::Tsm => Method::Tsm,
            MethodArg::Coverage => Method::Coverage,
            MethodArg::Reference => Method::Reference {
                slices: args.slices,
            },
            MethodArg::Plain => Method::Plain { time: 0.5 },
        },
        ..RenderSettings::default()
    };
    let mut renderer = Renderer::new(&ctx)?;
    let result = renderer.render(&scene, &settings, &mut report)?;

    report("writing images");
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating output directory {}", args.out.display()))?;
    let stem = format!("{}-{}", scene.name, result.stats.method);
    let exr = args.out.join(format!("{stem}.exr"));
    let png = args.out.join(format!("{stem}.png"));
    let exposure = args
        .exposure
        .unwrap_or_else(|| auto_exposure(&result.image));
    write_exr(&exr, &result.image)?;
    write_png(&png, &result.image, exposure)?;
    let mut files = vec![exr.display().to_string(), png.display().to_string()];
    if args.heatmaps {
        report("writing heat maps");
        files.extend(write_heat_maps(&ctx, &result, &args.out, &stem)?);
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if args.json {
        let mut value = serde_json::to_value(&result.stats)?;
        value["files"] = serde_json::json!(files);
        value["exposure"] = serde_json::json!(exposure);
        println!("{}", serde_json::to_string(&value)?);
    } else {
        print!("{}", summary_text(&result.stats, &files));
        println!("PNG exposure: {exposure:+.2} stops");
    }
    super::validation_clean(&ctx)
}

/// Heat maps of the ranges stored per shadow-map pixel; for the coverage method also without
/// the coverage map, on the same scale so the two compare at a glance.
fn write_heat_maps(
    ctx: &Context,
    result: &crate::render::RenderResult,
    dir: &std::path::Path,
    stem: &str,
) -> anyhow::Result<Vec<String>> {
    let Some(map) = &result.shadow_map else {
        anyhow::bail!(
            "--heatmaps needs a method with depth-time ranges (temporal or coverage), not {}",
            result.stats.method
        );
    };
    let contents = map.download(ctx)?;
    let stored = contents.ranges_per_pixel();
    let mut maps = vec![(format!("{stem}-ranges.png"), stored)];
    if result.stats.method == "coverage" {
        let without = contents.ranges_without_coverage_per_pixel();
        maps.push((format!("{stem}-ranges-without-coverage.png"), without));
    }
    let max = maps
        .iter()
        .flat_map(|(_, v)| v.iter().copied())
        .max()
        .unwrap_or(0)
        .max(1) as f32;
    let mut files = Vec::new();
    for (name, counts) in maps {
        let values: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
        let heat = crate::compare::heat_map(&values, contents.width, contents.height, max)?;
        let path = dir.join(name);
        crate::output::write_rgb8_png(&path, heat.width, heat.height, &heat.data)?;
        files.push(path.display().to_string());
    }
    Ok(files)
}
