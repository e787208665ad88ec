//! `hard-static-silhouette`: a closed, tessellated box whose surface never changes while its
//! vertices move: each face's interior vertices swirl within the face's plane (a twist about
//! the face's centre that fades to nothing at the face's border), its edge and corner
//! vertices stay put. Seen from the light, its silhouette edges (box edges between a face
//! turned to the light and one turned away) are static, and so is its exact shadow.
//!
//! A method that builds prisms from moving triangles sees a moving mesh here: sides of the
//! static silhouette edges must not leak light or produce a blurred shadow, and the moving
//! interior triangles must keep the shadow solid.
//!
//! The motion, exactly: a face point at normalised face coordinates (a, b) in [-1, 1]^2 is
//! turned about the face's centre by `TWIST_DEG * w` at t1 and by minus that at t0, with
//! w = (1 - a^2)(1 - b^2) (0 on the border, 1 at the centre); in between, every vertex
//! moves on the chord, which stays in the face's plane. Both poses and every blend of them
//! tile each face without folds (checked by the tests at 65 times).

use glam::Vec3;

use super::super::file::{SceneFile, TransformFile};
use super::super::parts::{ground, object};
use super::super::primitives::box_mesh;
use super::{camera, scene_file, spot, triangles};

const LIGHT: Vec3 = Vec3::new(-3.0, 8.0, 3.0);
const CENTRE: Vec3 = Vec3::new(0.0, 2.3, 0.0);
const SIZE: f32 = 2.0;
const SUBDIVISIONS: u32 = 8;
/// Turn of a face's centre region at t1 (minus this at t0), degrees.
const TWIST_DEG: f32 = 30.0;
/// The box's static orientation: turned about y.
const YAW_DEG: f32 = 25.0;

/// `p` (a vertex of the box centred at the origin) twisted by `deg` within its face: only
/// vertices with exactly one coordinate on the box's surface (face interiors) move.
fn twist(p: Vec3, deg: f32) -> Vec3 {
    let h = SIZE * 0.5;
    let on_surface = p.to_array().map(|c| c.abs() == h);
    if on_surface.iter().filter(|&&b| b).count() != 1 {
        return p;
    }
    let axis = on_surface.iter().position(|&b| b).unwrap();
    let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut c = p.to_array();
    let (a, b) = (c[j] / h, c[k] / h);
    let w = (1.0 - a * a) * (1.0 - b * b);
    let (sin, cos) = (deg.to_radians() * w).sin_cos();
    c[j] = (a * cos - b * sin) * h;
    c[k] = (a * sin + b * cos) * h;
    Vec3::from_array(c)
}

fn twisted(deg: f32) -> Vec<Vec3> {
    box_mesh(Vec3::splat(SIZE), SUBDIVISIONS)
        .into_iter()
        .map(|p| twist(p, deg))
        .collect()
}

pub(super) fn scene() -> SceneFile {
    let aim = LIGHT + (CENTRE - LIGHT) * (LIGHT.y / (LIGHT.y - CENTRE.y));
    scene_file(
        "hard-static-silhouette",
        camera(Vec3::new(3.2, 6.9, 6.7), Vec3::new(1.5, 1.65, -1.5)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        vec![
            ground(16.0, 8),
            object(
                "box",
                Vec3::new(0.7, 0.55, 0.3),
                true,
                triangles(twisted(-TWIST_DEG), twisted(TWIST_DEG)),
                TransformFile {
                    translation: Some(CENTRE),
                    rotation_axis: Some(Vec3::Y),
                    rotation_deg: Some(YAW_DEG),
                    scale: None,
                },
                None,
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::super::super::{Light, Mesh};
    use super::super::check::{mesh, scene};
    use super::*;

    /// A position's bits: the same vertex in every triangle that lists it.
    type Key = [u32; 3];

    fn key(p: Vec3) -> Key {
        p.to_array().map(f32::to_bits)
    }

    fn at(m: &Mesh, i: usize, t: f32) -> Vec3 {
        m.t0[i].lerp(m.t1[i], t)
    }

    /// The box's local frame, to read back which face a world point lies on.
    fn local(p: Vec3) -> Vec3 {
        super::super::turn(Vec3::Y, -YAW_DEG) * (p - CENTRE)
    }

    /// The mesh is closed (every edge shared by two triangles, once in each direction), its
    /// vertices stay on the box's surface, and no triangle folds at any of 65 times.
    #[test]
    fn the_surface_is_a_static_box_while_the_interior_moves() {
        let s = scene("hard-static-silhouette");
        let m = mesh(&s, "box");
        assert!(m.closed);
        let mut edges: HashMap<(Key, Key), i32> = HashMap::new();
        for tri in m.t0.chunks_exact(3) {
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                *edges.entry((key(tri[a]), key(tri[b]))).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge used twice the same way");
            assert_eq!(edges.get(&(b, a)), Some(&1), "open edge");
        }
        let h = SIZE * 0.5;
        let mut moving = 0;
        for (&a, &b) in m.t0.iter().zip(&m.t1) {
            let (la, lb) = (local(a), local(b));
            // On the same face at both ends (the face's coordinate unchanged), inside it.
            let axis = (0..3).find(|&i| (la[i].abs() - h).abs() < 1e-4).unwrap();
            assert!((lb[axis] - la[axis]).abs() < 1e-4, "{a} leaves its face");
            assert!(lb.abs().max_element() < h + 1e-4 && la.abs().max_element() < h + 1e-4);
            if (a - b).length() > 1e-3 {
                moving += 1;
            }
        }
        assert!(moving > m.t0.len() / 2, "{moving} moving vertices");
        for k in 0..=64 {
            let t = k as f32 / 64.0;
            for i in (0..m.t0.len()).step_by(3) {
                let [p, q, r] = [i, i + 1, i + 2].map(|j| at(m, j, t));
                let n = (q - p).cross(r - p);
                let outward = local((p + q + r) / 3.0);
                let face = (0..3)
                    .max_by(|&x, &y| outward[x].abs().total_cmp(&outward[y].abs()))
                    .unwrap();
                let mut expected = Vec3::ZERO;
                expected[face] = outward[face].signum();
                let expected = super::super::turn(Vec3::Y, YAW_DEG) * expected;
                assert!(
                    n.normalize().dot(expected) > 0.999,
                    "triangle {} folds or leaves its face at t = {t}",
                    i / 3
                );
            }
        }
    }

    /// Seen from the light, every silhouette edge (shared by a triangle facing the light
    /// and one facing away) has both its ends static, at every one of 65 times.
    #[test]
    fn silhouette_edges_seen_from_the_light_are_static() {
        let s = scene("hard-static-silhouette");
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let m = mesh(&s, "box");
        let mut silhouette = 0;
        for k in 0..=64 {
            let t = k as f32 / 64.0;
            // Directed edge (start, end) at t0 -> (triangle faces the light, vertex indices).
            let mut edges: HashMap<(Key, Key), (bool, usize, usize)> = HashMap::new();
            for i in (0..m.t0.len()).step_by(3) {
                let [p, q, r] = [i, i + 1, i + 2].map(|j| at(m, j, t));
                let facing = (q - p).cross(r - p).dot(light.position - p) > 0.0;
                for (a, b) in [(i, i + 1), (i + 1, i + 2), (i + 2, i)] {
                    edges.insert((key(m.t0[a]), key(m.t0[b])), (facing, a, b));
                }
            }
            for (&(a, b), &(facing, i, j)) in &edges {
                let (other, _, _) = edges[&(b, a)];
                if facing && !other {
                    silhouette += 1;
                    for v in [i, j] {
                        assert_eq!(m.t0[v], m.t1[v], "silhouette vertex {v} moves (t = {t})");
                    }
                }
            }
        }
        // A hexagon of box edges, 8 mesh edges per box edge, at each of the 65 times.
        assert_eq!(silhouette, 6 * 8 * 65);
    }
}
