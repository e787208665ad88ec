//! Collection sub-pass (paper 4.1-4.2): the prisms of all moving triangles, rasterized from
//! the light, every fragment appended to its pixel's list.

use super::coverage::CoverageMap;
use super::geometry::FrameInputs;
use super::gpu_types::{Counters, PassConstants, USE_COVERAGE};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::Result;
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, DescriptorBinding, DescriptorKind, DescriptorSet,
    Pipeline, attachmentless_pipeline, begin_attachmentless, memory_barrier,
};
use ash::vk;

pub struct CollectionPass {
    set: DescriptorSet,
    pipeline: Pipeline,
    /// Bound as the nearest map when no coverage map is built.
    placeholder: Buffer,
}

/// Every triangle's prism from the light (scene.vert, collection.geom), into `fragment`: the
/// collection pass and the coverage map's reset pass draw the same prisms.
pub(crate) fn prism_pipeline(
    ctx: &Context,
    set_layout: vk::DescriptorSetLayout,
    fragment_name: &str,
    fragment: &[u8],
) -> Result<Pipeline> {
    attachmentless_pipeline(
        ctx,
        set_layout,
        std::mem::size_of::<PassConstants>() as u32,
        &[
            (
                vk::ShaderStageFlags::VERTEX,
                "scene.vert",
                shaders::SCENE_VERT,
            ),
            (
                vk::ShaderStageFlags::GEOMETRY,
                "collection.geom",
                shaders::COLLECTION_GEOM,
            ),
            (vk::ShaderStageFlags::FRAGMENT, fragment_name, fragment),
        ],
    )
}

pub(crate) fn bindings(list: &[(u32, DescriptorKind)]) -> Vec<DescriptorBinding> {
    list.iter()
        .map(|&(binding, kind)| DescriptorBinding {
            binding,
            kind,
            stages: vk::ShaderStageFlags::ALL,
        })
        .collect()
}

impl CollectionPass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (1, Storage),
                (2, Storage),
                (3, Storage),
                (5, Storage),
                (6, Storage),
            ]),
        )?;
        let pipeline = prism_pipeline(
            ctx,
            set.layout(),
            "collection.frag",
            shaders::COLLECTION_FRAG,
        )?;
        let placeholder = Buffer::new(ctx, "no nearest map", 8, BufferUsage::Storage)?;
        Ok(Self {
            set,
            pipeline,
            placeholder,
        })
    }

    /// Records: clear the lists, draw every triangle's prism. The map's counters say
    /// afterwards whether it had room (see `TemporalShadowMap`). With `coverage`, also fills
    /// its nearest map (the extension's first pass; [`super::CoveragePass`] follows).
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        inputs: FrameInputs<'_>,
        map: &TemporalShadowMap,
        coverage: Option<&CoverageMap>,
    ) {
        let FrameInputs { frame, geometry } = inputs;
        self.set.bind(&[
            frame,
            &geometry.vertices,
            &geometry.triangles,
            &map.heads,
            &map.counters,
            coverage.map_or(&self.placeholder, |c| &c.nearest),
        ]);
        // Earlier frames may still read these lists.
        memory_barrier(
            device,
            cmd,
            Access::ANY_SHADER_READ
                .and(Access::COMPUTE_RW)
                .and(Access::FRAGMENT_RW)
                .and(Access::TRANSFER_READ),
            Access::TRANSFER_WRITE,
        );
        let counters = Counters {
            node_capacity: map.node_capacity(),
            range_capacity: map.range_capacity(),
            ..Counters::default()
        };
        unsafe {
            device.cmd_fill_buffer(cmd, map.heads.raw(), 0, vk::WHOLE_SIZE, 0);
            // SAFETY: Counters is plain data.
            let bytes: &[u8] = std::slice::from_raw_parts(
                &counters as *const Counters as *const u8,
                std::mem::size_of::<Counters>(),
            );
            device.cmd_update_buffer(cmd, map.counters.raw(), 0, bytes);
            if let Some(c) = coverage {
                device.cmd_fill_buffer(cmd, c.nearest.raw(), 0, vk::WHOLE_SIZE, u32::MAX);
            }
        }
        memory_barrier(
            device,
            cmd,
            Access::TRANSFER_WRITE,
            Access::FRAGMENT_RW.and(Access::COMPUTE_RW),
        );
        begin_attachmentless(device, cmd, map.width(), map.height());
        self.pipeline.bind(device, cmd, self.set.raw());
        let constants = PassConstants {
            flags: if coverage.is_some() { USE_COVERAGE } else { 0 },
            node_address: map.nodes.device_address(),
            ..PassConstants::default()
        };
        self.pipeline.push(device, cmd, &constants);
        unsafe {
            device.cmd_draw(cmd, 3 * geometry.triangle_count(), 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
        memory_barrier(
            device,
            cmd,
            Access::FRAGMENT_RW,
            Access::COMPUTE_RW.and(Access::FRAGMENT_RW),
        );
    }
}
