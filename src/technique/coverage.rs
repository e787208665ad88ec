//! The coverage map (2017 paper, "Extension"): find the shadow-map pixels that one triangle
//! covers, nearest to the light, for the whole frame, so that generation stores only that
//! triangle's range there instead of every range.
//!
//! 1. Nearest map: the nearest prism fragment per pixel, as (depth, surface, triangle id),
//!    filled by the collection pass (it rasterizes the same prisms).
//! 2. [`CoveragePass`], caps: the triangles at t = 0 and t = 1; where the nearest fragment is
//!    the same triangle's cap at the other time, the pixel is marked with its id.
//! 3. [`CoveragePass`], reset: the prisms again; a mark is removed where another triangle is
//!    nearer at some time, or the triangle's own edge sweeps over the pixel (see
//!    coverage_reset.frag).

use super::collection::{PUSH_BYTES, PrismPipelines, PrismShaders, draw_each};
use super::draws::DrawList;
use super::gpu_types::{DepthFormat, PassConstants};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use super::view::LightView;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, Pipeline, attachmentless_pipeline, begin_attachmentless,
    memory_barrier,
};
use ash::vk;

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

/// Passes 2 and 3 of the extension. Immutable after creation: one serves every frame in
/// flight and every light.
pub struct CoveragePass {
    caps: Pipeline,
    reset: PrismPipelines,
}

impl CoveragePass {
    /// Creates the caps pipeline (vertex and fragment shader) and the reset pipeline (the
    /// collection pass's prisms with another fragment shader).
    pub fn new(ctx: &Context) -> Result<Self> {
        let caps = attachmentless_pipeline(
            ctx,
            PUSH_BYTES,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "coverage_caps.vert",
                    shaders::COVERAGE_CAPS_VERT,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "coverage.frag",
                    shaders::COVERAGE_FRAG,
                ),
            ],
        )?;
        let reset = PrismPipelines::new(
            ctx,
            PrismShaders {
                paper_fragment: ("coverage_reset.frag", shaders::COVERAGE_RESET_FRAG),
                exact_fragment: (
                    "coverage_reset_exact.frag",
                    shaders::COVERAGE_RESET_EXACT_FRAG,
                ),
                static_fragment: (
                    "coverage_reset_static.frag",
                    shaders::COVERAGE_RESET_STATIC_FRAG,
                ),
                ranges_fragment: None,
            },
        )?;
        Ok(Self { caps, reset })
    }

    /// Records passes 2 and 3 for `coverage`, after [`super::CollectionPass::record`] of
    /// `map` with the same coverage map (which wrote the header and filled the nearest map),
    /// and before [`super::GenerationPass::record`]; `light` is the collection's (its
    /// [`LightView::prisms`] picks the same prisms).
    ///
    /// # Safety
    /// As [`super::CollectionPass::record`], with `draws` the same list the collection pass
    /// drew.
    ///
    /// Synchronization: waits for the collection's fragment writes (its closing barrier) and
    /// earlier reads of the coverage map; leaves the coverage map written by the fragment
    /// stage and visible to compute and every shader read. State changed: the bound graphics
    /// pipeline, push constants, viewport, scissor.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &TemporalShadowMap,
        coverage: &CoverageMap,
    ) {
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW),
                Access::TRANSFER_WRITE,
            )
        };
        unsafe {
            device.cmd_fill_buffer(cmd, coverage.coverage.raw(), 0, vk::WHOLE_SIZE, u32::MAX);
            device.cmd_fill_buffer(cmd, coverage.cover_depth.raw(), 0, vk::WHOLE_SIZE, 0);
        }
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::FRAGMENT_RW) };
        unsafe { begin_attachmentless(device, cmd, coverage.width, coverage.height) };
        unsafe { self.caps.bind(device, cmd) };
        for time in [0.0, 1.0] {
            let constants = PassConstants {
                map: map.header_address(),
                mode: DepthFormat::DepthAndId as u32,
                time,
                ..PassConstants::default()
            };
            draw_each(device, cmd, &self.caps, draws, constants);
        }
        unsafe { device.cmd_end_rendering(cmd) };
        // The reset pass reads what the caps wrote, in other fragment invocations.
        unsafe { memory_barrier(device, cmd, Access::FRAGMENT_RW, Access::FRAGMENT_RW) };
        unsafe { begin_attachmentless(device, cmd, coverage.width, coverage.height) };
        let constants = PassConstants {
            map: map.header_address(),
            ..PassConstants::default()
        };
        self.reset
            .draw(device, cmd, light.prisms, draws, constants, true, false);
        unsafe { device.cmd_end_rendering(cmd) };
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::FRAGMENT_RW,
                Access::COMPUTE_RW.and(Access::ANY_SHADER_READ),
            )
        };
    }
}
