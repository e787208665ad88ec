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

use super::view::LightView;
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Quat, Vec3};

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
        if cos_turn <= MAX_LIGHT_TURN_DEG.to_radians().cos() {
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

    /// World -> light clip at t = 1 (at t = 0 for a still light): the matrix the shutter's
    /// closing positions are projected with.
    pub fn view_proj_at_end(&self) -> Mat4 {
        self.proj * self.end.map_or(self.view, |end| end.view)
    }
}
