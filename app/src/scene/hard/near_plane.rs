//! `hard-near-plane`: a flat plate that starts between the spot light and its shadow-map
//! near plane and moves through that plane, down and across, casting on the ground.
//!
//! A shadow map sees nothing nearer than its near plane, so every shadow-map method (the
//! brute-force reference included) can only show the plate's shadow from the time it
//! crosses; the exact shadow is there all frame. The plate is horizontal and the light
//! points straight down, so all its vertices are at one depth and cross together.
//!
//! In front of the near plane (depth along the light's axis > `near` = 2.5) exactly for
//! t in [0.4, 1]: the plate's depth is 1.5 + 2.5 t (from 1.5 at t0 to 4.0 at t1), so it is
//! behind the near plane (between the light and it) for t < 0.4, 40% of the shutter, and in
//! front of it for the last 60%.

use glam::{Vec2, Vec3};

use super::super::file::{MeshSpec, PlaneSpec, SceneFile};
use super::super::parts::{ground, object, translate};
use super::{camera, scene_file, spot};

const LIGHT: Vec3 = Vec3::new(0.0, 7.0, 0.0);
/// The plate's depth below the light (along the light's axis, straight down) at t0 and t1.
const DEPTHS: (f32, f32) = (1.5, 4.0);
/// When the plate crosses the near plane.
const CROSSING_T: f32 = 0.4;
/// The shadow map's near plane, as a depth along the light's axis: where the plate is at
/// `CROSSING_T` (2.5).
const NEAR: f32 = DEPTHS.0 + CROSSING_T * (DEPTHS.1 - DEPTHS.0);
/// The plate's centre at t0 and t1.
const PLATE_T0: Vec3 = Vec3::new(-0.3, LIGHT.y - DEPTHS.0, 0.2);
const PLATE_T1: Vec3 = Vec3::new(0.5, LIGHT.y - DEPTHS.1, -0.3);
const PLATE_SIZE: f32 = 0.8;

pub(super) fn scene() -> SceneFile {
    scene_file(
        "hard-near-plane",
        camera(Vec3::new(0.75, 10.2, 10.9), Vec3::new(-0.85, 2.75, 0.8)),
        spot(LIGHT, Vec3::ZERO, 40.0, NEAR, 20.0),
        vec![
            ground(16.0, 8),
            object(
                "plate",
                Vec3::new(0.8, 0.3, 0.3),
                false,
                MeshSpec::Plane(PlaneSpec {
                    size: Vec2::splat(PLATE_SIZE),
                    subdivisions: 4,
                }),
                translate(PLATE_T0),
                Some(translate(PLATE_T1)),
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::super::super::Light;
    use super::super::check::{mesh, scene};
    use super::*;

    /// Every plate vertex starts behind the near plane and ends in front of it, crossing it
    /// at t = 0.4; everything else is in front of it all frame.
    #[test]
    fn the_plate_crosses_the_near_plane_at_t_0_4() {
        let s = scene("hard-near-plane");
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        assert_eq!(light.near, NEAR);
        let depth = |p: Vec3| (p - light.position).dot(light.direction);
        let plate = mesh(&s, "plate");
        for (&a, &b) in plate.t0.iter().zip(&plate.t1) {
            let (d0, d1) = (depth(a), depth(b));
            assert!(d0 > 0.0 && d0 < NEAR && d1 > NEAR, "{d0} -> {d1}");
            // Depth is linear in t for linear motion: it equals `near` at one time.
            let crossing = (NEAR - d0) / (d1 - d0);
            assert!((crossing - CROSSING_T).abs() < 1e-5, "{crossing}");
            // Mid-way through the part in front of the plane, the plate is in front.
            let t = (CROSSING_T + 1.0) * 0.5;
            assert!(depth(a.lerp(b, t)) > NEAR);
        }
        for m in s.meshes.iter().filter(|m| m.name != "plate") {
            for &p in m.t0.iter().chain(&m.t1) {
                assert!(depth(p) > NEAR * 2.0, "{} too near the light", m.name);
            }
        }
    }
}
