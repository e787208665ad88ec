//! A frame driven through the library's public API alone (no app renderer): draws in,
//! temporal shadow map and lit image out. Tests use it to feed the passes geometry in forms
//! the app never produces (indexed, strided, offset, transformed) and compare the results.

use motion_shadows::gpu::{Context, OneShot};
use motion_shadows::technique::{
    CollectionPass, Counters, Draw, DrawList, GenerationPass, LightView, LightingPass,
    LightingTarget, LightingView, MAX_SAMPLES_PER_CHUNK, ShadowMapContents, ShadowSource,
    TemporalShadowMap,
};

/// What one frame produced.
pub struct Frame {
    pub rgb: Vec<f32>,
    pub counters: Counters,
    pub map: ShadowMapContents,
    /// Triangles the lighting pass dropped for an invalid index.
    pub lighting_invalid: u32,
}

/// Renders `draws` seen by `view` and lit by `light` with the temporal method, into an image
/// of `size` at `spp`, with a shadow map of `shadow_size` (grown and re-run until it fits).
pub fn render_draws(
    ctx: &Context,
    draws: &[Draw],
    light: &LightView,
    view: &LightingView,
    size: (u32, u32),
    shadow_size: (u32, u32),
    spp: u32,
) -> motion_shadows::Result<Frame> {
    let device = ctx.device();
    let collection = CollectionPass::new(ctx)?;
    let generation = GenerationPass::new(ctx)?;
    let lighting = LightingPass::new(ctx)?;
    let target = LightingTarget::new(ctx, size.0, size.1, spp, MAX_SAMPLES_PER_CHUNK)?;
    let mut list = DrawList::new(ctx, draws.len() as u32)?;
    let pixels = shadow_size.0 * shadow_size.1;
    let mut map = TemporalShadowMap::new(ctx, shadow_size.0, shadow_size.1, pixels, pixels)?;
    map.prepare_for(ctx, light, None)?;
    if light.lookup == motion_shadows::technique::Lookup::Exact {
        let ids = draws
            .iter()
            .map(|d| u64::from(d.first_triangle_id) + u64::from(d.triangle_count))
            .max()
            .unwrap_or(0);
        map.reserve_triangle_records(ctx, ids)?;
    }
    loop {
        OneShot::new(ctx)?.run(|cmd| {
            // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering; every
            // object outlives the submission, which `run` waits for.
            unsafe {
                list.record_update(device, cmd, draws)?;
                collection.record(device, cmd, &list, light, &map, None)?;
                generation.record(device, cmd, &map);
                map.record_counter_readback(device, cmd);
                lighting.record(
                    device,
                    cmd,
                    &list,
                    view,
                    ShadowSource::Temporal(&map),
                    &target,
                    None,
                )?;
            }
            // SAFETY: the same command buffer, after the frame's passes.
            unsafe { target.record_readback(device, cmd) };
            Ok(())
        })?;
        let counters = map.read_counters()?;
        if map.needs_more_room(&counters) {
            map.grow_to_fit(ctx, &counters)?;
            continue;
        }
        return Ok(Frame {
            rgb: target.read_rgb()?,
            counters,
            map: map.download(ctx)?,
            lighting_invalid: target.read_invalid_triangles()?,
        });
    }
}
