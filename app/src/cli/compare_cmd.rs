//! `motion-shadows compare`: reference, temporal and TSM of one scene (and with
//! `--truth raytrace`, the ray tracer), judged against the truth over the whole image and over
//! the moving-object mask.

use super::args::{CompareArgs, LookupArg, Preset, TruthArg};
use super::shared::{builtin_options, commit_outputs, progress_reporter};
use crate::compare::{ErrorStats, Rgb8Image, error_image, error_stats, side_by_side};
use crate::output::{
    RadianceImage, StagedFiles, auto_exposure, write_exr, write_png, write_rgb8_png,
};
use crate::render::{FrameStats, Method, RenderSettings, Renderer};
use crate::scene::{builtin, load_scene_file};
use anyhow::Context as _;
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::{Lookup, ShadowFilter};
use serde::Serialize;

/// A pixel belongs to the moving-object mask when most of its truth's samples see a moving
/// triangle.
const MASK_COVERAGE: f32 = 0.5;

#[derive(Serialize)]
struct MethodRow {
    method: String,
    errors: Option<ErrorStats>,
    /// RMSE over the static receivers: the pixels outside the moving-object mask.
    rmse_static: Option<f64>,
    /// GPU time of the method's shadow passes and of its lighting, milliseconds.
    shadow_ms: f64,
    lighting_ms: f64,
    shadow_map_bytes: u64,
    stats: FrameStats,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    /// The method the errors are measured against: "reference" or "raytrace".
    truth: String,
    width: u32,
    height: u32,
    spp: u32,
    reference_slices: u32,
    /// `--lookup`: `exact` adds the temporal map read with the exact lookup
    /// (`temporal-exact`); `depth`, the papers' depth lines only.
    lookup: &'static str,
    moving_mask_pixels: usize,
    methods: Vec<MethodRow>,
    files: Vec<String>,
}

/// The scene and spp of `preset` (the deferred frame takes its scene: it has no spp).
pub(super) fn preset_defaults(preset: Option<Preset>) -> (&'static str, u32) {
    match preset {
        Some(Preset::Fig10) => ("walker-toward-light", 20),
        Some(Preset::Fig9) | None => ("cubes-toward-light", 8),
    }
}

/// (shadow, lighting) milliseconds. The ray tracer's BVH build counts as its shadow step (the
/// structure built before any sample is shaded, as a shadow map is) and its tracing as its
/// lighting; both are CPU times.
fn split_times(stats: &FrameStats) -> (f64, f64) {
    let lighting =
        |p: &str| p.starts_with("lighting") || p == "reference slices" || p == "raytrace";
    let sum = |keep: &dyn Fn(&str) -> bool| {
        stats
            .passes
            .iter()
            .filter(|p| p.counted() && keep(&p.pass))
            .fold(0.0, |total, p| total + p.gpu_ms)
    };
    (sum(&|p| !lighting(p)), sum(&lighting))
}

fn write_pair(
    staged: &StagedFiles,
    stem: &str,
    image: &RadianceImage,
    exposure: f32,
) -> anyhow::Result<()> {
    write_exr(staged.temp_path(&format!("{stem}.exr"))?, image)?;
    write_png(staged.temp_path(&format!("{stem}.png"))?, image, exposure)?;
    Ok(())
}

/// The methods a comparison renders, the truth first, each with its lookup; with `--lookup
/// exact`, the temporal map read with the exact lookup (`temporal-exact`) after the papers'.
fn methods(truth: TruthArg, slices: u32, lookup: LookupArg) -> Vec<(Method, Lookup)> {
    let reference = Method::Reference { slices };
    let mut methods = match truth {
        TruthArg::Reference => vec![reference, Method::Temporal, Method::Tsm],
        TruthArg::Raytrace => vec![Method::Raytrace, reference, Method::Temporal, Method::Tsm],
    }
    .into_iter()
    .map(|m| (m, Lookup::DepthLine))
    .collect::<Vec<_>>();
    if lookup == LookupArg::Exact {
        let temporal = methods.len() - 1;
        methods.insert(temporal, (Method::Temporal, Lookup::Exact));
    }
    methods
}

/// Every file a comparison of `scene` writes, in the order the report lists them (`methods`:
/// their names).
fn output_names(scene: &str, methods: &[&str]) -> Vec<String> {
    let mut names = vec![
        format!("{scene}-compare.png"),
        format!("{scene}-compare-error.png"),
    ];
    for (i, method) in methods.iter().enumerate() {
        names.push(format!("{scene}-{method}.exr"));
        names.push(format!("{scene}-{method}.png"));
        if i > 0 {
            names.push(format!("{scene}-{method}-error.png"));
        }
    }
    names
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    use super::unread_options::{COMPARE_OPTIONS, context, refuse_unread};
    refuse_unread(
        &args.given,
        COMPARE_OPTIONS,
        args.frame,
        None,
        &context("compare", args.frame, None),
    )?;
    if args.frame == super::args::FrameArg::Deferred {
        return super::compare_deferred::run(args);
    }
    let (preset_scene, preset_spp) = preset_defaults(args.preset);
    let spp = args.spp.unwrap_or(preset_spp);
    let settings = |(method, lookup)| RenderSettings {
        width: args.width,
        height: args.height,
        spp,
        seed: args.seed,
        shadow_size: args.shadow_size,
        method,
        shadow_estimator: args.shadow_estimator.estimator(),
        prisms: args.prisms.construction(),
        receiver: args.receiver.test(args.receiver_plane),
        // The brute-force reference stays the papers' (a filtered one would not converge to
        // the truth); the filter is for the methods being compared.
        shadow_filter: match method {
            Method::Reference { .. } => ShadowFilter::None,
            _ => args.shadow_filter.filter(),
        },
        static_layer: args.static_layer.settings().0,
        keep_static_layer: args.static_layer.settings().1,
        range_storage: args.range_storage.storage(),
        pruning: args.pruning.pruning(),
        lookup,
        ..RenderSettings::default()
    };
    let methods = methods(args.truth, args.slices, args.lookup);
    // Checked before anything is loaded or rendered.
    for &method in &methods {
        settings(method).validate()?;
    }
    let (bar, mut report) = progress_reporter();
    // Sized for the costlier renderer of the run: the ray tracer when it is the truth.
    crate::scene::memory::set_renderer(args.truth == super::args::TruthArg::Raytrace);
    let scene = match (&args.scene_file, &args.scene) {
        (Some(path), _) => load_scene_file(path)?,
        (None, name) => builtin(
            name.as_deref().unwrap_or(preset_scene),
            &builtin_options(&args.random),
        )?,
    };
    let names: Vec<&str> = methods.iter().map(|&m| settings(m).method_name()).collect();
    let staged = StagedFiles::prepare(&args.out, &output_names(&scene.name, &names))
        .with_context(|| format!("preparing the output directory {}", args.out.display()))?;
    let ctx = Context::headless(&ContextOptions::from_env())?;
    let mut renderer = Renderer::new(&ctx)?;

    let mut results = Vec::new();
    for &method in &methods {
        if let (Method::Reference { slices }, _) = method {
            report(&format!("reference ({slices} slices)"));
        }
        results.push(crate::frame::render(
            Some(&mut renderer),
            &scene,
            &settings(method),
            &mut report,
        )?);
    }
    let truth = &results[0];
    let mask: Vec<bool> = truth
        .moving_coverage
        .iter()
        .map(|&c| c > MASK_COVERAGE)
        .collect();
    let mask_pixels = mask.iter().filter(|&&m| m).count();

    report("writing images");
    let exposure = auto_exposure(&truth.image);
    let mut rows = Vec::new();
    let mut panels = Vec::new();
    let mut error_panels = Vec::new();
    // One scale for all error images, so they can be compared by eye: a tenth of the
    // truth's robust peak radiance.
    let max_error = (crate::compare::peak_radiance(&truth.image) * 0.1) as f32;
    for (i, result) in results.iter().enumerate() {
        let is_truth = i == 0;
        let method = result.stats.method.clone();
        let stem = format!("{}-{method}", scene.name);
        write_pair(&staged, &stem, &result.image, exposure)?;
        let label = match method.as_str() {
            "reference" => format!("reference M={}", args.slices),
            _ => {
                let estimator = if method.starts_with("temporal")
                    && result.stats.shadow_estimator == "analytic"
                {
                    " analytic"
                } else {
                    ""
                };
                let filter = match result.stats.shadow_filter.as_str() {
                    "none" => String::new(),
                    other => format!(" {other}"),
                };
                format!("{method}{estimator}{filter} {spp} spp")
            }
        };
        panels.push((
            label.clone(),
            Rgb8Image::from_radiance(&result.image, exposure)?,
        ));
        let errors = if is_truth {
            None
        } else {
            let heat = error_image(&result.image, &truth.image, max_error.max(1e-6))?;
            let path = staged.temp_path(&format!("{stem}-error.png"))?;
            write_rgb8_png(path, heat.width, heat.height, &heat.data)?;
            error_panels.push((format!("{method} error"), heat));
            let mask = (mask_pixels > 0).then_some(mask.as_slice());
            Some(error_stats(&result.image, &truth.image, mask)?)
        };
        let static_mask: Vec<bool> = mask.iter().map(|&m| !m).collect();
        let rmse_static = if is_truth || !static_mask.contains(&true) {
            None
        } else {
            error_stats(&result.image, &truth.image, Some(&static_mask))?.rmse_masked
        };
        let (shadow_ms, lighting_ms) = split_times(&result.stats);
        rows.push(MethodRow {
            method,
            errors,
            rmse_static,
            shadow_ms,
            lighting_ms,
            shadow_map_bytes: if result.stats.shadow_map_bytes_eq2 > 0 {
                result.stats.shadow_map_bytes_eq2 + result.stats.static_layer_bytes
            } else {
                result.stats.shadow_map_bytes_allocated
            },
            stats: result.stats.clone(),
        });
    }
    let refs: Vec<(&str, &Rgb8Image)> = panels.iter().map(|(l, i)| (l.as_str(), i)).collect();
    let side = side_by_side(&refs, [24, 24, 24]);
    let side_path = staged.temp_path(&format!("{}-compare.png", scene.name))?;
    write_rgb8_png(side_path, side.width, side.height, &side.data)?;
    let refs: Vec<(&str, &Rgb8Image)> = error_panels.iter().map(|(l, i)| (l.as_str(), i)).collect();
    let errors = side_by_side(&refs, [24, 24, 24]);
    let errors_path = staged.temp_path(&format!("{}-compare-error.png", scene.name))?;
    write_rgb8_png(errors_path, errors.width, errors.height, &errors.data)?;
    let files = commit_outputs(staged, bar)?;

    let report_data = Report {
        scene: scene.name.clone(),
        truth: names[0].to_owned(),
        width: args.width,
        height: args.height,
        spp,
        reference_slices: args.slices,
        lookup: args.lookup.name(),
        moving_mask_pixels: mask_pixels,
        methods: rows,
        files,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report_data)?);
    } else {
        print!("{}", table(&report_data));
    }
    super::validation_clean(&ctx)
}

fn table(r: &Report) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{}: {}x{}, {} spp, reference {} slices, errors against {}, moving-object mask {} pixels",
        r.scene, r.width, r.height, r.spp, r.reference_slices, r.truth, r.moving_mask_pixels
    );
    let _ = writeln!(
        s,
        "{:<14} {:>10} {:>9} {:>12} {:>12} {:>11} {:>11} {:>12} {:>12}",
        "method",
        "RMSE",
        "PSNR dB",
        "RMSE static",
        "RMSE mask",
        "PSNR mask",
        "shadow ms",
        "lighting ms",
        "shadow MiB"
    );
    for row in &r.methods {
        let (rmse, psnr, rmse_m, psnr_m) = match &row.errors {
            Some(e) => (
                format!("{:.5}", e.rmse),
                format!("{:.2}", e.psnr_db),
                e.rmse_masked.map_or("-".into(), |v| format!("{v:.5}")),
                e.psnr_masked_db.map_or("-".into(), |v| format!("{v:.2}")),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        let rmse_s = row.rmse_static.map_or("-".into(), |v| format!("{v:.5}"));
        let _ = writeln!(
            s,
            "{:<14} {:>10} {:>9} {:>12} {:>12} {:>11} {:>11.1} {:>12.1} {:>12.2}",
            row.method,
            rmse,
            psnr,
            rmse_s,
            rmse_m,
            psnr_m,
            row.shadow_ms,
            row.lighting_ms,
            row.shadow_map_bytes as f64 / (1024.0 * 1024.0)
        );
    }
    for f in &r.files {
        let _ = writeln!(s, "wrote {f}");
    }
    s
}
