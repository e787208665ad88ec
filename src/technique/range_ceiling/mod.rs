//! An upper bound on the ranges a temporal frame stores, from the host's positions alone, so
//! that a map reserved for it never runs out of room: no frame is drawn twice or grown a frame
//! late. How loose it is, and what it replaced: `docs/src/generation.md`, "One attempt: the
//! upper bound".
//!
//! Why it bounds (the exact construction, `exact_prism.glsl`): a triangle's corners move
//! linearly and stay in front of the light, so each of its images lies in the convex hull of
//! its six projected corners (a perspective projection keeps segments straight while w > 0),
//! and it stores ranges only at texel centres it covers: centres in that hull
//! (`footprint.rs`). At one centre, it stores one range per covered run (`runs.rs`). A triangle
//! reaching behind the light has no finite images there: its footprint is the centres whose
//! rays meet its swept hull in front of the light (`beyond_light.rs`), every texel only where
//! that hull holds the light itself.
//!
//! Kept loose where exactness would cost: the footprint is the hull grown by
//! `GROWTH_TEXELS` (for f32 and the rasterizer), a triangle reaching behind the light counts
//! the cap at every centre of its footprint, and only culling of closed meshes is mirrored
//! (`culling.rs`; not triangles behind the static layer). `app/tests/gpu/range_bound.rs`
//! checks it is never below the count, and how far above, on every built-in scene;
//! `tests/gpu/range_ceiling.rs` that an engine's map reserved with it never overflows.

mod beyond_light;
mod boxes;
mod conservative;
mod culling;
mod footprint;
mod frustum;
mod host_draw;
mod hull;
mod map;
mod runs;

pub use host_draw::HostDraw;

use glam::{DMat4, DVec2, DVec3, DVec4, Vec3};

use super::gpu_constants::EXACT_MAX_RUNS as GLSL_EXACT_MAX_RUNS;
use super::view::{LightView, Lookup, PrismConstruction};
use crate::error::Result;
use culling::faces_away_whole_frame;
use footprint::Footprint;
use frustum::clip_to_frustum;
use map::Map;
use runs::{det_sign_changes, turning_edges};

/// The exact prism's most covered runs per texel ([`GLSL_EXACT_MAX_RUNS`], which the shaders'
/// `ExactRuns` holds), as the ceiling's arithmetic takes it.
const EXACT_MAX_RUNS: u64 = GLSL_EXACT_MAX_RUNS as u64;
/// Corners imaged beyond this many map widths, or with w this close to 0 (relative to the
/// largest |w|), count as near or behind the light: f32 no longer places them within the
/// footprint's growth.
const FAR_MAP_WIDTHS: f64 = 64.0;
const NEAR_W: f64 = 1e-4;

/// At most how many depth-time ranges a temporal frame with the exact construction (the
/// default) stores in a map of a given size, from the triangles' corners at t = 0 and t = 1:
/// reserve that many ([`super::TemporalShadowMap::reserve_for`] does) and no frame overflows.
/// How loose it is: `docs/src/generation.md`, "One attempt: the upper bound".
#[derive(Debug, Clone)]
pub struct RangeCeiling {
    setup: Setup,
    /// The exact lookup's conservative collection (`conservative.rs`): one range per texel
    /// its grown footprint covers.
    conservative: bool,
}

impl RangeCeiling {
    /// For a map of `width` x `height` texels lit by `light`; None with the papers' prisms
    /// (`PrismConstruction::Paper`, not bounded here) and for a moving light
    /// (`LightView::end`: its triangles move in the light's moving frame, which this does not
    /// follow). With the exact lookup's conservative collection (`Lookup::Exact`), which
    /// covers whole texels, it counts the texels of each triangle's grown footprint (one
    /// range, or one static name, each).
    pub fn new(light: &LightView, width: u32, height: u32) -> Option<Self> {
        let bounded = light.prisms == PrismConstruction::Exact && !light.is_moving();
        bounded.then(|| Self {
            conservative: light.lookup == Lookup::Exact,
            setup: Setup {
                to_view: light.view.as_dmat4(),
                proj: light.proj.as_dmat4(),
                orthographic: !light.is_spot(),
                map: Map {
                    width: f64::from(width),
                    height: f64::from(height),
                },
            },
        })
    }

    /// At most how many ranges one triangle stores, its world-space corners at t = 0 and
    /// t = 1; `closed` as its draw's [`super::Draw::closed`]. A triangle of a static draw
    /// stores none where the frame keeps static draws in the static layer
    /// ([`super::TemporalShadowMap::uses_static_layer`]): leave those out.
    pub fn triangle(&self, t0: &[Vec3; 3], t1: &[Vec3; 3], closed: bool) -> u64 {
        if self.conservative {
            self.setup.conservative_ranges_at_most(t0, t1, closed)
        } else {
            self.setup.triangle_ranges_at_most(t0, t1, closed)
        }
    }

    /// The sum over a draw's triangles (static or not: the caller leaves out static draws
    /// where the static layer holds them).
    pub fn draw(&self, draw: &HostDraw) -> Result<u64> {
        Ok(draw
            .triangles()?
            .map(|(t0, t1)| self.triangle(&t0, &t1, draw.closed))
            .sum())
    }
}

#[derive(Debug, Clone)]
struct Setup {
    to_view: DMat4,
    proj: DMat4,
    orthographic: bool,
    map: Map,
}

/// A triangle at both ends in the light's view space (e0, e1) and as clip (x, y, w) (v0,
/// v1), in f64.
struct LightSpace {
    e0: [DVec3; 3],
    e1: [DVec3; 3],
    v0: [DVec3; 3],
    v1: [DVec3; 3],
}

impl Setup {
    fn light_space(&self, t0: &[Vec3; 3], t1: &[Vec3; 3]) -> LightSpace {
        let view = |p: Vec3| -> DVec3 { self.to_view.transform_point3(p.as_dvec3()) };
        let clip = |p: DVec3| -> DVec3 {
            let c: DVec4 = self.proj * p.extend(1.0);
            DVec3::new(c.x, c.y, c.w)
        };
        let (e0, e1) = (t0.map(view), t1.map(view));
        LightSpace {
            e0,
            e1,
            v0: e0.map(clip),
            v1: e1.map(clip),
        }
    }

    fn triangle_ranges_at_most(&self, t0: &[Vec3; 3], t1: &[Vec3; 3], closed: bool) -> u64 {
        let LightSpace { e0, e1, v0, v1 } = self.light_space(t0, t1);
        let map = &self.map;
        let moving = t0 != t1;
        let max_runs = if moving { EXACT_MAX_RUNS } else { 1 };
        let corners = || v0.iter().chain(&v1);
        if corners().all(|c| c.z <= 0.0) {
            // Wholly behind the light: the geometry shader emits nothing.
            return 0;
        }
        if closed && faces_away_whole_frame(&e0, &e1, self.orthographic) {
            return 0;
        }
        let w_scale = corners().map(|c| c.z.abs()).fold(0.0, f64::max);
        if !corners().all(|c| c.is_finite()) {
            return max_runs * map.texels();
        }
        if !moving {
            // One run, [0, 1], where the triangle covers the centre: its part inside the
            // light's frustum, projected.
            let inside = clip_to_frustum(&v0, NEAR_W * w_scale);
            let images: Vec<DVec2> = inside.iter().map(|&c| map.texel(c)).collect();
            return Footprint::new(&images, map).count(&[]).0;
        }
        let images: Vec<DVec2> = corners().map(|&c| map.texel(c)).collect();
        let reach = FAR_MAP_WIDTHS * map.width.max(map.height);
        let near = corners().any(|c| c.z <= NEAR_W * w_scale);
        if near || images.iter().any(|p| p.abs().max_element() > reach) {
            // Near or behind the light: the images of the corners no longer bound the
            // triangle's; the footprint is that of the swept hull's part in front of it, and
            // every centre counts the shader's cap.
            let corners: Vec<DVec3> = corners().copied().collect();
            return match map.beyond_the_light_footprint(&corners, reach) {
                Some(points) => EXACT_MAX_RUNS * Footprint::new(&points, map).count(&[]).0,
                None => EXACT_MAX_RUNS * map.texels(),
            };
        }
        let footprint = Footprint::new(&images, map);
        let turning = turning_edges(&v0, &v1, map, &footprint);
        let (centres, turns) = footprint.count(&turning);
        let runs = (1 + det_sign_changes(&v0, &v1)) * centres + turns;
        runs.min(EXACT_MAX_RUNS * centres)
    }
}

#[cfg(test)]
mod tests;
