//! `motion-shadows render`: scene -> renderer -> EXR + PNG -> summary.

use super::args::{FrameArg, MethodArg, RenderArgs};
use super::shared::{commit_outputs, load_scene, progress_reporter, render_settings};
use super::summary::summary_text;
use crate::output::{StagedFiles, auto_exposure, write_exr, write_png};
use crate::render::{Method, RenderResult, RenderSettings, Renderer};
use crate::scene::Scene;
use anyhow::Context as _;
use motion_shadows::gpu::{Context, ContextOptions};

/// The Vulkan device `settings`' method renders on; none for the ray tracer, which needs
/// no device (nor a Vulkan installation).
pub fn device_for(
    settings: &RenderSettings,
    report: &mut dyn FnMut(&str),
) -> anyhow::Result<Option<Context>> {
    if settings.method == Method::Raytrace {
        return Ok(None);
    }
    report("creating the Vulkan device");
    Ok(Some(Context::headless(&ContextOptions::from_env())?))
}

/// One frame, on `renderer` (made on `device_for`'s device), or without one on the ray
/// tracer.
pub fn render_frame(
    renderer: Option<&mut Renderer>,
    scene: &Scene,
    settings: &RenderSettings,
    report: &mut dyn FnMut(&str),
) -> anyhow::Result<RenderResult> {
    Ok(crate::frame::render(renderer, scene, settings, report)?)
}

/// The heat maps `--heatmaps` writes for a frame of `method` named `stem`.
fn heat_map_names(method: MethodArg, stem: &str) -> Vec<String> {
    let mut names = vec![format!("{stem}-ranges.png")];
    if method == MethodArg::Coverage {
        names.push(format!("{stem}-ranges-without-coverage.png"));
    }
    names
}

/// Refuses the options that `args`' frame and method do not read (`unread_options.rs`),
/// once the deferred frame's settings are checked (a method it cannot take is named first).
pub fn refuse_unread_options(args: &RenderArgs, command: &str) -> anyhow::Result<()> {
    use super::unread_options::{RENDER_OPTIONS, context, refuse_unread};
    use clap::ValueEnum as _;
    let method = match args.frame {
        FrameArg::Forward => None,
        FrameArg::Deferred => {
            super::deferred_cmd::deferred_settings(args)?;
            Some(args.method)
        }
    };
    let name = args
        .method
        .to_possible_value()
        .map(|v| v.get_name().to_owned());
    let context = context(command, args.frame, name.as_deref());
    refuse_unread(&args.given, RENDER_OPTIONS, args.frame, method, &context)?;
    refuse_unread_forward_lookup(args, &context)
}

/// The forward frame reads `--lookup` with the temporal method only (its map); typed with
/// another method it is refused by name, as the deferred frame refuses it.
fn refuse_unread_forward_lookup(args: &RenderArgs, context: &str) -> anyhow::Result<()> {
    if args.frame == FrameArg::Forward
        && args.method != MethodArg::Temporal
        && args.given.iter().any(|g| g == "--lookup")
    {
        anyhow::bail!(
            "--lookup does not apply to {context}: it sets how the temporal map is read \
             (--method temporal); leave it out"
        );
    }
    // The exact lookup's map does not sort or prune its ranges.
    if args.frame == FrameArg::Forward && args.lookup == super::args::LookupArg::Exact {
        refuse_with_exact_lookup(&args.given)?;
    }
    Ok(())
}

/// Refuses the options the temporal map built for the exact lookup does not read.
fn refuse_with_exact_lookup(given: &[String]) -> anyhow::Result<()> {
    for flag in ["--range-storage", "--pruning"] {
        if given.iter().any(|g| g == flag) {
            anyhow::bail!(
                "{flag} does not apply with --lookup exact: the exact lookup's map keeps its \
                 ranges unsorted (no sorting, no pruning); leave it out"
            );
        }
    }
    Ok(())
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    refuse_unread_options(args, "render")?;
    if args.frame == FrameArg::Deferred {
        return super::deferred_cmd::run(args);
    }
    // Everything that can be checked without the scene or a device is checked first, so a
    // run never fails after minutes of rendering for a reason it could have told at once.
    let settings = render_settings(args);
    settings.validate()?;
    if args.heatmaps && !matches!(args.method, MethodArg::Temporal | MethodArg::Coverage) {
        anyhow::bail!(
            "--heatmaps needs a method with depth-time ranges (temporal or coverage), not {}",
            settings.method.name()
        );
    }
    let (bar, mut report) = progress_reporter();
    report("loading the scene");
    let scene = load_scene(args)?;
    let stem = format!("{}-{}", scene.name, settings.method_name());
    let (exr, png) = (format!("{stem}.exr"), format!("{stem}.png"));
    let mut names = vec![exr.clone(), png.clone()];
    if args.heatmaps {
        names.extend(heat_map_names(args.method, &stem));
    }
    let staged = StagedFiles::prepare(&args.out, &names)
        .with_context(|| format!("preparing the output directory {}", args.out.display()))?;

    let ctx = device_for(&settings, &mut report)?;
    let mut renderer = ctx.as_ref().map(Renderer::new).transpose()?;
    let mut result = render_frame(renderer.as_mut(), &scene, &settings, &mut report)?;
    for run in 1..args.runs {
        report(&format!("run {} of {}", run + 1, args.runs));
        let again = render_frame(renderer.as_mut(), &scene, &settings, &mut |_| {})?;
        if again.stats.frame_ms < result.stats.frame_ms {
            result = again;
        }
    }
    result.stats.runs = args.runs;
    // Its resources are released before the validation layer's messages are counted.
    drop(renderer);

    report("writing images");
    let exposure = args
        .exposure
        .unwrap_or_else(|| auto_exposure(&result.image));
    write_exr(staged.temp_path(&exr)?, &result.image)?;
    write_png(staged.temp_path(&png)?, &result.image, exposure)?;
    if let (true, Some(ctx)) = (args.heatmaps, &ctx) {
        report("writing heat maps");
        write_heat_maps(ctx, &result, &staged, &names[2..])?;
    }
    let files = commit_outputs(staged, bar)?;
    if args.json {
        let mut value = serde_json::to_value(&result.stats)?;
        value["files"] = serde_json::json!(files);
        value["exposure"] = serde_json::json!(exposure);
        println!("{}", serde_json::to_string(&value)?);
    } else {
        print!("{}", summary_text(&result.stats, &files));
        println!("PNG exposure: {exposure:+.2} stops");
    }
    ctx.as_ref().map_or(Ok(()), super::validation_clean)
}

/// Heat maps of the ranges stored per shadow-map pixel; for the coverage method also without
/// the coverage map, on the same scale so the two compare at a glance. `names`: from
/// [`heat_map_names`], staged in `staged`.
fn write_heat_maps(
    ctx: &Context,
    result: &RenderResult,
    staged: &StagedFiles,
    names: &[String],
) -> anyhow::Result<()> {
    let Some(map) = &result.shadow_map else {
        anyhow::bail!(
            "--heatmaps needs a method with depth-time ranges (temporal or coverage), not {}",
            result.stats.method
        );
    };
    let contents = map.download(ctx)?;
    let mut maps = vec![contents.ranges_per_pixel()];
    if result.stats.method == "coverage" {
        maps.push(contents.ranges_without_coverage_per_pixel());
    }
    anyhow::ensure!(
        maps.len() == names.len(),
        "{} heat maps for {} file names",
        maps.len(),
        names.len()
    );
    let max = maps
        .iter()
        .flat_map(|v| v.iter().copied())
        .max()
        .unwrap_or(0)
        .max(1) as f32;
    for (name, counts) in names.iter().zip(maps) {
        let values: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
        let heat = crate::compare::heat_map(&values, contents.width, contents.height, max)?;
        crate::output::write_rgb8_png(
            staged.temp_path(name)?,
            heat.width,
            heat.height,
            &heat.data,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::args::{Cli, Command};

    /// The deferred frame with a method that has no temporal map refuses `--lookup` by name.
    #[test]
    fn a_deferred_tsm_frame_refuses_the_lookup() {
        let cli = Cli::try_parse_recording_given([
            "motion-shadows",
            "render",
            "--frame",
            "deferred",
            "--method",
            "tsm",
            "--lookup",
            "exact",
        ])
        .expect("parses");
        let Some(Command::Render(tsm)) = cli.command else {
            panic!("render parses to Command::Render");
        };
        let refused = refuse_unread_options(&tsm, "render").expect_err("TSM has no exact lookup");
        assert!(refused.to_string().contains("--lookup"), "{refused}");
    }
}
