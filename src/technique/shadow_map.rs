//! The temporal shadow map: per-pixel linked lists of prism fragments (collection sub-pass)
//! and of depth-time ranges (generation sub-pass), in plain storage buffers reached by device
//! address. A small header buffer (`MsShadowMap` in `glsl/motion_shadows.glsl`) holds the
//! light of the frame and every buffer's address: a host shader needs only the header's
//! address to test shadows.

use super::coverage::CoverageMap;
use super::draws::DrawList;
use super::gpu_types::{
    Counters, DRAW_STATIC, DrawRecord, MAX_LIST_NODES, ShadowMapHeader, TriangleRecord,
};
use super::light_motion::RECORDED_EXACT;
use super::path_buffers::PathBuffers;
use super::pruning::Pruning;
use super::range_ceiling::{HostDraw, RangeCeiling};
use super::view::{LightView, Lookup};
use crate::error::{Error, Result};
use crate::gpu::{Access, Buffer, BufferUsage, Context, OneShot, memory_barrier};
use ash::vk;
use glam::{Mat4, UVec4};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU8, AtomicU32, Ordering};

/// What `download` copies back: the map's buffers as host data, and their readers.
mod contents;
pub use contents::ShadowMapContents;

const COUNTER_BYTES: u64 = std::mem::size_of::<Counters>() as u64;
/// The static name lists' first words: the count, the capacity and two unused.
const STATIC_NAMES_HEADER_BYTES: u64 = 16;

/// How a map keeps the ranges its collection pass stores itself
/// ([`TemporalShadowMap::collects_ranges`]; frames that store nodes are paired by the
/// generation pass into per-texel runs either way).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum RangeStorage {
    /// Each texel's ranges contiguous in the range buffer, in order of start time (the
    /// header's `MS_SORTED_RANGES`): the collection links them into lists in a second buffer
    /// of the same capacity, and the generation pass sorts each list into places it takes
    /// with one atomic, leaving out ranges that cannot decide a test (pruning,
    /// `docs/src/pruning.md`: by default those behind the static layer where receivers are
    /// tested at their plane's depth, `LightView::receiver_plane`; [`super::Pruning`] picks
    /// the rule). Lookups read a texel's ranges from consecutive addresses and stop at the
    /// first that starts after the time they test.
    #[default]
    Sorted,
    /// Per-texel linked lists in the order the collection's atomics ran (one range buffer).
    Lists,
}

/// One temporal shadow map: one light's view for one frame in flight. Create one per light
/// and per frame in flight; the passes that fill and read it are shared by all.
///
/// Resizing: a map has a fixed texel size; make a new one for another size (after the frames
/// using the old one have completed). Its fragment and range capacities grow with
/// [`Self::grow_to_fit`] when [`Self::needs_more_room`] says a frame overflowed.
pub struct TemporalShadowMap {
    width: u32,
    height: u32,
    node_capacity: u32,
    range_capacity: u32,
    range_storage: RangeStorage,
    pruning: Pruning,
    /// Which of the buffers only some paths use the map holds ([`Self::prepare_for`]).
    buffers: PathBuffers,
    /// The header (`MsShadowMap`): light and buffer addresses, written by the collection pass.
    pub(crate) header: Buffer,
    /// Per pixel: index + 1 of the newest node, 0 for none.
    pub(crate) heads: Buffer,
    /// The fragments ([`Node`]).
    pub(crate) nodes: Buffer,
    /// [`Counters`]: counts written by the passes, capacities by the collection pass.
    pub(crate) counters: Buffer,
    /// Per pixel: index + 1 of the first range, 0 for none.
    pub(crate) range_heads: Buffer,
    /// The ranges ([`Range`]).
    pub(crate) ranges: Buffer,
    /// With [`RangeStorage::Sorted`], the lists the collection links its ranges into before
    /// the generation pass sorts them into `ranges` (the range capacity); one range otherwise.
    pub(crate) range_lists: Buffer,
    /// The generation pass's list of pixels with long fragment lists (a count, indirect
    /// dispatch arguments, then up to one index per pixel); the sorting's long lists too.
    pub(crate) long_pixels: Buffer,
    /// The static layer: per pixel, the nearest triangle of a static draw (depth key << 32 |
    /// id), in place of their fragments in the lists (see [`Self::uses_static_layer`]).
    pub(crate) static_nearest: Buffer,
    /// The generation pass's indirect dispatches (x, y, z group counts and a pad each), set
    /// by the collection: every 8x8-texel tile of the map where the lists hold fragments,
    /// none where the collection stored the ranges itself ([`Self::collects_ranges`]); then
    /// the sorting's ([`RangeStorage::Sorted`], only where the collection stored the
    /// ranges).
    pub(crate) tiles: Buffer,
    counters_readback: Buffer,
    /// What the static layer holds, as far as the host has said it submitted
    /// ([`Self::static_layer_submitted`]).
    static_layer_source: Mutex<StaticLayerState>,
    /// Times the collection pass has drawn the static layer into this map.
    static_layer_builds: AtomicU32,
    /// With [`Lookup::Exact`]: one [`super::TriangleRecord`] per global triangle id, written
    /// by the collection ([`Self::reserve_triangle_records`]); none until then.
    pub(crate) triangle_records: Option<Buffer>,
    /// With [`Lookup::Exact`] and the static layer: the static name lists (a count, a
    /// capacity, 2 unused words, a head per texel, then (id, next) pairs; see
    /// [`super::ShadowMapHeader::static_names`]), made with the triangle records.
    pub(crate) static_names: Option<Buffer>,
    /// What the last recorded collection built the map for ([`LightView::recorded_flags`]).
    pub(super) built_for: AtomicU8,
}

/// What the static layer holds for keeping: nothing is kept on the strength of a recording
/// alone, so a recorded pass that is never submitted needs no undoing.
#[derive(Default)]
struct StaticLayerState {
    /// What the layer holds, drawn by a submitted pass: later passes may keep it.
    kept: Option<StaticLayerSource>,
    /// What the last recorded pass that drew the layer drew it for, until the host says that
    /// pass was submitted.
    recorded: Option<StaticLayerSource>,
}

/// What a static layer's contents follow from: the light's view and projection and the
/// static draws (with their places in the draw list).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StaticLayerSource {
    view: Mat4,
    proj: Mat4,
    draws: Vec<(usize, DrawRecord)>,
}

impl StaticLayerSource {
    /// What a collection of `draws` lit by `light` would draw into the static layer.
    pub fn of(light: &LightView, draws: &DrawList) -> Self {
        Self {
            view: light.view,
            proj: light.proj,
            draws: draws
                .records()
                .iter()
                .copied()
                .enumerate()
                .filter(|(_, r)| r.flags() & DRAW_STATIC != 0 && r.triangle_count > 0)
                .collect(),
        }
    }
}

use super::gpu_constants::{
    DISPATCH_PAIRING, DISPATCH_SORT, DISPATCH_SORT_LONG, DISPATCH_WORDS, TILE_TEXELS,
};

/// The header's `size.z` for sorted ranges (`MS_SORTED_RANGES` in
/// `glsl/motion_shadows.glsl`, which a host includes without the generated constants).
pub const MS_SORTED_RANGES: u32 = 1;

/// Bytes of a buffer of `count` elements, if the device can hold it: `limit` is what one
/// descriptor can address, or (for buffers reached by address) one allocation.
fn checked_bytes(what: &'static str, count: u64, element: u64, limit: u64) -> Result<u64> {
    let needed = count * element;
    if needed > limit || count >= u32::MAX as u64 {
        return Err(Error::DeviceLimit {
            what,
            count,
            element_bytes: element,
            needed_bytes: needed,
            limit_bytes: limit,
        });
    }
    Ok(needed)
}

impl TemporalShadowMap {
    /// A map of `width` x `height` pixels with room for the given numbers of fragments and
    /// ranges. Too small is never undefined behaviour, and a frame that overflows is never
    /// silently wrong either, but it is incomplete: fragments and ranges past the capacities
    /// are counted and dropped, so that frame's shadows miss casters.
    /// [`Self::needs_more_room`] says so after the frame's fence; grow the map then
    /// ([`Self::grow_to_fit`], [`Self::reserve`]) and use the next frame (or record the frame
    /// again, as the standalone renderer does). Start near the counts a typical frame needs
    /// to avoid that frame.
    ///
    /// The map holds the buffers of the default light's path (the exact construction, the
    /// static layer, depth lines, no coverage map), which stores no fragment: its node
    /// buffer is made, at `node_capacity`, by [`Self::prepare_for`] (or [`Self::reserve_for`])
    /// for a light whose frames store fragments; the collection refuses such a frame before.
    /// Bytes per map and path: docs/src/integration.md#bytes-per-map.
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        node_capacity: u32,
        range_capacity: u32,
    ) -> Result<Self> {
        Self::with_storage(
            ctx,
            width,
            height,
            node_capacity,
            range_capacity,
            RangeStorage::default(),
        )
    }

    /// [`Self::new`] with the given [`RangeStorage`] (`new` takes the default, sorted).
    pub fn with_storage(
        ctx: &Context,
        width: u32,
        height: u32,
        node_capacity: u32,
        range_capacity: u32,
        range_storage: RangeStorage,
    ) -> Result<Self> {
        Self::build(
            ctx,
            (width, height),
            node_capacity,
            range_capacity,
            range_storage,
            PathBuffers::default_path(range_storage),
        )
    }

    /// Makes the map hold exactly the buffers a frame lit by `light` (with or without a
    /// coverage map) uses, at the map's capacities: the node buffer where such a frame stores
    /// fragments, the sorting's lists where it sorts its ranges, the long-list pixels where
    /// its generation pass pairs or sorts, the static layer where it keeps static draws there
    /// for depth lines (docs/src/integration.md#bytes-per-map). Nothing happens where the map
    /// holds them already; otherwise, like [`Self::reserve`], it makes new buffers and retires
    /// the old ones (what the static layer held is forgotten). A map whose frames use several
    /// lights' paths wants one per path, or the default path's buffers and this call for
    /// each other light before its frames (the collection refuses a frame that needs a buffer
    /// the map lacks).
    pub fn prepare_for(
        &mut self,
        ctx: &Context,
        light: &LightView,
        coverage: Option<&CoverageMap>,
    ) -> Result<()> {
        let needed = PathBuffers::of_light(light, coverage.is_some(), self.range_storage);
        if needed != self.buffers {
            self.rebuild(ctx, self.node_capacity, self.range_capacity, needed)?;
        }
        Ok(())
    }

    /// An error naming what to call when a frame lit by `light` (with or without a coverage
    /// map) needs a buffer the map does not hold.
    pub(crate) fn check_prepared_for(
        &self,
        light: &LightView,
        coverage: Option<&CoverageMap>,
    ) -> Result<()> {
        let needed = PathBuffers::of_light(light, coverage.is_some(), self.range_storage);
        match self.buffers.missing_from(needed) {
            None => Ok(()),
            Some(missing) => Err(Error::InvalidArgument(format!(
                "the shadow map holds no {missing}, which a frame lit by this light uses (its \
                 static layer, construction, lookup or coverage map differ from the default \
                 light's): call TemporalShadowMap::prepare_for (or reserve_for) with this light \
                 before recording the frame"
            ))),
        }
    }

    fn build(
        ctx: &Context,
        (width, height): (u32, u32),
        node_capacity: u32,
        range_capacity: u32,
        range_storage: RangeStorage,
        buffers: PathBuffers,
    ) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "shadow map size {width}x{height}"
            )));
        }
        let pixels = width as u64 * height as u64;
        let addressed = ctx.max_addressed_buffer_bytes();
        let head_bytes = checked_bytes("the shadow map's list heads", pixels, 4, addressed)?;
        // One node, range, index or key where the path leaves a buffer unused.
        let node_bytes = if buffers.nodes {
            checked_bytes(
                "the fragment (node) buffer",
                node_capacity.max(1) as u64,
                16,
                addressed,
            )?
        } else {
            16
        };
        let range_bytes = checked_bytes(
            "the range buffer",
            range_capacity.max(1) as u64,
            24,
            addressed,
        )?;
        let list_bytes = if buffers.sorted_lists {
            range_bytes
        } else {
            24
        };
        let long_bytes = 16 + if buffers.long_lists { head_bytes } else { 0 };
        let static_bytes = if buffers.static_layer {
            2 * head_bytes
        } else {
            8
        };
        Ok(Self {
            width,
            height,
            node_capacity: node_capacity.max(1),
            range_capacity: range_capacity.max(1),
            range_storage,
            pruning: Pruning::default(),
            buffers,
            header: Buffer::new(
                ctx,
                "shadow map header",
                std::mem::size_of::<ShadowMapHeader>() as u64,
                BufferUsage::Storage,
            )?,
            heads: Buffer::new(ctx, "node heads", head_bytes, BufferUsage::Storage)?,
            nodes: Buffer::new(ctx, "nodes", node_bytes, BufferUsage::Storage)?,
            counters: Buffer::new(ctx, "counters", COUNTER_BYTES, BufferUsage::Storage)?,
            range_heads: Buffer::new(ctx, "range heads", head_bytes, BufferUsage::Storage)?,
            ranges: Buffer::new(ctx, "ranges", range_bytes, BufferUsage::Storage)?,
            range_lists: Buffer::new(ctx, "range lists", list_bytes, BufferUsage::Storage)?,
            long_pixels: Buffer::new(ctx, "long-list pixels", long_bytes, BufferUsage::Storage)?,
            static_nearest: Buffer::new(ctx, "static layer", static_bytes, BufferUsage::Storage)?,
            tiles: Buffer::new(
                ctx,
                "generation dispatches",
                u64::from(DISPATCH_WORDS) * 4,
                BufferUsage::Storage,
            )?,
            counters_readback: Buffer::new(
                ctx,
                "counters readback",
                COUNTER_BYTES,
                BufferUsage::Readback,
            )?,
            static_layer_source: Mutex::new(StaticLayerState::default()),
            static_layer_builds: AtomicU32::new(0),
            triangle_records: None,
            static_names: None,
            built_for: AtomicU8::new(0),
        })
    }

    /// Makes room for the triangle records of the exact lookup ([`Lookup::Exact`]): one per
    /// global triangle id below `triangles` (a [`super::DrawList`]'s `id_end()`), 96 bytes
    /// each. Only grows; the old buffer is retired like the others ([`Self::reserve`]). A
    /// map without room for every id of its draws refuses the exact collection. The first
    /// call also makes the static name lists (the exact lookup's static layer) with room for
    /// one name per texel; a frame that needs more says so ([`Self::needs_more_room`]) and
    /// [`Self::grow_to_fit`] makes it.
    pub fn reserve_triangle_records(&mut self, ctx: &Context, triangles: u64) -> Result<()> {
        if self.static_names.is_none() {
            let texels = u64::from(self.width) * u64::from(self.height);
            self.reserve_static_names(ctx, u32::try_from(texels).unwrap_or(u32::MAX))?;
        }
        if triangles <= self.triangle_record_capacity() {
            return Ok(());
        }
        // A kept static layer's records are in the old buffer.
        self.forget_static_layer();
        let bytes = checked_bytes(
            "the triangle records",
            triangles,
            std::mem::size_of::<TriangleRecord>() as u64,
            ctx.max_addressed_buffer_bytes(),
        )?;
        self.triangle_records = Some(Buffer::new(
            ctx,
            "triangle records",
            bytes,
            BufferUsage::Storage,
        )?);
        Ok(())
    }

    /// Makes room for `names` names in the static name lists of the exact lookup's static
    /// layer (each static triangle once per texel its shadow touches, 8 bytes; plus 4 bytes
    /// a texel). Only grows; a new buffer holds no layer, so the next collection redraws it.
    pub fn reserve_static_names(&mut self, ctx: &Context, names: u32) -> Result<()> {
        if self.static_names.is_some() && names <= self.static_name_capacity() {
            return Ok(());
        }
        let texels = u64::from(self.width) * u64::from(self.height);
        let addressed = ctx.max_addressed_buffer_bytes();
        let bytes = checked_bytes("the static name lists", u64::from(names.max(1)), 8, addressed)?
            .checked_add(STATIC_NAMES_HEADER_BYTES + 4 * texels)
            .filter(|&b| b <= addressed)
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "the static name lists for {names} names over {texels} texels are more than the device addresses ({addressed} bytes)"
                ))
            })?;
        self.static_names = Some(Buffer::new(
            ctx,
            "static names",
            bytes,
            BufferUsage::Storage,
        )?);
        self.forget_static_layer();
        Ok(())
    }

    /// Names the static name lists have room for (0 without them; see
    /// [`Self::reserve_static_names`]).
    pub fn static_name_capacity(&self) -> u32 {
        let texels = u64::from(self.width) * u64::from(self.height);
        self.static_names.as_ref().map_or(0, |b| {
            let names = (b.size() - STATIC_NAMES_HEADER_BYTES - 4 * texels) / 8;
            u32::try_from(names).unwrap_or(u32::MAX)
        })
    }

    /// Whether a frame lit by `light` keeps its static triangles in the static name lists
    /// (the exact lookup with the static layer).
    pub(crate) fn uses_static_names(
        &self,
        light: &LightView,
        coverage: Option<&CoverageMap>,
    ) -> bool {
        light.lookup == Lookup::Exact && self.uses_static_layer(light, coverage)
    }

    /// The lookup the last recorded collection built the map for ([`LightView::lookup`];
    /// [`Lookup::DepthLine`] before any).
    pub fn recorded_lookup(&self) -> Lookup {
        if self.built_for.load(Ordering::Relaxed) & RECORDED_EXACT != 0 {
            Lookup::Exact
        } else {
            Lookup::DepthLine
        }
    }

    /// Triangle ids the map's triangle records have room for (0 without records).
    pub fn triangle_record_capacity(&self) -> u64 {
        self.triangle_records.as_ref().map_or(0, |b| {
            b.size() / std::mem::size_of::<TriangleRecord>() as u64
        })
    }

    /// Texels across.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Texels down.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Fragments the map has room for on a path that stores them (its node buffer is made at
    /// this size only for such a path, [`Self::prepare_for`]).
    pub fn node_capacity(&self) -> u32 {
        self.node_capacity
    }
    /// Ranges the map has room for.
    pub fn range_capacity(&self) -> u32 {
        self.range_capacity
    }
    /// How the map keeps the ranges its collection stores itself.
    pub fn range_storage(&self) -> RangeStorage {
        self.range_storage
    }

    /// This map with the given [`Pruning`] rule for its sort (maps start with the default,
    /// [`Pruning::StaticLayer`]); kept when the map grows ([`Self::grow_to_fit`],
    /// [`Self::reserve`]). Only a map that sorts its ranges ([`Self::sorts_ranges`]) prunes.
    /// The generation pass makes the cover rule's pipelines the first time it records such a
    /// map, unless [`super::GenerationPass::prepare`] made them earlier.
    pub fn with_pruning(mut self, pruning: Pruning) -> Self {
        self.pruning = pruning;
        self
    }

    /// The pruning rule the generation pass's sort applies to this map.
    pub fn pruning(&self) -> Pruning {
        self.pruning
    }

    /// Whether a frame lit by `light` (with or without a coverage map) leaves each texel's
    /// ranges contiguous and in order of start time (the header's `MS_SORTED_RANGES`): with
    /// [`RangeStorage::Sorted`] where the collection stores the ranges itself.
    pub fn sorts_ranges(&self, light: &LightView, coverage: Option<&CoverageMap>) -> bool {
        self.range_storage == RangeStorage::Sorted
            && self.collects_ranges(light, coverage)
            // Pruning decides at texel centres: not sound for the exact lookup's ranges.
            && light.lookup == Lookup::DepthLine
    }

    /// The device address of the map's header (`MsShadowMap` in `glsl/motion_shadows.glsl`):
    /// what a host shader needs to test shadows with `ms_shadowed` / `ms_visibility`. It
    /// changes when the map grows ([`Self::grow_to_fit`] makes new buffers).
    pub fn header_address(&self) -> u64 {
        self.header.device_address()
    }

    /// Whether the collection pass of a frame lit by `light` (with or without a coverage
    /// map) stores each covered run of a moving triangle as its range at once, so that no
    /// node is stored and [`super::GenerationPass`] finds nothing to pair: the exact
    /// construction with the static layer or the exact lookup ([`Lookup::Exact`]), without a
    /// coverage map (its passes need the nodes). A map used only that way needs no node
    /// capacity.
    pub fn collects_ranges(&self, light: &LightView, coverage: Option<&CoverageMap>) -> bool {
        light.collects_ranges(coverage.is_some())
    }

    /// Whether a frame lit by `light` (with or without a coverage map) keeps static draws'
    /// triangles in the static layer rather than in the lists: when `light` asks for it,
    /// with the exact construction (static draws skip the geometry shader there), the
    /// depth-line lookup (the exact lookup needs every triangle named) and no coverage map
    /// (its passes need every fragment).
    pub fn uses_static_layer(&self, light: &LightView, coverage: Option<&CoverageMap>) -> bool {
        light.uses_static_layer(coverage.is_some())
    }

    /// Records the header's update for a frame lit by `light` (with or without a coverage
    /// map), between the barriers that order it after earlier readers and before later ones.
    pub(crate) fn record_header(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        light: &LightView,
        coverage: Option<&CoverageMap>,
        outer_barriers: bool,
    ) {
        let sorted = self.sorts_ranges(light, coverage);
        self.built_for
            .store(light.recorded_flags(), Ordering::Relaxed);
        let header = ShadowMapHeader {
            light: light.gpu(),
            size: UVec4::new(self.width, self.height, sorted as u32 * MS_SORTED_RANGES, 0),
            range_heads: self.range_heads.device_address(),
            ranges: self.ranges.device_address(),
            coverage: coverage.map_or(0, |c| c.coverage.device_address()),
            cover_depth: coverage.map_or(0, |c| c.cover_depth.device_address()),
            heads: self.heads.device_address(),
            nodes: self.nodes.device_address(),
            counters: self.counters.device_address(),
            long_pixels: self.long_pixels.device_address(),
            nearest: coverage.map_or(0, |c| c.nearest.device_address()),
            static_nearest: if self.uses_static_layer(light, coverage)
                && light.lookup == Lookup::DepthLine
            {
                self.static_nearest.device_address()
            } else {
                0
            },
            tiles: self.tiles.device_address(),
            list_ranges: if sorted {
                self.range_lists.device_address()
            } else {
                self.ranges.device_address()
            },
            triangles: match (&self.triangle_records, light.lookup) {
                (Some(records), Lookup::Exact) => records.device_address(),
                _ => 0,
            },
            static_names: match &self.static_names {
                Some(names) if self.uses_static_names(light, coverage) => names.device_address(),
                _ => 0,
            },
            light_end: light.gpu_end(),
        };
        if outer_barriers {
            // SAFETY: `cmd` is recording outside a render pass on a graphics and compute queue (the
            // collection pass's contract, which calls this), so the shader and transfer stages
            // named are supported.
            unsafe { memory_barrier(device, cmd, Access::ANY_SHADER_READ, Access::TRANSFER_WRITE) };
        }
        // SAFETY: plain data of the header's size; recording outside a render pass (the
        // collection pass's contract).
        unsafe { self.header.record_write(device, cmd, &[header]) };
    }

    /// How many times a collection pass has drawn this map's static layer (with
    /// [`LightView::keep_static_layer`], once per change of light or static draws; new
    /// buffers from [`Self::grow_to_fit`] or [`Self::reserve`] start again from 0).
    pub fn static_layer_builds(&self) -> u32 {
        self.static_layer_builds.load(Ordering::Relaxed)
    }

    fn static_layer_state(&self) -> std::sync::MutexGuard<'_, StaticLayerState> {
        self.static_layer_source
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// Makes the next collection pass redraw the static layer, kept or not: call it when a
    /// static draw's buffer contents changed in place.
    pub fn forget_static_layer(&self) {
        *self.static_layer_state() = StaticLayerState::default();
    }

    /// Tells the map that the command buffer with its last recorded collection pass was
    /// submitted: a static layer that pass drew may then be kept by later passes (with
    /// [`LightView::keep_static_layer`]). Recording alone never marks a layer as kept, so a
    /// recorded pass that is not submitted needs nothing undone; without this call the layer
    /// is redrawn by every pass (slower, never wrong).
    ///
    /// Call it after the submission and before recording this map's next collection pass.
    /// (Saying so of a pass that was not submitted makes later passes keep a layer that was
    /// never drawn: wrong shadows, though no memory is misused.)
    pub fn static_layer_submitted(&self) {
        let mut state = self.static_layer_state();
        if let Some(recorded) = state.recorded.take() {
            state.kept = Some(recorded);
        }
    }

    /// Whether the static layer holds what `source` would draw (a kept layer).
    pub(crate) fn static_layer_is(&self, source: &StaticLayerSource) -> bool {
        self.static_layer_state().kept.as_ref() == Some(source)
    }

    /// Notes that a recorded pass draws the static layer for `source` (`None`: not to be
    /// kept). What the layer held is not kept any more; `source` is, once the pass is
    /// submitted ([`Self::static_layer_submitted`]).
    pub(crate) fn static_layer_drawn(&self, source: Option<StaticLayerSource>) {
        self.static_layer_builds.fetch_add(1, Ordering::Relaxed);
        let mut state = self.static_layer_state();
        state.kept = None;
        state.recorded = source;
    }

    /// Records clearing the range heads and setting the generation's dispatches: every tile,
    /// or none when the collection stores the ranges itself (`collects_ranges`); the
    /// sorting's only then, with [`RangeStorage::Sorted`] (`sorts`). Transfer writes; the
    /// caller orders them with its barriers.
    pub(crate) fn record_clear_ranges(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        collects_ranges: bool,
        sorts: bool,
    ) {
        let tiles = [
            self.width.div_ceil(TILE_TEXELS),
            self.height.div_ceil(TILE_TEXELS),
            1,
            0,
        ];
        let none = [0, 1, 1, 0];
        // Pairing, sorting each texel's list, sorting the long lists (its first tier counts
        // their groups).
        let (pairing, sort) = match (collects_ranges, sorts) {
            (false, _) => (tiles, none),
            (true, false) => (none, none),
            (true, true) => (none, tiles),
        };
        let mut words = [0u32; DISPATCH_WORDS as usize];
        for (at, groups) in [
            (DISPATCH_PAIRING, pairing),
            (DISPATCH_SORT, sort),
            (DISPATCH_SORT_LONG, none),
        ] {
            words[at as usize..at as usize + 4].copy_from_slice(&groups);
        }
        // SAFETY: recording outside a render pass (the collection pass's contract).
        unsafe {
            device.cmd_fill_buffer(cmd, self.range_heads.raw(), 0, vk::WHOLE_SIZE, 0);
            self.tiles.record_write(device, cmd, &words);
        }
    }

    /// The buffers the map's passes use (every one but the counters' readback).
    fn pass_buffers(&self) -> [&Buffer; 10] {
        [
            &self.header,
            &self.heads,
            &self.nodes,
            &self.counters,
            &self.range_heads,
            &self.ranges,
            &self.range_lists,
            &self.long_pixels,
            &self.static_nearest,
            &self.tiles,
        ]
    }

    /// Bytes of GPU memory the map's buffers occupy.
    pub fn allocated_bytes(&self) -> u64 {
        self.pass_buffers().iter().map(|b| b.size()).sum::<u64>()
            + self.triangle_records.as_ref().map_or(0, |b| b.size())
            + self.static_names.as_ref().map_or(0, |b| b.size())
    }

    /// Each buffer the map allocated, by its allocation's name, with the bytes of its
    /// allocation (what a host's allocator counts: [`crate::gpu::Context::from_raw_with_allocator`]).
    pub fn allocations(&self) -> Vec<(&str, u64)> {
        self.pass_buffers()
            .into_iter()
            .chain([&self.counters_readback])
            .chain(self.triangle_records.as_ref())
            .chain(self.static_names.as_ref())
            .map(|b| (b.name(), b.allocated_bytes()))
            .collect()
    }

    /// Whether a frame with these counts overflowed this map (its output is then incomplete
    /// and the frame must be recorded again after [`Self::grow_to_fit`]).
    pub fn needs_more_room(&self, counts: &Counters) -> bool {
        let nodes_stored = counts.ranges_direct == 0;
        counts.wrapped != 0
            || (nodes_stored && counts.node_count > self.node_capacity)
            || counts.range_count > self.range_capacity
            || counts.static_names > self.static_name_capacity()
    }

    /// An error if the frame that produced `counts` had pixels whose fragment lists were too
    /// long to pair (their ranges are missing), or triangles dropped for an invalid index:
    /// the frame must not be used.
    pub fn check_complete(&self, counts: &Counters) -> Result<()> {
        if counts.wrapped != 0 {
            return Err(Error::FragmentCountOverflow);
        }
        if counts.invalid_triangles > 0 {
            return Err(Error::InvalidIndices {
                triangles: counts.invalid_triangles,
            });
        }
        if counts.overlong_pixels == 0 {
            return Ok(());
        }
        Err(Error::FragmentListTooLong {
            pixels: counts.overlong_pixels,
            longest: counts.longest_list,
            more: if counts.longest_list >= 8 * MAX_LIST_NODES {
                " or more"
            } else {
                ""
            },
            limit: MAX_LIST_NODES,
        })
    }

    /// Reallocates to the given capacities (at least the current ones): an engine that
    /// grows between frames may keep headroom above the last frame's counts, e.g.
    /// `map.reserve(ctx, counts.node_count / 4 * 5, counts.range_count / 4 * 5)`. Like
    /// [`Self::grow_to_fit`], it retires the old buffers: they are destroyed once no pending
    /// frame can use them ([`Context::begin_frame`], [`Context::collect`]), so it may be
    /// called while frames that use the map are in flight.
    pub fn reserve(&mut self, ctx: &Context, nodes: u32, ranges: u32) -> Result<()> {
        let nodes = nodes.max(self.node_capacity);
        let ranges = ranges.max(self.range_capacity);
        if (nodes, ranges) != (self.node_capacity, self.range_capacity) {
            self.rebuild(ctx, nodes, ranges, self.buffers)?;
        }
        Ok(())
    }

    /// New lists for `nodes` and `ranges` with `buffers` (the old buffers retired), keeping
    /// the exact lookup's triangle records and static name lists; what the static layer
    /// holds is forgotten (the next collection redraws it). On error the map is unchanged.
    fn rebuild(
        &mut self,
        ctx: &Context,
        nodes: u32,
        ranges: u32,
        buffers: PathBuffers,
    ) -> Result<()> {
        let fresh = Self::build(
            ctx,
            (self.width, self.height),
            nodes,
            ranges,
            self.range_storage,
            buffers,
        )?
        .with_pruning(self.pruning);
        let records = self.triangle_records.take();
        let names = self.static_names.take();
        *self = fresh;
        self.triangle_records = records;
        self.static_names = names;
        Ok(())
    }

    /// Reserves room for all that a frame of `draws` lit by `light` (with or without a
    /// coverage map) can store, bounded from the host's positions by [`RangeCeiling`]: such
    /// a frame never runs out of room, so it never has to be grown a frame late. Returns the
    /// ranges it has room for, or None with the papers' prisms ([`RangeCeiling::new`]), not
    /// bounded (grow after a frame that overflowed instead). Static draws are left out where
    /// the frame keeps them in the static layer (the exact lookup's static names reserved
    /// for them instead). Like [`Self::reserve`], it only grows, and retires the
    /// old buffers; it also makes the buffers `light`'s path uses that the map lacks (as
    /// [`Self::prepare_for`], keeping the others). Errors if the bound is more than a map counts (u32) or the device holds.
    pub fn reserve_for(
        &mut self,
        ctx: &Context,
        light: &LightView,
        coverage: Option<&CoverageMap>,
        draws: &[HostDraw],
    ) -> Result<Option<u64>> {
        let needed = PathBuffers::of_light(light, coverage.is_some(), self.range_storage);
        if self.buffers.missing_from(needed).is_some() {
            let buffers = self.buffers.union(needed);
            self.rebuild(ctx, self.node_capacity, self.range_capacity, buffers)?;
        }
        let Some(ceiling) = RangeCeiling::new(light, self.width, self.height) else {
            return Ok(None);
        };
        let static_layer = self.uses_static_layer(light, coverage);
        let static_names = self.uses_static_names(light, coverage);
        let (mut ranges, mut names) = (0u64, 0u64);
        for draw in draws {
            if !(static_layer && draw.is_static()) {
                ranges += ceiling.draw(draw)?;
            } else if static_names {
                names += ceiling.draw(draw)?;
            }
        }
        // Where nodes are stored, a run's range pairs two of them.
        let nodes = if self.collects_ranges(light, coverage) {
            0
        } else {
            ranges.saturating_mul(2)
        };
        let counted = |n: u64, what: &str| {
            u32::try_from(n).map_err(|_| {
                Error::InvalidArgument(format!(
                    "the draws may store up to {n} {what}, more than a temporal shadow map counts ({})",
                    u32::MAX
                ))
            })
        };
        self.reserve(ctx, counted(nodes, "nodes")?, counted(ranges, "ranges")?)?;
        if names > u64::from(self.static_name_capacity()) {
            self.reserve_static_names(ctx, counted(names, "static names")?)?;
        }
        Ok(Some(ranges))
    }

    /// Reallocates to hold exactly what `counts` says a frame needs (and at least the
    /// current capacities). Errors with the figures if the device cannot address that much.
    /// The old buffers are retired, not freed at once (see [`Self::reserve`]).
    pub fn grow_to_fit(&mut self, ctx: &Context, counts: &Counters) -> Result<()> {
        if counts.wrapped != 0 {
            return Err(Error::FragmentCountOverflow);
        }
        // A frame that stored its ranges directly stored no node: its count is exact and
        // needs no node room.
        let nodes_stored = counts.ranges_direct == 0;
        let nodes = if nodes_stored {
            counts.node_count.max(self.node_capacity)
        } else {
            self.node_capacity
        };
        // When fragments overflowed, the ranges counted came from incomplete lists. Ranges
        // pair fragments, so about half the fragments plus a little for odd groups is a good
        // guess that keeps the allocation near equation (2); should it fall short, the range
        // count of the next run is exact and one more run fits.
        let estimate = if nodes_stored && counts.node_count > self.node_capacity {
            counts.node_count / 2 + counts.node_count / 64
        } else {
            0
        };
        let ranges = counts.range_count.max(self.range_capacity).max(estimate);
        self.rebuild(ctx, nodes, ranges, self.buffers)?;
        if counts.static_names > self.static_name_capacity() {
            self.reserve_static_names(ctx, counts.static_names)?;
        }
        Ok(())
    }

    /// Records a copy of the counters for [`Self::read_counters`] (after the submission
    /// completes). Call after the generation pass.
    ///
    /// # Safety
    /// `cmd` was allocated from the map's device, is recording, outside any render pass; no
    /// other command buffer reads back this map's counters at the same time.
    ///
    /// Synchronization: waits for the compute stage's counter writes (the generation pass);
    /// leaves the copy visible to host reads once the submission's fence has signalled.
    pub unsafe fn record_counter_readback(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is of the map's device, recording outside any render pass (the contract);
        // its queue runs the generation pass's compute work, so it supports the compute and
        // transfer stages.
        unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_READ) };
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: COUNTER_BYTES,
        }];
        // SAFETY: both buffers are this map's, alive as long as `self` (dropping them retires them
        // past pending frames), each COUNTER_BYTES long, and the counters were made visible to
        // transfer reads just above; no other readback of this map runs at the same time (the
        // contract).
        unsafe {
            device.cmd_copy_buffer(
                cmd,
                self.counters.raw(),
                self.counters_readback.raw(),
                &region,
            )
        };
        // SAFETY: the same command buffer, outside a render pass; host reads are a valid
        // destination once the fence signals.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
    }

    /// The counters copied by [`Self::record_counter_readback`], once that submission has
    /// completed.
    pub fn read_counters(&self) -> Result<Counters> {
        Ok(self.counters_readback.read::<Counters>(1)?[0])
    }

    /// Copies the static layer back to the host (see [`ShadowMapContents::static_layer`]).
    pub fn download_static_layer(&self, ctx: &Context) -> Result<Vec<u64>> {
        if !self.buffers.static_layer {
            // No layer on this map's path: every texel holds none.
            return Ok(vec![u64::MAX; (self.width * self.height) as usize]);
        }
        download(
            ctx,
            &self.static_nearest,
            (self.width * self.height) as usize,
        )
    }

    /// Copies the whole map back to the host (for tests, heat maps and debugging).
    pub fn download(&self, ctx: &Context) -> Result<ShadowMapContents> {
        let counts = self.read_counters()?;
        let pixels = (self.width * self.height) as usize;
        // Where the collection stored the ranges itself, there are no lists (the heads held
        // the texels' run counts).
        let lists = counts.ranges_direct == 0;
        let nodes = if lists && self.buffers.nodes {
            counts.node_count.min(self.node_capacity) as usize
        } else {
            0
        };
        // Sorted ranges fill the buffer's first `sorted_count` places (fewer than the lists
        // held where some were pruned).
        let sorted = !lists && self.range_storage == RangeStorage::Sorted;
        let stored = if sorted {
            counts.sorted_count
        } else {
            counts.range_count
        };
        let ranges = stored.min(self.range_capacity) as usize;
        Ok(ShadowMapContents {
            width: self.width,
            height: self.height,
            heads: if lists {
                download(ctx, &self.heads, pixels)?
            } else {
                vec![0; pixels]
            },
            nodes: download(ctx, &self.nodes, nodes)?,
            range_heads: download(ctx, &self.range_heads, pixels)?,
            ranges: download(ctx, &self.ranges, ranges)?,
            static_layer: self.download_static_layer(ctx)?,
            static_names: match &self.static_names {
                Some(buffer) if counts.static_names > 0 => {
                    let names = counts.static_names.min(self.static_name_capacity()) as usize;
                    let header = (STATIC_NAMES_HEADER_BYTES / 4) as usize;
                    let words: Vec<u32> = download(ctx, buffer, header + pixels + 2 * names)?;
                    words[header..].to_vec()
                }
                _ => Vec::new(),
            },
        })
    }
}

/// Copies the first `count` elements of a device-local buffer to the host.
pub(crate) fn download<T: bytemuck::Pod>(
    ctx: &Context,
    buffer: &Buffer,
    count: usize,
) -> Result<Vec<T>> {
    if !buffer.is_of(ctx) {
        return Err(Error::InvalidArgument(format!(
            "{} was made with another context than the one given to copy it",
            buffer.name()
        )));
    }
    let bytes = (count * std::mem::size_of::<T>()) as u64;
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let staging = Buffer::new(ctx, "download", bytes, BufferUsage::Readback)?;
    let device = ctx.device();
    OneShot::new(ctx)?.run(|cmd| {
        // SAFETY: `cmd` is the OneShot's own command buffer, recording, outside any render pass, on
        // the context's graphics and compute queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::ANY_SHADER_READ
                    .and(Access::COMPUTE_RW)
                    .and(Access::FRAGMENT_RW),
                Access::TRANSFER_READ,
            )
        };
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: bytes,
        }];
        // SAFETY: `bytes` is within both buffers: the staging buffer was made with exactly `bytes`,
        // and every caller (all in this file) passes a count clamped to `buffer`'s capacity (per-
        // texel buffers: width x height; the others: min(count, capacity)). Both are of `ctx`
        // (checked above) and outlive the OneShot, which waits.
        unsafe { device.cmd_copy_buffer(cmd, buffer.raw(), staging.raw(), &region) };
        // SAFETY: the same OneShot command buffer, outside a render pass; host reads are a valid
        // destination once its fence signals.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
        Ok(())
    })?;
    staging.read(count)
}
