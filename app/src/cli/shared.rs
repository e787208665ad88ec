//! What the commands share: the scene they load, the renderer's settings from the render
//! options, progress on stderr, and the end of every run that writes files.

use super::args::{FrameArg, MethodArg, RandomCubesArgs, RenderArgs};
use crate::render::{Method, RenderSettings};
use crate::scene::{BuiltinOptions, Scene, builtin, load_scene_file};
use indicatif::{ProgressBar, ProgressStyle};
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
