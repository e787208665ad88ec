//! The warning for a temporal shadow map that received nothing, naming its real cause. Two
//! causes look alike from the counters: every triangle is outside what the light sees, or
//! some are inside but the map is so coarse that no texel centre falls in any of them (a
//! `--shadow-size 256x1` map is one row of centres, which a scene can miss entirely). A vertex
//! inside the light's view tells them apart: then the texel grid is to blame.

use glam::Vec3;
use motion_shadows::technique::{LightView, PrismConstruction};

use crate::scene::Scene;

/// The warning text for an empty map of `shadow_size` texels.
pub(super) fn empty_map_warning(
    scene: &Scene,
    light: &LightView,
    shadow_size: (u32, u32),
    prisms: PrismConstruction,
) -> String {
    if any_vertex_in_view(scene, light, prisms) {
        let (w, h) = shadow_size;
        return format!(
            "no triangle reaches the shadow map: the geometry is inside the light's view, but \
             no texel centre of the {w}x{h} map falls inside a triangle (the map is too coarse \
             along one side; raise --shadow-size): the image has no shadows"
        );
    }
    // The exact construction is not clipped by the light's near and far planes.
    let outside = match prisms {
        PrismConstruction::Exact => "the light's cone or box",
        PrismConstruction::Paper => "the light's cone or its near..far depth range",
    };
    format!("no triangle reaches the shadow map (all outside {outside}): the image has no shadows")
}

/// Whether some vertex, at either end of the shutter, projects inside the map's square, in
/// front of the light; for the papers' prisms, which the near and far planes clip, also
/// within that depth range (Vulkan clip space: z in [0, w]).
fn any_vertex_in_view(scene: &Scene, light: &LightView, prisms: PrismConstruction) -> bool {
    let view_proj = light.proj * light.view;
    let clipped = prisms == PrismConstruction::Paper;
    let inside = |p: &Vec3| {
        let clip = view_proj * p.extend(1.0);
        let square = clip.w > 0.0 && clip.x.abs() < clip.w && clip.y.abs() < clip.w;
        square && (!clipped || (0.0..=clip.w).contains(&clip.z))
    };
    scene
        .meshes
        .iter()
        .flat_map(|m| m.t0.iter().chain(&m.t1))
        .any(inside)
}
