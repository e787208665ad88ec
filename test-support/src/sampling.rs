//! A CPU model of the lighting pass's samples (the library's mirror of shared.glsl's
//! `pixel_key` and `pixel_sample`, plus `camera_ray`) and of what each sample sees, written
//! from the shaders' definitions: a sample at time t looks along its camera ray and hits a
//! triangle iff the ray meets the triangle's position at t between the near and far planes.

use glam::{DVec3, Vec3, Vec4};

// The app's GPU tests follow the samples too; the library's own use only `CameraRays`.
pub use motion_shadows::technique::sampling::{pixel_key, pixel_sample};

/// The camera ray through an image position: `ray00 + x dx + y dy` (unit view-axis
/// component, so a hit's ray parameter is its view depth).
pub struct CameraRays {
    pub origin: Vec3,
    pub ray00: Vec4,
    pub dx: Vec4,
    pub dy: Vec4,
    pub near: f32,
    pub far: f32,
}

impl CameraRays {
    /// The rays the lighting pass casts for `camera` at `size` (its `CameraParams`).
    pub fn of(camera: &motion_shadows::technique::CameraView, size: (u32, u32)) -> Self {
        let view = motion_shadows::technique::LightingView {
            camera: *camera,
            seed: 0,
            ambient: 0.0,
            estimator: Default::default(),
            filter: Default::default(),
        };
        let params = motion_shadows::technique::CameraParams::new(&view, size, 1);
        Self {
            origin: params.position.truncate(),
            ray00: params.ray00,
            dx: params.ray_dx,
            dy: params.ray_dy,
            near: params.position.w,
            far: params.forward.w,
        }
    }

    pub fn direction(&self, x: f32, y: f32) -> DVec3 {
        (self.ray00.truncate() + x * self.dx.truncate() + y * self.dy.truncate()).as_dvec3()
    }
}

/// Whether a ray hits a triangle: `Some(true)`/`Some(false)` when the answer is clear of
/// rounding, `None` when the ray passes within `margin` (in barycentric terms) of an edge or
/// its view depth within a relative `margin` of the near or far plane.
pub fn hits(rays: &CameraRays, dir: DVec3, tri: [DVec3; 3], margin: f64) -> Option<bool> {
    let origin = rays.origin.as_dvec3();
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return Some(false);
    }
    let s = origin - tri[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let depth = e2.dot(q) / det;
    let (near, far) = (f64::from(rays.near), f64::from(rays.far));
    let depth_margin = margin * depth.abs().max(1.0);
    let bary = [u, v, 1.0 - u - v];
    if bary.iter().any(|b| b.abs() < margin)
        || (depth - near).abs() < depth_margin
        || (depth - far).abs() < depth_margin
    {
        return None;
    }
    Some(bary.iter().all(|&b| b > 0.0) && depth > near && depth < far)
}
