//! The reference rasterizer: which fragments (perspective-correct depth and time) an
//! emitted triangle leaves at a pixel centre, and how far a pixel centre is from any edge
//! that decides its coverage. In f64, so that its own rounding is negligible.

use super::{CpuFragment, LightSetup, PrismVertex};
use glam::DVec2;

/// An emitted triangle projected to the framebuffer.
struct ScreenTri {
    pos: [DVec2; 3],
    inv_w: [f64; 3],
    ndc_z: [f64; 3],
    depth: [f64; 3],
    time: [f64; 3],
    /// Twice the signed screen area; either winding is rasterized.
    area2: f64,
}

/// `None` when a vertex is at or behind the eye (w <= 0): those need real near-plane
/// clipping, which this model does not implement (see `fragments_at_pixel`).
fn project(tri: &[PrismVertex; 3], light: &LightSetup) -> Option<ScreenTri> {
    if tri.iter().any(|v| v.clip.w <= 0.0) {
        return None;
    }
    let (w, h) = (f64::from(light.width), f64::from(light.height));
    let pos = tri.map(|v| {
        let inv = 1.0 / f64::from(v.clip.w);
        DVec2::new(
            (f64::from(v.clip.x) * inv * 0.5 + 0.5) * w,
            (f64::from(v.clip.y) * inv * 0.5 + 0.5) * h,
        )
    });
    Some(ScreenTri {
        pos,
        inv_w: tri.map(|v| 1.0 / f64::from(v.clip.w)),
        ndc_z: tri.map(|v| f64::from(v.clip.z) / f64::from(v.clip.w)),
        depth: tri.map(|v| f64::from(v.depth)),
        time: tri.map(|v| f64::from(v.time)),
        area2: (pos[1] - pos[0]).perp_dot(pos[2] - pos[0]),
    })
}

impl ScreenTri {
    /// Screen-space barycentrics of `p` (undefined for zero area).
    fn barycentrics(&self, p: DVec2) -> [f64; 3] {
        let [a, b, c] = self.pos;
        [
            (c - b).perp_dot(p - b) / self.area2,
            (a - c).perp_dot(p - c) / self.area2,
            (b - a).perp_dot(p - a) / self.area2,
        ]
    }

    /// Inside the triangle (ties included: tests stay clear of them) and not z-clipped.
    fn covers(&self, p: DVec2) -> Option<[f64; 3]> {
        if self.area2 == 0.0 {
            return None;
        }
        let l = self.barycentrics(p);
        if l.iter().any(|&x| x < 0.0) {
            return None;
        }
        // With every w > 0, clipping against z = 0 and z = w removes exactly the
        // screen points whose ndc z (affine in screen space) leaves [0, 1]. The x/y
        // planes never remove a pixel centre inside the framebuffer.
        let z = dot3(l, self.ndc_z);
        (0.0..=1.0).contains(&z).then_some(l)
    }

    /// Screen-space gradient of ndc z, to locate the near/far clip lines.
    fn ndc_z_gradient(&self) -> DVec2 {
        let [a, b, c] = self.pos;
        ((c - b).perp() * self.ndc_z[0]
            + (a - c).perp() * self.ndc_z[1]
            + (b - a).perp() * self.ndc_z[2])
            / self.area2
    }
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn pixel_centre(x: u32, y: u32) -> DVec2 {
    DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5)
}

/// Fragments at the centre of pixel (x, y), in no particular order.
///
/// Only triangles entirely in front of the eye (w > 0 at all three vertices) are
/// rasterized; any other triangle is skipped, so tests must keep their geometry in
/// front of the light (always true for an orthographic light, where w = 1). Zero-area
/// triangles (e.g. the side surfaces of a static triangle) produce nothing. Pixels
/// outside the framebuffer produce nothing.
pub fn fragments_at_pixel(
    tris: &[[PrismVertex; 3]],
    light: &LightSetup,
    x: u32,
    y: u32,
) -> Vec<CpuFragment> {
    if x >= light.width || y >= light.height {
        return Vec::new();
    }
    let p = pixel_centre(x, y);
    tris.iter()
        .filter_map(|tri| project(tri, light))
        .filter_map(|st| {
            let l = st.covers(p)?;
            // Perspective-correct: attributes are affine in clip space, so interpolate
            // attr/w and 1/w linearly on screen.
            let at = |l: [f64; 3]| {
                let wts = [0, 1, 2].map(|i| l[i] * st.inv_w[i]);
                let sum: f64 = wts.iter().sum();
                (dot3(wts, st.depth) / sum, dot3(wts, st.time) / sum)
            };
            let (depth, time) = at(l);
            // Barycentrics extend affinely past the edges, so a nearby point may lie outside.
            const STEP: f64 = 1e-3;
            let (dx, dy) = (
                at(st.barycentrics(p + DVec2::X * STEP)),
                at(st.barycentrics(p + DVec2::Y * STEP)),
            );
            let slope = |d: f64, ddx: f64, ddy: f64| (DVec2::new(ddx - d, ddy - d) / STEP).length();
            Some(CpuFragment {
                depth: depth as f32,
                time: time as f32,
                depth_per_pixel: slope(depth, dx.0, dy.0) as f32,
                time_per_pixel: slope(time, dx.1, dy.1) as f32,
            })
        })
        .collect()
}

fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Distance in pixels from the centre of pixel (x, y) to the nearest boundary that
/// decides coverage there: every edge of every projected triangle (zero-area ones
/// included, to stay conservative), plus the near/far clip lines of triangles that
/// cover the pixel. Triangles skipped by `fragments_at_pixel` (some w <= 0) are skipped
/// here too. `f32::INFINITY` when nothing is near.
pub fn edge_margin_at_pixel(tris: &[[PrismVertex; 3]], light: &LightSetup, x: u32, y: u32) -> f32 {
    let p = pixel_centre(x, y);
    let mut margin = f64::INFINITY;
    for st in tris.iter().filter_map(|tri| project(tri, light)) {
        for i in 0..3 {
            margin = margin.min(distance_to_segment(p, st.pos[i], st.pos[(i + 1) % 3]));
        }
        if let Some(l) = st.covers(p) {
            let grad = st.ndc_z_gradient().length();
            if grad > 0.0 {
                let z = dot3(l, st.ndc_z);
                margin = margin.min(z.abs() / grad).min((1.0 - z).abs() / grad);
            }
        }
    }
    margin as f32
}
