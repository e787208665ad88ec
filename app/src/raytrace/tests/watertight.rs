//! The triangle test: no ray aimed at a shared edge or vertex of a tessellated quad falls
//! through, and hits and distances agree with an independent f64 computation.

use super::point;
use crate::raytrace::intersect::{Ray, RayF32};
use crate::scene::rng::SplitMix64;
use glam::{DVec3, Vec3};
use std::collections::{HashMap, HashSet};

/// A quad of `n` x `n` cells, each two triangles (diagonals alternating), in a tilted plane,
/// its inner vertices jittered in the plane and (when `bumpy`) out of it, positions rounded to
/// f32 as a scene's are. Returns the vertices and the triangles' vertex indices.
fn tessellated_quad(rng: &mut SplitMix64, n: usize, bumpy: bool) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let centre = DVec3::new(0.3, -0.7, 1.1);
    let u = DVec3::new(0.8, 0.35, -0.2).normalize();
    let w = u.cross(DVec3::new(0.1, 0.2, 1.0)).normalize();
    let v = w.cross(u);
    let cell = 4.0 / n as f64;
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let inner = i > 0 && i < n && j > 0 && j < n;
            let (mut x, mut y, mut z) = (i as f64 * cell - 2.0, j as f64 * cell - 2.0, 0.0);
            if inner {
                x += 0.3 * cell * f64::from(rng.range(-1.0, 1.0));
                y += 0.3 * cell * f64::from(rng.range(-1.0, 1.0));
                if bumpy {
                    z = 0.4 * cell * f64::from(rng.range(-1.0, 1.0));
                }
            }
            let p = centre + x * u + y * v + z * w;
            vertices.push(p.as_vec3().as_dvec3());
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (vertices, triangles)
}

/// Points on the quad's inner edges (at random places along each, and at its ends: the inner
/// vertices), each the target of rays from many directions, with the triangles around it.
fn targets(
    rng: &mut SplitMix64,
    vertices: &[DVec3],
    triangles: &[[usize; 3]],
) -> Vec<(DVec3, Vec<usize>)> {
    let mut edges: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    let mut around: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(i);
            around.entry(a).or_default().push(i);
        }
    }
    // A ray at a vertex on the quad's border may pass just outside it: only inner vertices.
    let border: HashSet<usize> = edges
        .iter()
        .filter(|(_, tris)| tris.len() == 1)
        .flat_map(|(&(a, b), _)| [a, b])
        .collect();
    let mut inner: Vec<((usize, usize), Vec<usize>)> = edges
        .into_iter()
        .filter(|(_, tris)| tris.len() == 2)
        .collect();
    inner.sort_unstable();
    let mut points = Vec::new();
    for ((a, b), tris) in inner {
        for v in [a, b] {
            if !border.contains(&v) {
                points.push((vertices[v], around[&v].clone()));
            }
        }
        let (pa, pb) = (vertices[a], vertices[b]);
        for _ in 0..8 {
            points.push((pa + f64::from(rng.next_f32()) * (pb - pa), tris.clone()));
        }
        points.push((0.5 * (pa + pb), tris));
    }
    points
}

/// The lighting pass's own test (Moller-Trumbore in f32, shared.glsl `intersect_triangle`),
/// to show that the rays below do find cracks in a test that is not watertight.
fn moller_trumbore(origin: Vec3, dir: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return false;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    e2.dot(q) * inv > 0.0
}

#[test]
fn rays_at_shared_edges_and_vertices_never_miss() {
    let mut rng = SplitMix64::new(11);
    let (mut rays, mut misses64, mut misses32, mut misses_mt) = (0, 0, 0, 0);
    for bumpy in [false, true] {
        let (vertices, triangles) = tessellated_quad(&mut rng, 8, bumpy);
        let tris64: Vec<[DVec3; 3]> = triangles.iter().map(|t| t.map(|i| vertices[i])).collect();
        let tris32: Vec<[Vec3; 3]> = tris64.iter().map(|t| t.map(DVec3::as_vec3)).collect();
        let normal = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let plane = normal(&tris64[0]);
        for (target, adjacent) in targets(&mut rng, &vertices, &triangles) {
            for distance in [1.5, 20.0, 700.0] {
                for _ in 0..6 {
                    // Both sides of the surface, not within 3 degrees of its plane. Where the
                    // triangles around the target do not all face the ray the same way, the
                    // target is on a silhouette and a ray grazing it may miss them all.
                    let from = rng.unit_vector().as_dvec3();
                    let facing = adjacent.iter().map(|&i| normal(&tris64[i]).dot(from) > 0.0);
                    let facing: HashSet<bool> = facing.collect();
                    if from.dot(plane).abs() < 0.05 || facing.len() > 1 {
                        continue;
                    }
                    let origin = target + distance * from;
                    let dir = target - origin;
                    rays += 1;
                    let ray = Ray::new(origin, dir);
                    if !tris64
                        .iter()
                        .any(|t| ray.intersect(t, 0.0, f64::INFINITY).is_some())
                    {
                        misses64 += 1;
                    }
                    let (o32, d32) = (origin.as_vec3(), dir.as_vec3());
                    let ray32 = RayF32::new(o32, d32);
                    if !tris32
                        .iter()
                        .any(|t| ray32.intersect(t, 0.0, f32::INFINITY).is_some())
                    {
                        misses32 += 1;
                    }
                    if !tris32
                        .iter()
                        .any(|t| moller_trumbore(o32, d32, t[0], t[1], t[2]))
                    {
                        misses_mt += 1;
                    }
                }
            }
        }
    }
    eprintln!(
        "{rays} rays at shared edges and vertices: {misses64} missed (f64), {misses32} (f32), \
         {misses_mt} (Moller-Trumbore, f32)"
    );
    assert!(rays > 20_000, "only {rays} rays");
    assert_eq!(
        misses64, 0,
        "the f64 test let {misses64} of {rays} rays through"
    );
    assert_eq!(
        misses32, 0,
        "the f32 test let {misses32} of {rays} rays through"
    );
    assert!(
        misses_mt > 0,
        "the rays found no crack even in the test that has them: they test nothing"
    );
}

/// Hit or miss and the distance, from the plane and the three edges in f64, with the
/// barycentric coordinates; `None` where the ray is within `margin` of an edge or nearly
/// parallel to the plane (rounding could decide it either way).
fn independent(origin: DVec3, dir: DVec3, t: &[DVec3; 3], margin: f64) -> Option<Option<f64>> {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let denom = n.dot(dir);
    if denom.abs() < 1e-3 * n.length() * dir.length() {
        return None;
    }
    let s = n.dot(t[0] - origin) / denom;
    let q = origin + s * dir;
    let area = n.length_squared();
    let bary = [0, 1, 2].map(|k| {
        let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
        (b - a).cross(q - a).dot(n) / area
    });
    if bary.iter().any(|b| b.abs() < margin) || s.abs() < margin * dir.length().recip() {
        return None;
    }
    Some((bary.iter().all(|&b| b > 0.0) && s > 0.0).then_some(s))
}

#[test]
fn hits_and_distances_match_an_independent_f64_computation() {
    let mut rng = SplitMix64::new(5);
    let (mut decided, mut hits, mut cases) = (0, 0, 0);
    while cases < 20_000 {
        let tri = [0, 1, 2].map(|_| point(&mut rng, 2.0));
        if (tri[1] - tri[0]).cross(tri[2] - tri[0]).length() < 1e-3 {
            continue;
        }
        cases += 1;
        // Aimed near the triangle (barycentrics in [-0.3, 1.3]: a fifth hit);
        // directions of any length, as camera rays are not unit.
        let (u, v) = (rng.range(-0.3, 1.3), rng.range(-0.3, 1.3));
        let aim = tri[0] + f64::from(u) * (tri[1] - tri[0]) + f64::from(v) * (tri[2] - tri[0]);
        let origin = point(&mut rng, 6.0);
        let dir = (aim - origin) * f64::from(rng.range(0.1, 10.0));
        let ray = Ray::new(origin, dir);
        let got = ray.intersect(&tri, 0.0, f64::INFINITY);
        if let Some(expected) = independent(origin, dir, &tri, 1e-9) {
            decided += 1;
            match (got, expected) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "s {a} vs {b}");
                }
                (None, None) => {}
                _ => panic!("{tri:?} from {origin} along {dir}: {got:?}, expected {expected:?}"),
            }
        }
        // The f32 test, where rounding in f32 cannot decide it.
        let tri32 = tri.map(DVec3::as_vec3);
        let ray32 = RayF32::new(origin.as_vec3(), dir.as_vec3());
        let exact = tri32.map(Vec3::as_dvec3);
        if let Some(expected) = independent(
            origin.as_vec3().as_dvec3(),
            dir.as_vec3().as_dvec3(),
            &exact,
            1e-4,
        ) {
            let got = ray32.intersect(&tri32, 0.0, f32::INFINITY);
            assert_eq!(
                got.is_some(),
                expected.is_some(),
                "f32: {got:?} vs {expected:?}"
            );
            if let (Some(a), Some(b)) = (got, expected) {
                assert!((f64::from(a) - b).abs() <= 1e-4 * b.abs().max(1.0));
            }
        }
    }
    eprintln!("{decided} of {cases} cases decided, {hits} hits");
    assert!(
        decided > cases * 9 / 10 && hits > cases / 8,
        "{decided} decided, {hits} hits"
    );
}
