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
