//! Refuses scenes too large for single-precision ray tests, relative to the camera's near
//! distance (the bound and its derivation: `limits::MAX_COORDINATE_OVER_NEAR`). Such a
//! scene would otherwise render as a mostly black image with no error at all.

use glam::Vec3;

use super::limits::MAX_COORDINATE_OVER_NEAR;
use super::{Light, Scene, SceneError};

fn magnitude(p: Vec3) -> f32 {
    p.abs().max_element()
}

/// Every position the renderer computes with (vertices at both times, the camera, the light)
/// must have |coordinate| <= `MAX_COORDINATE_OVER_NEAR` x camera near. The error names the
/// first object past the bound. Expects finite values (checked before).
pub(super) fn check_precision(scene: &Scene) -> Result<(), SceneError> {
    let near = scene.camera.near;
    let bound = MAX_COORDINATE_OVER_NEAR * near;
    let refuse = |what: &str, value: f32| {
        SceneError::Invalid(format!(
            "{what}: coordinate {value:e} is {:.1e} times the camera's near distance {near}; \
             single-precision ray tests need |coordinate| <= {MAX_COORDINATE_OVER_NEAR:e} x near \
             (here {bound:e}): scale the scene down or move camera.near out \
             (docs/scene-format.md, \"Limits\")",
            value / near
        ))
    };
    let mut points = vec![("camera position", scene.camera.position)];
    if let Some(end) = scene.camera.t1 {
        points.push(("camera t1 position", end.position));
    }
    match &scene.light {
        Light::Spot(s) => points.push(("light (spot) position", s.position)),
        Light::Directional(d) => {
            points.push(("light (directional) center", d.center));
            points.push(("light (directional) eye", d.eye()));
        }
    }
    for (what, p) in points {
        if magnitude(p) > bound {
            return Err(refuse(what, magnitude(p)));
        }
    }
    for (i, mesh) in scene.meshes.iter().enumerate() {
        let largest = mesh
            .t0
            .iter()
            .chain(&mesh.t1)
            .map(|&p| magnitude(p))
            .fold(0.0, f32::max);
        if largest > bound {
            let what = format!("mesh #{i} ({:?})", super::clip::quoted(&mesh.name));
            return Err(refuse(&what, largest));
        }
    }
    Ok(())
}
