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
use super::light_motion::{RECORDED_EXACT, RECORDED_STATIC_NAMES};
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
mod header;
mod readback;
mod room;
pub(crate) use room::Bounded;
mod static_layer;
pub(crate) use static_layer::StaticLayerSource;
use static_layer::StaticLayerState;

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
    /// The counter readback records its entry and exit barriers (off: the host's,
    /// [`Self::with_host_barriers`]).
    pub(crate) outer_barriers: bool,
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

use super::gpu_constants::{
    DISPATCH_PAIRING, DISPATCH_SORT, DISPATCH_SORT_LONG, DISPATCH_WORDS, SORT_TILE_ROW, TILE_TEXELS,
};

/// The most tiles the sort's dispatch reaches: SORT_TILE_ROW across, as many rows as every
/// Vulkan device dispatches (maxComputeWorkGroupCount is at least 65,535 in each dimension).
const MAX_SORT_TILES: u64 = SORT_TILE_ROW as u64 * 65_535;

/// The generation's TILE_TEXELS x TILE_TEXELS tiles of a `width` x `height` map (the sort's
/// tile list has room for each: `gpu_constants::SORT_TILE_ROW`).
fn tile_count(width: u32, height: u32) -> u32 {
    width.div_ceil(TILE_TEXELS) * height.div_ceil(TILE_TEXELS)
}

impl TemporalShadowMap {
    /// The map's tiles ([`tile_count`]).
    pub(crate) fn tile_count(&self) -> u32 {
        tile_count(self.width, self.height)
    }
}

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
        let tiles =
            u64::from(width.div_ceil(TILE_TEXELS)) * u64::from(height.div_ceil(TILE_TEXELS));
        if tiles > MAX_SORT_TILES {
            return Err(Error::InvalidArgument(format!(
                "shadow map size {width}x{height}: {tiles} tiles of {TILE_TEXELS}x{TILE_TEXELS} \
                 texels, more than the sort's dispatch reaches ({MAX_SORT_TILES}: \
                 {SORT_TILE_ROW} across, 65,535 rows)"
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
                (u64::from(DISPATCH_WORDS) + 2 * u64::from(tile_count(width, height))) * 4,
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
            outer_barriers: true,
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

    /// Whether the last recorded collection kept the static triangles in the static name
    /// lists ([`Self::uses_static_names`]; false before any).
    pub(crate) fn recorded_static_names(&self) -> bool {
        self.built_for.load(Ordering::Relaxed) & RECORDED_STATIC_NAMES != 0
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
}
