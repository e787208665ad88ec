//! The scene's triangles as the tracer reads them: corners at shutter open and their motion,
//! in f64, with the global ids and the albedo the GPU methods give them.

use crate::scene::Scene;
use glam::{DVec3, Vec3};

/// One triangle: corner i is at `p0[i] + t * d[i]` at shutter time t.
///
/// That is the scene's `(1 - t) p0 + t p1`, written so that a corner that does not move
/// (`d = 0`) is exactly `p0` at every time: the GPU methods take a static triangle at t = 0
/// exactly, and triangles sharing a corner, one moving and one not, must see the same
/// corner at every time, or a watertight test would find a crack between them.
#[derive(Debug, Clone, Copy)]
pub struct Triangle {
    pub p0: [DVec3; 3],
    pub d: [DVec3; 3],
    /// Global id: position in scene order, mesh by mesh (as the GPU uploads them).
    pub id: u32,
    /// Index of its mesh in the scene (albedo).
    pub mesh: u32,
    /// Some corner moves (as the GPU decides: the f32 positions differ).
    pub moving: bool,
}

impl Triangle {
    pub fn new(p0: [Vec3; 3], p1: [Vec3; 3], id: u32, mesh: u32) -> Self {
        let moving = p0 != p1;
        let p0 = p0.map(Vec3::as_dvec3);
        let d = [0, 1, 2].map(|i| p1[i].as_dvec3() - p0[i]);
        Self {
            p0,
            d,
            id,
            mesh,
            moving,
        }
    }

    /// The corners at time t.
    #[inline]
    pub fn at(&self, t: f64) -> [DVec3; 3] {
        if !self.moving {
            return self.p0;
        }
        [0, 1, 2].map(|i| self.p0[i] + t * self.d[i])
    }

    /// Corners at t = 0 and at t = 1: (min, max) per shutter end.
    pub fn end_bounds(&self) -> [(DVec3, DVec3); 2] {
        [0.0, 1.0].map(|t| {
            let v = self.at(t);
            (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]))
        })
    }
}

/// Every mesh's triangles in scene order, ids counted as the GPU upload counts them.
pub fn scene_triangles(scene: &Scene) -> Vec<Triangle> {
    let mut triangles = Vec::with_capacity(scene.triangle_count());
    let mut id = 0u32;
    for (m, mesh) in scene.meshes.iter().enumerate() {
        for (c0, c1) in mesh.t0.chunks_exact(3).zip(mesh.t1.chunks_exact(3)) {
            triangles.push(Triangle::new(
                [c0[0], c0[1], c0[2]],
                [c1[0], c1[1], c1[2]],
                id,
                m as u32,
            ));
            id += 1;
        }
    }
    triangles
}
