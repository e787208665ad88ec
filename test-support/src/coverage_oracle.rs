//! An oracle for the covered times of a shadow-map texel that shares nothing with the exact
//! construction's algebra: in f64, the texel's ray (from the light's inverted matrices) is
//! intersected with each triangle at many times of the shutter (Moller-Trumbore), and every
//! change of the answer is narrowed down by bisection. No edge functions, no quadratics.

use super::scene::Scene;
use glam::{DVec3, DVec4};
use motion_shadows::technique::LightView;

/// Time steps of the scan; two changes closer than this may be missed (the tests skip
/// intervals and gaps shorter than a few steps anyway).
const STEPS: usize = 2048;

pub struct TexelRay {
    pub origin: DVec3,
    pub dir: DVec3,
    /// A perspective light sees only ahead of itself; an orthographic box the whole line.
    pub forward_only: bool,
    eye: DVec3,
    axis: DVec3,
}

pub fn texel_ray(light: &LightView, size: (u32, u32), x: u32, y: u32) -> TexelRay {
    map_ray(light, size, x as f64 + 0.5, y as f64 + 0.5)
}

/// The ray through the point (u, v) of the map, in texels from its corner (texel (x, y)
/// spans [x, x + 1) x [y, y + 1)).
pub fn map_ray(light: &LightView, size: (u32, u32), u: f64, v: f64) -> TexelRay {
    let inverse = (light.proj.as_dmat4() * light.view.as_dmat4()).inverse();
    let ndc_x = u / size.0 as f64 * 2.0 - 1.0;
    let ndc_y = v / size.1 as f64 * 2.0 - 1.0;
    let unproject = |z: f64| {
        let p = inverse * DVec4::new(ndc_x, ndc_y, z, 1.0);
        p.truncate() / p.w
    };
    let (near, far) = (unproject(0.0), unproject(1.0));
    let eye = light.position.as_dvec3();
    let spot = light.is_spot();
    TexelRay {
        origin: if spot { eye } else { near },
        dir: (far - near).normalize(),
        forward_only: spot,
        eye,
        axis: light.direction.as_dvec3().normalize(),
    }
}

/// A triangle whose corners move linearly over the shutter.
#[derive(Clone, Copy, Debug)]
pub struct MovingTriangle {
    pub p0: [DVec3; 3],
    pub p1: [DVec3; 3],
}

impl MovingTriangle {
    pub fn at(&self, t: f64) -> [DVec3; 3] {
        std::array::from_fn(|k| self.p0[k] + (self.p1[k] - self.p0[k]) * t)
    }
}

/// Every triangle of the scene in the renderer's id order (meshes in order).
pub fn scene_triangles(scene: &Scene) -> Vec<MovingTriangle> {
    let mut out = Vec::new();
    for m in &scene.meshes {
        for (a, b) in m.t0.chunks(3).zip(m.t1.chunks(3)) {
            out.push(MovingTriangle {
                p0: std::array::from_fn(|k| a[k].as_dvec3()),
                p1: std::array::from_fn(|k| b[k].as_dvec3()),
            });
        }
    }
    out
}

/// The ray parameter and barycentric coordinates (u, v) of the ray's meeting with the plane
/// of `tri`, or None when the ray runs parallel to it.
fn plane_hit(ray: &TexelRay, tri: [DVec3; 3]) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = ray.origin - tri[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) / det;
    Some((e2.dot(q) / det, u, v))
}

/// The smallest barycentric coordinate of the ray's meeting with the triangle's plane:
/// negative outside, positive inside, near zero close to an edge.
pub fn margin(ray: &TexelRay, tri: [DVec3; 3]) -> f64 {
    match plane_hit(ray, tri) {
        Some((_, u, v)) => u.min(v).min(1.0 - u - v),
        None => 0.0,
    }
}

/// The light depth (along its view axis) where the ray meets the triangle's plane.
pub fn plane_depth(ray: &TexelRay, tri: [DVec3; 3]) -> Option<f64> {
    let (s, _, _) = plane_hit(ray, tri)?;
    Some((ray.origin + ray.dir * s - ray.eye).dot(ray.axis))
}

/// The light depth (along its view axis) where the ray meets the triangle, if it does.
pub fn hit_depth(ray: &TexelRay, tri: [DVec3; 3]) -> Option<f64> {
    let (s, u, v) = plane_hit(ray, tri)?;
    let inside = u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (!ray.forward_only || s > 0.0);
    inside.then(|| (ray.origin + ray.dir * s - ray.eye).dot(ray.axis))
}

/// The intervals of [0, 1] during which the ray meets the triangle.
pub fn covered_intervals(ray: &TexelRay, tri: &MovingTriangle) -> Vec<(f64, f64)> {
    let covered = |t: f64| hit_depth(ray, tri.at(t)).is_some();
    let edge = |mut lo: f64, mut hi: f64, lo_state: bool| {
        for _ in 0..48 {
            let mid = 0.5 * (lo + hi);
            if covered(mid) == lo_state {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let mut out = Vec::new();
    let mut state = covered(0.0);
    let mut start = state.then_some(0.0);
    for i in 1..=STEPS {
        let (a, b) = ((i - 1) as f64 / STEPS as f64, i as f64 / STEPS as f64);
        let next = covered(b);
        if next != state {
            let at = edge(a, b, state);
            match start.take() {
                Some(s) => out.push((s, at)),
                None => start = Some(at),
            }
            state = next;
        }
    }
    if let Some(s) = start {
        out.push((s, 1.0));
    }
    out
}
