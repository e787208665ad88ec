//! One frame by any method: the device's renderer or the CPU ray tracer, chosen here, above
//! both (`render` drives the device, `raytrace` traces on the CPU; neither calls the other).

use crate::error::Result;
use crate::raytrace;
use crate::render::deferred::{DeferredMethod, DeferredResult, DeferredSettings};
use crate::render::{Method, RenderResult, RenderSettings, Renderer};
use crate::scene::Scene;

/// The stochastic frame of `settings.method`: [`Method::Raytrace`] on the CPU, every other
/// method on `renderer` (which must be given for them).
pub fn render(
    renderer: Option<&mut Renderer>,
    scene: &Scene,
    settings: &RenderSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<RenderResult> {
    match (settings.method, renderer) {
        (Method::Raytrace, _) => raytrace::render(scene, settings, progress),
        (_, Some(renderer)) => renderer.render(scene, settings, progress),
        (method, None) => Err(no_device(method.name())),
    }
}

/// The deferred frame of `deferred.method`: the truth on the CPU, every other method on
/// `renderer` (which must be given for them).
pub fn render_deferred(
    renderer: Option<&mut Renderer>,
    scene: &Scene,
    settings: &RenderSettings,
    deferred: &DeferredSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<DeferredResult> {
    match (deferred.method, renderer) {
        (DeferredMethod::Raytrace, _) => {
            raytrace::deferred::render_truth(scene, settings, deferred, progress)
        }
        (_, Some(renderer)) => renderer.render_deferred(scene, settings, deferred, progress),
        (method, None) => Err(no_device(&method.name())),
    }
}

fn no_device(method: &str) -> crate::Error {
    crate::Error::InvalidArgument(format!("the {method} method needs a Vulkan device"))
}
