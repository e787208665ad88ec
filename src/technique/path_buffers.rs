//! Which of a temporal shadow map's buffers a frame's path uses (issue 37: a map allocates
//! only those, [`super::TemporalShadowMap::prepare_for`]).

use super::shadow_map::RangeStorage;
use super::view::{LightView, Lookup};

/// The buffers of a map that only some paths use, by whether the map holds them at their full
/// size (one element otherwise, so that every address in the header stays valid):
/// docs/src/integration.md#bytes-per-map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct PathBuffers {
    /// The fragments at the node capacity (16 bytes each): paths that store them (the
    /// static layer off, the papers' prisms, a coverage map).
    pub(super) nodes: bool,
    /// The sorting's input lists at the range capacity (24 bytes a range): sorted ranges.
    pub(super) sorted_lists: bool,
    /// One long-list index per texel (4 bytes): paths whose generation pass pairs
    /// fragments or sorts ranges.
    pub(super) long_lists: bool,
    /// The depth-line static layer (8 bytes per texel).
    pub(super) static_layer: bool,
}

impl PathBuffers {
    /// What a frame uses that collects its ranges directly or not, for depth lines or not,
    /// with static draws in a static layer or not, with `storage`.
    fn of(
        collects_ranges: bool,
        depth_lines: bool,
        static_layer: bool,
        storage: RangeStorage,
    ) -> Self {
        let sorted_lists = storage == RangeStorage::Sorted && collects_ranges && depth_lines;
        Self {
            nodes: !collects_ranges,
            sorted_lists,
            long_lists: !collects_ranges || sorted_lists,
            static_layer: static_layer && depth_lines,
        }
    }

    /// What a frame lit by `light` (with or without a coverage map) uses.
    pub(super) fn of_light(light: &LightView, coverage: bool, storage: RangeStorage) -> Self {
        Self::of(
            light.collects_ranges(coverage),
            light.lookup == Lookup::DepthLine,
            light.uses_static_layer(coverage),
            storage,
        )
    }

    /// What the default light uses (the exact construction, the static layer, depth lines,
    /// no coverage map): the ranges collected directly, so no node buffer.
    pub(super) fn default_path(storage: RangeStorage) -> Self {
        Self::of(true, true, true, storage)
    }

    /// The first buffer `needed` has that these lack.
    pub(super) fn missing_from(self, needed: Self) -> Option<&'static str> {
        [
            (needed.nodes && !self.nodes, "fragment (node) buffer"),
            (
                needed.sorted_lists && !self.sorted_lists,
                "sorted ranges' lists",
            ),
            (needed.long_lists && !self.long_lists, "long-list pixels"),
            (needed.static_layer && !self.static_layer, "static layer"),
        ]
        .into_iter()
        .find_map(|(missing, name)| missing.then_some(name))
    }

    /// Both sets.
    pub(super) fn union(self, other: Self) -> Self {
        Self {
            nodes: self.nodes || other.nodes,
            sorted_lists: self.sorted_lists || other.sorted_lists,
            long_lists: self.long_lists || other.long_lists,
            static_layer: self.static_layer || other.static_layer,
        }
    }
}
