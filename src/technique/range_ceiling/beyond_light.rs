//! The footprint of a triangle that reaches behind the light: the centres whose rays meet its
//! swept hull in front of the light, as points whose convex hull holds them.

use glam::{DVec2, DVec3};

use super::map::Map;

/// A triangle reaching behind the light: each corner stands for a box this share of the
/// largest coordinate wide (f32 rounds corners by about 6e-8 of it), and a cone of recession
/// directions wider than `MAX_CONE` radians counts every centre (the far points it takes
/// grow as 1 / cos(span / 2)).
const BOX: f64 = 1e-5;
const MAX_CONE: f64 = 2.8;

impl Map {
    /// Points (texel units) whose convex hull holds every centre that a triangle moving
    /// within the convex hull of clip-space `corners` (x, y, w) can cover, some of them at
    /// or behind the light or imaged beyond `reach`; None where that may be every centre.
    ///
    /// A centre's ray r = (X, Y, 1) meets the hull in front of the light iff r is a
    /// nonnegative combination of the corners. Eliminating w (Fourier-Motzkin), those rays
    /// are the convex hull of the images of the corners in front plus the cone of the
    /// recession directions: the (x, y) of corners with w = 0 and, for each corner i in
    /// front and j behind, -w_j c_i + w_i c_j (whose w is 0). The device rounds its f32
    /// corners (a backward error far below `BOX`), so each corner is replaced by the corners
    /// of a box around it and the exact rule applied to those. An image beyond `reach` is
    /// cut back along its ray from the map's centre, its direction added. Where the cone is
    /// pointed, the hull plus the cone meets the map only within `far` of the points along
    /// the cone's two extreme directions.
    pub(super) fn beyond_the_light_footprint(
        &self,
        corners: &[DVec3],
        reach: f64,
    ) -> Option<Vec<DVec2>> {
        let scale = DVec2::new(0.5 * self.width, 0.5 * self.height);
        let centre = scale;
        let size = corners
            .iter()
            .map(|c| c.abs().max_element())
            .fold(0.0, f64::max);
        let h = BOX * size;
        let boxed: Vec<DVec3> = corners
            .iter()
            .flat_map(|c| {
                (0..8).map(move |k| {
                    let s = |bit: usize| if k >> bit & 1 == 1 { h } else { -h };
                    *c + DVec3::new(s(0), s(1), s(2))
                })
            })
            .collect();
        let mut points = Vec::new();
        let mut directions = Vec::new();
        for c in &boxed {
            if c.z > 0.0 {
                let off = self.texel(*c) - centre;
                let most = off.abs().max_element();
                if most > reach || !most.is_finite() {
                    let xy = c.truncate() * scale;
                    points.push(centre + xy * (reach / xy.abs().max_element()));
                    directions.push(xy);
                } else {
                    points.push(centre + off);
                }
            } else if c.z == 0.0 {
                directions.push(c.truncate() * scale);
            }
        }
        for i in boxed.iter().filter(|c| c.z > 0.0) {
            for j in boxed.iter().filter(|c| c.z < 0.0) {
                directions.push((-j.z * i.truncate() + i.z * j.truncate()) * scale);
            }
        }
        if points.is_empty() {
            return None;
        }
        if directions.is_empty() {
            return Some(points);
        }
        let (first, last) = pointed_cone(&directions)?;
        let (first, last) = (first.normalize(), last.normalize());
        // Far enough that a point farther along the cone from the hull is off the map.
        let half_span = first.angle_to(last).abs() / 2.0;
        let beyond = points
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max)
            + 2.0 * centre.length();
        let far = beyond / half_span.cos() + 1.0;
        let base = points.clone();
        for p in base {
            points.push(p + far * first);
            points.push(p + far * last);
        }
        Some(points)
    }
}

/// The extreme directions of the cone the nonzero `directions` span, counter-clockwise from
/// the first to the last, or None unless it spans at most `MAX_CONE` radians.
fn pointed_cone(directions: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let mut angles: Vec<(f64, DVec2)> = directions
        .iter()
        .filter(|d| d.length() > 0.0)
        .map(|d| (d.y.atan2(d.x), *d))
        .collect();
    angles.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = angles.len();
    if n == 0 {
        return None;
    }
    // The widest gap between neighbours (the last to the first across the wrap included):
    // the cone is the rest of the circle.
    let (mut gap, mut after) = (angles[0].0 + std::f64::consts::TAU - angles[n - 1].0, 0);
    for k in 1..n {
        let g = angles[k].0 - angles[k - 1].0;
        if g > gap {
            (gap, after) = (g, k);
        }
    }
    let span = std::f64::consts::TAU - gap;
    (span <= MAX_CONE).then(|| (angles[after].1, angles[(after + n - 1) % n].1))
}
