//! `motion-shadows view`: the deferred frame in a window; scripted with `--frames`, it
//! prints a summary (frame rate, per-pass GPU ms, allocations after the first frame) and
//! writes the last presented frame with `--screenshot`.

use super::args::{FrameArg, OnOff, ViewArgs, ViewMethodArg};
use super::shared::builtin_options;
use crate::output::write_rgb8_png;
use crate::render::deferred::{DeferredSettings, MAX_DEFERRED_TSM_MAPS};
use crate::render::{MAX_SPP, RenderSettings};
use crate::scene::{AnimatedScene, builtin, load_scene_file};
use crate::view::frame_loop::{FRAMES_IN_FLIGHT, FrameSettings};
use crate::view::method::ViewMethod;
use crate::view::{ViewOptions, ViewReport};
use anyhow::Context as _;

pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        shadow_size: args.shadow_size,
        spp: args.spp.clamp(1, MAX_SPP),
        shadow_estimator: args.shadow_estimator.estimator(),
        shadow_filter: args.shadow_filter.filter(),
        ..RenderSettings::default()
    };
    settings.validate()?;
    if args.method == ViewMethodArg::TemporalExact {
        // The exact lookup has no texels to filter: refused by name, as `render` does.
        RenderSettings {
            lookup: motion_shadows::technique::Lookup::Exact,
            ..settings.clone()
        }
        .validate()?;
    }
    if let Some((w, h)) = args.resize {
        RenderSettings {
            width: w,
            height: h,
            ..settings.clone()
        }
        .validate()
        .context("--resize")?;
    }
    let deferred = DeferredSettings {
        camera_time: args.camera_time,
        moving_receivers: !args.static_receivers,
        ..DeferredSettings::default()
    };
    deferred.validate().context("--camera-time")?;
    anyhow::ensure!(
        (1..=MAX_DEFERRED_TSM_MAPS).contains(&args.tsm_maps),
        "--tsm-maps {}: must be 1..={MAX_DEFERRED_TSM_MAPS}",
        args.tsm_maps
    );
    anyhow::ensure!(
        (1..=MAX_SPP).contains(&args.spp),
        "--spp {}: must be 1..={MAX_SPP}",
        args.spp
    );
    anyhow::ensure!(
        args.frame == FrameArg::Deferred
            || matches!(
                args.method,
                ViewMethodArg::Temporal | ViewMethodArg::TemporalExact
            ),
        "--frame forward: the viewer's stochastic frame is the temporal map's (--method \
         temporal or temporal-exact), not {}",
        method_name(args)
    );
    let method = view_method(args.method, args.tsm_maps);
    let split = args.split.map(|m| view_method(m, args.tsm_maps));
    if let Some(right) = split {
        anyhow::ensure!(
            right != method,
            "--split {}: the same method as --method (the split view compares two)",
            right.name()
        );
        anyhow::ensure!(
            args.frame == FrameArg::Deferred,
            "--split {}: the split view shows the deferred frame, not --frame forward",
            right.name()
        );
    }
    crate::scene::memory::set_renderer(false);
    let scene = match &args.scene_file {
        Some(path) => load_scene_file(path)?,
        None => builtin(&args.scene, &builtin_options(&args.random))?,
    };
    // A moving light or camera: the deferred frame takes both (the camera where it is at
    // the G-buffer's time, the mask with the light moving), as `render --frame deferred`
    // does, and refuses what it refuses; the stochastic frame takes neither.
    if args.frame == FrameArg::Forward {
        let viewer = "the viewer's stochastic frame (view --frame forward)";
        crate::render::upload::refuse_moving_light(&scene, viewer)?;
        crate::render::camera_motion::refuse_moving_camera(&scene, viewer)?;
    }
    // Every method the method key reaches (a turning light: the depth-line mask refuses a sun,
    // the exact mask one over moving geometry).
    let mut shown = method;
    loop {
        crate::render::upload::check_moving_light_deferred(&scene, &shown.deferred(&deferred))?;
        shown = shown.next(args.tsm_maps);
        if shown == method {
            break;
        }
    }
    // Only scenes with an animation can play (the others are refused by AnimatedScene with
    // the reason, which the overlay shows as "still scene").
    let animation = match &args.scene_file {
        Some(path) => AnimatedScene::file(path).ok(),
        None => AnimatedScene::builtin(&args.scene, &builtin_options(&args.random)).ok(),
    };
    let frame = FrameSettings {
        camera_time: deferred.camera_time,
        moving_receivers: deferred.moving_receivers,
        exposure: args.exposure,
        shadow_size: settings.shadow_size(),
    };
    let name = scene.name.clone();
    let report = crate::view::run(ViewOptions {
        scene,
        settings,
        deferred,
        frame,
        method,
        tsm_maps: args.tsm_maps,
        split,
        overlay: args.overlay == OnOff::On,
        stochastic: args.frame == FrameArg::Forward,
        spp: args.spp,
        animation,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        resize: args.resize,
        validation: std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1"),
    })?;
    anyhow::ensure!(
        report.validation_messages.is_empty(),
        "the Vulkan validation layer reported {} message(s):\n{}",
        report.validation_messages.len(),
        report.validation_messages.join("\n")
    );
    let mut files = Vec::new();
    if let Some(path) = &args.screenshot {
        let shot = report
            .screenshot
            .as_ref()
            .context("no frame was presented: no screenshot to write")?;
        write_rgb8_png(path, shot.size.0, shot.size.1, &shot.rgb)?;
        files.push(path.display().to_string());
    }
    print_summary(args, &name, &report, &files)
}

fn print_summary(
    args: &ViewArgs,
    scene: &str,
    report: &ViewReport,
    files: &[String],
) -> anyhow::Result<()> {
    let timed = report.stats.timed_frames.max(1) as f64;
    let passes: Vec<(String, f64)> = report
        .stats
        .pass_ms
        .iter()
        .filter(|(p, _)| p != "start")
        .map(|(p, ms)| (p.clone(), ms / timed))
        .collect();
    let allocations = report.allocations;
    if args.json {
        let value = serde_json::json!({
            "scene": scene,
            "method": method_name(&ViewArgs {
                frame: FrameArg::Deferred,
                split: None,
                ..args.clone()
            }),
            "frame": match args.frame {
                FrameArg::Deferred => "deferred",
                FrameArg::Forward => "forward",
            },
            "spp": args.spp,
            "split": args.split.map(|m| view_method(m, args.tsm_maps).name()),
            "device": report.device,
            "frames": report.frames,
            "frames_in_flight": FRAMES_IN_FLIGHT,
            "width": report.size.0,
            "height": report.size.1,
            "seconds_after_first_frame": report.seconds_after_first,
            "fps": report.fps(),
            "gpu_ms_per_frame": passes
                .iter()
                .map(|(p, ms)| serde_json::json!({"pass": p, "gpu_ms": ms}))
                .collect::<Vec<_>>(),
            "map_bytes": report.stats.map_bytes,
            "incomplete_frames": report.stats.incomplete_frames,
            "swapchains_made": report.stats.swapchains_made,
            "allocations": {
                "setup": allocations.setup,
                "after_first_frame": allocations.after_first_frame,
                "events": allocations.events,
            },
            "files": files,
        });
        println!("{}", serde_json::to_string(&value)?);
        return Ok(());
    }
    println!(
        "view of {scene} ({}) on {}: {} frames at {}x{}, {FRAMES_IN_FLIGHT} in flight, {:.2} \
         fps after the first",
        method_name(args),
        report.device,
        report.frames,
        report.size.0,
        report.size.1,
        report.fps()
    );
    for (pass, ms) in &passes {
        println!("  {pass:<18} {ms:>9.2} ms");
    }
    println!(
        "  maps {:.1} MiB; allocations: {} at setup, {} after the first frame, {} on events \
         (resize, screenshot); swapchains made {}",
        report.stats.map_bytes as f64 / (1 << 20) as f64,
        allocations.setup,
        allocations.after_first_frame,
        allocations.events,
        report.stats.swapchains_made
    );
    for f in files {
        println!("  wrote {f}");
    }
    Ok(())
}

fn view_method(arg: ViewMethodArg, tsm_maps: u32) -> ViewMethod {
    match arg {
        ViewMethodArg::Temporal => ViewMethod::Temporal,
        ViewMethodArg::TemporalExact => ViewMethod::TemporalExact,
        ViewMethodArg::Tsm => ViewMethod::Tsm { maps: tsm_maps },
        ViewMethodArg::Plain => ViewMethod::Tsm { maps: 1 },
    }
}

fn method_name(args: &ViewArgs) -> String {
    let method = match args.method {
        ViewMethodArg::Temporal => "temporal".to_owned(),
        ViewMethodArg::TemporalExact => "temporal-exact".to_owned(),
        ViewMethodArg::Tsm => format!("tsm-{}", args.tsm_maps),
        ViewMethodArg::Plain => "plain".to_owned(),
    };
    let method = match args.split {
        Some(right) => format!(
            "{method} | {} (split)",
            view_method(right, args.tsm_maps).name()
        ),
        None => method,
    };
    match args.frame {
        FrameArg::Deferred => method,
        FrameArg::Forward => format!("{method}, forward frame at {} spp", args.spp),
    }
}
