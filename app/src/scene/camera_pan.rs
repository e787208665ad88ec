//! `camera-pan`: the default scene (cubes-toward-light) filmed by a camera panning sideways
//! during the shutter (issue 38): position and target carried together, so its orientation
//! holds and every still thing (the ground, the pillar) blurs on screen as well as the cubes.

use glam::Vec3;

use super::builtin::cubes_toward_light;
use super::file::{CameraPoseFile, SceneFile};

/// How far the camera (and the point it looks at) is carried along +x by t = 1: about a
/// tenth of the image's width at the scene's centre, 17 units away.
pub(super) const CAMERA_CARRIED: Vec3 = Vec3::new(1.5, 0.0, 0.0);

pub(super) fn camera_pan() -> SceneFile {
    let mut file = cubes_toward_light();
    file.name = Some("camera-pan".to_owned());
    file.camera.t1 = Some(CameraPoseFile {
        position: Some(file.camera.position + CAMERA_CARRIED),
        target: Some(file.camera.target + CAMERA_CARRIED),
        up: None,
    });
    file
}
