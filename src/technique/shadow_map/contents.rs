//! A host copy of a temporal shadow map ([`super::TemporalShadowMap::download`]), for tests,
//! heat maps and debugging.

use super::super::gpu_types::{Node, Range};

/// A host copy of a temporal shadow map.
#[derive(Debug, Clone)]
pub struct ShadowMapContents {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// Per texel: index + 1 of its newest fragment (0 everywhere where the collection stored
    /// the ranges itself, [`super::TemporalShadowMap::collects_ranges`]).
    pub heads: Vec<u32>,
    /// The fragments (none where the collection stored the ranges itself).
    pub nodes: Vec<Node>,
    /// Per texel: index + 1 of its first range.
    pub range_heads: Vec<u32>,
    /// The ranges.
    pub ranges: Vec<Range>,
    /// Per texel: the static layer's nearest static triangle (depth key << 32 | id, all ones
    /// for none). Meaningful when the frame used the static layer
    /// ([`super::TemporalShadowMap::uses_static_layer`]); static triangles are in the lists
    /// otherwise.
    pub static_layer: Vec<u64>,
    /// With [`crate::technique::Lookup::Exact`] and the static layer: the static name lists, a head per
    /// texel (index + 1 of its first name, 0 for none) then (triangle id, next) pairs; empty
    /// otherwise (see [`Self::static_names_at`]).
    pub static_names: Vec<u32>,
}

impl ShadowMapContents {
    /// The static layer's triangle in texel (x, y) and its depth there, if any.
    pub fn static_at(&self, x: u32, y: u32) -> Option<(u32, f32)> {
        let key = self.static_layer[(y * self.width + x) as usize];
        let id = key as u32;
        (id != super::super::gpu_types::NO_TRIANGLE).then(|| (id, static_depth((key >> 32) as u32)))
    }

    /// The static triangles texel (x, y)'s static name list holds (the exact lookup's static
    /// layer), newest first; none without the lists.
    pub fn static_names_at(&self, x: u32, y: u32) -> Vec<u32> {
        let texels = (self.width * self.height) as usize;
        if self.static_names.len() < texels {
            return Vec::new();
        }
        let (heads, pairs) = self.static_names.split_at(texels);
        let names: Vec<[u32; 2]> = pairs.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
        let first = heads[(y * self.width + x) as usize];
        Self::walk(&names, first, |n| n[1])
            .iter()
            .map(|n| n[0])
            .collect()
    }

    fn walk<T: Copy>(items: &[T], first: u32, next: impl Fn(&T) -> u32) -> Vec<T> {
        let mut out = Vec::new();
        let mut link = first;
        while link != 0 && (link as usize) <= items.len() && out.len() <= items.len() {
            let item = items[link as usize - 1];
            out.push(item);
            link = next(&item);
        }
        out
    }

    /// The fragments stored at pixel (x, y).
    pub fn nodes_at(&self, x: u32, y: u32) -> Vec<Node> {
        let first = self.heads[(y * self.width + x) as usize];
        Self::walk(&self.nodes, first, |n| n.next)
    }

    /// Ranges stored per pixel, row-major (for heat maps).
    pub fn ranges_per_pixel(&self) -> Vec<u32> {
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .map(|(x, y)| self.ranges_at(x, y).len() as u32)
            .collect()
    }

    /// Ranges per pixel that generation would store without a coverage map: per triangle,
    /// half its fragments rounded up (pairs, and an odd one's zero-length range).
    pub fn ranges_without_coverage_per_pixel(&self) -> Vec<u32> {
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let mut ids: Vec<u32> = self.nodes_at(x, y).iter().map(|n| n.id).collect();
                ids.sort_unstable();
                ids.chunk_by(|a, b| a == b)
                    .map(|group| group.len().div_ceil(2) as u32)
                    .sum()
            })
            .collect()
    }

    /// The depth-time ranges stored at pixel (x, y).
    pub fn ranges_at(&self, x: u32, y: u32) -> Vec<Range> {
        let first = self.range_heads[(y * self.width + x) as usize];
        Self::walk(&self.ranges, first, |r| r.next)
    }
}

/// The depth a static-layer key holds (the inverse of `ms_static_key` in motion_shadows.glsl).
fn static_depth(key: u32) -> f32 {
    f32::from_bits(if key & 0x8000_0000 != 0 {
        key & 0x7fff_ffff
    } else {
        !key
    })
}
