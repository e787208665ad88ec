//! The texel centres a triangle's ranges may lie at, and how many of them an edge may turn
//! at, counted row by row.

use glam::DVec2;

use super::hull::convex_hull;
use super::map::{Affine, Map};

/// How far the hull is grown, in texels: far more than f32 rounding of the corners' images
/// (about 1e-3 texel at 4096 texels), far less than a texel. (A triangle that does not move
/// is cut to the light's frustum first; the cut points are as exact as its corners.)
pub(super) const GROWTH_TEXELS: f64 = 0.125;

/// The texel centres a triangle's ranges may lie at: the convex hull of its corners' images
/// at t = 0 and t = 1, grown by `GROWTH_TEXELS`, within the map.
pub(super) struct Footprint {
    /// Each hull edge as a x + b y + c >= 0 inside, grown (a unit normal).
    edges: Vec<(f64, f64, f64)>,
    /// The grown hull's box, within the map's centres; None when it holds none.
    pub(super) bounds: Option<(DVec2, DVec2)>,
}

impl Footprint {
    pub(super) fn new(points: &[DVec2], map: &Map) -> Self {
        Self::grown(points, map, GROWTH_TEXELS)
    }

    /// The hull of `points` grown by `growth` texels (at least `GROWTH_TEXELS`), within the
    /// map.
    pub(super) fn grown(points: &[DVec2], map: &Map, growth: f64) -> Self {
        let hull = convex_hull(points);
        let n = hull.len();
        let mut edges = Vec::with_capacity(n.max(2));
        // A hull of two points is a segment: both of its sides bound the slab around it.
        for k in 0..if n == 2 {
            2
        } else if n >= 3 {
            n
        } else {
            0
        } {
            let (u, v) = (hull[k], hull[(k + 1) % n]);
            let d = (v - u).normalize();
            // Counter-clockwise hull: inside is to the left of u -> v.
            let (a, b) = (-d.y, d.x);
            edges.push((a, b, -(a * u.x + b * u.y) + growth));
        }
        let lo = hull.iter().copied().fold(DVec2::INFINITY, DVec2::min) - growth;
        let hi = hull.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max) + growth;
        let lo = lo.max(DVec2::splat(0.5));
        let hi = hi.min(DVec2::new(map.width - 0.5, map.height - 0.5));
        Self {
            edges,
            bounds: (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi)),
        }
    }

    /// Centres (x + 0.5, y + 0.5) inside, row by row; and the sum over them of how many of
    /// `turning` edges are not monotone there (e_k' at t = 0 and t = 1 not of one sign by
    /// the margin).
    pub(super) fn count(&self, turning: &[(Affine, Affine, f64)]) -> (u64, u64) {
        let Some((lo, hi)) = self.bounds else {
            return (0, 0);
        };
        let (mut count, mut turns) = (0u64, 0u64);
        let mut row = (lo.y - 0.5).ceil();
        while row + 0.5 <= hi.y {
            let y = row + 0.5;
            let (mut from, mut to) = (lo.x, hi.x);
            for &(a, b, c) in &self.edges {
                let rest = b * y + c;
                if a > 0.0 {
                    from = from.max(-rest / a);
                } else if a < 0.0 {
                    to = to.min(-rest / a);
                } else if rest < 0.0 {
                    to = f64::NEG_INFINITY;
                }
            }
            // Centre columns i with from <= i + 0.5 <= to.
            let (first, last) = ((from - 0.5).ceil(), (to - 0.5).floor());
            if last >= first {
                let n = (last - first + 1.0) as u64;
                count += n;
                for &(at0, at1, margin) in turning {
                    let safe = monotone_columns(at0, at1, margin, y, (first, last));
                    turns += n - safe;
                }
            }
            row += 1.0;
        }
        (count, turns)
    }
}

/// Columns i in `cols` (inclusive) whose centre (i + 0.5, y) has both affine functions
/// above `margin`, or both below `-margin` (strictly).
fn monotone_columns(f: Affine, g: Affine, margin: f64, y: f64, cols: (f64, f64)) -> u64 {
    let mut safe = 0u64;
    for sign in [1.0, -1.0] {
        // sign * (a x + r) > margin for x = i + 0.5: an open half-line of i.
        let (mut lo, mut hi) = (cols.0, cols.1);
        for h in [f, g] {
            let (a, r) = (sign * h.0, sign * (h.1 * y + h.2));
            // a (i + 0.5) > margin - r
            let bound = (margin - r) / a - 0.5;
            if a > 0.0 {
                lo = lo.max(bound.floor() + 1.0);
            } else if a < 0.0 {
                hi = hi.min(bound.ceil() - 1.0);
            } else if r <= margin {
                hi = f64::NEG_INFINITY;
            }
        }
        if hi >= lo {
            safe += (hi - lo + 1.0) as u64;
        }
    }
    safe
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Centres within `GROWTH_TEXELS` of the hull of `points` (inside it, or that near its
    /// boundary), texel by texel: never more than the footprint counts, and every centre
    /// inside the hull itself counted.
    #[test]
    fn the_footprint_holds_every_centre_of_the_hull() {
        let map = Map {
            width: 41.0,
            height: 29.0,
        };
        let cases: [&[DVec2]; 4] = [
            &[
                DVec2::new(1.2, 2.7),
                DVec2::new(30.4, 5.1),
                DVec2::new(8.9, 21.3),
                DVec2::new(12.0, 3.0),
                DVec2::new(35.5, 25.5),
                DVec2::new(20.0, 10.0),
            ],
            // Reaching past the map on every side.
            &[
                DVec2::new(-5.0, -3.0),
                DVec2::new(10.0, 40.0),
                DVec2::new(55.0, 4.0),
            ],
            // A segment, and a point.
            &[
                DVec2::new(2.5, 2.5),
                DVec2::new(30.5, 20.5),
                DVec2::new(16.5, 11.5),
            ],
            &[DVec2::new(7.5, 7.5), DVec2::new(7.5, 7.5)],
        ];
        for points in cases {
            let hull = convex_hull(points);
            let inside = |p: DVec2, grow: f64| -> bool {
                match hull.len() {
                    1 => p.distance(hull[0]) <= grow,
                    2 => {
                        let (u, v) = (hull[0], hull[1]);
                        let t = ((p - u).dot(v - u) / (v - u).length_squared()).clamp(0.0, 1.0);
                        p.distance(u + t * (v - u)) <= grow
                    }
                    n => (0..n).all(|k| {
                        let (u, v) = (hull[k], hull[(k + 1) % n]);
                        (v - u).perp_dot(p - u) / (v - u).length() >= -grow
                    }),
                }
            };
            let (mut strict, mut near) = (0, 0);
            for y in 0..29 {
                for x in 0..41 {
                    let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                    strict += u64::from(inside(p, 0.0));
                    near += u64::from(inside(p, GROWTH_TEXELS));
                }
            }
            let counted = Footprint::new(points, &map).count(&[]).0;
            assert!(counted >= near, "{points:?}: {counted} < {near}");
            // Growing the edges' lines overshoots only at corners and the segment's ends.
            assert!(counted <= near + 4, "{points:?}: {counted} vs {near}");
            assert!(strict <= near);
        }
    }
}
