//! The image, pixel by pixel: the lighting pass's samples (the library's CPU mirror of the
//! shaders' sampling and the same camera rays), each traced and shaded, averaged per pixel.

use super::bvh::Bvh;
use super::intersect::Ray;
use super::shade::Shading;
use crate::render::upload::camera_view_of;
use crate::scene::Camera;
use glam::{DVec3, Vec2, Vec3};
use motion_shadows::technique::sampling::{pixel_key, pixel_sample};
use motion_shadows::technique::{CameraParams, LightingView, ShadowEstimator};
use rayon::prelude::*;

/// The camera rays of the GPU's lighting pass (`camera_ray` in shared.glsl), from the same
/// [`CameraParams`] the renderer gives it.
#[derive(Debug, Clone)]
pub struct CameraRays {
    origin: Vec3,
    ray00: Vec3,
    dx: Vec3,
    dy: Vec3,
    near: f64,
    far: f64,
    spp: u32,
    seed: u32,
    /// A camera that moves during the shutter: its path and the image size, each sample's
    /// ray shot from where the camera is at that sample's time. `None`: a still camera.
    path: Option<(Camera, (u32, u32))>,
}

impl CameraRays {
    pub fn new(params: &CameraParams) -> Self {
        Self {
            origin: params.position.truncate(),
            ray00: params.ray00.truncate(),
            dx: params.ray_dx.truncate(),
            dy: params.ray_dy.truncate(),
            near: f64::from(params.position.w),
            far: f64::from(params.forward.w),
            spp: params.image.z,
            seed: params.image.w,
            path: None,
        }
    }

    /// The rays of `camera` over the shutter: a still camera's are [`CameraRays::new`]'s,
    /// bit for bit; a moving one's are those of [`Camera::at`] each sample's time.
    pub fn over_shutter(params: &CameraParams, camera: &Camera) -> Self {
        let size = (params.image.x, params.image.y);
        Self {
            path: camera.moves().then(|| (camera.clone(), size)),
            ..Self::new(params)
        }
    }

    /// The ray through image position `at` at shutter time `t`: [`CameraRays::ray`] of the
    /// camera where it is at `t`.
    pub fn ray_at(&self, at: Vec2, t: f32) -> Ray {
        let Some((camera, size)) = &self.path else {
            return self.ray(at);
        };
        // The same arithmetic as the still camera's rays, for the pose at `t`.
        let view = LightingView {
            camera: camera_view_of(&camera.at(t), *size),
            seed: self.seed,
            ambient: 0.0,
            estimator: ShadowEstimator::Sampled,
            filter: Default::default(),
        };
        Self::new(&CameraParams::new(&view, *size, self.spp)).ray(at)
    }

    /// The ray through image position `at` (pixels from the top-left corner), in f32 as the
    /// shader computes it; its direction has unit length along the view axis, so a hit's ray
    /// parameter is its view depth.
    pub fn ray(&self, at: Vec2) -> Ray {
        let dir = self.ray00 + at.x * self.dx + at.y * self.dy;
        Ray::new(self.origin.as_dvec3(), dir.as_dvec3())
    }
}

/// One pixel: its radiance averaged over the samples and the share of samples that see a
/// moving triangle.
pub fn trace_pixel(x: u32, y: u32, rays: &CameraRays, shading: &Shading) -> (DVec3, f64) {
    let bvh: &Bvh = shading.bvh;
    let key = pixel_key(x, y, rays.seed);
    let (mut sum, mut moving) = (DVec3::ZERO, 0u32);
    for k in 0..rays.spp {
        let (t, offset) = pixel_sample(key, k, rays.spp);
        let ray = rays.ray_at(Vec2::new(x as f32, y as f32) + offset, t);
        let t = f64::from(t);
        // The GPU keeps hits with view depth in [near, far].
        let Some(hit) = bvh.closest(&ray, t, rays.near, rays.far) else {
            continue;
        };
        let tri = &bvh.triangles()[hit.index as usize];
        moving += u32::from(tri.moving);
        sum += shading.radiance(&ray, hit.s, tri, t);
    }
    let n = f64::from(rays.spp);
    (sum / n, f64::from(moving) / n)
}

/// Rows `first..` of a `width`-pixel image, as many as `rgb` (3 values per pixel) and
/// `moving` (the share of samples seeing a moving triangle) hold, in parallel over rows.
pub fn trace_rows(
    first: u32,
    width: u32,
    rgb: &mut [f32],
    moving: &mut [f32],
    rays: &CameraRays,
    shading: &Shading,
) {
    let w = width as usize;
    rgb.par_chunks_mut(3 * w)
        .zip(moving.par_chunks_mut(w))
        .enumerate()
        .for_each(|(row, (rgb, moving))| {
            let y = first + row as u32;
            for x in 0..width {
                let (radiance, share) = trace_pixel(x, y, rays, shading);
                let i = x as usize;
                rgb[3 * i..3 * i + 3].copy_from_slice(&radiance.as_vec3().to_array());
                moving[i] = share as f32;
            }
        });
}
