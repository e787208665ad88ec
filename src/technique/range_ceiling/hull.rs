//! The convex hull of points in the plane.

use glam::DVec2;

/// The convex hull, counter-clockwise, without collinear points (Andrew's monotone chain);
/// one point for coincident ones, two for collinear ones.
pub(super) fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        // The chain's last point is the next chain's first.
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hull_drops_inner_and_collinear_points() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 2.0),
        ];
        let hull = convex_hull(&square);
        assert_eq!(hull.len(), 4);
        let area: f64 = (0..4)
            .map(|k| hull[k].perp_dot(hull[(k + 1) % 4]))
            .sum::<f64>()
            / 2.0;
        assert_eq!(area, 4.0, "counter-clockwise, area 4");
        assert_eq!(
            convex_hull(&[DVec2::ZERO, DVec2::ONE, DVec2::splat(3.0)]).len(),
            2
        );
    }
}
