//! The truth for a deferred ("engine") frame: a G-buffer drawn at one camera time T and, per
//! pixel, the share of the shutter during which that G-buffer point sees the light.
//!
//! The G-buffer point is a fixed barycentric point of the triangle the pixel centre's camera
//! ray sees at T (nearest hit as [`Bvh::closest`] finds it, no back-face culling), so it
//! moves linearly with that triangle's corners (or, with standing receivers, stays where it is
//! at T all shutter); its lit fraction is exact
//! ([`shutter::lit_fraction`]), not sampled. Shading is `shade.rs`'s at time T, the direct
//! term weighted by that fraction instead of one shadow ray's answer.

use super::bvh::Bvh;
use super::intersect::Ray;
use super::pixels::CameraRays;
use super::shade::{Shading, ShadingLight, facing_normal};
use super::shutter;
use super::triangles::scene_triangles;
use crate::error::{Error, Result};
use crate::output::RadianceImage;
use crate::render::MAX_IMAGE_SIDE;
use crate::render::deferred::{DeferredResult, DeferredSettings, direct_factor};
use crate::render::upload::{camera_view_of, light_at, moving_light_view};
use crate::render::{PassTime, RenderSettings};
use crate::scene::Scene;
use glam::{DVec3, Vec2};
use motion_shadows::technique::{CameraParams, LightingView};
use rayon::prelude::*;
use std::time::Instant;

/// Progress is reported about this many times per image.
const PROGRESS_STEPS: u32 = 16;

/// The truth's G-buffer and lit fraction, row-major from the top-left pixel. Pixels whose
/// camera ray meets nothing (between the camera's near and far planes) have `hit` false,
/// `lit` 1, and zeros elsewhere.
#[derive(Debug, Clone, PartialEq)]
pub struct DeferredTruth {
    pub width: u32,
    pub height: u32,
    /// Share of the shutter [0, 1] during which the pixel's point sees the light, whatever
    /// its orientation (a point facing away from the light still gets its visibility).
    pub lit: Vec<f32>,
    pub hit: Vec<bool>,
    /// The camera ray's hit point at time T.
    pub position: Vec<[f32; 3]>,
    /// The triangle the camera ray hits (its global id, as the G-buffer's id image holds
    /// it); `u32::MAX` where it hits nothing.
    pub triangle: Vec<u32>,
    /// The unit normal at time T, turned toward the camera.
    pub normal: Vec<[f32; 3]>,
    pub albedo: Vec<[f32; 3]>,
    /// Radiance, 3 values per pixel: ambient plus the direct term times `lit`.
    pub rgb: Vec<f32>,
}

#[derive(Debug, Clone, Copy, Default)]
struct Pixel {
    lit: f32,
    hit: bool,
    position: [f32; 3],
    triangle: u32,
    normal: [f32; 3],
    albedo: [f32; 3],
    rgb: [f32; 3],
}

/// Host bytes a pixel of the deferred truth takes at its peak: the truth's per-pixel vectors
/// (lit share, hit, position, normal, albedo, radiance: 53 B), a band of rows being traced,
/// the facing flags, and the images written from it. Measured peak (render, 2026-12-07):
/// 57-59 bytes a pixel at 1024x1024 and 2048x2048; the figure keeps a margin.
pub const TRUTH_BYTES_PER_PIXEL: u64 = 80;

/// Ok when the deferred truth of a `width` x `height` image fits in what this process can
/// still use; otherwise refused with the figures (it would abort mid-allocation, where no
/// error handler sees it).
pub fn check_truth_memory(width: u32, height: u32) -> Result<()> {
    let pixels = u64::from(width) * u64::from(height);
    crate::scene::memory::check_bytes(
        pixels.saturating_mul(TRUTH_BYTES_PER_PIXEL),
        &format!("the deferred truth at {width}x{height}"),
        &format!("{TRUTH_BYTES_PER_PIXEL} bytes a pixel"),
        "tracing, use a smaller --width/--height",
    )
    .map_err(Error::Memory)
}

/// The deferred truth of `scene` at `width` x `height`, G-buffer at `camera_time` in [0, 1],
/// receivers moving with their triangles ([`deferred_truth_with`]).
pub fn deferred_truth(
    scene: &Scene,
    width: u32,
    height: u32,
    camera_time: f32,
    shadow_size: (u32, u32),
    progress: &mut dyn FnMut(&str),
) -> Result<DeferredTruth> {
    deferred_truth_with(
        scene,
        width,
        height,
        camera_time,
        shadow_size,
        true,
        progress,
    )
}

/// The deferred truth of `scene` at `width` x `height`, G-buffer at `camera_time` in [0, 1].
/// `shadow_size` only sizes the light's view, whose shading numbers (direction, cone,
/// emission) are the GPU's. `moving_receivers` off: each pixel's point stands still where the
/// G-buffer shows it for the whole shutter (what the mask with standing receivers computes).
pub fn deferred_truth_with(
    scene: &Scene,
    width: u32,
    height: u32,
    camera_time: f32,
    shadow_size: (u32, u32),
    moving_receivers: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<DeferredTruth> {
    let side_ok = |v: u32| (1..=MAX_IMAGE_SIDE).contains(&v);
    if ![width, height, shadow_size.0, shadow_size.1]
        .into_iter()
        .all(side_ok)
    {
        return Err(Error::InvalidArgument(format!(
            "deferred truth: image {width}x{height}, shadow map {}x{}: each side must be \
             1..={MAX_IMAGE_SIDE}",
            shadow_size.0, shadow_size.1
        )));
    }
    if !(0.0..=1.0).contains(&camera_time) {
        return Err(Error::InvalidArgument(format!(
            "deferred truth: camera time {camera_time} must be in [0, 1]"
        )));
    }
    scene.validate()?;
    check_truth_memory(width, height)?;

    progress(&format!(
        "deferred truth: building the motion BVH over {} triangles",
        scene.triangle_count()
    ));
    let bvh = Bvh::new(&scene_triangles(scene));
    // The same view, scale and albedos as the per-sample tracer (`raytrace::render`).
    let view = LightingView {
        // The camera where it is at the camera time, as the G-buffer's.
        camera: camera_view_of(&scene.camera.at(camera_time), (width, height)),
        seed: 0,
        ambient: scene.ambient,
        estimator: Default::default(),
        filter: Default::default(),
    };
    let params = CameraParams::new(&view, (width, height), 1);
    let rays = CameraRays::new(&params);
    let (near, far) = (f64::from(params.position.w), f64::from(params.forward.w));
    let (lo, hi) = scene.bounds();
    let scale = f64::from((hi - lo).length().max(lo.abs().max(hi.abs()).max_element()));
    let ambient = f64::from(scene.ambient);
    let shading = Shading {
        bvh: &bvh,
        light: ShadingLight::new(&moving_light_view(scene, shadow_size)?, scale),
        albedo: scene
            .meshes
            .iter()
            .map(|m| (m.albedo.as_dvec3(), ambient * m.albedo.as_dvec3()))
            .collect(),
    };
    let t = f64::from(camera_time);

    let n = width as usize * height as usize;
    let mut out = DeferredTruth {
        width,
        height,
        lit: Vec::with_capacity(n),
        hit: Vec::with_capacity(n),
        position: Vec::with_capacity(n),
        triangle: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        albedo: Vec::with_capacity(n),
        rgb: Vec::with_capacity(3 * n),
    };
    let band = height.div_ceil(PROGRESS_STEPS).max(1);
    for first in (0..height).step_by(band as usize) {
        let end = (first + band).min(height);
        progress(&format!(
            "deferred truth: rows {first}..{end} of {height} ({} threads)",
            rayon::current_num_threads()
        ));
        let rows: Vec<Vec<Pixel>> = (first..end)
            .into_par_iter()
            .map(|y| {
                (0..width)
                    .map(|x| {
                        let ray = rays.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                        pixel(&ray, t, (near, far), &shading, moving_receivers)
                    })
                    .collect()
            })
            .collect();
        for p in rows.into_iter().flatten() {
            out.lit.push(p.lit);
            out.hit.push(p.hit);
            out.position.push(p.position);
            out.triangle.push(p.triangle);
            out.normal.push(p.normal);
            out.albedo.push(p.albedo);
            out.rgb.extend_from_slice(&p.rgb);
        }
    }
    Ok(out)
}

/// One pixel centre's camera ray at time `t`; its point moves with its triangle over the
/// shutter, or with `moving` off stands where it is at `t`.
fn pixel(ray: &Ray, t: f64, (near, far): (f64, f64), shading: &Shading, moving: bool) -> Pixel {
    let Some(hit) = shading.bvh.closest(ray, t, near, far) else {
        return Pixel {
            lit: 1.0,
            triangle: u32::MAX,
            ..Pixel::default()
        };
    };
    let tri = &shading.bvh.triangles()[hit.index as usize];
    let p = ray.origin + hit.s * ray.dir;
    let w = barycentrics(ray, &tri.at(t));
    let at = |time: f64| {
        let v = tri.at(time);
        w[0] * v[0] + w[1] * v[1] + w[2] * v[2]
    };
    let (from, to) = if moving {
        (at(0.0), at(1.0))
    } else {
        (at(t), at(t))
    };
    let lit = shutter::lit_fraction(shading.bvh, &shading.light, from, to, tri.id);
    let (direct, ambient) = shading.unshadowed(p, ray.dir, tri, t);
    let rgb = direct.map_or(ambient, |d| d * lit + ambient);
    Pixel {
        lit: lit as f32,
        hit: true,
        position: p.as_vec3().to_array(),
        triangle: tri.id,
        normal: facing_normal(tri, t, ray.dir).as_vec3().to_array(),
        albedo: shading.albedo[tri.mesh as usize].0.as_vec3().to_array(),
        rgb: rgb.as_vec3().to_array(),
    }
}

/// The barycentric weights of the point where `ray` crosses triangle `v`: each corner's
/// weight is the edge function of the opposite edge (the ray's projection along itself, as
/// the watertight test computes them), normalised. Rounding can leave a weight slightly
/// negative at an edge; it is clamped, so the point stays on the triangle.
fn barycentrics(ray: &Ray, v: &[DVec3; 3]) -> [f64; 3] {
    let [a, b, c] = v.map(|p| p - ray.origin);
    let d = ray.dir;
    let e = [b.dot(c.cross(d)), c.dot(a.cross(d)), a.dot(b.cross(d))];
    let sum = e[0] + e[1] + e[2];
    if sum == 0.0 {
        return [1.0 / 3.0; 3];
    }
    let e = e.map(|x| (x / sum).max(0.0));
    let total = e[0] + e[1] + e[2];
    e.map(|x| x / total)
}

/// The deferred frame of [`crate::render::deferred::DeferredMethod::Raytrace`]: the truth, on the CPU (no device), as
/// a [`DeferredResult`] like the device's methods give.
pub fn render_truth(
    scene: &Scene,
    settings: &RenderSettings,
    deferred: &DeferredSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<DeferredResult> {
    let start = Instant::now();
    settings.validate()?;
    deferred.validate()?;
    scene.validate()?;
    let truth = deferred_truth_with(
        scene,
        settings.width,
        settings.height,
        deferred.camera_time,
        settings.shadow_size(),
        deferred.moving_receivers,
        progress,
    )?;
    let trace_ms = start.elapsed().as_secs_f64() * 1e3;
    // Shaded, as the truth's pixels are, with the light where it is at the camera time.
    let light = light_at(scene, settings.shadow_size(), deferred.camera_time)?;
    let facing = (0..truth.hit.len())
        .map(|i| {
            truth.hit[i]
                && direct_factor(
                    &light,
                    glam::Vec3::from(truth.position[i]).as_dvec3(),
                    glam::Vec3::from(truth.normal[i]).as_dvec3(),
                )
                .is_some()
        })
        .collect();
    Ok(DeferredResult {
        image: RadianceImage::new(settings.width, settings.height, truth.rgb)?,
        lit: truth.lit,
        hit: truth.hit,
        triangle: truth.triangle,
        facing,
        method: deferred.method.name(),
        passes: vec![PassTime {
            pass: "raytrace".to_owned(),
            gpu_ms: trace_ms,
        }],
        shadow_and_mask_ms: trace_ms,
        shadow_bytes: 0,
        wall_ms: trace_ms,
    })
}
