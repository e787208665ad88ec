//! A camera that moves during the shutter (issue 38): its pose at t = 1 beside the
//! [`CameraView`] of t = 0, and what the lighting pass reads of it.
//!
//! The lighting pass follows McGuire et al. 2010: each vertex's clip position at t = 0 is
//! made with the t = 0 camera and at t = 1 with the t = 1 camera, and a sample at time t sees
//! the vertices where the linear blend of the two puts them. The pass works in the t = 0
//! camera's frame: a vertex's t = 1 position is carried to where the t = 0 camera must see it
//! to see it as the t = 1 camera does ([`GpuCameraEnd::frame`]), and the stochastic raster,
//! its per-pixel time bounds and the per-sample ray tests run unchanged on those corners.
//! Blending clip positions linearly is exact for a camera that translates without turning (a
//! pan: the view is the same rotation of a linearly moving offset); for a turning camera a
//! point's image moves along the chord between its two ends rather than the arc the true
//! camera sweeps (docs/src/scene-format.md, "A moving camera").

use super::gpu_types::GpuCameraEnd;
use super::view::CameraView;
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Vec3};

/// A moving camera's pose at t = 1 ([`CameraView::end`]). The projection, near and far
/// planes stay those of t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraEnd {
    /// Eye position at t = 1.
    pub position: Vec3,
    /// Unit view direction at t = 1.
    pub forward: Vec3,
    /// World -> view at t = 1.
    pub view: Mat4,
}

impl CameraView {
    /// This camera, moving during the shutter from its pose at t = 0 (`self`) to the camera at
    /// `position` looking at `target` with `up` at t = 1 (projection, near and far planes
    /// unchanged). Between the two ends each vertex's clip position moves linearly (module
    /// documentation of `camera_motion`). Refused (with [`crate::Error::InvalidArgument`]) for
    /// non-finite values, a target at the position, or an `up` along the view direction.
    pub fn moving_to(mut self, position: Vec3, target: Vec3, up: Vec3) -> crate::Result<Self> {
        let forward = target - position;
        if !position.is_finite()
            || !target.is_finite()
            || !up.is_finite()
            || forward.length() == 0.0
            || forward.cross(up).length() == 0.0
        {
            return Err(crate::Error::InvalidArgument(format!(
                "CameraView::moving_to: position {position}, target {target} and up {up} must \
                 be finite, the target away from the position and up not along the view"
            )));
        }
        self.end = Some(CameraEnd {
            position,
            forward: forward.normalize(),
            view: look_at_mat4(position, target, up),
        });
        Ok(self)
    }

    /// Whether the camera moves during the shutter (it has a pose at t = 1).
    pub fn is_moving(&self) -> bool {
        self.end.is_some()
    }

    /// The pose at t = 1 as the lighting pass reads it; `None` for a still camera.
    pub fn gpu_end(&self) -> Option<GpuCameraEnd> {
        self.end.map(|end| GpuCameraEnd {
            frame: self.view.inverse() * end.view,
            position: end.position.extend(1.0),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> CameraView {
        CameraView::perspective(
            Vec3::new(0.0, 8.0, 16.0),
            Vec3::new(0.0, 2.6, 0.0),
            Vec3::Y,
            45.0,
            4.0 / 3.0,
            0.1,
            100.0,
        )
    }

    /// The frame carries a point to where the t = 0 view sees it as the t = 1 view does:
    /// view0 (frame p) = view1 p, for a camera that translates and turns.
    #[test]
    fn the_end_frame_shows_the_t0_view_what_the_t1_view_sees() {
        let moving = camera()
            .moving_to(
                Vec3::new(3.0, 7.0, 15.0),
                Vec3::new(-1.0, 2.0, 1.0),
                Vec3::Y,
            )
            .unwrap();
        let frame = moving.gpu_end().unwrap().frame;
        let end = moving.end.unwrap();
        for p in [Vec3::new(1.0, 2.0, 3.0), Vec3::new(-4.0, 0.5, -2.0)] {
            let seen_at_start = moving.view.transform_point3(frame.transform_point3(p));
            let seen_at_end = end.view.transform_point3(p);
            assert!(
                seen_at_start.distance(seen_at_end) < 1e-4,
                "{seen_at_start} vs {seen_at_end}"
            );
        }
        assert!(camera().gpu_end().is_none() && !camera().is_moving());
    }

    #[test]
    fn a_pose_that_is_no_camera_is_refused_by_name() {
        let at = Vec3::new(1.0, 2.0, 3.0);
        for (position, target, up) in [
            (at, at, Vec3::Y),
            (at, at + Vec3::Y, Vec3::Y),
            (Vec3::NAN, at, Vec3::Y),
        ] {
            let refused = camera()
                .moving_to(position, target, up)
                .expect_err("refused");
            assert!(
                refused.to_string().contains("CameraView::moving_to"),
                "{refused}"
            );
        }
    }
}
