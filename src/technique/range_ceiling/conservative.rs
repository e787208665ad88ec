//! The bound for the exact lookup's conservative collection (`Lookup::Exact`,
//! `collection_conservative.geom`): it draws each triangle's footprint, the hull of its six
//! corners' images, grown by a texel's half-diagonal on top of the default growth, so that
//! every texel whose square the swept triangle touches is drawn; its fragment shader stores
//! one range (a still triangle kept in the static layer: one static name) per texel drawn.
//! Where a corner is at or behind the light it stores at every texel; where one is imaged far
//! out it draws the whole map and stores where the corners' box meets the texel.

use glam::{DVec2, DVec3, Vec3};

use super::culling::faces_away_whole_frame;
use super::footprint::{Footprint, GROWTH_TEXELS};
use super::{FAR_MAP_WIDTHS, NEAR_W};
use super::{LightSpace, Setup};

/// `HALF_DIAGONAL_TEXELS` of `collection_exact_geom.glsl`, rounded up: every point of a
/// texel lies within it of the texel's centre.
const HALF_DIAGONAL_TEXELS: f64 = 0.7072;

/// Images this many map widths out count as far: the geometry shader draws the whole map
/// beyond 64 NDC (32 map widths), so the host counts it from half that on.
const CONSERVATIVE_FAR_MAP_WIDTHS: f64 = FAR_MAP_WIDTHS / 4.0;

impl Setup {
    /// At most how many ranges (or static names) the conservative collection stores for one
    /// triangle: one per texel centre in its grown footprint, every texel where the
    /// footprint is not bounded.
    pub(super) fn conservative_ranges_at_most(
        &self,
        t0: &[Vec3; 3],
        t1: &[Vec3; 3],
        closed: bool,
    ) -> u64 {
        let LightSpace { e0, e1, v0, v1 } = self.light_space(t0, t1);
        let corners: Vec<DVec3> = v0.iter().chain(&v1).copied().collect();
        let map = &self.map;
        if corners.iter().all(|c| c.z <= 0.0) {
            // Wholly behind the light: the geometry shader emits nothing.
            return 0;
        }
        if closed && faces_away_whole_frame(&e0, &e1, self.orthographic) {
            return 0;
        }
        if !corners.iter().all(|c| c.is_finite()) {
            return map.texels();
        }
        let w_scale = corners.iter().map(|c| c.z.abs()).fold(0.0, f64::max);
        // The geometry shader draws nothing where every corner is beyond one side of the
        // light's frustum (x < -w, ...): so here by a margin, f32 there culling at least this.
        let margin = NEAR_W * w_scale;
        let beyond = |side: &dyn Fn(&DVec3) -> f64| corners.iter().all(|c| side(c) > margin);
        let sides: [&dyn Fn(&DVec3) -> f64; 4] =
            [&|c| -c.z - c.x, &|c| c.x - c.z, &|c| -c.z - c.y, &|c| {
                c.y - c.z
            }];
        if sides.iter().any(|side| beyond(side)) {
            return 0;
        }
        if corners.iter().any(|c| c.z <= margin) {
            // At or behind the light: stored at every texel drawn, the whole map.
            return map.texels();
        }
        let images: Vec<DVec2> = corners.iter().map(|&c| map.texel(c)).collect();
        let reach = CONSERVATIVE_FAR_MAP_WIDTHS * map.width.max(map.height);
        let growth = GROWTH_TEXELS + HALF_DIAGONAL_TEXELS;
        let outline = if images.iter().any(|p| p.abs().max_element() > reach) {
            // Drawn as the whole map, stored where the corners' box meets the texel (all in
            // front of the light: the fragment shader's `square_times`): the box, its far
            // sides held at the reach (beyond the map all the same).
            let lo = images.iter().fold(DVec2::INFINITY, |a, &p| a.min(p));
            let hi = images.iter().fold(DVec2::NEG_INFINITY, |a, &p| a.max(p));
            let (lo, hi) = (lo.max(DVec2::splat(-reach)), hi.min(DVec2::splat(reach)));
            vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]
        } else {
            images
        };
        let centres = Footprint::grown(&outline, map, growth).count(&[]).0;
        centres.min(map.texels())
    }
}

#[cfg(test)]
mod tests {
    use super::super::map::Map;
    use super::*;
    use glam::DMat4;

    const N: u32 = 20;

    /// A spot light looking down -z (in front at z < 0) over an N x N map.
    fn spot() -> Setup {
        Setup {
            to_view: DMat4::IDENTITY,
            proj: glam::camera::rh::proj::vulkan::perspective(1.2, 1.0, 0.1, 50.0).as_dmat4(),
            orthographic: false,
            map: Map {
                width: f64::from(N),
                height: f64::from(N),
            },
        }
    }

    /// Texels whose square, grown by 1/16 texel (the fragment shader's margin), holds the
    /// image of some point of the still triangle `t` (sampled on a 400 x 400 grid of
    /// barycentric steps): the texels the conservative collection stores it at, at least.
    fn touched(setup: &Setup, t: &[Vec3; 3]) -> u64 {
        let mut hit = vec![false; (N * N) as usize];
        let steps = 400;
        for i in 0..=steps {
            for j in 0..=steps - i {
                let (a, b) = (
                    f64::from(i) / f64::from(steps),
                    f64::from(j) / f64::from(steps),
                );
                let p = t[0].as_dvec3() * (1.0 - a - b) + t[1].as_dvec3() * a + t[2].as_dvec3() * b;
                let c = setup.proj * p.extend(1.0);
                if c.w <= 0.0 {
                    continue;
                }
                let texel = setup.map.texel(DVec3::new(c.x, c.y, c.w));
                for y in 0..N {
                    for x in 0..N {
                        let near =
                            |v: f64, k: u32| (v - (f64::from(k) + 0.5)).abs() <= 0.5 + 1.0 / 16.0;
                        if near(texel.x, x) && near(texel.y, y) {
                            hit[(y * N + x) as usize] = true;
                        }
                    }
                }
            }
        }
        hit.iter().filter(|&&h| h).count() as u64
    }

    /// A triangle reaching behind the light is stored at every texel, unless every corner is
    /// beyond one side of the frustum (the geometry shader then draws nothing).
    #[test]
    fn behind_the_light_the_whole_map_unless_beyond_a_side() {
        let setup = spot();
        let left = [
            Vec3::new(-10.0, 0.0, -1.0),
            Vec3::new(-10.0, 1.0, -1.0),
            Vec3::new(-10.0, 0.0, 1.0),
        ];
        assert_eq!(setup.conservative_ranges_at_most(&left, &left, false), 0);
        let across = [
            Vec3::new(-10.0, 0.0, -1.0),
            Vec3::new(10.0, 1.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let whole = u64::from(N * N);
        assert_eq!(
            setup.conservative_ranges_at_most(&across, &across, false),
            whole
        );
    }

    /// A still triangle with a corner nearly level with the light (imaged hundreds of map
    /// widths out): bounded by its corners' box within the map, which holds every texel it
    /// touches, and is far below the whole map.
    #[test]
    fn far_imaged_corners_are_bounded_by_their_box() {
        let setup = spot();
        let t = [
            Vec3::new(0.5, 0.5, -1.0),
            Vec3::new(0.55, 0.5, -1.0),
            Vec3::new(0.5, 0.5, -0.002),
        ];
        let bound = setup.conservative_ranges_at_most(&t, &t, false);
        let stored = touched(&setup, &t);
        assert!(stored > 0);
        assert!(stored <= bound, "touched {stored}, bound {bound}");
        assert!(
            bound * 4 < u64::from(N * N),
            "bound {bound} of {} texels",
            N * N
        );
    }
}
