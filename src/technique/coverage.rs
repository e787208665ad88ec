//! The coverage map (2017 paper, "Extension"): find the shadow-map pixels that one triangle
//! covers, nearest to the light, for the whole frame, so that generation stores only that
//! triangle's range there instead of every range.
//!
//! 1. Nearest map: the nearest prism fragment per pixel, as (depth, surface, triangle id),
//!    filled by the collection pass (it rasterizes the same prisms).
//! 2. `CoveragePass` (coverage_pass.rs, a research pass), caps: the triangles at t = 0 and t = 1; where the nearest fragment is
//!    the same triangle's cap at the other time, the pixel is marked with its id.
//! 3. `CoveragePass`, reset: the prisms again; a mark is removed where another triangle is
//!    nearer at some time, or the triangle's own edge sweeps over the pixel (see
//!    coverage_reset.frag).

use crate::error::{Error, Result};
use crate::gpu::{Buffer, BufferUsage, Context};

/// Triangle ids share 32 bits with the surface kind in the nearest map.
pub const MAX_COVERAGE_TRIANGLES: u32 = 1 << 30;

/// The nearest map and the coverage map of a `width` x `height` shadow map.
pub struct CoverageMap {
    width: u32,
    height: u32,
    /// Per pixel: depth bits << 32 | surface << 30 | triangle id of the nearest fragment.
    pub(crate) nearest: Buffer,
    /// Per pixel: the covering triangle's id, or u32::MAX for none (the paper's -1).
    pub(crate) coverage: Buffer,
    /// Per pixel: the covering triangle's depth at t = 0 and at t = 1 (two floats).
    pub(crate) cover_depth: Buffer,
}

impl CoverageMap {
    /// The maps for a `width` x `height` temporal shadow map (one per map, per frame in
    /// flight).
    pub fn new(ctx: &Context, width: u32, height: u32) -> Result<Self> {
        let pixels = width as u64 * height as u64;
        let limit = ctx.max_addressed_buffer_bytes();
        if pixels * 8 > limit {
            return Err(Error::DeviceLimit {
                what: "the nearest map",
                count: pixels,
                element_bytes: 8,
                needed_bytes: pixels * 8,
                limit_bytes: limit,
            });
        }
        Ok(Self {
            width,
            height,
            nearest: Buffer::new(ctx, "nearest map", pixels * 8, BufferUsage::Storage)?,
            coverage: Buffer::new(ctx, "coverage map", pixels * 4, BufferUsage::Storage)?,
            cover_depth: Buffer::new(ctx, "cover depth", pixels * 8, BufferUsage::Storage)?,
        })
    }

    /// Bytes of the three maps: 20 per pixel. The paper's nearest and coverage maps take 12;
    /// the covering triangle's two depths let the reset pass compare at each fragment's time.
    pub fn allocated_bytes(&self) -> u64 {
        self.nearest.size() + self.coverage.size() + self.cover_depth.size()
    }

    /// Texels across.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Texels down.
    pub fn height(&self) -> u32 {
        self.height
    }
}
