//! A light that moves during the shutter: its pose at t = 1 ([`LightEnd`]) next to the pose at
//! t = 0 that the rest of [`LightView`] describes.
//!
//! Interpolation: the position moves linearly, `L(t) = (1 - t) L0 + t L1`; the direction is
//! the normalised linear blend, `D(t) = normalize((1 - t) D0 + t D1)` (nlerp), the same
//! straight-line blend every vertex of a scene follows. Along a shadow ray only the
//! direction's line matters, so a directional light's ray direction `(1 - t) D0 + t D1` stays
//! linear in t (the exact lookups' and the exact truth's polynomials keep their degree); a
//! spot's direction only places its cone. Against a turn at constant angular speed (slerp) the
//! blend is behind, then ahead, by at most 0.04 degrees for a 20-degree turn.
//!
//! The shadow map of a moving light is built in the light's moving frame: each vertex's
//! light-clip position at t = 0 with the t = 0 view, at t = 1 with the t = 1 view, linear
//! between. For a translating light (same direction at both ends) that is the light's frame at
//! every t exactly; for a turning one the blend of the two clip positions is not the clip
//! position under the turned view at t, and differs from it by a term in t (1 - t) that
//! grows with the turn (see docs/src/scene-format.md, "A moving light").

use super::gpu_types::{DRAW_STATIC, DrawRecord, GpuLightEnd};
use super::shadow_map::TemporalShadowMap;
use super::view::{LightView, Lookup};
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Quat, Vec3};
use std::sync::atomic::Ordering;

/// The light's pose at shutter close, t = 1 (see the module's documentation for the motion
/// between).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightEnd {
    /// Position at t = 1 (spot), or the point a directional light's orthographic view is
    /// seen from at t = 1.
    pub position: Vec3,
    /// Unit direction the light points in at t = 1.
    pub direction: Vec3,
    /// World -> light view at t = 1: the view at t = 0 turned by the shortest rotation from
    /// the t = 0 direction to this one and moved to `position` (no roll about the axis).
    pub view: Mat4,
}

/// [`TemporalShadowMap`]'s record of what its last collection was for: the exact lookup.
pub(super) const RECORDED_EXACT: u8 = 1;
/// ... a moving light.
pub(super) const RECORDED_MOVING_LIGHT: u8 = 2;
/// ... static name lists (the exact lookup with the static layer).
pub(super) const RECORDED_STATIC_NAMES: u8 = 4;

impl TemporalShadowMap {
    /// Whether the last recorded collection built the map for a moving light
    /// ([`LightView::end`]; false before any).
    pub fn recorded_for_moving_light(&self) -> bool {
        self.built_for.load(Ordering::Relaxed) & RECORDED_MOVING_LIGHT != 0
    }
}

/// Directions at the two ends of a moving light's shutter must be less than this many degrees
/// apart (the blend of the two directions is defined, and the map's frame turns by less than
/// a right angle).
pub const MAX_LIGHT_TURN_DEG: f32 = 90.0;

impl LightView {
    /// This light, moving during the shutter from its pose at t = 0 (`self`'s position and
    /// direction) to `position` and `direction` at t = 1 (for a directional light the
    /// position is the point its orthographic view is seen from, as
    /// [`LightView::directional`] places it: `center - direction * distance`). The cone,
    /// emission, projection and lookup settings stay those of t = 0. Refused (with
    /// [`crate::Error::InvalidArgument`]) for a zero or non-finite direction, a non-finite
    /// position, or directions [`MAX_LIGHT_TURN_DEG`] or more apart.
    pub fn moving_to(mut self, position: Vec3, direction: Vec3) -> crate::Result<Self> {
        if !position.is_finite() || !direction.is_finite() || direction.length() == 0.0 {
            return Err(crate::Error::InvalidArgument(format!(
                "LightView::moving_to: position {position} and direction {direction} must be \
                 finite, the direction non-zero"
            )));
        }
        let direction = direction.normalize();
        let cos_turn = self.direction.dot(direction);
        // cos(90 degrees) is 0 exactly; its f32 radians are not.
        if cos_turn <= 0.0 {
            return Err(crate::Error::InvalidArgument(format!(
                "LightView::moving_to: the light turns {:.1} degrees during the shutter; at \
                 most {MAX_LIGHT_TURN_DEG} (less) is supported",
                cos_turn.clamp(-1.0, 1.0).acos().to_degrees()
            )));
        }
        let turn = Quat::from_rotation_arc(self.direction, direction);
        let up = turn * self.view.inverse().y_axis.truncate();
        self.end = Some(LightEnd {
            position,
            direction,
            view: look_at_mat4(position, position + direction, up),
        });
        Ok(self)
    }

    /// Whether the light moves during the shutter (it has a pose at t = 1).
    pub fn is_moving(&self) -> bool {
        self.end.is_some()
    }

    /// Position and unit direction at shutter time `t` (module documentation); a still
    /// light's own, unchanged.
    pub fn pose_at(&self, t: f32) -> (Vec3, Vec3) {
        match &self.end {
            None => (self.position, self.direction),
            Some(end) => (
                self.position.lerp(end.position, t),
                self.direction.lerp(end.direction, t).normalize(),
            ),
        }
    }

    /// The pose at t = 1 as a temporal map's header holds it (zeros for a still light).
    pub fn gpu_end(&self) -> GpuLightEnd {
        match &self.end {
            None => GpuLightEnd::default(),
            Some(end) => GpuLightEnd {
                view: end.view,
                frame: self.view.inverse() * end.view,
                position: end.position.extend(1.0),
                direction: end.direction.extend(self.gpu().direction.w),
            },
        }
    }

    /// What a map's collection for this light records ([`RECORDED_EXACT`],
    /// [`RECORDED_MOVING_LIGHT`]).
    pub(super) fn recorded_flags(&self) -> u8 {
        let exact = if self.lookup == Lookup::Exact {
            RECORDED_EXACT
        } else {
            0
        };
        exact
            | if self.is_moving() {
                RECORDED_MOVING_LIGHT
            } else {
                0
            }
    }

    /// Whether the light turns during the shutter (its direction at t = 1 is not t = 0's).
    pub fn is_turning(&self) -> bool {
        self.end.is_some_and(|end| end.direction != self.direction)
    }

    /// Refused with [`crate::Error::InvalidArgument`] where this light turns in a way the exact
    /// lookup cannot follow, over the draws `records`. The conservative collection bounds a
    /// triangle's swept shadow by the hull of its corners' two projections (t = 0's by the
    /// t = 0 view, t = 1's by the t = 1 view), and the lookups read the map through the blend of
    /// the two views. A still point's image under the blend is the blend of its two images, in
    /// that hull; a moving point's is off it by `t (1 - t) (V1 - V0) (p1 - p0)`, so every draw
    /// must be static ([`super::Draw::is_static`]). The blended view's centre is a spot's
    /// position only while the spot turns in place (carried, it leaves it by
    /// `t (1 - t) (V0 L1 + V1 L0)`); a directional light's ray stays the blended view's own
    /// direction (docs/src/exact-lookups.md#a-turning-light).
    pub(crate) fn refuse_turning_exact(&self, records: &[DrawRecord]) -> crate::Result<()> {
        let Some(end) = self.end.filter(|_| self.is_turning()) else {
            return Ok(());
        };
        if self.is_spot() && end.position != self.position {
            return Err(crate::Error::InvalidArgument(
                "the exact lookup (Lookup::Exact) takes a turning spot light only turning in \
                 place (LightView::end with another position too): use the depth-line lookup"
                    .into(),
            ));
        }
        if let Some(moving) = records
            .iter()
            .find(|r| r.flags() & DRAW_STATIC == 0 && r.triangle_count > 0)
        {
            return Err(crate::Error::InvalidArgument(format!(
                "the exact lookup (Lookup::Exact) takes a turning light (LightView::end with \
                 another direction) only over static draws; the draw of triangle ids {} .. {} \
                 moves: use the depth-line lookup",
                moving.first_id,
                moving.first_id as u64 + moving.triangle_count as u64
            )));
        }
        Ok(())
    }

    /// Refused with [`crate::Error::InvalidArgument`] naming `what` (a pass or a setting that
    /// does not take a moving light yet) where this light moves.
    pub(crate) fn refuse_moving(&self, what: &str) -> crate::Result<()> {
        if self.is_moving() {
            return Err(crate::Error::InvalidArgument(format!(
                "{what} does not take a moving light (LightView::end) yet: build it with the \
                 light still, or use the temporal map's depth-line lookup"
            )));
        }
        Ok(())
    }

    /// World -> light clip at t = 1 (at t = 0 for a still light): the matrix the shutter's
    /// closing positions are projected with.
    pub fn view_proj_at_end(&self) -> Mat4 {
        self.proj * self.end.map_or(self.view, |end| end.view)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(position: Vec3, direction: Vec3) -> LightView {
        LightView::spot(position, direction, 30.0, 1.0, 0.5, 20.0, (64, 64))
    }

    /// A draw record of `triangles` triangles from id `first`, static or moving.
    fn record(first: u32, triangles: u32, is_static: bool) -> DrawRecord {
        let flags = if is_static { DRAW_STATIC } else { 0 };
        DrawRecord {
            first_id: first,
            triangle_count: triangles,
            albedo_flags: glam::Vec4::new(0.0, 0.0, 0.0, flags as f32),
            ..DrawRecord::default()
        }
    }

    #[test]
    fn the_exact_lookup_takes_a_turning_light_over_static_draws_a_spot_turning_in_place() {
        let d = Vec3::new(0.2, -1.0, 0.1);
        let light = spot(Vec3::new(0.0, 5.0, 0.0), d);
        assert!(!light.is_turning());
        let still = [record(0, 4, true), record(4, 2, true)];
        let one_moves = [record(0, 4, true), record(4, 2, false)];
        let carried = light.moving_to(Vec3::new(3.0, 5.0, 0.0), d).unwrap();
        assert!(carried.is_moving() && !carried.is_turning());
        assert!(carried.refuse_turning_exact(&one_moves).is_ok());
        let turned = light
            .moving_to(Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.5, -1.0, 0.1))
            .unwrap();
        assert!(turned.is_turning());
        assert!(turned.refuse_turning_exact(&still).is_ok());
        let refused = turned.refuse_turning_exact(&one_moves).unwrap_err();
        assert!(
            refused.to_string().contains("ids 4 .. 6 moves"),
            "{refused}"
        );
        let turned_and_carried = light
            .moving_to(Vec3::new(3.0, 5.0, 0.0), Vec3::new(0.5, -1.0, 0.1))
            .unwrap();
        let refused = turned_and_carried.refuse_turning_exact(&still).unwrap_err();
        assert!(
            refused.to_string().contains("turning in place"),
            "{refused}"
        );
        let sun = LightView::directional(d, 1.0, Vec3::ZERO, 10.0, 20.0, 1.0, 40.0, (64, 64));
        let turning_sun = sun
            .moving_to(Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.5, -1.0, 0.1))
            .unwrap();
        assert!(turning_sun.refuse_turning_exact(&still).is_ok());
        assert!(turning_sun.refuse_turning_exact(&one_moves).is_err());
    }

    #[test]
    fn a_translating_light_ends_with_the_view_of_a_light_built_there() {
        let d = Vec3::new(0.2, -1.0, 0.1);
        let moved = spot(Vec3::new(0.0, 5.0, 0.0), d)
            .moving_to(Vec3::new(3.0, 5.0, -1.0), d)
            .unwrap();
        let built_there = spot(Vec3::new(3.0, 5.0, -1.0), d);
        let end = moved.end.unwrap();
        assert!(end.view.abs_diff_eq(built_there.view, 1e-6), "{}", end.view);
        assert_eq!(moved.pose_at(0.5).0, Vec3::new(1.5, 5.0, -0.5));
        assert_eq!(moved.pose_at(0.5).1, built_there.direction);
    }

    #[test]
    fn a_turning_light_looks_along_its_end_direction_without_roll() {
        let (d0, d1) = (Vec3::NEG_Y, Vec3::new(1.0, -1.0, 0.0).normalize());
        let light = spot(Vec3::ZERO, d0)
            .moving_to(Vec3::X, Vec3::new(2.0, -2.0, 0.0))
            .unwrap();
        let end = light.end.unwrap();
        // The end view looks down -z along d1 from the end position.
        let ahead = end.view.transform_point3(Vec3::X + d1);
        assert!(ahead.abs_diff_eq(Vec3::NEG_Z, 1e-6), "{ahead}");
        // The whole frame turned by 45 degrees about z (the axis of d0 x d1), right and up
        // axes too: no roll about the light's axis.
        let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        for axis in 0..2 {
            let start = light.view.inverse().col(axis).truncate();
            let got = end.view.inverse().col(axis).truncate();
            assert!(got.abs_diff_eq(turn * start, 1e-6), "{axis}: {got} {start}");
        }
        // Halfway: the normalised blend, 22.5 degrees from each end.
        let half = light.pose_at(0.5).1;
        assert!((half.angle_between(d0).to_degrees() - 22.5).abs() < 1e-4);
    }

    #[test]
    fn a_right_angle_turn_and_a_zero_direction_are_refused() {
        let light = spot(Vec3::ZERO, Vec3::NEG_Y);
        let turned = light
            .moving_to(Vec3::ZERO, Vec3::X)
            .unwrap_err()
            .to_string();
        assert!(turned.contains("turns 90.0 degrees"), "{turned}");
        let zero = light
            .moving_to(Vec3::ZERO, Vec3::ZERO)
            .unwrap_err()
            .to_string();
        assert!(zero.contains("non-zero"), "{zero}");
        assert!(!light.is_moving());
        assert_eq!(light.view_proj_at_end(), light.proj * light.view);
    }
}
