//! The moving camera (issue 38 item 3): what takes it and what refuses it. The ray tracer's
//! forward frame shoots each sample's ray from the camera at that sample's time; the GPU
//! frames and the deferred truth do not take it yet, and say so by name rather than render
//! the camera at t = 0 only.

use crate::error::{Error, Result};
use crate::scene::Scene;

/// Refuses a scene whose camera moves for `what` (a method, a frame, the viewer) that does
/// not take a moving camera yet: it would see the scene from the camera at t = 0 only.
pub fn refuse_moving_camera(scene: &Scene, what: &str) -> Result<()> {
    if scene.camera.moves() {
        return Err(Error::InvalidArgument(format!(
            "scene {:?}: its camera moves during the shutter (the camera's \"t1\"), which \
             {what} does not take yet; render --method raytrace (the forward frame) does",
            scene.name
        )));
    }
    Ok(())
}
