//! `motion-shadows render --frame deferred`: scene -> G-buffer -> lit shares -> shaded image,
//! EXR + PNG of the image, a PNG of the lit shares (the mask), and a summary.

use super::args::{MethodArg, RenderArgs};
use super::shared::{commit_outputs, load_scene, progress_reporter, render_settings};
use crate::frame;
use crate::output::{StagedFiles, auto_exposure, write_exr, write_png, write_rgb8_png};
use crate::render::Renderer;
use crate::render::deferred::{DeferredMethod, DeferredSettings};
use anyhow::Context as _;
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::Lookup;

/// The deferred frame's settings for `args`.
pub fn deferred_settings(args: &RenderArgs) -> anyhow::Result<DeferredSettings> {
    let method = match args.method {
        MethodArg::Temporal => DeferredMethod::Temporal,
        MethodArg::Tsm => DeferredMethod::Tsm {
            maps: args.tsm_maps,
        },
        MethodArg::Plain => DeferredMethod::Plain,
        MethodArg::Raytrace => DeferredMethod::Raytrace,
        other => anyhow::bail!(
            "--frame deferred takes --method temporal, tsm, plain or raytrace, not {other:?}"
        ),
    };
    let settings = DeferredSettings {
        method,
        camera_time: args.camera_time,
        moving_receivers: !args.static_receivers,
        // Only the temporal map has the exact lookup; the others refuse `--lookup` by name
        // (unread_options.rs).
        lookup: if method == DeferredMethod::Temporal {
            args.lookup.lookup()
        } else {
            Lookup::DepthLine
        },
    };
    settings.validate()?;
    if method == DeferredMethod::Raytrace {
        // Before the scene is loaded: the truth's memory (it would abort past it).
        crate::raytrace::deferred::check_truth_memory(args.width, args.height)?;
    }
    Ok(settings)
}

/// The mask as an 8-bit grey image (lit share 1 = white).
pub fn mask_rgb8(lit: &[f32]) -> Vec<u8> {
    lit.iter()
        .flat_map(|&v| [(v.clamp(0.0, 1.0) * 255.0).round() as u8; 3])
        .collect()
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let settings = render_settings(args);
    settings.validate()?;
    let deferred = deferred_settings(args)?;
    let (bar, mut report) = progress_reporter();
    report("loading the scene");
    let scene = load_scene(args)?;
    let stem = format!("{}-deferred-{}", scene.name, deferred.name());
    let (exr, png, mask) = (
        format!("{stem}.exr"),
        format!("{stem}.png"),
        format!("{stem}-mask.png"),
    );
    let names = [exr.clone(), png.clone(), mask.clone()];
    let staged = StagedFiles::prepare(&args.out, &names)
        .with_context(|| format!("preparing the output directory {}", args.out.display()))?;

    let ctx = if deferred.method == DeferredMethod::Raytrace {
        None
    } else {
        report("creating the Vulkan device");
        Some(Context::headless(&ContextOptions::from_env())?)
    };
    // On the device, or without one the truth (which needs none); the fastest of --runs.
    let mut renderer = ctx.as_ref().map(Renderer::new).transpose()?;
    let mut result =
        frame::render_deferred(renderer.as_mut(), &scene, &settings, &deferred, &mut report)?;
    for run in 1..args.runs {
        report(&format!("run {} of {}", run + 1, args.runs));
        let again =
            frame::render_deferred(renderer.as_mut(), &scene, &settings, &deferred, &mut |_| {})?;
        if again.shadow_and_mask_ms < result.shadow_and_mask_ms {
            result = again;
        }
    }
    // Its resources are released before the validation layer's messages are counted.
    drop(renderer);

    report("writing images");
    let exposure = args
        .exposure
        .unwrap_or_else(|| auto_exposure(&result.image));
    write_exr(staged.temp_path(&exr)?, &result.image)?;
    write_png(staged.temp_path(&png)?, &result.image, exposure)?;
    write_rgb8_png(
        staged.temp_path(&mask)?,
        result.image.width,
        result.image.height,
        &mask_rgb8(&result.lit),
    )?;
    let files = commit_outputs(staged, bar)?;
    let (shadow_width, shadow_height) = settings.shadow_size();
    let passes: Vec<_> = result
        .passes
        .iter()
        .map(|p| serde_json::json!({"pass": p.pass, "gpu_ms": p.gpu_ms}))
        .collect();
    let value = serde_json::json!({
        "scene": scene.name,
        "frame": "deferred",
        "method": result.method,
        "width": settings.width,
        "height": settings.height,
        "shadow_width": shadow_width,
        "shadow_height": shadow_height,
        "camera_time": deferred.camera_time,
        "moving_receivers": deferred.moving_receivers,
        "lookup": args.lookup.name(),
        "passes": passes,
        "shadow_and_mask_ms": result.shadow_and_mask_ms,
        "wall_ms": result.wall_ms,
        "files": files,
        "exposure": exposure,
    });
    if args.json {
        println!("{}", serde_json::to_string(&value)?);
    } else {
        println!(
            "{} deferred frame of {} ({}x{}, shadow map {shadow_width}x{shadow_height}, \
             G-buffer at t = {}, receivers {})",
            result.method,
            scene.name,
            settings.width,
            settings.height,
            deferred.camera_time,
            if deferred.moving_receivers {
                "moving"
            } else {
                "standing still"
            }
        );
        for p in &result.passes {
            println!("  {:<12} {:>9.2} ms", p.pass, p.gpu_ms);
        }
        println!("  shadow pass + mask {:.2} ms", result.shadow_and_mask_ms);
        for f in &files {
            println!("  wrote {f}");
        }
        println!("PNG exposure: {exposure:+.2} stops");
    }
    ctx.as_ref().map_or(Ok(()), super::validation_clean)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::args::{Cli, Command};

    fn render_args(extra: &[&str]) -> RenderArgs {
        let cli = Cli::try_parse_recording_given(
            ["motion-shadows", "render", "--frame", "deferred"]
                .iter()
                .chain(extra),
        )
        .expect("parses");
        let Some(Command::Render(args)) = cli.command else {
            panic!("render parses to Command::Render");
        };
        args
    }

    /// `--lookup` reaches the deferred frame's settings (default the depth line); a method
    /// without the temporal map refuses it (render_cmd's tests).
    #[test]
    fn the_lookup_reaches_the_deferred_settings() {
        let depth = deferred_settings(&render_args(&[])).expect("settings");
        assert_eq!(depth.lookup, Lookup::DepthLine);
        let exact = deferred_settings(&render_args(&["--lookup", "exact"])).expect("settings");
        assert_eq!(exact.lookup, Lookup::Exact);
        assert_eq!(exact.name(), "temporal-exact");
    }
}
