//! The map's texel grid: clip-space points to texel units, and functions of a texel centre's
//! ray as affine functions of its texel coordinates.

use glam::{DVec2, DVec3};

#[derive(Debug, Clone)]
pub(super) struct Map {
    pub(super) width: f64,
    pub(super) height: f64,
}

impl Map {
    pub(super) fn texels(&self) -> u64 {
        (self.width * self.height) as u64
    }

    /// Clip (x, y, w) to texel units (texel x's centre at x + 0.5).
    pub(super) fn texel(&self, c: DVec3) -> DVec2 {
        DVec2::new(
            (c.x / c.z + 1.0) * 0.5 * self.width,
            (c.y / c.z + 1.0) * 0.5 * self.height,
        )
    }

    /// r . n for the centre's ray r = (X, Y, 1) (NDC), as an affine function of texel
    /// coordinates: (a, b, c) with r . n = a x + b y + c.
    pub(super) fn affine(&self, n: DVec3) -> (f64, f64, f64) {
        (
            2.0 * n.x / self.width,
            2.0 * n.y / self.height,
            n.z - n.x - n.y,
        )
    }
}

/// An affine function of texel coordinates, a x + b y + c.
pub(super) type Affine = (f64, f64, f64);

pub(super) fn eval(f: Affine, p: DVec2) -> f64 {
    f.0 * p.x + f.1 * p.y + f.2
}
