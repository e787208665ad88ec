//! `--method raytrace`: an exact reference that shares none of the shadow-map methods'
//! assumptions (no shadow map, no resolution, no normal offset or depth bias, no near plane
//! on the light's side), so that it can see the errors they all share.
//!
//! It takes the lighting pass's own samples (same pixel positions and times, from the
//! library's CPU mirror of the shaders' sampling, and the same camera rays) and traces, for
//! each, the camera ray and then a shadow ray against the triangles at that sample's time,
//! through a motion BVH ([`bvh`]) with a watertight ray/triangle test ([`intersect`]), and
//! shades it as the GPU's resolve pass does ([`shade`]). On the CPU, in parallel with rayon;
//! no Vulkan device is needed.
//!
//! What it does not copy from the GPU methods, on purpose: closed meshes are not back-face
//! culled (the nearest surface is the one seen, wherever the camera is), and the triangle test
//! is exact where Moller-Trumbore rounds (shared edges). Everything else that decides a pixel
//! (near and far planes of the camera, the nearest hit with ties to the lowest id, a static
//! triangle at t = 0 exactly, the shading) is the GPU's.

pub mod bvh;
pub mod deferred;
pub mod intersect;
pub mod pixels;
pub mod shade;
pub mod shutter;
pub mod triangles;

use crate::error::Result;
use crate::output::RadianceImage;
use crate::render::upload::{camera_view, moving_light_view};
use crate::render::{FrameStats, PassTime, RenderResult, RenderSettings};
use crate::scene::Scene;
use bvh::Bvh;
use motion_shadows::technique::{CameraParams, LightingView, ShadowEstimator};
use pixels::{CameraRays, trace_rows};
use shade::{Shading, ShadingLight};
use std::time::Instant;

/// Progress is reported about this many times per image (each band of rows is traced in
/// parallel, then reported).
const PROGRESS_STEPS: u32 = 16;

/// Renders `scene` with the lighting pass's samples for `settings` (size, spp, seed), traced.
/// The stats have no shadow map (its fields are 0) and two passes, "bvh build" and
/// "raytrace", whose times are CPU wall-clock milliseconds.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<RenderResult> {
    let start = Instant::now();
    settings.validate()?;
    scene.validate()?;
    let (width, height) = (settings.width, settings.height);

    progress(&format!(
        "raytrace: building the motion BVH over {} triangles",
        scene.triangle_count()
    ));
    let build_start = Instant::now();
    let bvh = Bvh::new(&triangles::scene_triangles(scene));
    let build_ms = build_start.elapsed().as_secs_f64() * 1e3;

    let view = LightingView {
        camera: camera_view(scene, (width, height)),
        seed: settings.seed,
        ambient: scene.ambient,
        estimator: settings.shadow_estimator,
        filter: Default::default(),
    };
    let params = CameraParams::new(&view, (width, height), settings.spp);
    let rays = CameraRays::over_shutter(&params, &scene.camera);
    let (lo, hi) = scene.bounds();
    let scale = f64::from((hi - lo).length().max(lo.abs().max(hi.abs()).max_element()));
    let ambient = f64::from(scene.ambient);
    let shading = Shading {
        bvh: &bvh,
        light: ShadingLight::new(&moving_light_view(scene, settings.shadow_size())?, scale),
        albedo: scene
            .meshes
            .iter()
            .map(|m| (m.albedo.as_dvec3(), ambient * m.albedo.as_dvec3()))
            .collect(),
    };

    let trace_start = Instant::now();
    let band = height.div_ceil(PROGRESS_STEPS).max(1);
    let w = width as usize;
    let mut rgb = vec![0.0f32; 3 * w * height as usize];
    let mut moving_coverage = vec![0.0f32; w * height as usize];
    let bands = rgb
        .chunks_mut(3 * w * band as usize)
        .zip(moving_coverage.chunks_mut(w * band as usize));
    for (i, (rgb, moving)) in bands.enumerate() {
        let first = i as u32 * band;
        progress(&format!(
            "raytrace: rows {first}..{} of {height} ({} spp, {} threads)",
            first + (moving.len() / w) as u32,
            settings.spp,
            rayon::current_num_threads()
        ));
        trace_rows(first, width, rgb, moving, &rays, &shading);
    }
    let trace_ms = trace_start.elapsed().as_secs_f64() * 1e3;

    let stats = FrameStats {
        scene: scene.name.clone(),
        method: "raytrace".to_owned(),
        shadow_estimator: match settings.shadow_estimator {
            ShadowEstimator::Sampled => "sampled",
            ShadowEstimator::Analytic => "analytic",
        }
        .to_owned(),
        shadow_filter: "none".to_owned(),
        prisms: crate::render::stats::prisms_name(settings.prisms).to_owned(),
        range_storage: "lists".to_owned(),
        pruning: "none".to_owned(),
        lookup: "none".to_owned(),
        receiver_plane: settings.receiver_plane(),
        width,
        height,
        shadow_width: 0,
        shadow_height: 0,
        spp: settings.spp,
        seed: settings.seed,
        triangles: bvh.triangles().len() as u32,
        fragments: 0,
        fragments_stored: 0,
        ranges: 0,
        ranges_without_coverage: 0,
        shadow_map_bytes_eq2: 0,
        shadow_map_bytes_transient: 0,
        ranges_pruned: 0,
        shadow_map_bytes_eq2_unpruned: 0,
        static_layer_bytes: 0,
        static_layer_kept: false,
        light_moves: scene.light.moves(),
        camera_moves: scene.camera.moves(),
        shadow_map_bytes_eq2_without_coverage: 0,
        coverage_map_bytes: 0,
        shadow_map_bytes_allocated: 0,
        longest_fragment_list: 0,
        shadow_pass_attempts: 1,
        ranges_at_most: None,
        samples_per_chunk: settings.spp,
        // The BVH stands in for the shadow side, the trace for the lighting (as `compare`
        // splits them).
        shadow_pass_ms: build_ms,
        lighting_pass_ms: trace_ms,
        frame_ms: build_ms + trace_ms,
        runs: 1,
        passes: vec![
            PassTime {
                pass: "bvh build".to_owned(),
                gpu_ms: build_ms,
            },
            PassTime {
                pass: "raytrace".to_owned(),
                gpu_ms: trace_ms,
            },
        ],
        warnings: Vec::new(),
        wall_ms: start.elapsed().as_secs_f64() * 1e3,
        device: format!("CPU ({} rayon threads)", rayon::current_num_threads()),
    };
    Ok(RenderResult {
        image: RadianceImage::new(width, height, rgb)?,
        moving_coverage,
        stats,
        shadow_map: None,
    })
}

#[cfg(test)]
mod tests;
