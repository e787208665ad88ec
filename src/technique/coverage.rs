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

use super::collection::{bindings, prism_pipeline};
use super::geometry::FrameInputs;
use super::gpu_types::{DepthFormat, PassConstants};
use super::shaders;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, DescriptorKind, DescriptorSet, Pipeline,
    attachmentless_pipeline, begin_attachmentless, memory_barrier,
};
use ash::vk;

/// Triangle ids share 32 bits with the surface kind in the nearest map.
pub const MAX_COVERAGE_TRIANGLES: u32 = 1 << 30;

/// The nearest map and the coverage map of a `width` x `height` shadow map.
pub struct CoverageMap {
    width: u32,
    height: u32,
    /// Per pixel: depth bits << 32 | surface << 30 | triangle id of the nearest fragment.
    pub nearest: Buffer,
    /// Per pixel: the covering triangle's id, or u32::MAX for none (the paper's -1).
    pub coverage: Buffer,
    /// Per pixel: the covering triangle's depth at t = 0 and at t = 1 (two floats).
    pub cover_depth: Buffer,
}

impl CoverageMap {
    pub fn new(ctx: &Context, width: u32, height: u32) -> Result<Self> {
        let pixels = width as u64 * height as u64;
        if pixels * 8 > ctx.max_buffer_bytes() {
            return Err(Error::DeviceLimit {
                what: "the nearest map",
                count: pixels,
                element_bytes: 8,
                needed_bytes: pixels * 8,
                limit_bytes: ctx.max_buffer_bytes(),
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

    pub fn width(&self) -> u32 {
        self.width
    }
    pub fn height(&self) -> u32 {
        self.height
    }
}

/// Passes 2 and 3 of the extension. Record after [`super::CollectionPass::record`] with the
/// same map (which fills the nearest map) and before [`super::GenerationPass::record`].
pub struct CoveragePass {
    caps_set: DescriptorSet,
    caps: Pipeline,
    reset_set: DescriptorSet,
    reset: Pipeline,
}

impl CoveragePass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let caps_set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (1, Storage),
                (3, Storage),
                (4, Storage),
                (5, Storage),
            ]),
        )?;
        let caps = attachmentless_pipeline(
            ctx,
            caps_set.layout(),
            std::mem::size_of::<PassConstants>() as u32,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "shadow_depth.vert",
                    shaders::SHADOW_DEPTH_VERT,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "coverage.frag",
                    shaders::COVERAGE_FRAG,
                ),
            ],
        )?;
        let reset_set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (1, Storage),
                (2, Storage),
                (4, Storage),
                (5, Storage),
            ]),
        )?;
        let reset = prism_pipeline(
            ctx,
            reset_set.layout(),
            "coverage_reset.frag",
            shaders::COVERAGE_RESET_FRAG,
        )?;
        Ok(Self {
            caps_set,
            caps,
            reset_set,
            reset,
        })
    }

    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        inputs: FrameInputs<'_>,
        map: &CoverageMap,
    ) {
        let FrameInputs { frame, geometry } = inputs;
        self.caps_set.bind(&[
            frame,
            &geometry.vertices,
            &map.nearest,
            &map.coverage,
            &map.cover_depth,
        ]);
        self.reset_set.bind(&[
            frame,
            &geometry.vertices,
            &geometry.triangles,
            &map.coverage,
            &map.cover_depth,
        ]);
        memory_barrier(
            device,
            cmd,
            Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW),
            Access::TRANSFER_WRITE,
        );
        unsafe {
            device.cmd_fill_buffer(cmd, map.coverage.raw(), 0, vk::WHOLE_SIZE, u32::MAX);
            device.cmd_fill_buffer(cmd, map.cover_depth.raw(), 0, vk::WHOLE_SIZE, 0);
        }
        memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::FRAGMENT_RW);
        begin_attachmentless(device, cmd, map.width, map.height);
        self.caps.bind(device, cmd, self.caps_set.raw());
        for time in [0.0, 1.0] {
            let constants = PassConstants {
                mode: DepthFormat::DepthAndId as u32,
                time,
                ..PassConstants::default()
            };
            self.caps.push(device, cmd, &constants);
            unsafe { device.cmd_draw(cmd, 3 * geometry.triangle_count(), 1, 0, 0) };
        }
        unsafe { device.cmd_end_rendering(cmd) };
        // The reset pass reads what the caps wrote, in other fragment invocations.
        memory_barrier(device, cmd, Access::FRAGMENT_RW, Access::FRAGMENT_RW);
        begin_attachmentless(device, cmd, map.width, map.height);
        self.reset.bind(device, cmd, self.reset_set.raw());
        self.reset.push(device, cmd, &PassConstants::default());
        unsafe {
            device.cmd_draw(cmd, 3 * geometry.triangle_count(), 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
        memory_barrier(
            device,
            cmd,
            Access::FRAGMENT_RW,
            Access::COMPUTE_RW.and(Access::ANY_SHADER_READ),
        );
    }
}
