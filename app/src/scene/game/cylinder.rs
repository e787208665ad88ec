//! A faceted cylinder as a plain triangle list, for `game-level`'s pillars. The scene format
//! has boxes and planes only; a round pillar is built in memory and written into the scene
//! file as explicit `triangles`, as the characters are, so the file format needs no new
//! mesh kind.

use glam::Vec3;

/// A closed cylinder around +y from y = 0 to `height`, of `facets` flat sides (at least 3),
/// each split into `rings` quads up its height (at least 1), with a fan cap at each end:
/// 2 * facets * rings + 2 * facets triangles, counter-clockwise seen from outside. The
/// side rings give the renderer vertices to work with, as the boxes' subdivisions do.
pub(super) fn cylinder_mesh(radius: f32, height: f32, facets: u32, rings: u32) -> Vec<Vec3> {
    let (facets, rings) = (facets.max(3), rings.max(1));
    let around = |k: u32, y: f32| {
        let a = std::f32::consts::TAU * k as f32 / facets as f32;
        // k == facets lands exactly on k == 0, so the side closes without a seam.
        let (s, c) = if k == facets { (0.0, 1.0) } else { a.sin_cos() };
        Vec3::new(radius * c, y, -radius * s)
    };
    let level = |r: u32| height * r as f32 / rings as f32;
    let mut out = Vec::with_capacity(6 * (facets * (rings + 1)) as usize);
    for k in 0..facets {
        for r in 0..rings {
            let (a, b) = (around(k, level(r)), around(k + 1, level(r)));
            let (c, d) = (around(k + 1, level(r + 1)), around(k, level(r + 1)));
            // Going around counter-clockwise seen from +y, then up: outward normal.
            out.extend_from_slice(&[a, b, c, a, c, d]);
        }
        let top = Vec3::new(0.0, height, 0.0);
        out.extend_from_slice(&[top, around(k, height), around(k + 1, height)]);
        out.extend_from_slice(&[Vec3::ZERO, around(k + 1, 0.0), around(k, 0.0)]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts, bounds, every triangle facing away from the axis (sides) or along it (caps),
    /// and closed: every edge is shared by exactly two triangles in opposite directions.
    #[test]
    fn closed_outward_cylinder_of_the_asked_size() {
        let (radius, height, facets, rings) = (0.4, 3.0, 12, 5);
        let tris = cylinder_mesh(radius, height, facets, rings);
        assert_eq!(tris.len() / 3, (2 * facets * rings + 2 * facets) as usize);
        for t in tris.chunks_exact(3) {
            let normal = (t[1] - t[0]).cross(t[2] - t[0]);
            let centroid = (t[0] + t[1] + t[2]) / 3.0;
            let outward = if t.iter().all(|p| p.y == height) {
                Vec3::Y
            } else if t.iter().all(|p| p.y == 0.0) {
                Vec3::NEG_Y
            } else {
                Vec3::new(centroid.x, 0.0, centroid.z)
            };
            assert!(normal.length() > 0.0, "degenerate triangle {t:?}");
            assert!(
                normal.normalize().dot(outward.normalize()) > 0.95,
                "inward at {centroid}"
            );
            for p in t {
                let r = (p.x * p.x + p.z * p.z).sqrt();
                assert!(r <= radius + 1e-6 && (0.0..=height).contains(&p.y), "{p}");
            }
        }
        let key = |p: Vec3| (p * 1e4).round().as_ivec3().to_array();
        let mut edges = std::collections::HashMap::new();
        for t in tris.chunks_exact(3) {
            for i in 0..3 {
                *edges.entry((key(t[i]), key(t[(i + 1) % 3]))).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a:?}-{b:?} used {n} times one way");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a:?}-{b:?} has no twin");
        }
    }
}
