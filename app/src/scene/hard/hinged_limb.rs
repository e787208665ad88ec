//! `hard-hinged-limb`: a thin box limb hinged at one end, turning 30 degrees about a
//! vertical axis through the hinge, above the ground; a static post holds the hinge.
//!
//! Turning about one end, the limb's edges sweep fans whose parts near the hinge barely
//! move while the far end moves most: the prism sides are far from the bilinear patches the
//! papers' construction assumes.
//!
//! The motion, exactly: the t0 pose is the limb at -15 degrees, the t1 pose at +15 degrees
//! (rigid rotations about the hinge axis), and every vertex moves on the chord between its
//! two positions. At time t the limb is therefore turned by atan((2t - 1) tan 15) degrees
//! and its horizontal extent from the axis scaled by sqrt(t^2 + (1 - t)^2 + 2t(1 - t) cos 30)
//! (0.966 at t = 0.5). Points on the hinge axis do not move at all; the rest of the hinge end
//! (0.08 from the axis) moves at most 0.04.

use glam::Vec3;

use super::super::file::{BoxSpec, MeshSpec, SceneFile, TransformFile};
use super::super::parts::{ground, object, translate};
use super::{camera, scene_file, spot, turn};

const LIGHT: Vec3 = Vec3::new(-2.5, 8.0, 3.0);
/// The hinge: on the limb's axis at the centre of its end face.
const HINGE: Vec3 = Vec3::new(-1.3, 2.0, 0.2);
/// Full size; the limb lies along its local x, the hinge at local x = -LIMB.x / 2.
const LIMB: Vec3 = Vec3::new(2.4, 0.16, 0.16);
/// Quads per face edge: fine, so the renderer has vertices along the limb.
const SUBDIVISIONS: u32 = 8;
/// Angles about +y at t0 and t1, degrees (0: the limb along +x).
const ANGLES: [f32; 2] = [-15.0, 15.0];

const fn hinge_local() -> Vec3 {
    Vec3::new(-LIMB.x * 0.5, 0.0, 0.0)
}

/// The rigid pose turning the limb `deg` degrees about the vertical axis through the hinge.
fn pose(deg: f32) -> TransformFile {
    TransformFile {
        translation: Some(HINGE - turn(Vec3::Y, deg) * hinge_local()),
        rotation_axis: Some(Vec3::Y),
        rotation_deg: Some(deg),
        scale: None,
    }
}

pub(super) fn scene() -> SceneFile {
    let middle = HINGE + Vec3::X * LIMB.x * 0.5;
    let aim = LIGHT + (middle - LIGHT) * (LIGHT.y / (LIGHT.y - middle.y));
    // The post stops 0.02 below the limb's underside.
    let post_height = HINGE.y - LIMB.y * 0.5 - 0.02;
    scene_file(
        "hard-hinged-limb",
        camera(Vec3::new(1.5, 4.0, 4.6), Vec3::new(0.4, 1.0, -0.4)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        vec![
            ground(16.0, 8),
            object(
                "post",
                Vec3::new(0.5, 0.5, 0.55),
                true,
                MeshSpec::Box(BoxSpec {
                    size: Vec3::new(0.3, post_height, 0.3),
                    subdivisions: 2,
                }),
                translate(Vec3::new(HINGE.x, post_height * 0.5, HINGE.z)),
                None,
            ),
            object(
                "limb",
                Vec3::new(0.85, 0.42, 0.22),
                true,
                MeshSpec::Box(BoxSpec {
                    size: LIMB,
                    subdivisions: SUBDIVISIONS,
                }),
                pose(ANGLES[0]),
                Some(pose(ANGLES[1])),
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::super::super::primitives::box_mesh;
    use super::super::check::{centre, mesh, scene};
    use super::*;
    use glam::Vec2;

    /// The limb is rigid at both ends, turns 30 degrees about the vertical axis through the
    /// hinge, and its vertices on that axis do not move.
    #[test]
    fn the_limb_turns_30_degrees_about_a_fixed_hinge() {
        let s = scene("hard-hinged-limb");
        let limb = mesh(&s, "limb");
        assert_eq!(limb.t0.len(), box_mesh(LIMB, SUBDIVISIONS).len());
        // The box's centre (its vertex mean) turns 30 degrees about the hinge, at hinge height.
        let (c0, c1) = (centre(&limb.t0) - HINGE, centre(&limb.t1) - HINGE);
        assert!(c0.y.abs() < 1e-5 && c1.y.abs() < 1e-5);
        assert!((c0.length() - LIMB.x * 0.5).abs() < 1e-4);
        let angle = c0.angle_between(c1).to_degrees();
        assert!((angle - 30.0).abs() < 1e-2, "{angle}");
        assert!(c0.cross(c1).y > 0.0, "turns about +y");
        let axis_distance = |p: Vec3| Vec2::new(p.x - HINGE.x, p.z - HINGE.z).length();
        let mut on_axis = 0;
        for (&a, &b) in limb.t0.iter().zip(&limb.t1) {
            // A rotation about the vertical axis: same height, same distance from the axis,
            // and the chord of a 30-degree arc.
            assert!((a.y - b.y).abs() < 1e-5);
            let r = axis_distance(a);
            assert!((axis_distance(b) - r).abs() < 1e-4);
            let chord = 2.0 * r * 15.0_f32.to_radians().sin();
            assert!(((a - b).length() - chord).abs() < 1e-4, "{a} -> {b}");
            if r < 1e-5 {
                on_axis += 1;
                assert!((a - b).length() < 1e-5, "a hinge vertex moves: {a} -> {b}");
            }
            // The hinge end (local x = -LIMB.x / 2) never moves more than its half width
            // times the turn.
            if (a - HINGE).dot(c0.normalize()).abs() < 1e-4 {
                assert!((a - b).length() <= 0.0415, "{a} -> {b}");
            }
        }
        // Every vertex on the axis: the end face's centre column (9 of them, each in the
        // 4 or 2 triangles around it), at both ends.
        assert!(on_axis >= 9, "{on_axis}");
        let tip = limb
            .t0
            .iter()
            .zip(&limb.t1)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f32::max);
        assert!(tip > 1.2, "the far end moves {tip}");
    }

    #[test]
    fn the_post_is_static_under_the_hinge() {
        let s = scene("hard-hinged-limb");
        let post = mesh(&s, "post");
        assert_eq!(post.t0, post.t1);
        let top = post.t0.iter().map(|p| p.y).fold(0.0, f32::max);
        let bottom = post.t0.iter().map(|p| p.y).fold(f32::MAX, f32::min);
        assert!(
            bottom == 0.0 && top < HINGE.y - LIMB.y * 0.5,
            "{bottom} {top}"
        );
    }
}
