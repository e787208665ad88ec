//! Watertight ray/triangle intersection (Woop, Benthin and Wald 2013, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1)), both faces.
//!
//! The ray is sheared so that it runs along +z from the origin; the triangle's three edge
//! functions are then 2D cross products of the sheared vertices. A point on an edge shared by
//! two triangles gets exactly opposite edge functions in both (the products are the same, only
//! the subtraction is reversed), so a ray through a shared edge or vertex hits at least one of
//! them: no sample falls through a crack between the triangles of a tessellated surface, as it
//! can with Moller-Trumbore (the GPU methods' test), whose barycentrics are rounded per
//! triangle.
//!
//! Two precisions: [`Ray`] (f64 throughout) traces every image; [`RayF32`] is the paper's f32
//! version with its double-precision recomputation of edge functions that round to zero,
//! kept for the measurement in the tests (the two cost about the same on a CPU, and f64 leaves
//! the shadow rays' origins ~1e-15 of the scene's size off the surface instead of ~1e-7).

use glam::{DVec3, Vec3};

/// The axis of the largest component, then the two others in an order that keeps the
/// triangle's winding after the shear (swapped when the ray points down that axis).
fn permutation(dir: [f64; 3]) -> [usize; 3] {
    let a = dir.map(f64::abs);
    let kz = if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    };
    let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if dir[kz] < 0.0 {
        std::mem::swap(&mut kx, &mut ky);
    }
    [kx, ky, kz]
}

/// A ray `origin + s dir` with its shear precomputed (f64).
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
    /// `1 / dir` per component, for the bounding-box slabs.
    pub inv_dir: DVec3,
    k: [usize; 3],
    shear: [f64; 3],
}

impl Ray {
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        let k = permutation(dir.to_array());
        let d = dir.to_array();
        Self {
            origin,
            dir,
            inv_dir: dir.recip(),
            k,
            shear: [d[k[0]] / d[k[2]], d[k[1]] / d[k[2]], 1.0 / d[k[2]]],
        }
    }

    /// The ray parameter `s` in `[s_min, s_max]` where the ray meets triangle `v`, either
    /// face; `None` when it misses (a degenerate triangle never hits). Points on an edge count
    /// as hits.
    #[inline]
    pub fn intersect(&self, v: &[DVec3; 3], s_min: f64, s_max: f64) -> Option<f64> {
        let [kx, ky, kz] = self.k;
        let [sx, sy, sz] = self.shear;
        let a = (v[0] - self.origin).to_array();
        let b = (v[1] - self.origin).to_array();
        let c = (v[2] - self.origin).to_array();
        let (ax, ay) = (a[kx] - sx * a[kz], a[ky] - sy * a[kz]);
        let (bx, by) = (b[kx] - sx * b[kz], b[ky] - sy * b[kz]);
        let (cx, cy) = (c[kx] - sx * c[kz], c[ky] - sy * c[kz]);
        let u = cx * by - cy * bx;
        let v_ = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        finish(u, v_, w, [sz * a[kz], sz * b[kz], sz * c[kz]], s_min, s_max)
    }
}

/// The paper's last steps, shared by both precisions: the sign test (both faces: all edge
/// functions of one sign, zeros allowed), the determinant, and the hit distance compared
/// before dividing.
#[inline]
fn finish(u: f64, v: f64, w: f64, z: [f64; 3], s_min: f64, s_max: f64) -> Option<f64> {
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let s = (u * z[0] + v * z[1] + w * z[2]) / det;
    (s >= s_min && s <= s_max).then_some(s)
}

/// The paper's f32 version: a ray with its shear in f32.
#[derive(Debug, Clone, Copy)]
pub struct RayF32 {
    pub origin: Vec3,
    pub dir: Vec3,
    k: [usize; 3],
    shear: [f32; 3],
}

impl RayF32 {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let k = permutation(dir.as_dvec3().to_array());
        let d = dir.to_array();
        Self {
            origin,
            dir,
            k,
            shear: [d[k[0]] / d[k[2]], d[k[1]] / d[k[2]], 1.0 / d[k[2]]],
        }
    }

    /// As [`Ray::intersect`], computed in f32; an edge function that rounds to exactly zero
    /// is recomputed in f64 from the same sheared f32 vertices (the paper's fallback), so the
    /// sign of a point near an edge is decided consistently for both triangles sharing it.
    #[inline]
    pub fn intersect(&self, v: &[Vec3; 3], s_min: f32, s_max: f32) -> Option<f32> {
        let [kx, ky, kz] = self.k;
        let [sx, sy, sz] = self.shear;
        let a = (v[0] - self.origin).to_array();
        let b = (v[1] - self.origin).to_array();
        let c = (v[2] - self.origin).to_array();
        let (ax, ay) = (a[kx] - sx * a[kz], a[ky] - sy * a[kz]);
        let (bx, by) = (b[kx] - sx * b[kz], b[ky] - sy * b[kz]);
        let (cx, cy) = (c[kx] - sx * c[kz], c[ky] - sy * c[kz]);
        let mut u = cx * by - cy * bx;
        let mut v_ = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v_ == 0.0 || w == 0.0 {
            let d = f64::from;
            u = (d(cx) * d(by) - d(cy) * d(bx)) as f32;
            v_ = (d(ax) * d(cy) - d(ay) * d(cx)) as f32;
            w = (d(bx) * d(ay) - d(by) * d(ax)) as f32;
        }
        if (u < 0.0 || v_ < 0.0 || w < 0.0) && (u > 0.0 || v_ > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v_ + w;
        if det == 0.0 {
            return None;
        }
        let s = (u * sz * a[kz] + v_ * sz * b[kz] + w * sz * c[kz]) / det;
        (s >= s_min && s <= s_max).then_some(s)
    }
}
