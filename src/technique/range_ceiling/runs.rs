//! How many runs one texel centre holds: at most one per stretch between sign changes of the
//! triangle's orientation det(V(t)), where every edge function e_k is monotone in t there,
//! and one more for each edge that may turn.
//!
//! With r = (X, Y, 1) the centre's ray and v_k(t) the corners' clip (x, y, w), the run
//! boundaries are the roots of e_k(t) = det(v_i(t), v_j(t), r) = A + B t + C t^2, and the
//! centre is covered while every e_k has the sign of det(V(t)), a cubic that is the same for
//! every centre (Cramer, see `light_crossing.glsl`). If every e_k is monotone on [0, 1] at
//! every centre of the footprint, {e_k has a given sign} is an interval, their intersection
//! too, so each stretch between sign changes of det(V) holds at most one run: runs <= 1 +
//! those sign changes. e_k' = B + 2 C t is affine in t and in r, so it keeps one sign over
//! [0, 1] x footprint iff it has that sign at t = 0 and t = 1 at the footprint's corners.
//! Elsewhere (an e_k that turns, a corner at or behind the light) the shader's own cap holds:
//! `EXACT_MAX_RUNS`.

use glam::{DVec2, DVec3};

use super::footprint::Footprint;
use super::map::{Affine, Map, eval};

/// e_k' must keep its sign by this share of its largest value over the footprint's
/// corners, so f32's roots cannot split a run the f64 test calls monotone.
const MONOTONE_MARGIN: f64 = 1e-6;

/// For each edge k whose e_k may turn somewhere in the footprint: e_k' = B + 2 C t at t = 0
/// and t = 1, as affine functions of the texel, and the margin by which both must share a
/// sign for e_k to count as monotone there.
pub(super) fn turning_edges(
    v0: &[DVec3; 3],
    v1: &[DVec3; 3],
    map: &Map,
    footprint: &Footprint,
) -> Vec<(Affine, Affine, f64)> {
    let Some((lo, hi)) = footprint.bounds else {
        return Vec::new();
    };
    let corners = [
        DVec2::new(lo.x, lo.y),
        DVec2::new(hi.x, lo.y),
        DVec2::new(lo.x, hi.y),
        DVec2::new(hi.x, hi.y),
    ];
    let d: [DVec3; 3] = [0, 1, 2].map(|k| v1[k] - v0[k]);
    let mut turning = Vec::new();
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // det(a, b, r) = r . (a x b).
        let n_b = v0[i].cross(d[j]) + d[i].cross(v0[j]);
        let n_c = d[i].cross(d[j]);
        let at0 = map.affine(n_b);
        let at1 = map.affine(n_b + 2.0 * n_c);
        let values = corners.iter().flat_map(|&p| [eval(at0, p), eval(at1, p)]);
        let largest = values.clone().map(f64::abs).fold(0.0, f64::max);
        if largest == 0.0 {
            // e_k does not change at all: no root.
            continue;
        }
        let margin = MONOTONE_MARGIN * largest;
        let mut values = values;
        if values.clone().all(|v| v > margin) || values.all(|v| v < -margin) {
            continue;
        }
        turning.push((at0, at1, margin));
    }
    turning
}

/// At most how many times det(V(t)) changes sign in (0, 1): it is monotone between the roots
/// of its derivative, so once per stretch between them at most, counted where its ends'
/// signs differ or either end is too near zero to tell.
pub(super) fn det_sign_changes(v0: &[DVec3; 3], v1: &[DVec3; 3]) -> u64 {
    let at = |t: f64| {
        let v = [0, 1, 2].map(|k| v0[k].lerp(v1[k], t));
        v[0].dot(v[1].cross(v[2]))
    };
    // Its magnitude's scale, for "too near zero".
    let scale = (0..=4)
        .map(|i| {
            let v = [0, 1, 2].map(|k| v0[k].lerp(v1[k], f64::from(i) / 4.0));
            v[0].length() * v[1].length() * v[2].length()
        })
        .fold(0.0, f64::max);
    let d: [DVec3; 3] = [0, 1, 2].map(|k| v1[k] - v0[k]);
    let p = v0;
    let c1 = d[0].dot(p[1].cross(p[2])) + p[0].dot(d[1].cross(p[2])) + p[0].dot(p[1].cross(d[2]));
    let c2 = p[0].dot(d[1].cross(d[2])) + d[0].dot(p[1].cross(d[2])) + d[0].dot(d[1].cross(p[2]));
    let c3 = d[0].dot(d[1].cross(d[2]));
    let mut ends = vec![0.0, 1.0];
    ends.extend(quadratic_roots01(3.0 * c3, 2.0 * c2, c1));
    ends.sort_by(f64::total_cmp);
    let tiny = 1e-9 * scale;
    ends.windows(2)
        .filter(|e| {
            let (a, b) = (at(e[0]), at(e[1]));
            a.abs() <= tiny || b.abs() <= tiny || (a < 0.0) != (b < 0.0)
        })
        .count() as u64
}

/// The real roots of a t^2 + b t + c in (0, 1) (a linear or constant one too).
fn quadratic_roots01(a: f64, b: f64, c: f64) -> Vec<f64> {
    let roots = if a == 0.0 {
        if b == 0.0 { vec![] } else { vec![-c / b] }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            vec![]
        } else {
            let q = -0.5 * (b + disc.sqrt().copysign(b));
            if q == 0.0 {
                vec![0.0]
            } else {
                vec![q / a, c / q]
            }
        }
    };
    roots.into_iter().filter(|r| *r > 0.0 && *r < 1.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle translating (every corner the same displacement) under an orthographic
    /// light: each e_k is linear in t, so one run per centre; a turning one may have more.
    #[test]
    fn edges_turn_only_where_the_triangle_turns() {
        let map = Map {
            width: 64.0,
            height: 64.0,
        };
        let whole = Footprint::new(
            &[
                DVec2::splat(0.0),
                DVec2::new(64.0, 0.0),
                DVec2::splat(64.0),
                DVec2::new(0.0, 64.0),
            ],
            &map,
        );
        let tri = [
            DVec3::new(-0.5, -0.5, 1.0),
            DVec3::new(0.5, -0.4, 1.0),
            DVec3::new(0.0, 0.5, 1.0),
        ];
        let moved = tri.map(|c| c + DVec3::new(0.3, 0.1, 0.0));
        assert!(turning_edges(&tri, &moved, &map, &whole).is_empty());
        assert_eq!(det_sign_changes(&tri, &moved), 0);
        // Turned by 180 degrees about its centroid: the edges sweep over centres and back.
        let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
        let turned = tri.map(|c| DVec3::new(2.0 * centroid.x - c.x, 2.0 * centroid.y - c.y, 1.0));
        let turning = turning_edges(&tri, &turned, &map, &whole);
        assert!(!turning.is_empty());
        let (centres, turns) = whole.count(&turning);
        assert_eq!(centres, 64 * 64);
        assert!(turns > 0 && turns < 3 * centres, "{turns}");
        // Mirrored through a line: the orientation flips once.
        let mirrored = tri.map(|c| DVec3::new(-c.x, c.y, 1.0));
        assert_eq!(det_sign_changes(&tri, &mirrored), 1);
    }
}
