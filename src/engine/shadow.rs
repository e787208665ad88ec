//! The per-light shadow object: one light's map per frame in flight, the passes that fill it,
//! and one call per frame that records them into the host's command buffer.

use ash::vk;

use super::frame::ShadowFrame;
use super::mesh::Mesh;
use super::settings::{ShadowSettings, StaticLayer};
use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::technique::{
    CollectionPass, DrawList, GenerationPass, LightView, Lookup, MaskBindings, MaskInputs,
    TemporalShadowMap, VisibilityMaskPass,
};

/// Draws a frame's list has room for until a frame needs more.
const INITIAL_DRAWS: usize = 16;
/// A map that must grow for a frame's meshes grows half again what they need: moving
/// meshes' room changes a little every frame, and each reallocation also forgets a kept
/// static layer (found by the deferred example: a kept layer redrawn two frames later).
const ROOM_HEADROOM_QUARTERS: u64 = 2;

/// What one frame in flight holds.
struct Slot {
    map: TemporalShadowMap,
    draws: DrawList,
    /// Draws the list has room for.
    draw_capacity: usize,
    /// The mask's bindings and the pixels they were made for.
    mask: Option<(MaskBindings, (u32, u32))>,
    /// The frame last recorded into this slot, and the ranges reserved for it (None: not
    /// bounded, grown after an overflow instead).
    recorded: Option<(u64, Option<u64>)>,
    /// The frame whose collection last drew the static layer, until it is known completed.
    layer_drawn_at: Option<u64>,
}

/// One light's temporal shadow: its maps (one per frame in flight), the collection and
/// generation passes, and the visibility mask when the settings ask for it. A frame is one
/// [`Self::record_frame`] into the host's command buffer and, after that frame's fence,
/// [`Self::finish_frame`].
pub struct LightShadow {
    settings: ShadowSettings,
    light: LightView,
    collection: CollectionPass,
    generation: GenerationPass,
    mask: Option<VisibilityMaskPass>,
    slots: Vec<Slot>,
}

impl LightShadow {
    /// The passes and one map per frame in flight, for `settings`. Errors name a setting out
    /// of range (or a device without what the mask needs).
    pub fn new(ctx: &Context, settings: ShadowSettings) -> Result<Self> {
        let (width, height) = settings.map_size;
        if settings.frames_in_flight == 0 {
            return Err(Error::InvalidArgument(
                "ShadowSettings::frames_in_flight is 0: at least one frame records".into(),
            ));
        }
        let shader_stages = crate::gpu::Access::ANY_SHADER_READ.stages;
        if !shader_stages.contains(settings.lookup_stages) {
            return Err(Error::InvalidArgument(format!(
                "ShadowSettings::lookup_stages {:?} names stages no shader reads the map in \
                 (only {shader_stages:?})",
                settings.lookup_stages
            )));
        }
        let mut light = settings.light.view(settings.map_size)?;
        light.static_layer = settings.static_layer != StaticLayer::Off;
        light.keep_static_layer = settings.static_layer == StaticLayer::Kept;
        light.lookup = settings.lookup;
        let slots = (0..settings.frames_in_flight)
            .map(|_| -> Result<Slot> {
                let mut map = TemporalShadowMap::with_storage(
                    ctx,
                    width,
                    height,
                    1,
                    1,
                    settings.range_storage,
                )?
                .with_pruning(settings.pruning);
                map.prepare_for(ctx, &light, None)?;
                Ok(Slot {
                    map,
                    draws: DrawList::new(ctx, INITIAL_DRAWS as u32)?,
                    draw_capacity: INITIAL_DRAWS,
                    mask: None,
                    recorded: None,
                    layer_drawn_at: None,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let generation = GenerationPass::new(ctx)?;
        generation.prepare(settings.pruning)?;
        Ok(Self {
            light,
            collection: CollectionPass::new(ctx)?,
            generation,
            mask: settings
                .mask
                .then(|| VisibilityMaskPass::new(ctx))
                .transpose()?,
            slots,
            settings,
        })
    }

    /// With the mask's walks stopping after about `budget` loop iterations and `rounds`
    /// follow-up rounds ([`VisibilityMaskPass::with_loop_budget`],
    /// [`VisibilityMaskPass::with_follow_up_rounds`]): for tests of what a device's loop
    /// limit does, with small scenes. Call it before the first frame.
    #[doc(hidden)]
    pub fn with_mask_loop_budget(mut self, ctx: &Context, budget: u32, rounds: u32) -> Self {
        self.mask = self.mask.map(|pass| {
            pass.with_loop_budget(ctx, budget)
                .with_follow_up_rounds(rounds)
        });
        self
    }

    /// The settings it was made with.
    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    /// Moves the shadow to `light` (nothing when it is the light it has): new maps and
    /// passes for the same settings, as [`Self::new`] makes them (a kept static layer is
    /// redrawn; a [`Self::with_mask_loop_budget`] is not carried over). The old ones are
    /// dropped as the context drops objects: they wait for the frames told to
    /// [`Context::begin_frame`] so far, so a host in the middle of frames in flight calls it
    /// between frames, as it would drop any of the library's objects.
    pub fn set_light(&mut self, ctx: &Context, light: super::Light) -> Result<()> {
        if light != self.settings.light {
            *self = Self::new(
                ctx,
                ShadowSettings {
                    light,
                    ..self.settings
                },
            )?;
        }
        Ok(())
    }

    /// The light as the passes see it (from [`ShadowSettings::light`] and the map's size).
    pub fn light_view(&self) -> &LightView {
        &self.light
    }

    /// The map frame `frame` records into (its header's address is what the host's shaders
    /// pass to `ms_visibility`; [`ShadowFrame::map_header`] gives it too).
    pub fn map(&self, frame: u64) -> &TemporalShadowMap {
        &self.slots[self.slot(frame)].map
    }

    fn slot(&self, frame: u64) -> usize {
        (frame % self.slots.len() as u64) as usize
    }

    /// Makes every map redraw its static layer (with [`StaticLayer::Kept`]): call it when a
    /// still mesh's buffer contents changed under the same description.
    pub fn forget_static_layer(&self) {
        for slot in &self.slots {
            slot.map.forget_static_layer();
        }
    }

    /// Records frame `frame`'s shadow of `meshes` into `cmd`: the draw list, the collection,
    /// the generation, the mask when [`ShadowSettings::mask`] is on (`mask` its inputs, given
    /// exactly then), and the counters' readback. Before recording it tells `ctx` the frame
    /// ([`Context::begin_frame`]) and reserves the room the meshes' shadow can need, from the
    /// same descriptions the draws come from (a map that must grow grows half again what
    /// they need, so that room that varies a little between frames does not reallocate, and
    /// forget a kept static layer, every frame). A static layer kept ([`StaticLayer::Kept`]) is
    /// kept once the frame that drew it has completed ([`Context::collect`]). Returns what
    /// the host's shaders and render graph need ([`ShadowFrame`]). On error nothing is
    /// recorded.
    ///
    /// # Safety
    /// - `cmd` was allocated from `ctx`'s device, is recording, outside any render pass or
    ///   dynamic rendering, and will run on `ctx`'s queue (graphics and compute), after the
    ///   command buffers of this object's earlier frames.
    /// - Each mesh's position and index streams satisfy their own contracts
    ///   ([`crate::PositionStream::from_device_address`]) until `cmd` completes, and the host's
    ///   writes to them are visible to shader reads (the `DrawStreams` first access in
    ///   [`ShadowFrame::collection`]).
    /// - `mask`: as [`VisibilityMaskPass::record`]'s contract for its views and layouts.
    pub unsafe fn record_frame(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        frame: u64,
        meshes: &[Mesh],
        mask: Option<&MaskInputs>,
    ) -> Result<ShadowFrame> {
        let mask_pass = match (&self.mask, mask) {
            (Some(pass), Some(inputs)) => Some((pass, inputs)),
            (None, None) => None,
            (Some(_), None) => {
                return Err(Error::InvalidArgument(
                    "ShadowSettings::mask is on: record_frame needs the mask's inputs".into(),
                ));
            }
            (None, Some(_)) => {
                return Err(Error::InvalidArgument(
                    "mask inputs given, but ShadowSettings::mask is off: turn it on or pass None"
                        .into(),
                ));
            }
        };
        let draws = meshes
            .iter()
            .enumerate()
            .map(|(i, m)| m.draw(i))
            .collect::<Result<Vec<_>>>()?;
        let at = self.slot(frame);
        if let Some((last, _)) = self
            .slots
            .iter()
            .filter_map(|s| s.recorded)
            .max_by_key(|r| r.0)
        {
            if frame <= last {
                return Err(Error::InvalidArgument(format!(
                    "frame {frame} recorded after frame {last}: frame numbers must increase"
                )));
            }
        }
        ctx.begin_frame(frame);
        let light = self.light;
        let slot = &mut self.slots[at];
        // The layer drawn by a frame that has completed was submitted: later frames keep it.
        if let Some(drawn) = slot.layer_drawn_at {
            if ctx.completed_frame().is_some_and(|done| done >= drawn) {
                slot.map.static_layer_submitted();
                slot.layer_drawn_at = None;
            }
        }
        if draws.len() > slot.draw_capacity {
            // The old list is retired until this frame completes (begin_frame above).
            let capacity = draws.len().next_power_of_two();
            slot.draws = DrawList::new(ctx, u32::try_from(capacity).unwrap_or(u32::MAX))?;
            slot.draw_capacity = capacity;
        }
        if light.lookup == Lookup::Exact {
            let ids = meshes.iter().map(Mesh::id_end).max().unwrap_or(0);
            slot.map.reserve_triangle_records(ctx, ids)?;
        }
        let reserved =
            slot.map
                .reserve_bounded(ctx, &light, None, meshes, ROOM_HEADROOM_QUARTERS)?;
        if let Some((_, inputs)) = mask_pass {
            let fits = slot
                .mask
                .as_ref()
                .is_some_and(|(_, size)| size.0 >= inputs.size.0 && size.1 >= inputs.size.1);
            if !fits {
                let pass = self.mask.as_ref().ok_or_else(|| {
                    Error::InvalidArgument("no mask pass for the mask's inputs".into())
                })?;
                slot.mask = Some((pass.bindings(ctx, inputs.size)?, inputs.size));
            }
        }
        let device = ctx.device();
        let builds = slot.map.static_layer_builds();
        // SAFETY: the caller's contract: `cmd` records outside rendering on ctx's graphics and
        // compute queue; the streams are valid; the list, map and bindings are this object's,
        // used by its frames in order on one queue (each pass's barriers order the uses).
        unsafe {
            slot.draws.record_update(device, cmd, &draws)?;
            self.collection
                .record(device, cmd, &slot.draws, &light, &slot.map, None)?;
        }
        let static_layer_drawn = slot.map.static_layer_builds() != builds;
        if static_layer_drawn {
            slot.layer_drawn_at = Some(frame);
        }
        // SAFETY: as above, later in the same command buffer.
        unsafe { self.generation.record(device, cmd, &slot.map) };
        if let (Some((pass, inputs)), Some((bindings, _))) = (mask_pass, slot.mask.as_mut()) {
            // SAFETY: as above; the mask's views are the caller's contract.
            let masked = unsafe { pass.record(device, cmd, bindings, inputs, &slot.map) };
            if let Err(e) = masked {
                // A command buffer the host will not submit must not leave a layer to keep.
                slot.map.forget_static_layer();
                slot.layer_drawn_at = None;
                return Err(e);
            }
        }
        // SAFETY: as above.
        unsafe { slot.map.record_counter_readback(device, cmd) };
        slot.recorded = Some((frame, reserved));
        Ok(ShadowFrame::new(
            &self.collection,
            &self.generation,
            mask_pass,
            &slot.draws,
            &light,
            &slot.map,
            static_layer_drawn,
        )
        .with_lookups(&slot.map, self.settings.lookup_stages))
    }

    /// After frame `frame`'s fence (and [`Context::collect`]): checks that its shadow is
    /// complete. Errors with [`Error::RoomExceeded`] where it stored more than was reserved
    /// from its meshes (a bound too small; the map is grown to fit), and as
    /// [`TemporalShadowMap::check_complete`] otherwise; with the mask on, errors with
    /// [`Error::MaskCutShort`] where the device's loop limit may have cut some mask pixels'
    /// lookups short ([`MaskBindings::read_over_budget_pixels`]). A frame whose room could not be
    /// bounded (a moving light) that overflowed grows its map and errors likewise.
    pub fn finish_frame(&mut self, ctx: &Context, frame: u64) -> Result<()> {
        let at = self.slot(frame);
        let slot = &mut self.slots[at];
        let Some((recorded, reserved)) = slot.recorded.filter(|r| r.0 == frame) else {
            return Err(Error::InvalidArgument(format!(
                "finish_frame({frame}): that frame was not the last recorded into its map"
            )));
        };
        let counts = slot.map.read_counters()?;
        if slot.map.needs_more_room(&counts) {
            let capacity = slot.map.range_capacity();
            slot.map.grow_to_fit(ctx, &counts)?;
            return Err(Error::RoomExceeded {
                frame: recorded,
                stored: counts.range_count,
                reserved: reserved.map_or(capacity, |r| r.min(u64::from(u32::MAX)) as u32),
            });
        }
        slot.map.check_complete(&counts)?;
        // A device with a loop limit (lavapipe) may have cut some mask pixels' lookups short:
        // the pass counted them, and a host that is not told would trust those values.
        if let Some((bindings, _)) = &slot.mask {
            let pixels = bindings.read_over_budget_pixels()?;
            if pixels > 0 {
                return Err(Error::MaskCutShort {
                    frame: recorded,
                    pixels,
                });
            }
        }
        Ok(())
    }
}
