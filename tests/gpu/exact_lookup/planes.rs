//! The exact lookup where a caster and a receiver's plane meet: the self-shadow epsilon
//! applies only to a receiver on the triangle's plane to within rounding (`ms_exact_s_from`).

use super::{
    HALF_EXTENT, Receiver, SPOT_CONE_DEG, SPOT_HEIGHT, assert_near, at_time, lit_fractions, still,
};
use crate::support::scene::{
    DirectionalLight, Light, mesh, overhead_spot, scene, square, translated,
};
use glam::Vec3;
use motion_shadows::technique::NO_TRIANGLE;

/// A wall standing on the ground at x = 1 (z from -1 to 1, 1 high; still, and sliding by 0.5
/// along z, in its own plane) shadows the ground from its very foot: receivers a hair past it
/// on the far side from the light meet it within the first 1e-4 of their shadow rays, the
/// range MS_EXACT_SELF_EPSILON leaves out for a receiver on a triangle's own plane, yet they
/// lie off the wall's plane, so it shadows them (as the ray tracer, whose epsilon is 1e-7);
/// the same hair on the light's side is lit. Over the shutter (receivers still and moving
/// along the foot) and at one time. The lights:
/// the overhead spot (the ray's s is a share of the 6-unit segment: s = d / (1 + d) for a
/// receiver d past the wall) and a sun slanting toward +x (s in the world: sqrt(5) d against
/// the epsilon's 1e-4 x 8, the map's width).
#[test]
fn a_wall_shadows_the_ground_from_its_foot() {
    let slanting_sun = Light::Directional(DirectionalLight {
        direction: Vec3::new(1.0, -2.0, 0.0).normalize(),
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent: HALF_EXTENT,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
    });
    let spot = overhead_spot(SPOT_HEIGHT, SPOT_CONE_DEG);
    let wall = {
        let (a, b) = (Vec3::new(1.0, 0.0, -1.0), Vec3::new(1.0, 1.0, -1.0));
        let (c, d) = (Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, 0.0, 1.0));
        vec![a, b, c, a, c, d]
    };
    // Past the wall: above the off-plane margin (~2e-5 here, the sliding wall's reach
    // included), inside 1e-4 of the ray.
    for (light, hairs) in [(spot, [5e-5, 8e-5]), (slanting_sun, [1e-4, 2e-4])] {
        for slide in [Vec3::ZERO, Vec3::Z * 0.5] {
            let s = scene(
                "wall",
                light.clone(),
                vec![mesh("wall", wall.clone(), translated(&wall, slide), false)],
            );
            let mut receivers = Vec::new();
            let mut want = Vec::new();
            // Within the wall's z span all shutter long.
            for z in [-0.25, 0.25, 0.75] {
                for d in hairs {
                    for (x, lit) in [(1.0 + d, 0.0), (1.0 - d, 1.0)] {
                        let p = Vec3::new(x, 0.0, z);
                        receivers.push(still(p));
                        receivers.push(at_time(p, 0.4));
                        want.extend([lit, lit]);
                    }
                }
            }
            // And moving along the wall's foot, past its still or sliding triangles.
            for d in hairs {
                for (x, lit) in [(1.0 + d, 0.0), (1.0 - d, 1.0)] {
                    receivers.push(Receiver {
                        p0: Vec3::new(x, 0.0, -0.25),
                        p1: Vec3::new(x, 0.0, 0.5),
                        own: NO_TRIANGLE,
                        at: None,
                    });
                    want.push(lit);
                }
            }
            let got = lit_fractions(&s, &receivers);
            assert_near(&format!("wall sliding by {slide}"), &got, &want, &receivers);
        }
    }
}

/// A receiver a rounding below its own ground triangle (1e-6, as a G-buffer's f32 point lies
/// off its plane), just beside the edge it shares with a coplanar neighbour, under a sun 5
/// degrees above the horizon: its shadow ray climbs through the ground plane a few 1e-5 on,
/// inside the neighbour, past the ray tracer's epsilon. It lies on the neighbour's plane to
/// within rounding, so MS_EXACT_SELF_EPSILON applies and the neighbour does not shadow it
/// (without that, a grazing light speckles every shared edge of a level's floor). Over the
/// shutter and at one time.
#[test]
fn a_coplanar_neighbour_does_not_shadow_a_receiver_beside_their_shared_edge() {
    let h = 5f32.to_radians().tan();
    let low_sun = Light::Directional(DirectionalLight {
        // Travelling toward +x and -z, across the square's diagonal x = z.
        direction: Vec3::new(1.0, -h * 2f32.sqrt(), -1.0).normalize(),
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent: HALF_EXTENT,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
    });
    let ground = square(-1.0, -1.0, 2.0, 0.0);
    let s = scene(
        "floor",
        low_sun,
        vec![mesh("floor", ground.clone(), ground, false)],
    );
    // Triangle 1 is (-1, -1), (1, 1), (1, -1) in xz: where x >= z. Along the ray toward the
    // light, (-1, h sqrt(2), 1), x - z falls by 2 while y climbs h sqrt(2): the ray is through
    // y = 0 once x - z fell by sqrt(2) 1e-6 / h ~ 1.6e-5, inside triangle 0.
    let mut receivers = Vec::new();
    for e in [2e-6, 5e-6, 1e-5] {
        let p = Vec3::new(0.3 + e, -1e-6, 0.3);
        let on = Receiver { own: 1, ..still(p) };
        receivers.push(on);
        receivers.push(Receiver {
            own: 1,
            ..at_time(p, 0.6)
        });
    }
    let got = lit_fractions(&s, &receivers);
    assert_near(&s.name, &got, &vec![1.0; receivers.len()], &receivers);
}
