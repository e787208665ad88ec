//! Room for a frame: whether one overflowed, and growing the lists to what it needed or to a
//! bound computed beforehand.

use super::*;

/// A draw as the room reservation sees it: whether it stands still all shutter (the static
/// layer then holds it), and at most how many ranges its triangles store.
pub(crate) trait Bounded {
    /// Nothing of it moves during the shutter.
    fn is_still(&self) -> bool;
    /// The ceiling's bound over its triangles, or why it cannot be bounded.
    fn ranges_at_most(&self, ceiling: &RangeCeiling) -> Result<u64>;
}

impl Bounded for HostDraw<'_> {
    fn is_still(&self) -> bool {
        self.is_static()
    }
    fn ranges_at_most(&self, ceiling: &RangeCeiling) -> Result<u64> {
        ceiling.draw(self)
    }
}

impl TemporalShadowMap {
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
    pub(super) fn rebuild(
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
        // Who records the readback's barriers is the host's choice, kept with the buffers.
        let outer_barriers = self.outer_barriers;
        *self = fresh;
        self.triangle_records = records;
        self.static_names = names;
        self.outer_barriers = outer_barriers;
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
        self.reserve_bounded(ctx, light, coverage, draws, 0)
    }

    /// [`Self::reserve_for`] for any draw description the ceiling bounds (the host's copies,
    /// or the engine layer's meshes). Where the map must grow, it grows `headroom_quarters`
    /// quarters more than the frame needs, so that frames whose room varies a little do not
    /// each reallocate (which also forgets a kept static layer).
    pub(crate) fn reserve_bounded<D: Bounded>(
        &mut self,
        ctx: &Context,
        light: &LightView,
        coverage: Option<&CoverageMap>,
        draws: &[D],
        headroom_quarters: u64,
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
            if !(static_layer && draw.is_still()) {
                ranges += draw.ranges_at_most(&ceiling)?;
            } else if static_names {
                names += draw.ranges_at_most(&ceiling)?;
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
        let with_headroom = |n: u64, capacity: u32| {
            if n > u64::from(capacity) {
                (n + n / 4 * headroom_quarters)
                    .min(u64::from(u32::MAX))
                    .max(n)
            } else {
                n
            }
        };
        self.reserve(
            ctx,
            counted(with_headroom(nodes, self.node_capacity), "nodes")?,
            counted(with_headroom(ranges, self.range_capacity), "ranges")?,
        )?;
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
}
