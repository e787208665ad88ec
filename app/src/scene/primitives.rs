//! Tessellated boxes and planes as plain triangle lists, plus the rigid transform used to
//! place them. Tessellation matters: the renderer's motion blur works per vertex, so big
//! faces are split to give it enough vertices to move.

use glam::{Mat4, Quat, Vec2, Vec3};

/// Appends a grid of `n` x `n` quads (2 triangles each) spanning
/// `center ± u ± v`. Wound counter-clockwise around u x v, which is the outward normal.
fn push_grid(out: &mut Vec<Vec3>, center: Vec3, u: Vec3, v: Vec3, n: u32) {
    let point = |i: u32, j: u32| {
        let a = 2.0 * i as f32 / n as f32 - 1.0;
        let b = 2.0 * j as f32 / n as f32 - 1.0;
        center + u * a + v * b
    };
    for i in 0..n {
        for j in 0..n {
            let (p00, p10, p11, p01) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            out.extend_from_slice(&[p00, p10, p11, p00, p11, p01]);
        }
    }
}

/// Box of the given full size centred at the origin; each face is a `subdivisions` x
/// `subdivisions` grid (0 is treated as 1), so 12 * n^2 triangles, wound counter-clockwise
/// seen from outside (cross(b - a, c - a) points outward).
pub fn box_mesh(size: Vec3, subdivisions: u32) -> Vec<Vec3> {
    let n = subdivisions.max(1);
    let h = size * 0.5;
    let (x, y, z) = (Vec3::X * h.x, Vec3::Y * h.y, Vec3::Z * h.z);
    // (outward normal offset, u, v) with u x v along the outward normal.
    let faces = [
        (x, y, z),
        (-x, z, y),
        (y, z, x),
        (-y, x, z),
        (z, x, y),
        (-z, y, x),
    ];
    let mut out = Vec::with_capacity(36 * (n * n) as usize);
    for (c, u, v) in faces {
        push_grid(&mut out, c, u, v, n);
    }
    out
}

/// Plane in XZ at y = 0, centred at the origin, `size.x` along X and `size.y` along Z; a
/// `subdivisions` x `subdivisions` grid (0 is treated as 1), 2 * n^2 triangles, normal +Y
/// (counter-clockwise seen from above).
pub fn plane_mesh(size: Vec2, subdivisions: u32) -> Vec<Vec3> {
    let n = subdivisions.max(1);
    let mut out = Vec::with_capacity(6 * (n * n) as usize);
    let u = Vec3::Z * (size.y * 0.5);
    let v = Vec3::X * (size.x * 0.5);
    push_grid(&mut out, Vec3::ZERO, u, v, n);
    out
}

/// Scale, then rotate `rotation_deg` degrees about `rotation_axis` (right-hand rule; any
/// non-zero length; a zero axis means no rotation), then translate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidTransform {
    pub translation: Vec3,
    pub rotation_axis: Vec3,
    pub rotation_deg: f32,
    pub scale: Vec3,
}

impl Default for RigidTransform {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation_axis: Vec3::Y,
            rotation_deg: 0.0,
            scale: Vec3::ONE,
        }
    }
}

impl RigidTransform {
    pub fn rotation(&self) -> Quat {
        match self.rotation_axis.try_normalize() {
            Some(axis) => Quat::from_axis_angle(axis, self.rotation_deg.to_radians()),
            None => Quat::IDENTITY,
        }
    }

    pub fn to_mat4(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation(), self.translation)
    }

    /// Transforms every point (positions, so translation applies).
    pub fn apply(&self, points: &[Vec3]) -> Vec<Vec3> {
        let m = self.to_mat4();
        points.iter().map(|&p| m.transform_point3(p)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normals(tris: &[Vec3]) -> impl Iterator<Item = (Vec3, Vec3)> + '_ {
        tris.chunks_exact(3)
            .map(|t| ((t[1] - t[0]).cross(t[2] - t[0]), (t[0] + t[1] + t[2]) / 3.0))
    }

    #[test]
    fn box_counts_and_outward_winding() {
        for n in [1, 2, 5] {
            let size = Vec3::new(1.0, 2.0, 3.0);
            let tris = box_mesh(size, n);
            assert_eq!(tris.len(), 3 * 12 * (n * n) as usize);
            for (normal, centroid) in normals(&tris) {
                // Outward: the normal points along the face's offset from the centre.
                let face = (centroid / (size * 0.5)).abs();
                let axis = if face.x > 0.999 {
                    Vec3::X
                } else if face.y > 0.999 {
                    Vec3::Y
                } else {
                    Vec3::Z
                };
                assert!(
                    normal.dot(centroid * axis) > 0.0,
                    "inward triangle at {centroid}"
                );
                assert!((normal.normalize() - (centroid * axis).normalize()).length() < 1e-4);
            }
            let (lo, hi) = tris
                .iter()
                .fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
            assert_eq!((lo, hi), (-size * 0.5, size * 0.5));
        }
        assert_eq!(box_mesh(Vec3::ONE, 0).len(), 36);
    }

    #[test]
    fn plane_counts_and_up_winding() {
        let tris = plane_mesh(Vec2::new(4.0, 2.0), 3);
        assert_eq!(tris.len(), 3 * 2 * 9);
        for (normal, _) in normals(&tris) {
            assert!(normal.y > 0.0 && normal.x == 0.0 && normal.z == 0.0);
        }
        assert!(
            tris.iter()
                .all(|p| p.y == 0.0 && p.x.abs() <= 2.0 && p.z.abs() <= 1.0)
        );
        assert!(tris.iter().any(|p| p.x == 2.0) && tris.iter().any(|p| p.z == -1.0));
    }

    #[test]
    fn transform_order_is_scale_rotate_translate() {
        let t = RigidTransform {
            translation: Vec3::new(10.0, 0.0, 0.0),
            rotation_axis: Vec3::Z * 3.0,
            rotation_deg: 90.0,
            scale: Vec3::new(2.0, 1.0, 1.0),
        };
        // (1,0,0) -> scale (2,0,0) -> rotate about Z (0,2,0) -> translate (10,2,0).
        let p = t.apply(&[Vec3::X])[0];
        assert!((p - Vec3::new(10.0, 2.0, 0.0)).length() < 1e-5, "{p}");
        let id = RigidTransform {
            rotation_axis: Vec3::ZERO,
            rotation_deg: 30.0,
            ..Default::default()
        };
        assert_eq!(id.to_mat4(), Mat4::IDENTITY);
        assert_eq!(RigidTransform::default().to_mat4(), Mat4::IDENTITY);
    }
}
