//! Midpoint (1-to-4) subdivision of a moving triangle list: each triangle becomes its three
//! corner triangles and the middle one, at t0 and at t1 alike. The midpoint of an edge whose
//! ends move linearly itself moves linearly, so subdividing the two end poses is the same
//! as subdividing the surface at every shutter time; the surface is unchanged, only finer.

use glam::Vec3;

use super::Mesh;

/// `mesh` subdivided `levels` times: 4^levels as many triangles, same winding. Each edge
/// midpoint is computed as (a + b) / 2, which is the same float whichever triangle (and so
/// whichever edge direction) computes it, so a watertight mesh stays watertight.
pub fn subdivide(mesh: &Mesh, levels: u32) -> Mesh {
    let mut t0 = mesh.t0.clone();
    let mut t1 = mesh.t1.clone();
    for _ in 0..levels {
        t0 = split(&t0);
        t1 = split(&t1);
    }
    Mesh {
        name: mesh.name.clone(),
        albedo: mesh.albedo,
        closed: mesh.closed,
        t0,
        t1,
    }
}

fn split(points: &[Vec3]) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(points.len() * 4);
    for t in points.chunks_exact(3) {
        let (a, b, c) = (t[0], t[1], t[2]);
        let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
        out.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(points: &[Vec3]) -> f32 {
        points
            .chunks_exact(3)
            .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0)
            .sum()
    }

    /// Whether `p` lies on triangle `t` (in its plane, barycentric coordinates in [0, 1]).
    fn on_triangle(p: Vec3, t: &[Vec3]) -> bool {
        let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
        let n = e1.cross(e2);
        let scale = n.length();
        if (d.dot(n) / scale).abs() > 1e-5 {
            return false;
        }
        let v = d.cross(e2).dot(n) / (scale * scale);
        let w = e1.cross(d).dot(n) / (scale * scale);
        v >= -1e-6 && w >= -1e-6 && v + w <= 1.0 + 1e-6
    }

    #[test]
    fn subdivision_keeps_the_surface_at_both_times() {
        // Two triangles that turn and stretch over the shutter.
        let t0 = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.5),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let t1 = vec![
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(2.0, 2.0, 2.0),
            Vec3::new(0.0, 0.0, 3.0),
        ];
        let mesh = Mesh {
            name: "m".into(),
            albedo: Vec3::ONE,
            closed: false,
            t0,
            t1,
        };
        let fine = subdivide(&mesh, 3);
        assert_eq!(fine.triangle_count(), 2 * 64);
        for (coarse, fine) in [(&mesh.t0, &fine.t0), (&mesh.t1, &fine.t1)] {
            let (a, b) = (area(coarse), area(fine));
            assert!((a - b).abs() < 1e-5 * a, "area {a} became {b}");
            // Each original triangle's 64 pieces lie on it, in order.
            for (k, piece) in fine.chunks_exact(3 * 64).enumerate() {
                let original = &coarse[3 * k..3 * k + 3];
                assert!(piece.iter().all(|&p| on_triangle(p, original)));
                // Same winding as the original.
                let n = (original[1] - original[0]).cross(original[2] - original[0]);
                assert!(
                    piece
                        .chunks_exact(3)
                        .all(|t| { (t[1] - t[0]).cross(t[2] - t[0]).dot(n) > 0.0 })
                );
            }
        }
        // A vertex at shutter time s is the same blend of the coarse corners at t0 and t1,
        // so the fine mesh at s is the coarse mesh at s subdivided: checked at s = 1/2.
        let mid = |m: &Mesh| Mesh {
            t0: m
                .t0
                .iter()
                .zip(&m.t1)
                .map(|(a, b)| (*a + *b) * 0.5)
                .collect(),
            t1: m.t1.clone(),
            ..m.clone()
        };
        let direct = subdivide(&mid(&mesh), 3).t0;
        let blended = mid(&fine).t0;
        assert!(
            direct
                .iter()
                .zip(&blended)
                .all(|(a, b)| (*a - *b).length() < 1e-5)
        );
    }
}
