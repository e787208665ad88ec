//! The bound for a mesh whose positions only the GPU holds (deformed by a compute pass): the
//! host gives the triangle count and points whose convex hull holds every vertex at shutter
//! open and at shutter close (the 8 corners of a box each, say), and every triangle counts
//! what the worst triangle inside that hull could store.
//!
//! Why it bounds: a triangle's corners move linearly from the first hull to the second, so at
//! every time they lie in the convex hull of both; its images then lie in the hull of that
//! hull's projected corners (while w > 0, as for one triangle, `footprint.rs`), and at one
//! texel centre it stores at most the shader's cap of runs (one for a still triangle). Where
//! the hull reaches behind the light, the footprint is that of its part in front
//! (`beyond_light.rs`), every texel where that is unbounded.

use glam::{DMat4, DVec2, DVec3, DVec4, Vec3};

use super::footprint::{Footprint, GROWTH_TEXELS};
use super::{EXACT_MAX_RUNS, FAR_MAP_WIDTHS, NEAR_W, RangeCeiling};

/// `HALF_DIAGONAL_TEXELS` of the conservative collection (`conservative.rs`): every point of
/// a texel lies within it of the texel's centre.
const HALF_DIAGONAL_TEXELS: f64 = 0.7072;

impl RangeCeiling {
    /// At most how many ranges (or static names) one triangle stores whose world-space
    /// corners lie in the convex hull of `t0` at shutter open and of `t1` at shutter close;
    /// `moving`: whether it may move (a still one stores one run per centre).
    pub(crate) fn triangle_within(&self, t0: &[Vec3], t1: &[Vec3], moving: bool) -> u64 {
        let setup = &self.setup;
        let to_clip: DMat4 = setup.proj * setup.to_view;
        let corners: Vec<DVec3> = t0
            .iter()
            .chain(t1)
            .map(|p| {
                let c: DVec4 = to_clip * p.as_dvec3().extend(1.0);
                DVec3::new(c.x, c.y, c.w)
            })
            .collect();
        let map = &setup.map;
        if corners.iter().all(|c| c.z <= 0.0) {
            // Wholly behind the light: w is affine, so every triangle inside is too.
            return 0;
        }
        let max_runs = if moving && !self.conservative {
            EXACT_MAX_RUNS
        } else {
            1
        };
        if !corners.iter().all(|c| c.is_finite()) {
            return max_runs * map.texels();
        }
        let w_scale = corners.iter().map(|c| c.z.abs()).fold(0.0, f64::max);
        let near = corners.iter().any(|c| c.z <= NEAR_W * w_scale);
        let images: Vec<DVec2> = corners.iter().map(|&c| map.texel(c)).collect();
        let reach = FAR_MAP_WIDTHS * map.width.max(map.height);
        let far = images.iter().any(|p| p.abs().max_element() > reach);
        if self.conservative {
            // One range per texel its grown footprint covers; near or far: the whole map.
            if near || far {
                return map.texels();
            }
            let growth = GROWTH_TEXELS + HALF_DIAGONAL_TEXELS;
            return Footprint::grown(&images, map, growth).count(&[]).0;
        }
        if near || far {
            return match map.beyond_the_light_footprint(&corners, reach) {
                Some(points) => EXACT_MAX_RUNS * Footprint::new(&points, map).count(&[]).0,
                None => EXACT_MAX_RUNS * map.texels(),
            };
        }
        max_runs * Footprint::new(&images, map).count(&[]).0
    }
}
