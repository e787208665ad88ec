//! `hard-grazing`: a directional light 7 degrees above the ground and blocks standing on
//! the ground (their bottom faces on it), some static, some sliding or turning, with
//! shadows 8.1 times as long as the blocks are tall (3.7 to 8.1 units).
//!
//! At grazing light a shadow-map texel covers a long strip of ground (1 / sin 7 ~ 8 texel
//! widths), and every receiver offset along the normal or bias in depth moves the shadow's
//! start a long way from the block's foot: contact shadows and light leaks show here.
//!
//! The motion: the sliding blocks translate along the ground (one across the light, one
//! along it); the turning block's poses are 0 and 40 degrees about its vertical axis and its
//! vertices move on the chords between them (so it shrinks to cos 20 = 0.94 of its width
//! mid-shutter). Every block's bottom stays on the ground all frame.

use glam::{Vec2, Vec3};

use super::super::file::{
    BoxSpec, LightFile, MeshSpec, ObjectFile, PlaneSpec, SceneFile, TransformFile,
};
use super::super::parts::{object, translate};
use super::{GROUND_ALBEDO, camera, scene_file};

/// The light's elevation above the ground, degrees.
pub(super) const ELEVATION_DEG: f32 = 7.0;
/// The ground: 20 x 12, its centre here (the light's box is centred on it).
const GROUND_CENTRE: Vec3 = Vec3::new(1.0, 0.0, 0.0);
const GROUND_SIZE: Vec2 = Vec2::new(20.0, 12.0);
/// Radiance of the lit ground (lower than the spot scenes': faces turned to the light get
/// 1 / sin 7 ~ 8 times the ground's irradiance).
const GROUND_RADIANCE: f32 = 0.3;

/// Travelling mostly along +x, a little toward +z (the camera), 7 degrees downward.
fn direction() -> Vec3 {
    let horizontal = Vec3::new(1.0, 0.0, 0.25).normalize();
    let e = ELEVATION_DEG.to_radians();
    horizontal * e.cos() - Vec3::Y * e.sin()
}

fn block(size: Vec3, x: f32, z: f32, turn_deg: f32) -> TransformFile {
    TransformFile {
        translation: Some(Vec3::new(x, size.y * 0.5, z)),
        rotation_axis: Some(Vec3::Y),
        rotation_deg: Some(turn_deg),
        scale: None,
    }
}

/// A closed box of `size` standing on the ground at (x, z) at t0, at (x1, z1) turned
/// `turn_deg` at t1 (`None`: static).
fn standing(name: &str, albedo: Vec3, size: Vec3, at: Vec2, to: Option<(Vec2, f32)>) -> ObjectFile {
    object(
        name,
        albedo,
        true,
        MeshSpec::Box(BoxSpec {
            size,
            subdivisions: 3,
        }),
        block(size, at.x, at.y, 0.0),
        to.map(|(p, deg)| block(size, p.x, p.y, deg)),
    )
}

pub(super) fn scene() -> SceneFile {
    // Dark: a face turned to the light gets 1 / sin 7 ~ 8 times the ground's irradiance, so
    // these faces come out at about half the ground's radiance (albedo 0.8) and show against
    // it at the exposure that suits the ground.
    let sandstone = Vec3::new(0.07, 0.055, 0.04);
    let slate = Vec3::new(0.035, 0.05, 0.07);
    let rust = Vec3::new(0.075, 0.035, 0.02);
    let objects = vec![
        object(
            "ground",
            Vec3::splat(GROUND_ALBEDO),
            false,
            MeshSpec::Plane(PlaneSpec {
                size: GROUND_SIZE,
                subdivisions: 16,
            }),
            translate(GROUND_CENTRE),
            None,
        ),
        standing(
            "block-static",
            sandstone,
            Vec3::new(0.6, 0.8, 0.6),
            Vec2::new(-6.0, -2.5),
            None,
        ),
        standing(
            "wall-static",
            sandstone,
            Vec3::new(1.0, 0.5, 0.4),
            Vec2::new(-4.5, 2.0),
            None,
        ),
        standing(
            "pole-static",
            slate,
            Vec3::new(0.15, 1.0, 0.15),
            Vec2::new(-3.0, -0.5),
            None,
        ),
        standing(
            "block-across",
            rust,
            Vec3::new(0.5, 0.6, 0.5),
            Vec2::new(-5.5, 0.0),
            Some((Vec2::new(-5.5, 0.9), 0.0)),
        ),
        standing(
            "block-along",
            rust,
            Vec3::new(0.5, 0.7, 0.5),
            Vec2::new(-2.5, 2.8),
            Some((Vec2::new(-1.5, 2.8), 0.0)),
        ),
        standing(
            "slab-turning",
            slate,
            Vec3::new(1.2, 0.45, 0.2),
            Vec2::new(-1.5, -3.2),
            Some((Vec2::new(-1.5, -3.2), 40.0)),
        ),
    ];
    let e = ELEVATION_DEG.to_radians();
    scene_file(
        "hard-grazing",
        camera(Vec3::new(-0.7, 13.0, 10.0), Vec3::new(-0.7, 0.0, 0.3)),
        LightFile::Directional {
            direction: direction(),
            irradiance: GROUND_RADIANCE * std::f32::consts::PI / GROUND_ALBEDO / e.sin(),
            center: GROUND_CENTRE,
            // The ground's half diagonal is 11.7: all of it inside the box.
            half_extent: 12.5,
            distance: 15.0,
            near: 1.0,
            far: 35.0,
            t1: None,
        },
        objects,
    )
}

#[cfg(test)]
mod tests {
    use super::super::super::Light;
    use super::super::check::{casters, in_light, mesh, scene};
    use super::ELEVATION_DEG;

    #[test]
    fn the_light_grazes_and_the_blocks_stand_on_the_ground() {
        let s = scene("hard-grazing");
        let Light::Directional(light) = &s.light else {
            panic!("directional expected")
        };
        let elevation = (-light.direction.y).asin().to_degrees();
        assert!((5.0..=10.0).contains(&elevation), "{elevation}");
        assert!((elevation - ELEVATION_DEG).abs() < 1e-3);
        // The whole ground is inside the light's box, so every shadow falls in the map.
        for &p in &mesh(&s, "ground").t0 {
            assert!(
                in_light(&s.light, p),
                "ground corner {p} outside the light's box"
            );
        }
        let (mut moving, mut still) = (0, 0);
        let mut longest: f32 = 0.0;
        for m in casters(&s) {
            for points in [&m.t0, &m.t1] {
                let bottom = points.iter().map(|p| p.y).fold(f32::MAX, f32::min);
                assert_eq!(bottom, 0.0, "{} does not touch the ground", m.name);
                let top = points.iter().map(|p| p.y).fold(0.0, f32::max);
                longest = longest.max(top / elevation.to_radians().tan());
            }
            if m.t0 == m.t1 {
                still += 1;
            } else {
                moving += 1;
            }
        }
        assert!(moving >= 3 && still >= 3, "{moving} moving, {still} static");
        assert!(longest > 8.0, "longest shadow {longest}");
    }
}
