//! Recording the map's header for a frame and the reset of its range heads and dispatches.

use super::*;

impl TemporalShadowMap {
    /// Records the header's update for a frame lit by `light` (with or without a coverage
    /// map): a transfer write, which the caller's barriers order after earlier readers (the
    /// collection's entry barrier, or the host's) and before later ones.
    pub(crate) fn record_header(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        light: &LightView,
        coverage: Option<&CoverageMap>,
    ) {
        let sorted = self.sorts_ranges(light, coverage);
        let static_names = if self.uses_static_names(light, coverage) {
            RECORDED_STATIC_NAMES
        } else {
            0
        };
        self.built_for
            .store(light.recorded_flags() | static_names, Ordering::Relaxed);
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
        // SAFETY: plain data of the header's size; recording outside a render pass (the
        // collection pass's contract).
        unsafe { self.header.record_write(device, cmd, &[header]) };
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
        // their groups). The sort visits the tiles the collection lists (SORT_TILE_ROW): none
        // until it stores a range.
        let pairing = if collects_ranges { none } else { tiles };
        let mut words = [0u32; DISPATCH_WORDS as usize];
        for (at, groups) in [
            (DISPATCH_PAIRING, pairing),
            (DISPATCH_SORT, none),
            (DISPATCH_SORT_LONG, none),
        ] {
            words[at as usize..at as usize + 4].copy_from_slice(&groups);
        }
        // SAFETY: recording outside a render pass (the collection pass's contract).
        unsafe {
            device.cmd_fill_buffer(cmd, self.range_heads.raw(), 0, vk::WHOLE_SIZE, 0);
            self.tiles.record_write(device, cmd, &words);
            if collects_ranges && sorts {
                // The tiles' marks (the list after them is written where marked).
                device.cmd_fill_buffer(
                    cmd,
                    self.tiles.raw(),
                    u64::from(DISPATCH_WORDS) * 4,
                    u64::from(self.tile_count()) * 4,
                    0,
                );
            }
        }
    }
}
