//! What a method's maps need before a frame is recorded: the temporal map's room, reserved
//! from the host's positions for the depth-line and the exact lookup alike (so no frame
//! overflows, is grown after and misses casters), and TSM's maps. Used for the frame's method
//! and for the split view's right-hand one, each with its own maps.

use super::allocations::AllocationCounter;
use super::frame_slot::{TsmTargets, tsm_targets};
use super::method::ViewMethod;
use crate::scene::Scene;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{EngineTsmPass, HostDraw, LightView, TemporalShadowMap};

/// One side's maps and what it shows.
pub struct Side<'a> {
    pub method: ViewMethod,
    pub light: &'a LightView,
    pub map: &'a mut TemporalShadowMap,
    pub tsm: &'a mut Option<TsmTargets>,
    /// The method differs from this side's last frame's: what it makes is counted as an
    /// event (a method's first use), not as a frame's allocation.
    pub switched: bool,
}

/// Makes `side`'s maps ready for a frame of `scene` (`triangles` its triangle ids): TSM's
/// maps (with `tsm_pass`), or the temporal map's room. Returns the number of TSM maps, None
/// for the temporal methods.
pub fn prepare_side(
    ctx: &Context,
    side: Side<'_>,
    tsm_pass: Option<&EngineTsmPass>,
    scene: &Scene,
    triangles: u64,
    counter: &mut AllocationCounter,
) -> anyhow::Result<Option<u32>> {
    let mut prepare = |c: &mut AllocationCounter| match side.method {
        ViewMethod::Tsm { maps } => {
            let Some(pass) = tsm_pass else {
                anyhow::bail!("TSM's pass was not made");
            };
            let shadow = (side.map.width(), side.map.height());
            tsm_targets(side.tsm, ctx, pass, shadow, maps, c)?;
            Ok(Some(maps))
        }
        ViewMethod::TemporalExact => {
            // The exact lookup reads each triangle's corners from the map's records.
            let before = side.map.allocated_bytes();
            side.map.reserve_triangle_records(ctx, triangles)?;
            if side.map.allocated_bytes() != before {
                c.note(1);
            }
            reserve_map(ctx, side.map, side.light, scene, c)?;
            Ok(None)
        }
        ViewMethod::Temporal => {
            reserve_map(ctx, side.map, side.light, scene, c)?;
            Ok(None)
        }
    };
    if side.switched {
        counter.during_event(prepare)
    } else {
        prepare(counter)
    }
}

/// Reserves room in `map` for all that a frame of `scene` lit by `light` can store, from the
/// host's positions ([`TemporalShadowMap::reserve_for`], the exact lookup's conservative
/// collection included): such a frame never overflows and is never grown and drawn again.
/// Reserved before every frame: what the map can store changes with the animation. Counts
/// the map's growth as an allocation. Under a moving light nothing is reserved: the ceiling
/// does not bound the prisms of triangles moving in the light's moving frame
/// (`RangeCeiling::new`), so the map grows after a frame that overflowed, as the offline
/// frame's does, and that frame is counted incomplete (`incomplete_frames`).
pub fn reserve_map(
    ctx: &Context,
    map: &mut TemporalShadowMap,
    light: &LightView,
    scene: &Scene,
    counter: &mut AllocationCounter,
) -> anyhow::Result<()> {
    if light.is_moving() {
        return Ok(());
    }
    // As the upload draws them (`render::upload::scene_draws`): a mesh that does not move
    // names its positions twice (static: in the static layer, not in the lists), closed
    // meshes are culled.
    let closed = crate::scene::effective_closed(scene);
    let host_draws: Vec<HostDraw> = scene
        .meshes
        .iter()
        .zip(closed)
        .filter(|(m, _)| m.t0.len() >= 3)
        .map(|(m, closed)| {
            let t1 = if m.t0 == m.t1 { &m.t0 } else { &m.t1 };
            HostDraw {
                closed,
                ..HostDraw::new(&m.t0, t1, None)
            }
        })
        .collect();
    let before = map.allocated_bytes();
    if map.reserve_for(ctx, light, None, &host_draws)?.is_none() {
        anyhow::bail!(
            "the viewer's light has the papers' prisms, whose map room cannot be reserved \
             before the frame"
        );
    }
    if map.allocated_bytes() != before {
        counter.note(1);
    }
    Ok(())
}
