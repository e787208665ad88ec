//! Ordinary shadow maps at given times: the nearest depth (and triangle id) per pixel, one
//! layer per time. The baseline for static scenes, the brute-force reference's per-slice map,
//! and time-dependent shadow maps (one depth-only layer per time stratum).

use super::collection::bindings;
use super::geometry::FrameInputs;
use super::gpu_types::{DepthFormat, PassConstants};
use super::shaders;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, DescriptorKind, DescriptorSet, Pipeline,
    attachmentless_pipeline, begin_attachmentless, memory_barrier,
};
use ash::vk;

/// `layers` shadow maps of `width` x `height` in one buffer, layer after layer.
pub struct PlainShadowMap {
    width: u32,
    height: u32,
    layers: u32,
    format: DepthFormat,
    pub depths: Buffer,
}

impl PlainShadowMap {
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        layers: u32,
        format: DepthFormat,
    ) -> Result<Self> {
        let count = width as u64 * height as u64 * layers.max(1) as u64;
        let bytes = count * format.bytes();
        if bytes > ctx.max_buffer_bytes() {
            return Err(Error::DeviceLimit {
                what: "the ordinary shadow maps",
                count,
                element_bytes: format.bytes(),
                needed_bytes: bytes,
                limit_bytes: ctx.max_buffer_bytes(),
            });
        }
        Ok(Self {
            width,
            height,
            layers: layers.max(1),
            format,
            depths: Buffer::new(ctx, "ordinary shadow maps", bytes, BufferUsage::Storage)?,
        })
    }
    pub fn layers(&self) -> u32 {
        self.layers
    }
    pub fn format(&self) -> DepthFormat {
        self.format
    }
    /// Bytes of the maps' texels (the papers' figure for TSM: layers x 4 x pixels).
    pub fn bytes(&self) -> u64 {
        self.depths.size()
    }
}

pub struct PlainShadowPass {
    set: DescriptorSet,
    pipeline: Pipeline,
}

impl PlainShadowPass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let set = DescriptorSet::new(
            ctx,
            &bindings(&[(0, Uniform), (1, Storage), (3, Storage), (4, Storage)]),
        )?;
        let pipeline = attachmentless_pipeline(
            ctx,
            set.layout(),
            std::mem::size_of::<PassConstants>() as u32,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "shadow_depth.vert",
                    shaders::SHADOW_DEPTH_VERT,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "shadow_depth.frag",
                    shaders::SHADOW_DEPTH_FRAG,
                ),
            ],
        )?;
        Ok(Self { set, pipeline })
    }

    /// Renders layer i of `map` at `times[i]`.
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        inputs: FrameInputs<'_>,
        map: &PlainShadowMap,
        times: &[f32],
    ) {
        let FrameInputs { frame, geometry } = inputs;
        self.set
            .bind(&[frame, &geometry.vertices, &map.depths, &map.depths]);
        memory_barrier(
            device,
            cmd,
            Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW),
            Access::TRANSFER_WRITE,
        );
        unsafe { device.cmd_fill_buffer(cmd, map.depths.raw(), 0, vk::WHOLE_SIZE, u32::MAX) };
        memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::FRAGMENT_RW);
        begin_attachmentless(device, cmd, map.width, map.height);
        self.pipeline.bind(device, cmd, self.set.raw());
        for (layer, &t) in times.iter().enumerate().take(map.layers as usize) {
            let constants = PassConstants {
                first_sample: layer as u32,
                mode: map.format as u32,
                time: t,
                ..PassConstants::default()
            };
            self.pipeline.push(device, cmd, &constants);
            unsafe { device.cmd_draw(cmd, 3 * geometry.triangle_count(), 1, 0, 0) };
        }
        unsafe { device.cmd_end_rendering(cmd) };
        memory_barrier(device, cmd, Access::FRAGMENT_RW, Access::ANY_SHADER_READ);
    }
}
