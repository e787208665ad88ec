//! `Scene::validate`: catches what would otherwise become NaNs or a blank image on the GPU.
//! Messages name the object and field so a hand-written scene file can be fixed quickly.

use glam::Vec3;

use super::clip::quoted;
use super::name::scene_name_problem;
use super::precision::check_precision;
use super::{Camera, Light, Mesh, Scene, SceneError};

fn invalid(what: &str, msg: String) -> SceneError {
    SceneError::Invalid(format!("{what}: {msg}"))
}

fn finite(what: &str, field: &str, v: f32) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(invalid(what, format!("{field} is not finite ({v})")))
    }
}

fn finite3(what: &str, field: &str, v: Vec3) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(invalid(what, format!("{field} is not finite ({v})")))
    }
}

fn nonzero(what: &str, field: &str, v: Vec3) -> Result<(), SceneError> {
    finite3(what, field, v)?;
    if v.length_squared() > 1e-12 {
        Ok(())
    } else {
        Err(invalid(what, format!("{field} must be non-zero")))
    }
}

/// 0 < near < far, both finite.
fn depth_range(what: &str, near: f32, far: f32) -> Result<(), SceneError> {
    finite(what, "near", near)?;
    finite(what, "far", far)?;
    if near <= 0.0 {
        return Err(invalid(what, format!("near must be > 0, got {near}")));
    }
    if far <= near {
        return Err(invalid(
            what,
            format!("far ({far}) must be > near ({near})"),
        ));
    }
    Ok(())
}

fn check_camera(c: &Camera) -> Result<(), SceneError> {
    check_camera_pose("camera", c)?;
    if let Some(end) = c.t1 {
        finite3("camera t1", "up", end.up)?;
        for (what, t) in [("camera t1", 1.0), ("camera at t = 0.5", 0.5)] {
            check_camera_pose(what, &c.at(t))?;
        }
        // The view direction blends linearly; under 90 degrees of turn it can never pass
        // through zero between the ends (its dot with the t = 0 direction stays positive).
        let (d0, d1) = (c.target - c.position, end.target - end.position);
        if d0.dot(d1) <= 0.0 {
            return Err(invalid(
                "camera t1",
                "the view direction (target - position) turns 90 degrees or more from t = 0's"
                    .into(),
            ));
        }
    }
    Ok(())
}

fn check_camera_pose(what: &str, c: &Camera) -> Result<(), SceneError> {
    finite3(what, "position", c.position)?;
    finite3(what, "target", c.target)?;
    nonzero(what, "up", c.up)?;
    nonzero(
        what,
        "view direction (target - position)",
        c.target - c.position,
    )?;
    let view = (c.target - c.position).normalize();
    if view.cross(c.up.normalize()).length() < 1e-3 {
        return Err(invalid(what, "up is parallel to the view direction".into()));
    }
    finite(what, "fov_y_deg", c.fov_y_deg)?;
    if !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) {
        return Err(invalid(
            what,
            format!("fov_y_deg must be in (0, 180), got {}", c.fov_y_deg),
        ));
    }
    depth_range(what, c.near, c.far)
}

fn check_light(light: &Light) -> Result<(), SceneError> {
    match light {
        Light::Spot(s) => {
            let what = "light (spot)";
            finite3(what, "position", s.position)?;
            nonzero(what, "direction", s.direction)?;
            finite(what, "cone_angle_deg", s.cone_angle_deg)?;
            if !(s.cone_angle_deg > 0.0 && s.cone_angle_deg <= 89.0) {
                let msg = format!(
                    "cone_angle_deg (half angle) must be in (0, 89], got {}",
                    s.cone_angle_deg
                );
                return Err(invalid(what, msg));
            }
            finite(what, "intensity", s.intensity)?;
            if s.intensity < 0.0 {
                return Err(invalid(
                    what,
                    format!("intensity must be >= 0, got {}", s.intensity),
                ));
            }
            if let Some(end) = &s.t1 {
                finite3(what, "t1 position", end.position)?;
                nonzero(what, "t1 direction", end.direction)?;
                turn(what, s.direction, end.direction)?;
            }
            depth_range(what, s.near, s.far)
        }
        Light::Directional(d) => {
            let what = "light (directional)";
            nonzero(what, "direction", d.direction)?;
            finite(what, "irradiance", d.irradiance)?;
            if d.irradiance < 0.0 {
                return Err(invalid(
                    what,
                    format!("irradiance must be >= 0, got {}", d.irradiance),
                ));
            }
            finite3(what, "center", d.center)?;
            finite(what, "half_extent", d.half_extent)?;
            if d.half_extent <= 0.0 {
                return Err(invalid(
                    what,
                    format!("half_extent must be > 0, got {}", d.half_extent),
                ));
            }
            finite(what, "distance", d.distance)?;
            // The shadow camera looks from center - direction * distance at center.
            if d.distance <= 0.0 {
                return Err(invalid(
                    what,
                    format!("distance must be > 0, got {}", d.distance),
                ));
            }
            if let Some(end) = &d.t1 {
                nonzero(what, "t1 direction", end.direction)?;
                finite3(what, "t1 center", end.center)?;
                turn(what, d.direction, end.direction)?;
            }
            depth_range(what, d.near, d.far)
        }
    }
}

/// A moving light's directions at t = 0 and t = 1 must be less than
/// `MAX_LIGHT_TURN_DEG` apart (the library's own test, `LightView::moving_to`).
fn turn(what: &str, d0: Vec3, d1: Vec3) -> Result<(), SceneError> {
    use motion_shadows::technique::MAX_LIGHT_TURN_DEG;
    let cos_turn = d0.normalize().dot(d1.normalize());
    // cos(90 degrees) is 0 exactly; its f32 radians are not.
    if cos_turn <= 0.0 {
        let degrees = cos_turn.clamp(-1.0, 1.0).acos().to_degrees();
        return Err(invalid(
            what,
            format!(
                "t1 direction turns {degrees:.1} degrees from direction; a moving light may \
                 turn less than {MAX_LIGHT_TURN_DEG} degrees during the shutter"
            ),
        ));
    }
    Ok(())
}

fn check_mesh(index: usize, m: &Mesh) -> Result<(), SceneError> {
    let what = format!("mesh #{index} ({:?})", quoted(&m.name));
    let what = what.as_str();
    finite3(what, "albedo", m.albedo)?;
    if m.albedo.min_element() < 0.0 || m.albedo.max_element() > 1.0 {
        return Err(invalid(
            what,
            format!("albedo must be in [0, 1], got {}", m.albedo),
        ));
    }
    if m.t0.len() != m.t1.len() {
        let msg = format!("t0 has {} vertices but t1 has {}", m.t0.len(), m.t1.len());
        return Err(invalid(what, msg));
    }
    if m.t0.is_empty() {
        return Err(invalid(what, "has no triangles".into()));
    }
    if m.t0.len() % 3 != 0 {
        let msg = format!("vertex count {} is not a multiple of 3", m.t0.len());
        return Err(invalid(what, msg));
    }
    let bad = |ps: &[Vec3]| ps.iter().position(|p| !p.is_finite());
    if let Some(i) = bad(&m.t0) {
        return Err(invalid(
            what,
            format!("t0 vertex {i} is not finite ({})", m.t0[i]),
        ));
    }
    if let Some(i) = bad(&m.t1) {
        return Err(invalid(
            what,
            format!("t1 vertex {i} is not finite ({})", m.t1[i]),
        ));
    }
    Ok(())
}

impl Scene {
    /// Checks everything the renderer relies on: finite numbers, camera and light ranges
    /// (fov in (0, 180), 0 < near < far, non-zero directions, up not along the view, cone
    /// half angle in (0, 89], intensity >= 0), and per mesh: albedo in [0, 1], t0/t1 of
    /// equal, non-zero length that is a multiple of 3; the name is a safe file name and
    /// every coordinate is small enough for single-precision ray tests (`limits`).
    pub fn validate(&self) -> Result<(), SceneError> {
        if let Some(problem) = scene_name_problem(&self.name) {
            return Err(SceneError::Invalid(problem));
        }
        check_camera(&self.camera)?;
        check_light(&self.light)?;
        finite("scene", "ambient", self.ambient)?;
        if self.ambient < 0.0 {
            return Err(invalid(
                "scene",
                format!("ambient must be >= 0, got {}", self.ambient),
            ));
        }
        if self.meshes.is_empty() {
            return Err(invalid("scene", "has no meshes".into()));
        }
        self.meshes
            .iter()
            .enumerate()
            .try_for_each(|(i, m)| check_mesh(i, m))?;
        check_precision(self)
    }
}

#[cfg(test)]
mod tests {
    use super::super::SpotLight;
    use super::*;

    fn scene() -> Scene {
        let tri = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
        Scene {
            name: "t".into(),
            camera: Camera {
                position: Vec3::new(0.0, 2.0, 5.0),
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 45.0,
                near: 0.1,
                far: 100.0,
                t1: None,
            },
            light: Light::Spot(SpotLight {
                position: Vec3::Y * 5.0,
                direction: -Vec3::Y,
                cone_angle_deg: 40.0,
                intensity: 10.0,
                near: 0.5,
                far: 20.0,
                t1: None,
            }),
            ambient: 0.0,
            meshes: vec![Mesh {
                name: "tri".into(),
                albedo: Vec3::splat(0.5),
                closed: false,
                t0: tri.clone(),
                t1: tri,
            }],
        }
    }

    fn message(s: &Scene) -> String {
        match s.validate() {
            Err(SceneError::Invalid(m)) => m,
            other => panic!("expected Invalid, got {other:?}"),
        }
    }

    #[test]
    fn accepts_good_scene() {
        scene().validate().unwrap();
    }

    #[test]
    fn rejects_bad_values_naming_the_object() {
        let mut s = scene();
        s.camera.fov_y_deg = -5.0;
        assert!(message(&s).contains("camera") && message(&s).contains("fov_y_deg"));

        let mut s = scene();
        s.camera.up = Vec3::new(0.0, -2.0, -5.0);
        assert!(message(&s).contains("parallel"));

        let mut s = scene();
        s.meshes[0].t1.pop();
        let m = message(&s);
        assert!(
            m.contains("mesh #0") && m.contains("\"tri\"") && m.contains("t1"),
            "{m}"
        );

        let mut s = scene();
        s.meshes[0].albedo.x = 1.5;
        assert!(message(&s).contains("albedo"));

        let mut s = scene();
        s.meshes[0].t0[1].y = f32::NAN;
        assert!(message(&s).contains("t0 vertex 1"));

        let mut s = scene();
        if let Light::Spot(l) = &mut s.light {
            l.cone_angle_deg = 90.0;
        }
        assert!(message(&s).contains("cone_angle_deg"));

        let mut s = scene();
        s.meshes.clear();
        assert!(message(&s).contains("no meshes"));
    }

    #[test]
    fn bounds_cover_both_times() {
        let mut s = scene();
        s.meshes[0].t1[0] = Vec3::new(-1.0, 3.0, 0.0);
        assert_eq!(
            s.bounds(),
            (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 3.0, 1.0))
        );
        assert_eq!(s.triangle_count(), 1);
    }
}
