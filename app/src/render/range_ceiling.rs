//! The scene's upper bound on a temporal frame's ranges: the library's
//! [`RangeCeiling`] summed over the scene's triangles, in parallel (the
//! library itself spawns no threads).

use motion_shadows::technique::{LightView, RangeCeiling};
use rayon::prelude::*;

use crate::scene::Scene;

/// At most as many ranges as a temporal frame with the exact construction stores in a map
/// of `size` texels (moving triangles; static ones too unless `static_layer_used`, when the
/// static draws are in the layer), or None for the papers' prisms (not bounded) and for the
/// exact lookup: its static names are not bounded here, so "one attempt" would not hold;
/// the renderer grows that map after an overflow, as before the library bounded it.
pub fn ranges_at_most(
    scene: &Scene,
    light: &LightView,
    size: (u32, u32),
    static_layer_used: bool,
) -> Option<u64> {
    if light.lookup == motion_shadows::technique::Lookup::Exact {
        return None;
    }
    let ceiling = RangeCeiling::new(light, size.0, size.1)?;
    // The upload's culling flags: no culling where the light or camera is inside a mesh.
    let closed = crate::scene::effective_closed(scene);
    let mut total = 0u64;
    for (mesh, &closed) in scene.meshes.iter().zip(&closed) {
        // The same test the upload makes for a static draw (one stream named twice).
        if static_layer_used && mesh.t0 == mesh.t1 {
            continue;
        }
        total += mesh
            .t0
            .par_chunks_exact(3)
            .zip(mesh.t1.par_chunks_exact(3))
            .map(|(t0, t1)| {
                let corners = |c: &[glam::Vec3]| [c[0], c[1], c[2]];
                ceiling.triangle(&corners(t0), &corners(t1), closed)
            })
            .sum::<u64>();
    }
    Some(total)
}
