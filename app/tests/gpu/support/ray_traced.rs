//! The ray tracer as the expectation of a render: the same scene, size and samples traced
//! on the CPU (no shadow map, nothing shared with the technique's passes).

use motion_shadows_app::compare::error_stats;
use motion_shadows_app::output::RadianceImage;
use motion_shadows_app::render::{Method, RenderSettings};
use motion_shadows_app::scene::Scene;

/// The RMSE of `image` (rendered from `scene` with `settings`) against the ray tracer's
/// image of the same samples.
pub fn rmse_against_the_ray_tracer(
    scene: &Scene,
    settings: &RenderSettings,
    image: &RadianceImage,
) -> f64 {
    // The ray tracer has no map to look up.
    let traced = RenderSettings {
        method: Method::Raytrace,
        lookup: motion_shadows::technique::Lookup::DepthLine,
        ..settings.clone()
    };
    let truth = motion_shadows_app::raytrace::render(scene, &traced, &mut |_| {})
        .expect("the ray tracer's image");
    error_stats(image, &truth.image, None)
        .expect("images of one size")
        .rmse
}
