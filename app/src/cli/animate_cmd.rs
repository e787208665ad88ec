//! `motion-shadows animate`: consecutive frames of an animated scene, each with its own
//! shutter interval, written as PNGs and one animated GIF at one exposure.

use std::fs::File;
use std::io::BufWriter;
use std::time::Duration;

use anyhow::Context as _;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use serde::Serialize;

use super::args::{AnimateArgs, FrameArg};
use super::deferred_cmd::deferred_settings;
use super::render_cmd::{device_for, render_frame};
use super::shared::{builtin_options, commit_outputs, progress_reporter, render_settings};
use crate::output::{RadianceImage, StagedFiles, auto_exposure, encode_srgb8, write_png};
use crate::render::Renderer;
use crate::render::deferred::DeferredSettings;
use crate::scene::AnimatedScene;
use crate::scene::Scene;

/// GIF colour quantisation speed (1 best, 30 fastest): 10 is the encoder's recommended
/// trade-off, seconds per frame faster than 1 at 1024x768.
const GIF_SPEED: i32 = 10;

/// The `--json` summary.
#[derive(Debug, Serialize)]
struct AnimateSummary {
    scene: String,
    /// `forward` or `deferred` (`--frame`).
    frame: &'static str,
    /// Forward: the method as `render` names it (`temporal-exact` with `--lookup exact`);
    /// deferred: `temporal`, `temporal-exact`, `tsm-N`, `plain` or `raytrace`.
    method: String,
    /// `depth` or `exact` (`--lookup`): how the temporal map is read; `none` for the methods
    /// without one.
    lookup: &'static str,
    frames: u32,
    fps: f32,
    /// `--start`; null: the scene's own time (a file's models: each its own `time`).
    start: Option<f64>,
    /// Seconds from frame 0's shutter opening to each frame's: i / fps.
    frame_offsets_s: Vec<f64>,
    width: u32,
    height: u32,
    spp: u32,
    exposure: f32,
    /// Sum of each frame's GPU pass times (CPU times for the ray tracer; deferred: the shadow
    /// pass and the mask).
    frame_gpu_ms: Vec<f64>,
    frame_wall_ms: Vec<f64>,
    files: Vec<String>,
    gif: String,
}

pub fn run(args: &AnimateArgs) -> anyhow::Result<()> {
    let render = &args.render;
    // Everything that can be checked before a frame is rendered is, as `render` does.
    let settings = render_settings(render);
    settings.validate()?;
    anyhow::ensure!(
        !render.heatmaps,
        "--heatmaps is not available with animate (one set per frame would be mostly noise)"
    );
    anyhow::ensure!(
        render.runs == 1,
        "--runs is not available with animate (it renders each frame once)"
    );
    super::render_cmd::refuse_unread_options(render, "animate")?;
    let deferred = match render.frame {
        FrameArg::Deferred => Some(deferred_settings(render)?),
        FrameArg::Forward => None,
    };
    let (bar, mut report) = progress_reporter();
    report("loading the scene");
    crate::scene::memory::set_renderer(settings.method == crate::render::Method::Raytrace);
    let animated = match &render.scene_file {
        Some(path) => AnimatedScene::file(path)?,
        None => AnimatedScene::builtin(&render.scene, &builtin_options(&render.random))?,
    };
    // f64, as `AnimatedScene::at` wants: see there.
    let offset = |i: u32| f64::from(i) / f64::from(args.fps);
    // Frame 0 checks the scene itself; the others differ from it only in the poses.
    let first = animated.at(args.start, 0.0)?;
    let name = first.name.clone();
    let pngs: Vec<String> = (0..args.frames)
        .map(|i| format!("{name}-frame-{i:04}.png"))
        .collect();
    let gif_name = format!("{name}.gif");
    let mut names = pngs.clone();
    names.push(gif_name.clone());
    let staged = StagedFiles::prepare(&render.out, &names)
        .with_context(|| format!("preparing the output directory {}", render.out.display()))?;

    let ctx = device_for(&settings, &mut report)?;
    let mut renderer = ctx.as_ref().map(Renderer::new).transpose()?;
    let gif_file = File::create(staged.temp_path(&gif_name)?)
        .with_context(|| format!("creating {gif_name}"))?;
    let mut gif = GifEncoder::new_with_speed(BufWriter::new(gif_file), GIF_SPEED);
    gif.set_repeat(Repeat::Infinite)?;
    // `parse_fps` keeps 1 / fps within what a GIF delay holds, so nothing saturates here.
    let delay = Delay::from_saturating_duration(Duration::from_secs_f64(1.0 / f64::from(args.fps)));

    let mut exposure = render.exposure;
    let (mut gpu_ms, mut wall_ms) = (Vec::new(), Vec::new());
    for (i, png) in (0..args.frames).zip(&pngs) {
        let scene = if i == 0 {
            first.clone()
        } else {
            animated.at(args.start, offset(i))?
        };
        let n = args.frames;
        let mut frame_report = |m: &str| {
            if m.starts_with("warning:") || m.starts_with("note:") {
                report(m)
            } else {
                report(&format!("frame {}/{n}: {m}", i + 1))
            }
        };
        let frame = animate_frame(
            renderer.as_mut(),
            &scene,
            &settings,
            deferred.as_ref(),
            &mut frame_report,
        )?;
        // One exposure for all frames (the first's unless given), so the animation does not
        // flicker as the automatic one follows each frame's highlights.
        let exposure = *exposure.get_or_insert_with(|| auto_exposure(&frame.image));
        write_png(staged.temp_path(png)?, &frame.image, exposure)?;
        gif.encode_frame(Frame::from_parts(rgba(&frame.image, exposure), 0, 0, delay))
            .with_context(|| format!("encoding frame {i} of {gif_name}"))?;
        gpu_ms.push(frame.gpu_ms);
        wall_ms.push(frame.wall_ms);
    }
    drop(renderer);
    drop(gif);

    let files = commit_outputs(staged, bar)?;
    let summary = AnimateSummary {
        scene: name,
        frame: if deferred.is_some() {
            "deferred"
        } else {
            "forward"
        },
        method: deferred
            .as_ref()
            .map_or_else(|| settings.method_name().to_owned(), |d| d.name()),
        lookup: match &deferred {
            Some(d) if d.method == crate::render::deferred::DeferredMethod::Temporal => {
                render.lookup.name()
            }
            Some(_) => "none",
            None => crate::render::stats::lookup_name(settings.method, settings.lookup),
        },
        frames: args.frames,
        fps: args.fps,
        start: args.start,
        frame_offsets_s: (0..args.frames).map(offset).collect(),
        width: settings.width,
        height: settings.height,
        spp: settings.spp,
        exposure: exposure.unwrap_or(0.0),
        frame_gpu_ms: gpu_ms,
        frame_wall_ms: wall_ms,
        gif: files.last().cloned().unwrap_or_default(),
        files,
    };
    if render.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        println!(
            "{} frames of {} ({}), {} x {} at {} spp: {:.2} ms GPU, {:.0} ms wall per frame",
            summary.frames,
            summary.scene,
            summary.method,
            summary.width,
            summary.height,
            summary.spp,
            mean(&summary.frame_gpu_ms),
            mean(&summary.frame_wall_ms)
        );
        for f in &summary.files {
            println!("wrote {f}");
        }
        println!("PNG exposure: {:+.2} stops", summary.exposure);
    }
    ctx.as_ref().map_or(Ok(()), super::validation_clean)
}

/// One rendered frame of the animation.
struct AnimatedFrame {
    image: RadianceImage,
    gpu_ms: f64,
    wall_ms: f64,
}

/// Frame `scene` as `--frame` says: the stochastic forward frame, or the engine's deferred
/// frame (on `renderer`, or without one the ray tracer's exact truth).
fn animate_frame(
    renderer: Option<&mut Renderer>,
    scene: &Scene,
    settings: &crate::render::RenderSettings,
    deferred: Option<&DeferredSettings>,
    report: &mut dyn FnMut(&str),
) -> anyhow::Result<AnimatedFrame> {
    let Some(deferred) = deferred else {
        let result = render_frame(renderer, scene, settings, report)?;
        return Ok(AnimatedFrame {
            image: result.image,
            gpu_ms: result.stats.frame_ms,
            wall_ms: result.stats.wall_ms,
        });
    };
    let result = crate::frame::render_deferred(renderer, scene, settings, deferred, report)?;
    Ok(AnimatedFrame {
        image: result.image,
        gpu_ms: result.shadow_and_mask_ms,
        wall_ms: result.wall_ms,
    })
}

/// The frame as the PNG shows it, with an opaque alpha channel for the GIF encoder.
fn rgba(image: &RadianceImage, exposure: f32) -> RgbaImage {
    let rgb = encode_srgb8(image, exposure);
    let data = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    RgbaImage::from_raw(image.width, image.height, data)
        .expect("encode_srgb8 gives 3 bytes per pixel")
}
