//! Collection sub-pass (paper 4.1-4.2): the prisms of all moving triangles, rasterized from
//! the light, every fragment appended to its pixel's list. With the exact construction and
//! the static layer, each covered run goes straight to the pixel's range list instead
//! ([`TemporalShadowMap::collects_ranges`]): a run is the range the generation sub-pass would
//! pair from its two fragments, so that pass has nothing left to do and no node is stored.

use super::coverage::{CoverageMap, MAX_COVERAGE_TRIANGLES};
use super::declared_barriers::record_own;
use super::draws::DrawList;
use super::gpu_constants::STATIC_NAMES;
use super::gpu_types::{COUNT_INVALID, Counters, DRAW_STATIC, DrawRecord};
use super::push_constants::{DrawPush, DrawnPush, MapDrawPush, PushBlock};
use super::shaders;
use super::shadow_map::{StaticLayerSource, TemporalShadowMap};
use super::view::{LightView, Lookup, PrismConstruction};
use crate::error::{Error, Result};
use crate::gpu::Spirv;
use crate::gpu::{
    Access, Context, Pipeline, attachmentless_pipeline, begin_attachmentless, memory_barrier,
};
use ash::vk;

/// The collection sub-pass. Immutable after creation: one serves every frame in flight and
/// every light.
pub struct CollectionPass {
    pipelines: PrismPipelines,
    /// Records its entry and exit barriers (off: the host issues them from
    /// [`Self::accesses`], see `accesses.rs`).
    pub(crate) outer_barriers: bool,
}

/// Every triangle's prism from the light (scene.vert and the construction's geometry shader),
/// into the construction's fragment shader of a pass: the collection pass and the coverage
/// map's reset pass draw the same prisms.
pub(crate) struct PrismShaders {
    pub paper_fragment: (&'static str, Spirv<'static>),
    pub exact_fragment: (&'static str, Spirv<'static>),
    /// The exact construction's static draws (`collection_static.vert`, no geometry shader).
    pub static_fragment: (&'static str, Spirv<'static>),
    /// The exact construction storing each run as its range (the collection pass only).
    pub ranges_fragment: Option<(&'static str, Spirv<'static>)>,
    /// Whether to make the conservative collection's pipeline (the exact lookup; the
    /// collection pass only).
    pub conservative: bool,
}

/// One pipeline per [`PrismConstruction`] (and one for the exact construction's static
/// draws), so the construction is chosen per record.
pub(crate) struct PrismPipelines {
    exact: Pipeline,
    exact_static: Pipeline,
    exact_ranges: Option<Pipeline>,
    /// The conservative collection (Lookup::Exact): its own shaders, so that its code stays
    /// out of the default pipelines.
    exact_conservative: Option<Pipeline>,
    paper: Pipeline,
}

impl PrismPipelines {
    pub(crate) fn new(ctx: &Context, shaders: PrismShaders) -> Result<Self> {
        Ok(Self {
            exact: prism_pipeline(
                ctx,
                ("collection_exact.geom", shaders::COLLECTION_EXACT_GEOM),
                shaders.exact_fragment,
            )?,
            exact_static: attachmentless_pipeline(
                ctx,
                MapDrawPush::BYTES,
                &[
                    (
                        vk::ShaderStageFlags::VERTEX,
                        "collection_static.vert",
                        shaders::COLLECTION_STATIC_VERT,
                    ),
                    (
                        vk::ShaderStageFlags::FRAGMENT,
                        shaders.static_fragment.0,
                        shaders.static_fragment.1,
                    ),
                ],
            )?,
            exact_ranges: shaders
                .ranges_fragment
                .map(|fragment| {
                    prism_pipeline(
                        ctx,
                        ("collection_exact.geom", shaders::COLLECTION_EXACT_GEOM),
                        fragment,
                    )
                })
                .transpose()?,
            exact_conservative: shaders
                .conservative
                .then(|| {
                    prism_pipeline(
                        ctx,
                        (
                            "collection_conservative.geom",
                            shaders::COLLECTION_CONSERVATIVE_GEOM,
                        ),
                        (
                            "collection_conservative.frag",
                            shaders::COLLECTION_CONSERVATIVE_FRAG,
                        ),
                    )
                })
                .transpose()?,
            paper: prism_pipeline(
                ctx,
                ("collection.geom", shaders::COLLECTION_GEOM),
                shaders.paper_fragment,
            )?,
        })
    }

    /// Records every draw's prisms with `construction`'s pipelines (binding them), pushing
    /// `constants` with each draw's index; static draws only if `with_static` (with
    /// `static_names`, the conservative collection's into the static name lists); the exact
    /// construction's moving draws as ranges if `ranges` (and the pipelines have it). Inside
    /// dynamic rendering.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn draw(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        construction: PrismConstruction,
        draws: &DrawList,
        constants: MapDrawPush,
        with_static: bool,
        ranges: bool,
        conservative: bool,
        static_names: bool,
        light_moves: bool,
    ) {
        let exact_moving = match (&self.exact_conservative, &self.exact_ranges) {
            (Some(pipeline), _) if conservative => pipeline,
            (_, Some(pipeline)) if ranges => pipeline,
            _ => &self.exact,
        };
        let pipeline_of = |record: &DrawRecord| match construction {
            PrismConstruction::Paper => &self.paper,
            // The conservative collection (Lookup::Exact) gives static triangles the moving
            // ones' footprints: its lists name every triangle near a texel. Under a moving
            // light nothing stands still in the light's frame.
            _ if record.flags() & DRAW_STATIC != 0 && !conservative && !light_moves => {
                &self.exact_static
            }
            PrismConstruction::Exact => exact_moving,
        };
        let mut bound: Option<vk::Pipeline> = None;
        for (i, record) in draws.records().iter().enumerate() {
            if record.triangle_count == 0 || (!with_static && record.flags() & DRAW_STATIC != 0) {
                continue;
            }
            let pipeline = pipeline_of(record);
            if bound != Some(pipeline.raw()) {
                // SAFETY: `draw` runs only inside the dynamic rendering its callers (the collection
                // and time-dependent passes' record functions) began on `cmd`, and this pipeline is
                // one of this pass's, alive as long as `self`.
                unsafe { pipeline.bind(device, cmd) };
                bound = Some(pipeline.raw());
            }
            let mut constants = constants;
            if static_names && record.flags() & DRAW_STATIC != 0 {
                constants.flags |= STATIC_NAMES;
            }
            draw_one(device, cmd, pipeline, draws, i, record, constants);
        }
    }
}

fn prism_pipeline(
    ctx: &Context,
    (geometry_name, geometry): (&str, Spirv<'_>),
    (fragment_name, fragment): (&str, Spirv<'_>),
) -> Result<Pipeline> {
    attachmentless_pipeline(
        ctx,
        MapDrawPush::BYTES,
        &[
            (
                vk::ShaderStageFlags::VERTEX,
                "scene.vert",
                shaders::SCENE_VERT,
            ),
            (vk::ShaderStageFlags::GEOMETRY, geometry_name, geometry),
            (vk::ShaderStageFlags::FRAGMENT, fragment_name, fragment),
        ],
    )
}

/// Records one non-indexed draw of 3 vertices per triangle for every draw of the list (the
/// vertex shader fetches through the draw's own indices), pushing `constants` with each
/// draw's index. Inside dynamic rendering, with `pipeline` bound.
#[cfg_attr(not(feature = "research"), allow(dead_code))]
pub(crate) fn draw_each(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    draws: &DrawList,
    constants: impl DrawnPush,
) {
    for (i, record) in draws.records().iter().enumerate() {
        if record.triangle_count > 0 {
            draw_one(device, cmd, pipeline, draws, i, record, constants);
        }
    }
}

fn draw_one(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    draws: &DrawList,
    index: usize,
    record: &DrawRecord,
    constants: impl DrawnPush,
) {
    let constants = constants.with_draw(DrawPush {
        draws: draws.address(),
        draw_index: index as u32,
        draw_count: draws.draw_count(),
    });
    // SAFETY: the pipeline bound by the caller (`draw`, or the passes whose rendering calls
    // draw_each) has MapDrawPush's size as its push range, as every prism and cap pipeline here is
    // made with; the push is within that range.
    unsafe { pipeline.push(device, cmd, &constants) };
    // SAFETY: inside the rendering the caller began, with `pipeline` bound and its constants
    // pushed; the vertex shader reads only this draw's streams, which the draw list checked against
    // the bytes their buffers hold (record_update).
    unsafe { device.cmd_draw(cmd, 3 * record.triangle_count, 1, 0, 0) };
}

impl CollectionPass {
    /// Creates the pipeline (vertex, geometry and fragment shader; no attachments).
    pub fn new(ctx: &Context) -> Result<Self> {
        let pipelines = PrismPipelines::new(
            ctx,
            PrismShaders {
                paper_fragment: ("collection.frag", shaders::COLLECTION_FRAG),
                exact_fragment: ("collection_exact.frag", shaders::COLLECTION_EXACT_FRAG),
                static_fragment: ("collection_static.frag", shaders::COLLECTION_STATIC_FRAG),
                ranges_fragment: Some(("collection_ranges.frag", shaders::COLLECTION_RANGES_FRAG)),
                conservative: true,
            },
        )?;
        Ok(Self {
            pipelines,
            outer_barriers: true,
        })
    }

    /// Records the collection sub-pass of `map` for the frame lit by `light`: writes the map's
    /// header (light and buffer addresses), clears its lists and counters, and draws every
    /// triangle's prism, built as `light.prisms` says. Static draws go to the static layer
    /// ([`TemporalShadowMap::uses_static_layer`]); with [`LightView::keep_static_layer`] a
    /// layer drawn for the same light view and static draws is kept, and only the other draws
    /// are drawn; the moving draws' covered runs then go straight to the range lists
    /// ([`TemporalShadowMap::collects_ranges`]). The map's counters say afterwards whether it
    /// had room (see [`TemporalShadowMap::needs_more_room`]). With `coverage`, also fills its
    /// nearest map (the 2017 extension's first pass; [`super::CoveragePass`] follows).
    ///
    /// Errors (nothing recorded) when the coverage map's size differs from the map's, the
    /// draws' ids reach [`MAX_COVERAGE_TRIANGLES`] with a coverage map, or the map lacks a
    /// buffer this light's path uses ([`TemporalShadowMap::prepare_for`]).
    ///
    /// # Safety
    /// - `cmd` was allocated from `device` (the device the pass and the map were made on),
    ///   is in the recording state, outside any render pass or dynamic rendering, and will
    ///   run on a queue with graphics and compute.
    /// - `draws` was updated ([`DrawList::record_update`]) earlier in `cmd` or in a command
    ///   buffer submitted before it, and its position and index streams stay valid until
    ///   `cmd` completes (their own contracts).
    /// - `map` (and `coverage`) are not used by another command buffer that runs at the same
    ///   time; the barriers recorded here order this use after earlier uses in the same
    ///   queue.
    ///
    /// Synchronization: waits, with a global barrier, for every earlier use of the map's
    /// buffers (an earlier collection, the generation, lookups from any shader stage, the
    /// counter readback); leaves the lists (or the ranges) and the counters written by the
    /// fragment and transfer stages and made visible to the generation's compute shaders and
    /// indirect reads. Both barriers are derived from [`Self::accesses`] and those passes'
    /// declarations (see `accesses.rs`). A pass made [`Self::with_host_barriers`] records
    /// neither of those two barriers: the caller orders [`Self::accesses`] itself. State
    /// changed: the bound graphics pipeline, its push constants, viewport and scissor.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &TemporalShadowMap,
        coverage: Option<&CoverageMap>,
    ) -> Result<()> {
        if let Some(c) = coverage {
            if (c.width(), c.height()) != (map.width(), map.height()) {
                return Err(Error::InvalidArgument(format!(
                    "coverage map {}x{} for a shadow map of {}x{}",
                    c.width(),
                    c.height(),
                    map.width(),
                    map.height()
                )));
            }
            if draws.id_end() > MAX_COVERAGE_TRIANGLES as u64 {
                return Err(Error::InvalidArgument(format!(
                    "the coverage map handles triangle ids below {MAX_COVERAGE_TRIANGLES}, the draws reach {}",
                    draws.id_end()
                )));
            }
        }
        map.check_prepared_for(light, coverage)?;
        if light.lookup == Lookup::Exact {
            light.refuse_turning_exact(draws.records())?;
        }
        if coverage.is_some() {
            light.refuse_moving("the coverage map")?;
        }
        if light.lookup == Lookup::Exact {
            check_exact_lookup(draws, light, map, coverage)?;
        }
        let static_layer = map.uses_static_layer(light, coverage);
        // A kept static layer (LightView::keep_static_layer) is neither cleared nor redrawn;
        // what it was drawn for is only tracked when it may be kept.
        let source =
            (static_layer && light.keep_static_layer).then(|| StaticLayerSource::of(light, draws));
        let keep = source.as_ref().is_some_and(|s| map.static_layer_is(s));
        let redraw_layer = static_layer && !keep;
        let static_names = map.uses_static_names(light, coverage);
        let collects_ranges = map.collects_ranges(light, coverage);
        // Earlier frames may still read these lists.
        let own = super::own_barriers::collection(draws, light, map, coverage);
        let check = map.header.access_check();
        if self.outer_barriers {
            // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue
            // (this function's contract), so every stage named is supported.
            unsafe { record_own(device, cmd, check, "collection entry", own.entry.as_ref()) };
        }
        self.accesses(draws, light, map, coverage)
            .declare_run(check, "collection");
        map.record_header(device, cmd, light, coverage);
        let counters = Counters {
            node_capacity: map.node_capacity(),
            range_capacity: map.range_capacity(),
            ranges_direct: collects_ranges as u32,
            ..Counters::default()
        };
        // SAFETY: outside rendering (the contract). The fills and writes stay within the map's own
        // buffers: WHOLE_SIZE fills, and the static names buffer holds its 16-byte header and one
        // head per texel (heads_end) by construction; the counters get one Counters, their size.
        unsafe {
            device.cmd_fill_buffer(cmd, map.heads.raw(), 0, vk::WHOLE_SIZE, 0);
            map.record_clear_ranges(
                device,
                cmd,
                collects_ranges,
                map.sorts_ranges(light, coverage),
            );
            if redraw_layer && static_names {
                // The count, the capacity, then empty heads (the names need no clearing).
                let names = map
                    .static_names
                    .as_ref()
                    .map_or(vk::Buffer::null(), |b| b.raw());
                let heads_end = 16 + 4 * u64::from(map.width()) * u64::from(map.height());
                device.cmd_fill_buffer(cmd, names, 0, 4, 0);
                device.cmd_fill_buffer(cmd, names, 4, 4, map.static_name_capacity());
                device.cmd_fill_buffer(cmd, names, 8, heads_end - 8, 0);
            } else if redraw_layer {
                let empty = u32::MAX;
                device.cmd_fill_buffer(cmd, map.static_nearest.raw(), 0, vk::WHOLE_SIZE, empty);
            }
            map.counters.record_write(device, cmd, &[counters]);
            if let Some(c) = coverage {
                device.cmd_fill_buffer(cmd, c.nearest.raw(), 0, vk::WHOLE_SIZE, u32::MAX);
            }
        }
        // SAFETY: the same command buffer, outside rendering; stages its graphics and compute queue
        // supports.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::TRANSFER_WRITE,
                Access::ANY_SHADER_READ
                    .and(Access::FRAGMENT_RW)
                    .and(Access::COMPUTE_RW),
            )
        };
        // SAFETY: outside any rendering (the contract), and the map's size is the extent every
        // prism pipeline's viewport takes.
        unsafe { begin_attachmentless(device, cmd, map.width(), map.height()) };
        let conservative = light.lookup == Lookup::Exact;
        let constants = MapDrawPush {
            map: map.header_address(),
            flags: COUNT_INVALID,
            ..MapDrawPush::default()
        };
        self.pipelines.draw(
            device,
            cmd,
            light.prisms,
            draws,
            constants,
            !keep,
            collects_ranges,
            conservative,
            static_names,
            light.is_moving(),
        );
        // SAFETY: rendering was begun just above and every draw recorded into it has been recorded.
        unsafe { device.cmd_end_rendering(cmd) };
        if redraw_layer {
            map.static_layer_drawn(source);
        }
        if collects_ranges {
            // No generation pass pairs these ranges, and no coverage map drops any: what the
            // range count would be without one is the count itself.
            // SAFETY: rendering has ended, outside any render pass again; fragment and transfer
            // stages are supported on this queue.
            unsafe {
                memory_barrier(
                    device,
                    cmd,
                    Access::FRAGMENT_RW,
                    Access::TRANSFER_READ.and(Access::TRANSFER_WRITE),
                )
            };
            let count = std::mem::offset_of!(Counters, range_count) as u64;
            let without = std::mem::offset_of!(Counters, ranges_without_coverage) as u64;
            let region = [vk::BufferCopy {
                src_offset: count,
                dst_offset: without,
                size: 4,
            }];
            let counters = map.counters.raw();
            // SAFETY: the source and destination are different 4-byte ranges of the counters buffer
            // (range_count and ranges_without_coverage, both within Counters), made visible to
            // transfer by the barrier above.
            unsafe { device.cmd_copy_buffer(cmd, counters, counters, &region) };
            if let Some(names) = map.static_names.as_ref().filter(|_| static_names) {
                // The lists' count, kept with them across frames, for needs_more_room.
                let region = [vk::BufferCopy {
                    src_offset: 0,
                    dst_offset: std::mem::offset_of!(Counters, static_names) as u64,
                    size: 4,
                }];
                // SAFETY: 4 bytes at offset 0 of the names buffer (its count) into the counters'
                // static_names field, both within their buffers; the fragment writes to the names
                // were made visible to transfer by the barrier above.
                unsafe { device.cmd_copy_buffer(cmd, names.raw(), counters, &region) };
            }
        }
        if self.outer_barriers {
            // SAFETY: outside rendering, on the graphics and compute queue of the contract.
            unsafe { record_own(device, cmd, check, "collection exit", own.exit.as_ref()) };
        }
        Ok(())
    }
}

/// What the exact lookup's collection needs: the exact construction (its footprints), no
/// coverage map (its passes need the depth lines' fragments) and a record for every id.
fn check_exact_lookup(
    draws: &DrawList,
    light: &LightView,
    map: &TemporalShadowMap,
    coverage: Option<&CoverageMap>,
) -> Result<()> {
    if light.prisms != PrismConstruction::Exact {
        return Err(Error::InvalidArgument(
            "the exact lookup (Lookup::Exact) needs the exact construction (PrismConstruction::Exact), not the papers' prisms".into(),
        ));
    }
    if coverage.is_some() {
        return Err(Error::InvalidArgument(
            "the exact lookup (Lookup::Exact) does not take a coverage map".into(),
        ));
    }
    if map.uses_static_names(light, coverage) && map.static_name_capacity() == 0 {
        return Err(Error::InvalidArgument(
            "the exact lookup (Lookup::Exact) with the static layer needs the map's static name lists (TemporalShadowMap::reserve_triangle_records makes them)".into(),
        ));
    }
    if map.triangle_record_capacity() < draws.id_end() {
        return Err(Error::InvalidArgument(format!(
            "the exact lookup (Lookup::Exact) needs a triangle record per id: the draws reach {}, the map has room for {} (TemporalShadowMap::reserve_triangle_records)",
            draws.id_end(),
            map.triangle_record_capacity()
        )));
    }
    Ok(())
}
