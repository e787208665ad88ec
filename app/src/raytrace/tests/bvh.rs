//! The motion BVH finds what testing every triangle finds, at every time.

use super::point;
use crate::raytrace::bvh::Bvh;
use crate::raytrace::intersect::Ray;
use crate::raytrace::triangles::Triangle;
use crate::scene::rng::SplitMix64;
use glam::{DVec3, Vec3};

/// Triangles that stress the build and the time blend: small static ones, fast movers
/// (crossing much of the scene during the shutter), large ones, slivers, degenerate ones, and
/// a stack of identical copies (same centre: the median fallback, and ties broken by id).
fn scene_triangles(rng: &mut SplitMix64) -> Vec<Triangle> {
    let mut out = Vec::new();
    let mut push = |p0: [Vec3; 3], p1: [Vec3; 3]| {
        let id = out.len() as u32;
        out.push(Triangle::new(p0, p1, id, 0));
    };
    let v = |rng: &mut SplitMix64, r: f32| point(rng, r).as_vec3();
    for i in 0..3000 {
        let c = v(rng, 5.0);
        let size = match i % 10 {
            0 => 3.0,
            1 => 0.01,
            _ => 0.3,
        };
        let mut p0 = [0; 3].map(|_| c + v(rng, size));
        if i % 97 == 0 {
            p0[2] = p0[0] + 0.5 * (p0[1] - p0[0]); // degenerate: a segment
        }
        let p1 = match i % 3 {
            0 => p0,
            1 => {
                let by = v(rng, 4.0);
                p0.map(|p| p + by)
            }
            // Non-rigid: every corner on its own path.
            _ => p0.map(|p| p + v(rng, 0.8)),
        };
        push(p0, p1);
    }
    let (a, b) = (v(rng, 2.0), v(rng, 2.0));
    for _ in 0..40 {
        push(
            [a, b, Vec3::new(0.1, 0.2, 0.3)],
            [a, b, Vec3::new(0.1, 0.2, 0.3)],
        );
    }
    out
}

/// Nearest hit over all triangles, ties to the lowest id: (id, s).
fn brute_closest(
    tris: &[Triangle],
    ray: &Ray,
    t: f64,
    s_min: f64,
    s_max: f64,
) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    for tri in tris {
        if let Some(s) = ray.intersect(&tri.at(t), s_min, s_max) {
            if best.is_none_or(|(id, bs)| s < bs || (s == bs && tri.id < id)) {
                best = Some((tri.id, s));
            }
        }
    }
    best
}

fn random_ray(rng: &mut SplitMix64) -> Ray {
    let origin = point(rng, 8.0);
    // Mostly through the scene's middle, some anywhere; some axis-aligned (zero components).
    let dir = match (rng.next_u64() % 8) as u32 {
        0 => rng.unit_vector().as_dvec3(),
        1 => DVec3::new(0.0, 0.0, if origin.z > 0.0 { -1.0 } else { 1.0 }),
        _ => point(rng, 3.0) - origin,
    };
    Ray::new(origin, dir * f64::from(rng.range(0.2, 3.0)))
}

#[test]
fn closest_and_occluded_match_testing_every_triangle() {
    let mut rng = SplitMix64::new(3);
    let tris = scene_triangles(&mut rng);
    let bvh = Bvh::new(&tris);
    assert_eq!(bvh.triangles().len(), tris.len());
    let (mut hits, mut tie_checks) = (0, 0);
    for i in 0..4000 {
        let ray = random_ray(&mut rng);
        let t = match i % 5 {
            0 => 0.0,
            1 => 1.0,
            _ => f64::from(rng.next_f32()),
        };
        let (s_min, s_max) = if i % 4 == 0 {
            (0.3, 2.0)
        } else {
            (0.0, f64::INFINITY)
        };
        let expected = brute_closest(&tris, &ray, t, s_min, s_max);
        let got = bvh
            .closest(&ray, t, s_min, s_max)
            .map(|h| (bvh.triangles()[h.index as usize].id, h.s));
        assert_eq!(got, expected, "ray {ray:?} at t = {t}");
        hits += usize::from(got.is_some());
        tie_checks += usize::from(got.is_some_and(|(id, _)| id >= 3000));

        // Any hit but one triangle (the nearest, as a shadow ray skips its receiver).
        let skip = expected.map_or(u32::MAX, |(id, _)| id);
        let any = tris
            .iter()
            .any(|tri| tri.id != skip && ray.intersect(&tri.at(t), s_min, s_max).is_some());
        assert_eq!(
            bvh.occluded(&ray, t, s_min, s_max, skip),
            any,
            "ray {ray:?} at t = {t}"
        );
    }
    eprintln!("{hits} of 4000 rays hit, {tie_checks} on the stack of identical triangles");
    assert!(hits > 1500, "only {hits} hits");
}

/// A tree split at the median everywhere (what nodes past the SAH depth get, so that no
/// distribution of triangles makes the tree deeper than the traversal stack) finds the same.
#[test]
fn a_median_tree_finds_the_same_and_is_shallow() {
    let mut rng = SplitMix64::new(4);
    let tris = scene_triangles(&mut rng);
    let sah = Bvh::new(&tris);
    let median = Bvh::with_sah_depth(&tris, 0);
    // 3040 triangles, halved until at most 8: ceil(log2(3040 / 8)) + 1 levels.
    assert_eq!(median.depth(), 10);
    eprintln!("depth: SAH {}, median {}", sah.depth(), median.depth());
    for i in 0..2000 {
        let ray = random_ray(&mut rng);
        let t = f64::from(rng.next_f32());
        let expected = brute_closest(&tris, &ray, t, 0.0, f64::INFINITY);
        let got = median
            .closest(&ray, t, 0.0, f64::INFINITY)
            .map(|h| (median.triangles()[h.index as usize].id, h.s));
        assert_eq!(got, expected, "ray {i}");
    }
}
