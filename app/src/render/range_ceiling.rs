//! The scene's upper bound on a temporal frame's ranges: the library's
//! [`RangeCeiling`] summed over the scene's triangles, in parallel (the
//! library itself spawns no threads).

use motion_shadows::technique::{LightView, RangeCeiling};
use rayon::prelude::*;

use crate::scene::Scene;

/// At most as many ranges as a temporal frame with the exact construction stores in a map
/// of `size` texels (moving triangles; static ones too unless `static_layer_used`, when the
/// static draws are in the layer), or None for the papers' prisms (not bounded).
pub fn ranges_at_most(
    scene: &Scene,
    light: &LightView,
    size: (u32, u32),
    static_layer_used: bool,
) -> Option<u64> {
    room_at_most(scene, light, size, static_layer_used).map(|room| room.ranges)
}

/// The room a temporal frame needs at most, from the scene alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoomAtMost {
    /// Depth-time ranges ([`ranges_at_most`]).
    pub ranges: u64,
    /// Names in the exact lookup's static name lists (its static layer: each still
    /// triangle once per texel of its grown footprint); 0 for the depth-line lookup, whose
    /// static layer is one depth per texel.
    pub static_names: u64,
}

/// [`ranges_at_most`] with the exact lookup's static names beside the ranges: room for both
/// lets its first shadow pass run once too (without them the renderer grew the name lists
/// after an overflow and drew the pass again).
pub fn room_at_most(
    scene: &Scene,
    light: &LightView,
    size: (u32, u32),
    static_layer_used: bool,
) -> Option<RoomAtMost> {
    let names_still = light.lookup == motion_shadows::technique::Lookup::Exact;
    let ceiling = RangeCeiling::new(light, size.0, size.1)?;
    // The upload's culling flags: no culling where the light or camera is inside a mesh.
    let closed = crate::scene::effective_closed(scene);
    let mut room = RoomAtMost {
        ranges: 0,
        static_names: 0,
    };
    for (mesh, &closed) in scene.meshes.iter().zip(&closed) {
        // The same test the upload makes for a static draw (one stream named twice).
        let in_static_layer = static_layer_used && mesh.t0 == mesh.t1;
        if in_static_layer && !names_still {
            continue;
        }
        let most = mesh
            .t0
            .par_chunks_exact(3)
            .zip(mesh.t1.par_chunks_exact(3))
            .map(|(t0, t1)| {
                let corners = |c: &[glam::Vec3]| [c[0], c[1], c[2]];
                ceiling.triangle(&corners(t0), &corners(t1), closed)
            })
            .sum::<u64>();
        if in_static_layer {
            room.static_names += most;
        } else {
            room.ranges += most;
        }
    }
    Some(room)
}
