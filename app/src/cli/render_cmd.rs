//! `motion-shadows render`: scene -> renderer -> EXR + PNG -> summary.

use super::args::{FrameArg, MethodArg, RandomCubesArgs, RenderArgs};
use super::summary::summary_text;
use crate::output::{StagedFiles, auto_exposure, write_exr, write_png};
use crate::render::{Method, RenderResult, RenderSettings, Renderer};
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
        frame_time: None,
        subdivide: random.subdivide,
    }
}

pub fn load_scene(args: &RenderArgs) -> anyhow::Result<Scene> {
    crate::scene::memory::set_renderer(args.method == MethodArg::Raytrace);
    Ok(match &args.scene_file {
        Some(path) => load_scene_file(path)?,
        None => builtin(&args.scene, &builtin_options(&args.random))?,
    })
}

/// Progress on stderr: a spinner on a terminal, plain lines otherwise (logs, CI).
/// Renames a run's staged files into place and clears the progress bar: the end of every
/// command that writes files. Returns the files' paths as the summaries print them.
pub fn commit_outputs(
    staged: crate::output::StagedFiles,
    bar: Option<ProgressBar>,
) -> anyhow::Result<Vec<String>> {
    let files = staged
        .commit()?
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    Ok(files)
}

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
    // Notes and warnings must stay on screen: printed above the spinner, not as its message.
    let report = move |msg: &str| match &handle {
        Some(bar) if msg.starts_with("warning:") || msg.starts_with("note:") => bar.println(msg),
        Some(bar) => bar.set_message(msg.to_owned()),
        None => eprintln!("{msg}"),
    };
    (bar, report)
}

/// The renderer's settings for `args` (checked by the caller before anything is loaded).
pub fn render_settings(args: &RenderArgs) -> RenderSettings {
    RenderSettings {
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
            MethodArg::Raytrace => Method::Raytrace,
        },
        shadow_estimator: args.shadow_estimator.estimator(),
        prisms: args.prisms.construction(),
        receiver: args.receiver.test(args.receiver_plane),
        shadow_filter: args.shadow_filter.filter(),
        static_layer: args.static_layer.settings().0,
        keep_static_layer: args.static_layer.settings().1,
        range_storage: args.range_storage.storage(),
        pruning: args.pruning.pruning(),
        // The deferred frame's lookup is its mask's (deferred_cmd.rs).
        lookup: match args.frame {
            FrameArg::Forward => args.lookup.lookup(),
            FrameArg::Deferred => motion_shadows::technique::Lookup::DepthLine,
        },
        ..RenderSettings::default()
    }
}

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
    // The exact lookup's map keeps no static layer and does not sort or prune its ranges.
    if args.frame == FrameArg::Forward && args.lookup == super::args::LookupArg::Exact {
        refuse_with_exact_lookup(&args.given)?;
    }
    Ok(())
}

/// Refuses the options the temporal map built for the exact lookup does not read.
fn refuse_with_exact_lookup(given: &[String]) -> anyhow::Result<()> {
    for flag in ["--static-layer", "--range-storage", "--pruning"] {
        if given.iter().any(|g| g == flag) {
            anyhow::bail!(
                "{flag} does not apply with --lookup exact: the exact lookup's map keeps every \
                 triangle in its lists, unsorted (no static layer, no sorting or pruning); \
                 leave it out"
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
