//! Where a turning light's map misplaces what moves (issue 38). The temporal map blends each
//! vertex's light-clip positions at the two ends, `(1 - t) V0 p0 + t V1 p1`; a moving point
//! seen at t by the blended view is `((1 - t) V0 + t V1) ((1 - t) p0 + t p1)`, which differs
//! by `t (1 - t) (V1 - V0) (p1 - p0)`: nothing for a still point or a translating light, up to
//! a quarter of `(R1 - R0) (p1 - p0)` at mid-shutter for a point moving across the turn (R0,
//! R1: the two views' rotations). The temporal deferred mask takes a turning light only where
//! that stays below [`MISPLACEMENT_TOLERANCE`].

use crate::scene::Scene;
use glam::Mat3;
use motion_shadows::technique::LightView;

/// World units: below this the blend's misplacement of moving geometry is rounding. Measured
/// (docs/src/deferred-frame.md#a-turning-light): `moving-light`'s box sliding 2 units across
/// a flashlight turned 5 degrees about the vertical, misplaced by up to 0.044 at mid-shutter,
/// takes the mask from 0.0029 (the box held still) to 0.0186 RMSE against the truth.
pub const MISPLACEMENT_TOLERANCE: f32 = 1e-3;

/// The largest distance, in the light's view, by which the map of `light` (a moving one)
/// misplaces a vertex of `scene` at mid-shutter: `|(R1 - R0) (p1 - p0)| / 4`.
pub fn turn_misplacement(scene: &Scene, light: &LightView) -> f32 {
    if !light.is_turning() {
        return 0.0;
    }
    let r0 = Mat3::from_mat4(light.gpu().view);
    let r1 = Mat3::from_mat4(light.gpu_end().view);
    let turn = r1 - r0;
    scene
        .meshes
        .iter()
        .flat_map(|m| m.t0.iter().zip(&m.t1))
        .map(|(&p0, &p1)| (turn * (p1 - p0)).length() / 4.0)
        .fold(0.0, f32::max)
}
