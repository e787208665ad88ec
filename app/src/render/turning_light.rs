//! Where a turning light's map misplaces what moves (issue 38). The temporal map blends each
//! vertex's light-clip positions at the two ends, `(1 - t) V0 p0 + t V1 p1`; a moving point
//! seen at t by the blended view is `((1 - t) V0 + t V1) ((1 - t) p0 + t p1)`, which differs
//! by `t (1 - t) (V1 - V0) (p1 - p0)`: nothing for a still point or a translating light, up to
//! a quarter of `(R1 - R0) (p1 - p0)` at mid-shutter for a point moving across the turn (R0,
//! R1: the two views' rotations). A spot light carried across its turn leaves the blended
//! view's origin the same way (by `t (1 - t) (V0 L1 + V1 L0)`, a quarter of
//! `(R0 - R1) (L1 - L0)` at mid-shutter), so the rays from the light are no longer the map's.
//! The temporal deferred mask takes a turning spot light only where both stay below
//! [`MISPLACEMENT_TOLERANCE`].

use crate::scene::Scene;
use glam::{Mat3, Vec3};
use motion_shadows::technique::LightView;

/// World units: below this the blend's misplacement of moving geometry is rounding. Measured
/// (docs/src/deferred-frame.md#a-turning-light): `moving-light`'s box sliding 2 units across
/// the turn of a flashlight whose direction turns 5 degrees about the vertical (3.3 degrees
/// of turn), misplaced by up to 0.029 at mid-shutter, takes the mask from 0.0029 (the box held
/// still) to 0.0186 RMSE against the truth.
pub const MISPLACEMENT_TOLERANCE: f32 = 1e-3;

/// The largest distance, in the light's view, by which the map of `light` (a moving one)
/// misplaces a vertex of `scene`, or the light's own position, at mid-shutter:
/// `|(R1 - R0) (p1 - p0)| / 4` (for the light, its carry `L1 - L0`).
pub fn turn_misplacement(scene: &Scene, light: &LightView) -> f32 {
    if !light.is_turning() {
        return 0.0;
    }
    let r0 = Mat3::from_mat4(light.gpu().view);
    let r1 = Mat3::from_mat4(light.gpu_end().view);
    let turn = r1 - r0;
    let carried = light
        .end
        .map_or(Vec3::ZERO, |end| end.position - light.position);
    scene
        .meshes
        .iter()
        .flat_map(|m| m.t0.iter().zip(&m.t1))
        .map(|(&p0, &p1)| p1 - p0)
        .chain([carried])
        .map(|motion| (turn * motion).length() / 4.0)
        .fold(0.0, f32::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::upload::moving_light_view;
    use crate::scene::{BuiltinOptions, Light, builtin};
    use glam::{Quat, Vec3};

    /// `moving-light` (its box slides 2 units along x) with the flashlight turned by `deg`
    /// about `axis` during the shutter.
    fn turned(axis: Vec3, deg: f32) -> Scene {
        let mut scene = builtin("moving-light", &BuiltinOptions::default()).unwrap();
        let Light::Spot(light) = &mut scene.light else {
            panic!("spot expected")
        };
        let direction = Quat::from_axis_angle(axis, deg.to_radians()) * light.direction;
        light.t1.as_mut().unwrap().direction = direction;
        scene
    }

    /// The light turns by the shortest arc from its direction at t = 0 to t = 1's (the angle
    /// a between them, about their cross product's axis): a motion m is moved by that turn by
    /// the chord 2 sin(a / 2) times its part across the axis, here the box's 2-unit slide
    /// along x, a quarter of that at mid-shutter (the light's own 2-unit carry along x, the
    /// same). A direction tipped about x, the slide's and the carry's own axis, misplaces
    /// nothing; nor does a light that only translates.
    #[test]
    fn misplacement_is_a_quarter_of_the_chord_across_the_turn() {
        let misplaced =
            |scene: &Scene| turn_misplacement(scene, &moving_light_view(scene, (64, 64)).unwrap());
        let scene = turned(Vec3::Y, 5.0);
        let Light::Spot(light) = &scene.light else {
            panic!("spot expected")
        };
        let (d0, d1) = (
            light.direction.normalize(),
            light.t1.unwrap().direction.normalize(),
        );
        let axis = d0.cross(d1).normalize();
        let slide = Vec3::new(-2.0, 0.0, 0.0);
        let across_axis = (slide - slide.dot(axis) * axis).length();
        let expected = 2.0 * (d0.angle_between(d1) / 2.0).sin() * across_axis / 4.0;
        let across = misplaced(&scene);
        assert!((across - expected).abs() < 1e-4, "{across} vs {expected}");
        // Tipped about x: the box's slide and the light's 2-unit carry both lie on the axis.
        assert!(misplaced(&turned(Vec3::X, 20.0)) < 1e-5);
        let carried = builtin("moving-light", &BuiltinOptions::default()).unwrap();
        assert_eq!(misplaced(&carried), 0.0);
    }
}
