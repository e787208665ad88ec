//! Generation sub-pass (paper 4.3): fragments to depth-time ranges, once per shadow-map pixel.
//! Two tiers: every pixel with a short list (nearly all) is paired with small private arrays;
//! the few long lists go to a second, indirect dispatch with room for `MAX_LIST_NODES`.

use super::collection::bindings;
use super::coverage::CoverageMap;
use super::gpu_types::{PassConstants, USE_COVERAGE};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::Result;
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, DescriptorKind, DescriptorSet, Pipeline,
    compute_pipeline, memory_barrier,
};
use ash::vk;

pub struct GenerationPass {
    set: DescriptorSet,
    pipeline: Pipeline,
    long_pipeline: Pipeline,
    /// Bound as the coverage map when there is none.
    placeholder: Buffer,
}

impl GenerationPass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (3, Storage),
                (5, Storage),
                (6, Storage),
                (8, Storage),
                (9, Storage),
            ]),
        )?;
        let pipeline = compute_pipeline(
            ctx,
            set.layout(),
            std::mem::size_of::<PassConstants>() as u32,
            "generation.comp",
            shaders::GENERATION_COMP,
        )?;
        let long_pipeline = compute_pipeline(
            ctx,
            set.layout(),
            std::mem::size_of::<PassConstants>() as u32,
            "generation_long.comp",
            shaders::GENERATION_LONG_COMP,
        )?;
        let placeholder = Buffer::new(ctx, "no coverage map", 4, BufferUsage::Storage)?;
        Ok(Self {
            set,
            pipeline,
            long_pipeline,
            placeholder,
        })
    }

    /// Records the range generation; must follow [`super::CollectionPass::record`] on the
    /// same map (and [`super::CoveragePass::record`] when `coverage` is given: then a covered
    /// pixel stores no range: the coverage map holds what shadows there). Leaves the ranges readable by any
    /// later shader.
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        frame: &Buffer,
        map: &TemporalShadowMap,
        coverage: Option<&CoverageMap>,
    ) {
        self.set.bind(&[
            frame,
            &map.heads,
            &map.counters,
            &map.range_heads,
            coverage.map_or(&self.placeholder, |c| &c.coverage),
            &map.long_pixels,
        ]);
        // Empty long-pixel list; its indirect dispatch starts at 0 x 1 x 1 groups.
        let header: [u32; 4] = [0, 0, 1, 1];
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW.and(Access::INDIRECT_READ),
            Access::TRANSFER_WRITE,
        );
        unsafe {
            // SAFETY: plain u32s.
            let bytes = std::slice::from_raw_parts(header.as_ptr() as *const u8, 16);
            device.cmd_update_buffer(cmd, map.long_pixels.raw(), 0, bytes);
        }
        memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_RW);
        self.pipeline.bind(device, cmd, self.set.raw());
        let constants = PassConstants {
            flags: if coverage.is_some() { USE_COVERAGE } else { 0 },
            node_address: map.nodes.device_address(),
            range_address: map.ranges.device_address(),
            ..PassConstants::default()
        };
        self.pipeline.push(device, cmd, &constants);
        unsafe { device.cmd_dispatch(cmd, map.width().div_ceil(8), map.height().div_ceil(8), 1) };
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW,
            Access::COMPUTE_RW.and(Access::INDIRECT_READ),
        );
        self.long_pipeline.bind(device, cmd, self.set.raw());
        self.long_pipeline.push(device, cmd, &constants);
        unsafe { device.cmd_dispatch_indirect(cmd, map.long_pixels.raw(), 4) };
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW,
            Access::ANY_SHADER_READ.and(Access::COMPUTE_RW),
        );
    }
}
