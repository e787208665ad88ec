//! A CPU model of the lighting pass's samples (shared.glsl: `pixel_key`, `pixel_sample`,
//! `camera_ray`) and of what each sample sees, written from the shaders' definitions: a
//! sample at time t looks along its camera ray and hits a triangle iff the ray meets the
//! triangle's position at t between the near and far planes.

use glam::{DVec3, Vec3, Vec4};

fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

pub fn pixel_key(x: u32, y: u32, seed: u32) -> u32 {
    pcg_hash(x.wrapping_add(pcg_hash(y.wrapping_add(pcg_hash(seed)))))
}

/// Time in [0, 1) and position in the pixel of sample k: stratum (k + key mod spp) mod spp.
pub fn pixel_sample(key: u32, k: u32, spp: u32) -> (f32, [f32; 2]) {
    let h = pcg_hash(key ^ pcg_hash(k));
    let stratum = (k + key % spp) % spp;
    let t = (stratum as f32 + (h >> 8) as f32 * (1.0 / 16_777_216.0)) / spp as f32;
    let g = pcg_hash(h);
    let offset = [
        ((g & 0xffff) as f32 + 0.5) * (1.0 / 65536.0),
        ((g >> 16) as f32 + 0.5) * (1.0 / 65536.0),
    ];
    (t, offset)
}

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
