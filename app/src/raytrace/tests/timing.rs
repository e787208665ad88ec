//! How long one triangle test takes in f32 (with the paper's f64 fallback) and in f64, on
//! the same rays and triangles. A measurement, not a check: run with
//! `cargo test --release -p motion-shadows-app --lib timing -- --ignored --nocapture`.

use super::point;
use crate::raytrace::intersect::{Ray, RayF32};
use crate::scene::rng::SplitMix64;
use glam::{DVec3, Vec3};
use std::hint::black_box;
use std::time::Instant;

#[test]
#[ignore = "a measurement; prints ns per test"]
fn triangle_test_f32_against_f64() {
    let mut rng = SplitMix64::new(2);
    let tris: Vec<[DVec3; 3]> = (0..256)
        .map(|_| {
            let c = point(&mut rng, 3.0);
            [0; 3].map(|_| c + point(&mut rng, 0.5))
        })
        .collect();
    let tris32: Vec<[Vec3; 3]> = tris.iter().map(|t| t.map(DVec3::as_vec3)).collect();
    let rays: Vec<(DVec3, DVec3)> = (0..20_000)
        .map(|_| {
            let o = point(&mut rng, 8.0);
            (o, point(&mut rng, 2.0) - o)
        })
        .collect();
    let tests = (rays.len() * tris.len()) as f64;
    for round in 0..3 {
        let start = Instant::now();
        let mut hits64 = 0u32;
        for &(o, d) in &rays {
            let ray = Ray::new(o, d);
            for t in &tris {
                hits64 += u32::from(black_box(&ray).intersect(t, 0.0, f64::INFINITY).is_some());
            }
        }
        let ns64 = start.elapsed().as_secs_f64() * 1e9 / tests;
        let start = Instant::now();
        let mut hits32 = 0u32;
        for &(o, d) in &rays {
            let ray = RayF32::new(o.as_vec3(), d.as_vec3());
            for t in &tris32 {
                hits32 += u32::from(black_box(&ray).intersect(t, 0.0, f32::INFINITY).is_some());
            }
        }
        let ns32 = start.elapsed().as_secs_f64() * 1e9 / tests;
        eprintln!(
            "round {round}: f64 {ns64:.2} ns/test ({hits64} hits), f32 {ns32:.2} ns/test ({hits32} hits)"
        );
    }
}
