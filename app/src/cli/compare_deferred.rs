//! `motion-shadows compare --frame deferred`: the engine's frame of one scene with the truth,
//! the temporal mask, TSM-N and the plain map; a side-by-side PNG of the images and one of
//! the masks, and a table of each mask's RMSE against the truth (over the pixels the light
//! reaches, and over those in shadow) and its shadow pass + mask time.

use super::args::{CompareArgs, LookupArg};
use super::shared::{builtin_options, commit_outputs, progress_reporter};
use crate::compare::{Rgb8Image, mask_error, same_surface, side_by_side};
use crate::output::{StagedFiles, auto_exposure, write_rgb8_png};
use crate::raytrace::deferred::{check_truth_memory, render_truth};
use crate::render::deferred::{DeferredMethod, DeferredSettings};
use crate::render::upload::check_moving_light_deferred;
use crate::render::{RenderSettings, Renderer};
use crate::scene::{builtin, load_scene_file};
use anyhow::Context as _;
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::Lookup;

/// The frame's settings for `args` (the deferred frame reads its size, shadow size, receiver
/// test and static layer; the temporal map's options too).
pub fn render_settings(args: &CompareArgs) -> RenderSettings {
    RenderSettings {
        width: args.width,
        height: args.height,
        shadow_size: args.shadow_size,
        receiver: args.receiver.test(args.receiver_plane),
        static_layer: args.static_layer.settings().0,
        prisms: args.prisms.construction(),
        range_storage: args.range_storage.storage(),
        pruning: args.pruning.pruning(),
        ..RenderSettings::default()
    }
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let settings = render_settings(args);
    settings.validate()?;
    let methods = [
        DeferredMethod::Temporal,
        DeferredMethod::Tsm {
            maps: args.tsm_maps,
        },
        DeferredMethod::Plain,
    ];
    let deferred = |method| DeferredSettings {
        method,
        camera_time: args.camera_time,
        moving_receivers: true,
        lookup: Lookup::DepthLine,
    };
    // With --lookup exact, the temporal map's exact mask as one more method.
    let mut runs: Vec<DeferredSettings> = methods.iter().map(|&m| deferred(m)).collect();
    if args.lookup == LookupArg::Exact {
        runs.insert(
            1,
            DeferredSettings {
                lookup: Lookup::Exact,
                ..deferred(DeferredMethod::Temporal)
            },
        );
    }
    for run in &runs {
        run.validate()?;
    }
    // Before the scene is loaded: the truth's memory (it would abort past it).
    check_truth_memory(args.width, args.height)?;
    let (bar, mut report) = progress_reporter();
    // The exact truth is ray traced: sized for the ray tracer.
    crate::scene::memory::set_renderer(true);
    let scene = match (&args.scene_file, &args.scene) {
        (Some(path), _) => load_scene_file(path)?,
        (None, name) => builtin(
            name.as_deref()
                .unwrap_or(super::compare_cmd::preset_defaults(args.preset).0),
            &builtin_options(&args.random),
        )?,
    };
    // A method that does not take the scene's light motion (a turning light, say) is reported
    // as refused, with its reason, and the others are measured.
    let mut refused = Vec::new();
    runs.retain(|run| match check_moving_light_deferred(&scene, run) {
        Ok(()) => true,
        Err(e) => {
            refused.push((run.name(), e.to_string()));
            false
        }
    });
    if runs.is_empty() {
        anyhow::bail!("every method refuses the scene: {}", refused[0].1);
    }
    let stem = format!("{}-deferred-compare", scene.name);
    let names = [format!("{stem}.png"), format!("{stem}-masks.png")];
    let staged = StagedFiles::prepare(&args.out, &names)
        .with_context(|| format!("preparing the output directory {}", args.out.display()))?;

    report("the truth (CPU)");
    let truth = render_truth(
        &scene,
        &settings,
        &deferred(DeferredMethod::Raytrace),
        &mut report,
    )?;
    let ctx = Context::headless(&ContextOptions::from_env())?;
    let mut renderer = Renderer::new(&ctx)?;
    let mut results = Vec::new();
    for run in &runs {
        results.push(renderer.render_deferred(&scene, &settings, run, &mut report)?);
    }
    drop(renderer);

    report("writing images");
    let exposure = auto_exposure(&truth.image);
    let mask_image = |lit: &[f32]| {
        let mut img = Rgb8Image::new(args.width, args.height);
        for (i, &v) in lit.iter().enumerate() {
            let g = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            img.put(i as u32 % args.width, i as u32 / args.width, [g, g, g]);
        }
        img
    };
    let mut images = vec![(
        "truth".to_owned(),
        Rgb8Image::from_radiance(&truth.image, exposure)?,
        mask_image(&truth.lit),
    )];
    for r in &results {
        images.push((
            r.method.clone(),
            Rgb8Image::from_radiance(&r.image, exposure)?,
            mask_image(&r.lit),
        ));
    }
    for (k, name) in names.iter().enumerate() {
        let panels: Vec<(&str, &Rgb8Image)> = images
            .iter()
            .map(|(label, image, mask)| (label.as_str(), if k == 0 { image } else { mask }))
            .collect();
        let picture = side_by_side(&panels, [32, 32, 32]);
        write_rgb8_png(
            staged.temp_path(name)?,
            picture.width,
            picture.height,
            &picture.data,
        )?;
    }
    let files = commit_outputs(staged, bar)?;

    let mut rows: Vec<_> = results
        .iter()
        .map(|r| {
            let e = mask_error(&r.lit, &truth.lit, &truth.facing);
            let same = same_surface(&truth.facing, &r.triangle, &truth.triangle);
            let s = mask_error(&r.lit, &truth.lit, &same);
            serde_json::json!({
                "method": r.method,
                "rmse": e.rmse,
                "rmse_shadowed": e.rmse_shadowed,
                "pixels": e.pixels,
                "shadowed_pixels": e.shadowed_pixels,
                "rmse_same_surface": s.rmse,
                "pixels_same_surface": s.pixels,
                "shadow_and_mask_ms": r.shadow_and_mask_ms,
                "refused": null,
            })
        })
        .collect();
    rows.extend(refused.iter().map(|(method, reason)| {
        serde_json::json!({
            "method": method,
            "rmse": null,
            "rmse_shadowed": null,
            "pixels": null,
            "shadowed_pixels": null,
            "rmse_same_surface": null,
            "pixels_same_surface": null,
            "shadow_and_mask_ms": null,
            "refused": reason,
        })
    }));
    if args.json {
        let value = serde_json::json!({
            "scene": scene.name,
            "frame": "deferred",
            "camera_time": args.camera_time,
            "lookup": args.lookup.name(),
            "methods": rows,
            "truth_ms": truth.shadow_and_mask_ms,
            "files": files,
        });
        println!("{}", serde_json::to_string(&value)?);
    } else {
        println!(
            "deferred frame of {} ({}x{}, G-buffer at t = {}); mask RMSE against the exact \
             truth over the pixels the light reaches",
            scene.name, args.width, args.height, args.camera_time
        );
        println!(
            "  {:<14} {:>9} {:>16} {:>20} {:>22}",
            "method", "RMSE", "RMSE (shadowed)", "RMSE (same surface)", "shadow pass + mask ms"
        );
        for row in &rows {
            if let Some(reason) = row["refused"].as_str() {
                let method = row["method"].as_str().unwrap_or("");
                println!("  {method:<14} refused: {reason}");
                continue;
            }
            println!(
                "  {:<14} {:>9.5} {:>16.5} {:>20.5} {:>22.2}",
                row["method"].as_str().unwrap_or(""),
                row["rmse"].as_f64().unwrap_or(f64::NAN),
                row["rmse_shadowed"].as_f64().unwrap_or(f64::NAN),
                row["rmse_same_surface"].as_f64().unwrap_or(f64::NAN),
                row["shadow_and_mask_ms"].as_f64().unwrap_or(f64::NAN),
            );
        }
        for f in &files {
            println!("  wrote {f}");
        }
    }
    super::validation_clean(&ctx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::args::{Cli, Command};
    use clap::Parser as _;
    use motion_shadows::technique::{PrismConstruction, Pruning, RangeStorage};

    /// The temporal map's options reach the deferred comparison's temporal frame (they were
    /// dropped: it always built exact prisms, sorted ranges, the static-layer pruning).
    #[test]
    fn the_temporal_maps_options_reach_the_deferred_comparison() {
        let cli = Cli::try_parse_from([
            "motion-shadows",
            "compare",
            "--frame",
            "deferred",
            "--prisms",
            "paper",
            "--range-storage",
            "lists",
            "--pruning",
            "cover",
        ])
        .expect("parses");
        let Some(Command::Compare(args)) = cli.command else {
            panic!("compare parses to Command::Compare");
        };
        let settings = render_settings(&args);
        assert_eq!(settings.prisms, PrismConstruction::Paper);
        assert_eq!(settings.range_storage, RangeStorage::Lists);
        assert_eq!(settings.pruning, Pruning::Cover);
    }
}
