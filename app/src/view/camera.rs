//! The viewer's camera: starts as the scene's, orbits around its target (mouse drag), dollies
//! toward it (wheel) and flies (keys: the eye and the target move together). The eye and
//! target are kept as such, not rebuilt from angles, so that an untouched camera is exactly
//! the scene's (the scripted run compares with the offline frame of that camera).

use crate::scene::Camera;
use glam::{Quat, Vec3};
use motion_shadows::technique::CameraView;

/// Radians of orbit per pixel dragged.
const ORBIT_PER_PIXEL: f32 = 0.005;
/// The closest the view direction comes to the up axis (radians), so that the view stays
/// defined.
const MIN_ANGLE_TO_UP: f32 = 0.05;
/// Each wheel step moves the eye this share of its distance toward the target.
const DOLLY_PER_STEP: f32 = 0.1;

#[derive(Debug, Clone, PartialEq)]
pub struct CameraControl {
    pub position: Vec3,
    pub target: Vec3,
    up: Vec3,
    fov_y_deg: f32,
    near: f32,
    far: f32,
    start: Camera,
}

impl CameraControl {
    pub fn new(camera: &Camera) -> Self {
        Self {
            position: camera.position,
            target: camera.target,
            up: camera.up.normalize_or(Vec3::Y),
            fov_y_deg: camera.fov_y_deg,
            near: camera.near,
            far: camera.far,
            start: camera.clone(),
        }
    }

    /// Back to the scene's camera.
    pub fn reset(&mut self) {
        *self = Self::new(&self.start.clone());
    }

    /// The view for an image of `size` pixels (the offline renderer's `camera_view`).
    pub fn view(&self, (width, height): (u32, u32)) -> CameraView {
        // The scene's own up (not normalized here), as the offline frame passes it.
        CameraView::perspective(
            self.position,
            self.target,
            self.start.up,
            self.fov_y_deg,
            width as f32 / height.max(1) as f32,
            self.near,
            self.far,
        )
    }

    /// Turns the eye around the target: `dx` pixels around the up axis, `dy` pixels up or
    /// down (stopping short of the up axis).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        let offset = self.position - self.target;
        let yawed = Quat::from_axis_angle(self.up, -dx * ORBIT_PER_PIXEL) * offset;
        // Dragging down raises the eye: the angle to the up axis shrinks, within its range.
        let current = yawed.angle_between(self.up);
        let wanted = (current - dy * ORBIT_PER_PIXEL)
            .clamp(MIN_ANGLE_TO_UP, std::f32::consts::PI - MIN_ANGLE_TO_UP);
        let right = yawed.cross(self.up).normalize_or_zero();
        self.position = self.target + Quat::from_axis_angle(right, current - wanted) * yawed;
    }

    /// Moves the eye `steps` wheel steps toward the target (negative: away), never onto it.
    pub fn dolly(&mut self, steps: f32) {
        let offset = self.position - self.target;
        let scale = (1.0 - DOLLY_PER_STEP).powf(steps);
        let distance = (offset.length() * scale).max(self.near * 2.0);
        self.position = self.target + offset.normalize_or(Vec3::Z) * distance;
    }

    /// Flies the eye and the target together: `forward`, `right` and `up` in units of a
    /// tenth of the distance to the target (so the speed suits any scene's scale).
    pub fn fly(&mut self, forward: f32, right: f32, up: f32) {
        let offset = self.target - self.position;
        let step = offset.length() * 0.1;
        let ahead = offset.normalize_or(Vec3::NEG_Z);
        let side = ahead.cross(self.up).normalize_or(Vec3::X);
        let moved = (ahead * forward + side * right + self.up * up) * step;
        self.position += moved;
        self.target += moved;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 2.0, 10.0),
            target: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 100.0,
            t1: None,
        }
    }

    #[test]
    fn untouched_it_is_the_scene_camera_exactly() {
        let control = CameraControl::new(&camera());
        let c = camera();
        let expected = CameraView::perspective(
            c.position,
            c.target,
            c.up,
            c.fov_y_deg,
            16.0 / 9.0,
            c.near,
            c.far,
        );
        assert_eq!(control.view((1600, 900)).view, expected.view);
        assert_eq!(control.view((1600, 900)).proj, expected.proj);
    }

    #[test]
    fn orbit_keeps_the_distance_and_a_full_turn_comes_back() {
        let mut control = CameraControl::new(&camera());
        let distance = (control.position - control.target).length();
        // 2 pi / ORBIT_PER_PIXEL pixels across: one turn around the up axis.
        let pixels = std::f32::consts::TAU / ORBIT_PER_PIXEL;
        control.orbit(pixels / 2.0, 0.0);
        // Half a turn: the eye is on the other side of the target.
        assert!((control.position - Vec3::new(0.0, 2.0, -10.0)).length() < 1e-3);
        control.orbit(pixels / 2.0, 0.0);
        assert!((control.position - camera().position).length() < 1e-3);
        control.orbit(0.0, 10_000.0);
        assert!(((control.position - control.target).length() - distance).abs() < 1e-3);
        // Stopped short of the up axis: the view is still defined.
        let angle = (control.position - control.target).angle_between(Vec3::Y);
        assert!((angle - MIN_ANGLE_TO_UP).abs() < 1e-3, "{angle}");
    }

    #[test]
    fn dolly_and_fly_move_by_the_stated_amounts() {
        let mut control = CameraControl::new(&camera());
        let distance = (control.position - control.target).length();
        control.dolly(1.0);
        let closer = (control.position - control.target).length();
        assert!((closer - distance * 0.9).abs() < 1e-4);
        control.dolly(-1.0);
        assert!(((control.position - control.target).length() - distance).abs() < 1e-4);
        let before = control.clone();
        control.fly(1.0, 0.0, 0.0);
        let moved = control.position - before.position;
        assert!((moved.length() - distance * 0.1).abs() < 1e-4);
        assert!((control.target - before.target - moved).length() < 1e-5);
        control.reset();
        assert_eq!(control, CameraControl::new(&camera()));
    }
}
