//! The moving camera (issue 38 item 3): what takes it and what refuses it. The ray tracer's
//! forward frame shoots each sample's ray from the camera at that sample's time; the GPU's
//! forward frame (every method, through the library's lighting pass) moves each vertex's clip
//! position linearly from the t = 0 camera's to the t = 1 camera's ([`camera_view`]). The
//! deferred frames and the viewer do not take it yet, and say so by name rather than render
//! the camera at t = 0 only.

use crate::error::{Error, Result};
use crate::scene::Scene;
use motion_shadows::technique::CameraView;

/// The GPU forward frame's camera for an image of `image_size`: the scene's camera at t = 0,
/// with its pose at t = 1 where it moves (`CameraView::moving_to`).
pub fn camera_view(scene: &Scene, image_size: (u32, u32)) -> Result<CameraView> {
    let start = super::upload::camera_view(scene, image_size);
    match scene.camera.t1 {
        None => Ok(start),
        Some(end) => Ok(start.moving_to(end.position, end.target, end.up)?),
    }
}

/// Refuses a scene whose camera moves for `what` (a method, a frame, the viewer, a setting)
/// that does not take a moving camera: it would see the scene from the camera at t = 0 only.
pub fn refuse_moving_camera(scene: &Scene, what: &str) -> Result<()> {
    if scene.camera.moves() {
        return Err(Error::InvalidArgument(format!(
            "scene {:?}: its camera moves during the shutter (the camera's \"t1\"), which \
             {what} does not take; the forward frame (render, compare, animate) does",
            scene.name
        )));
    }
    Ok(())
}

/// Refuses the forward frame's settings whose shading takes the camera as still, where the
/// camera moves: the analytic estimator (a still receiver's lit share of the shutter at one
/// point, which a moving camera does not hold on one point) and the footprint filter (the
/// pixel's footprint measured from the camera at t = 0), named with what to use instead.
pub fn check_moving_camera_forward(scene: &Scene, settings: &super::RenderSettings) -> Result<()> {
    use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
    if settings.shadow_estimator == ShadowEstimator::Analytic {
        refuse_moving_camera(
            scene,
            "--shadow-estimator analytic (use --shadow-estimator sampled)",
        )?;
    }
    if settings.shadow_filter == ShadowFilter::Footprint {
        refuse_moving_camera(
            scene,
            "--shadow-filter footprint (use --shadow-filter none or bilinear)",
        )?;
    }
    Ok(())
}
