//! A lower bound on the ranges a temporal frame stores, from the scene alone, so that a map
//! that cannot fit on the device is refused before its shadow pass (issue 25, case 11a: the
//! need was known only after a whole collection, over a minute at 4096x4096 for a heavy
//! scene, which then had to be thrown away), and one that fits gets room for it at once.
//!
//! With the exact prisms, every (texel, moving triangle) pair whose texel centre the
//! triangle covers at some time of the shutter stores at least one range (a covered run:
//! stored directly, or as two nodes the generation pairs). The count of such pairs, with the
//! covered centres found at a few sample times, bounds the ranges from below. Counted only
//! where that holds for certain:
//! - triangles whose corners move (a static one may be in the static layer instead);
//! - at a sample time, all three corners in front of the light (nothing clipped or
//!   excluded) and, in a closed mesh, the triangle facing the light (one facing away all
//!   frame is culled; one facing it at some time is not);
//! - centres at least `INSET_TEXELS` inside every edge then, so f32 and the tie-break cannot
//!   drop them (an edge would have to cross half a texel in under 10^-5 of the shutter, below
//!   which a run may be kept or not);
//! - each pair once, however many samples cover it (the union of the images, row by row).
//!
//! Not for the papers' prisms or the coverage map (which stores no range where one triangle
//! covers a texel all frame), nor for a moving light: there the bound is 0.

use glam::{DMat4, DVec2, DVec3, DVec4, Vec3};
use motion_shadows::technique::{LightView, PrismConstruction};
use rayon::prelude::*;

use crate::scene::Scene;

/// How far inside every edge a texel centre must be to be counted, in texels.
const INSET_TEXELS: f64 = 0.5;
/// The most sample times per triangle (enough for images that overlap from one to the next
/// when a triangle moves up to about 30 times its own size).
const MAX_SAMPLES: usize = 32;

/// An image of the triangle at one sample time: each edge as a x + b y + c >= 0 inside, the
/// value a distance in texels, moved in by the inset; and its rows' range.
struct Image {
    edges: [(f64, f64, f64); 3],
    y_lo: f64,
    y_hi: f64,
}

impl Image {
    fn new(t: [DVec2; 3]) -> Option<Self> {
        let area = (t[1] - t[0]).perp_dot(t[2] - t[0]);
        if !area.is_finite() || area == 0.0 {
            return None;
        }
        let mut edges = [(0.0f64, 0.0f64, 0.0f64); 3];
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            let d = (v - u) * area.signum();
            let len = d.length();
            if len == 0.0 {
                return None;
            }
            // Inside is to the left of u -> v once the triangle is counter-clockwise.
            let (a, b) = (-d.y / len, d.x / len);
            edges[k] = (a, b, -(a * u.x + b * u.y) - INSET_TEXELS);
        }
        let ys = t.map(|p| p.y);
        Some(Self {
            edges,
            y_lo: ys.iter().copied().fold(f64::INFINITY, f64::min),
            y_hi: ys.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        })
    }

    /// The x range on the row at height `y` where every edge value is >= 0, within `x_range`.
    fn span(&self, y: f64, x_range: (f64, f64)) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = x_range;
        for &(a, b, c) in &self.edges {
            let rest = b * y + c;
            if a > 0.0 {
                lo = lo.max(-rest / a);
            } else if a < 0.0 {
                hi = hi.min(-rest / a);
            } else if rest < 0.0 {
                return None;
            }
        }
        (hi >= lo).then_some((lo, hi))
    }
}

/// (texel, triangle) pairs of moving triangles that cover the texel's centre at some time
/// of the shutter: at least as many ranges as the exact construction stores in a map of
/// `size` texels.
pub fn ranges_at_least(scene: &Scene, light: &LightView, size: (u32, u32)) -> u64 {
    // A moving light sees every triangle move (still ones too) along other paths than the
    // t = 0 view's: no claim (the map grows to fit instead).
    if light.prisms != PrismConstruction::Exact || light.is_moving() {
        return 0;
    }
    let to_clip: DMat4 = light.proj.as_dmat4() * light.view.as_dmat4();
    let eye = light.position.as_dvec3();
    let toward_light = -light.direction.as_dvec3();
    let orthographic = !light.is_spot();
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    // NDC to texel units (texel x's centre is at x + 0.5), or None behind the light.
    let texel = |p: DVec3| -> Option<DVec2> {
        let c: DVec4 = to_clip * p.extend(1.0);
        (c.w > 0.0 && c.is_finite())
            .then(|| DVec2::new((c.x / c.w + 1.0) * 0.5 * w, (c.y / c.w + 1.0) * 0.5 * h))
    };
    let mut total = 0u64;
    for mesh in &scene.meshes {
        // Triangles in parallel (a few seconds for millions of them on one core).
        total += mesh
            .t0
            .par_chunks_exact(3)
            .zip(mesh.t1.par_chunks_exact(3))
            .map_init(
                || Vec::with_capacity(MAX_SAMPLES),
                |images, (t0, t1)| {
                    triangle_pairs(
                        images,
                        t0,
                        t1,
                        mesh.closed,
                        &texel,
                        size,
                        eye,
                        toward_light,
                        orthographic,
                    )
                },
            )
            .sum::<u64>();
    }
    total
}

/// The pairs of one triangle (0 if it does not move): its images at the sample times where
/// it counts, united.
#[allow(clippy::too_many_arguments)]
fn triangle_pairs(
    images: &mut Vec<Image>,
    t0: &[Vec3],
    t1: &[Vec3],
    closed: bool,
    texel: &(impl Fn(DVec3) -> Option<DVec2> + Sync),
    size: (u32, u32),
    eye: DVec3,
    toward_light: DVec3,
    orthographic: bool,
) -> u64 {
    if t0 == t1 {
        return 0;
    }
    let p0: [DVec3; 3] = [0, 1, 2].map(|k| t0[k].as_dvec3());
    let p1: [DVec3; 3] = [0, 1, 2].map(|k| t1[k].as_dvec3());
    images.clear();
    for t in sample_times(&p0, &p1, texel) {
        let p = [0, 1, 2].map(|k| p0[k].lerp(p1[k], t));
        if closed {
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let to_light = if orthographic {
                toward_light
            } else {
                eye - p[0]
            };
            if n.dot(to_light) <= 0.0 {
                continue;
            }
        }
        let (Some(a), Some(b), Some(c)) = (texel(p[0]), texel(p[1]), texel(p[2])) else {
            continue;
        };
        images.extend(Image::new([a, b, c]));
    }
    centres_covered(images, size)
}

/// Sample times in [0, 1], 0 and 1 included, spaced so that the triangle's images at
/// consecutive ones overlap where it moves less than `MAX_SAMPLES` times its size.
fn sample_times(
    p0: &[DVec3; 3],
    p1: &[DVec3; 3],
    texel: &impl Fn(DVec3) -> Option<DVec2>,
) -> impl Iterator<Item = f64> {
    let ends = (0..3).map(|k| (texel(p0[k]), texel(p1[k])));
    let (mut moved, mut lo, mut hi) = (0.0f64, DVec2::INFINITY, DVec2::NEG_INFINITY);
    for (a, b) in ends {
        if let (Some(a), Some(b)) = (a, b) {
            moved = moved.max(a.distance(b));
            lo = lo.min(a);
            hi = hi.max(a);
        }
    }
    let extent = (hi - lo).min_element().max(1.0);
    let steps = if moved.is_finite() {
        (moved / extent).ceil().clamp(1.0, (MAX_SAMPLES - 1) as f64) as usize
    } else {
        MAX_SAMPLES - 1
    };
    (0..=steps).map(move |i| i as f64 / steps as f64)
}

/// Texel centres (x + 0.5, y + 0.5) of a `size` map inside at least one of `images`, row by
/// row (the union of the images' spans on each row).
fn centres_covered(images: &[Image], size: (u32, u32)) -> u64 {
    let Some(y_lo) = images.iter().map(|i| i.y_lo).reduce(f64::min) else {
        return 0;
    };
    let y_hi = images
        .iter()
        .map(|i| i.y_hi)
        .fold(f64::NEG_INFINITY, f64::max);
    let first = (y_lo - 0.5).ceil().max(0.0);
    let last = (y_hi - 0.5).floor().min(f64::from(size.1) - 1.0);
    let x_range = (0.5, f64::from(size.0) - 0.5);
    let mut spans = Vec::with_capacity(images.len());
    let mut count = 0u64;
    let mut row = first;
    while row <= last {
        let y = row + 0.5;
        spans.clear();
        // Centre columns x in [ceil(lo - 0.5), floor(hi - 0.5)], as integers.
        spans.extend(
            images
                .iter()
                .filter_map(|i| i.span(y, x_range))
                .filter_map(|(lo, hi)| {
                    let (a, b) = ((lo - 0.5).ceil(), (hi - 0.5).floor());
                    (b >= a).then_some((a as i64, b as i64))
                }),
        );
        spans.sort_unstable();
        let mut end = i64::MIN;
        for &(a, b) in &spans {
            let from = a.max(end.saturating_add(1));
            if b >= from {
                count += (b - from + 1) as u64;
            }
            end = end.max(b);
        }
        row += 1.0;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Centres at least the inset inside at least one of `triangles`, texel by texel.
    fn brute_force(triangles: &[[DVec2; 3]], size: (u32, u32)) -> u64 {
        let inside = |t: &[DVec2; 3], p: DVec2| {
            let area = (t[1] - t[0]).perp_dot(t[2] - t[0]);
            area != 0.0
                && (0..3).all(|k| {
                    let (u, v) = (t[k], t[(k + 1) % 3]);
                    let d = v - u;
                    d.length() > 0.0
                        && d.perp_dot(p - u) * area.signum() / d.length() >= INSET_TEXELS
                })
        };
        let mut n = 0;
        for y in 0..size.1 {
            for x in 0..size.0 {
                let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                n += u64::from(triangles.iter().any(|t| inside(t, p)));
            }
        }
        n
    }

    #[test]
    fn row_counts_match_a_per_texel_test_and_unite() {
        let size = (37, 23);
        let cases = [
            [
                DVec2::new(1.2, 2.7),
                DVec2::new(30.4, 5.1),
                DVec2::new(8.9, 21.3),
            ],
            // Clockwise, reaching past the map on two sides.
            [
                DVec2::new(-5.0, -3.0),
                DVec2::new(10.0, 40.0),
                DVec2::new(45.0, 4.0),
            ],
            // Thin: no centre half a texel inside.
            [
                DVec2::new(2.0, 2.0),
                DVec2::new(30.0, 2.6),
                DVec2::new(2.0, 2.9),
            ],
            [
                DVec2::new(3.0, 3.0),
                DVec2::new(3.0, 3.0),
                DVec2::new(9.0, 9.0),
            ],
        ];
        let images: Vec<Image> = cases.iter().filter_map(|t| Image::new(*t)).collect();
        for t in cases {
            let one: Vec<Image> = Image::new(t).into_iter().collect();
            assert_eq!(
                centres_covered(&one, size),
                brute_force(&[t], size),
                "{t:?}"
            );
        }
        // The union counts a centre inside two of them once.
        assert_eq!(centres_covered(&images, size), brute_force(&cases, size));
        assert!(brute_force(&cases[..1], size) > 100);
    }
}
