//! A still triangle cut to the light's frustum, so that its images lie on the map.

use glam::DVec3;

/// The polygon of clip-space (x, y, w) corners cut to the light's frustum: w >= `near_w`
/// and |x|, |y| <= w (Sutherland-Hodgman), so that its images lie on the map.
pub(super) fn clip_to_frustum(corners: &[DVec3; 3], near_w: f64) -> Vec<DVec3> {
    let planes: [DVec3; 5] = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, -1.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ];
    let mut poly = corners.to_vec();
    for (n, plane) in planes.iter().enumerate() {
        // Inside where plane . c >= offset (the near one) or >= 0.
        let offset = if n == 0 { near_w } else { 0.0 };
        let side = |c: DVec3| plane.dot(c) - offset;
        let mut out = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (sa, sb) = (side(a), side(b));
            if sa >= 0.0 {
                out.push(a);
            }
            if (sa >= 0.0) != (sb >= 0.0) {
                out.push(a.lerp(b, sa / (sa - sb)));
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}
