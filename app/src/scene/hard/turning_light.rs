//! `hard-turning-light`: a sun that turns 20 degrees during the shutter (its direction tipped
//! about the horizontal axis across it, from a high sun to a lower one) over three still
//! posts and a still box. Nothing in the scene moves, yet every shadow swings: the posts'
//! shadows grow from about 1.3 to 2.7 units and blur along their length, their feet staying
//! sharp where they touch the ground.
//!
//! A method must take the light at each sample's time (issue 38). Nothing stands still
//! relative to a moving light, so a method's static layer or static map is empty here. The
//! light's direction moves on the normalised blend of its two ends (the scene format's
//! "a moving light"), as the ray tracer's does.

use glam::Vec3;

use super::super::file::{BoxSpec, DirectionalPoseFile, LightFile, MeshSpec, SceneFile};
use super::super::parts::{ground, object, translate};
use super::{GROUND_ALBEDO, GROUND_RADIANCE, camera, scene_file, turn};

/// The sun's direction at t = 0 (from the sun toward the scene).
const SUN: Vec3 = Vec3::new(0.3, -1.0, -0.6);
/// How far the sun's direction turns by t = 1 (about the horizontal axis across it), degrees.
const TURN_DEG: f32 = 20.0;

pub(super) fn scene() -> SceneFile {
    let direction = SUN.normalize();
    let center = Vec3::new(0.0, 0.8, -1.0);
    let post = MeshSpec::Box(BoxSpec {
        size: Vec3::new(0.3, 2.0, 0.3),
        subdivisions: 1,
    });
    let mut objects = vec![ground(16.0, 8)];
    for (i, x) in [-1.5f32, 0.0, 1.5].into_iter().enumerate() {
        objects.push(object(
            &format!("post-{i}"),
            Vec3::new(0.75, 0.7, 0.55),
            true,
            post.clone(),
            translate(Vec3::new(x, 1.0, 0.0)),
            None,
        ));
    }
    objects.push(object(
        "box",
        Vec3::new(0.3, 0.5, 0.8),
        true,
        MeshSpec::Box(BoxSpec {
            size: Vec3::splat(0.8),
            subdivisions: 2,
        }),
        translate(Vec3::new(0.8, 0.4, 1.2)),
        None,
    ));
    scene_file(
        "hard-turning-light",
        camera(Vec3::new(0.0, 6.0, 7.0), Vec3::new(0.0, 0.3, -1.0)),
        LightFile::Directional {
            direction,
            // The ground's radiance GROUND_RADIANCE under the sun at t = 0: albedo/pi * E * cos.
            irradiance: GROUND_RADIANCE * std::f32::consts::PI / GROUND_ALBEDO / -direction.y,
            center,
            half_extent: 5.0,
            distance: 15.0,
            near: 1.0,
            far: 30.0,
            t1: Some(DirectionalPoseFile {
                direction: Some(turn(direction.cross(Vec3::Y), TURN_DEG) * direction),
                center: None,
            }),
        },
        objects,
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::scene;
    use crate::scene::Light;

    #[test]
    fn the_sun_turns_20_degrees_over_still_geometry() {
        let s = scene("hard-turning-light");
        let Light::Directional(sun) = &s.light else {
            panic!("a sun expected")
        };
        let end = sun.t1.expect("the sun turns");
        let angle = sun
            .direction
            .normalize()
            .angle_between(end.direction)
            .to_degrees();
        assert!((angle - 20.0).abs() < 1e-3, "{angle}");
        assert_eq!(end.center, sun.center);
        assert!(s.meshes.iter().all(|m| m.t0 == m.t1), "something moves");
    }
}
