//! The tracer's parts against independent answers: the triangle test against an f64
//! plane-and-edges brute force and on rays aimed at shared edges, the BVH against testing every
//! triangle.

mod bvh;
mod moving_camera;
mod moving_light;
mod shutter;
mod timing;
mod watertight;

use crate::scene::rng::SplitMix64;
use glam::DVec3;

/// A point with each coordinate uniform in [-r, r], rounded to f32 as scene positions are.
fn point(rng: &mut SplitMix64, r: f32) -> DVec3 {
    glam::Vec3::new(rng.range(-r, r), rng.range(-r, r), rng.range(-r, r)).as_dvec3()
}
