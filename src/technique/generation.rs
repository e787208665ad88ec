//! Generation sub-pass (paper 4.3): fragments to depth-time ranges, once per shadow-map pixel.

use super::collection::bindings;
use super::gpu_types::PassConstants;
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::Result;
use crate::gpu::{
    Access, Buffer, Context, DescriptorKind, DescriptorSet, Pipeline, compute_pipeline,
    memory_barrier,
};
use ash::vk;

pub struct GenerationPass {
    set: DescriptorSet,
    pipeline: Pipeline,
}

impl GenerationPass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (3, Storage),
                (4, Storage),
                (5, Storage),
                (6, Storage),
                (7, Storage),
            ]),
        )?;
        let pipeline = compute_pipeline(
            ctx,
            set.layout(),
            std::mem::size_of::<PassConstants>() as u32,
            "generation.comp",
            shaders::GENERATION_COMP,
        )?;
        Ok(Self { set, pipeline })
    }

    /// Records the range generation; must follow [`super::CollectionPass::record`] on the
    /// same map. Leaves the ranges readable by any later shader.
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        frame: &Buffer,
        map: &TemporalShadowMap,
    ) {
        self.set.bind(&[
            frame,
            &map.heads,
            &map.nodes,
            &map.counters,
            &map.range_heads,
            &map.ranges,
        ]);
        self.pipeline.bind(device, cmd, self.set.raw());
        self.pipeline.push(device, cmd, &PassConstants::default());
        unsafe { device.cmd_dispatch(cmd, map.width().div_ceil(8), map.height().div_ceil(8), 1) };
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW,
            Access::ANY_SHADER_READ.and(Access::COMPUTE_RW),
        );
    }
}
