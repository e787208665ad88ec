//! The device's culling of closed meshes, mirrored: a triangle it culls all frame stores no
//! range.

use glam::DVec3;

/// A closed mesh's triangle is culled here only if it faces away by this share of its
/// facing's scale (the device culls in f32).
const CULL_MARGIN: f64 = 1e-5;

/// Whether a closed mesh's triangle is culled: its facing (as `shared.glsl`'s `facing`)
/// negative at t = 0, 1/3, 2/3 and 1 with both inner Bernstein coefficients negative, each
/// by a margin, so that f32 on the device culls at least what this culls.
pub(super) fn faces_away_whole_frame(e0: &[DVec3; 3], e1: &[DVec3; 3], orthographic: bool) -> bool {
    let f = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0].map(|t| {
        let p = [0, 1, 2].map(|k| e0[k].lerp(e1[k], t));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let value = if orthographic { n.z } else { -n.dot(p[0]) };
        let scale = if orthographic {
            n.length()
        } else {
            n.length() * p[0].length()
        };
        (value, scale)
    });
    let margin = CULL_MARGIN * f.iter().map(|x| x.1).fold(0.0, f64::max);
    let v = f.map(|x| x.0);
    let b1 = (-5.0 * v[0] + 18.0 * v[1] - 9.0 * v[2] + 2.0 * v[3]) / 6.0;
    let b2 = (2.0 * v[0] - 9.0 * v[1] + 18.0 * v[2] - 5.0 * v[3]) / 6.0;
    [v[0], b1, b2, v[3]].iter().all(|&x| x < -margin)
}
