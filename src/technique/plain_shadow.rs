//! Ordinary shadow maps at given times: the nearest depth (and triangle id) per pixel, one
//! layer per time. The baseline for static scenes, the brute-force reference's per-slice map,
//! and time-dependent shadow maps (one depth-only layer per time stratum).

use super::collection::{PUSH_BYTES, draw_each};
use super::draws::DrawList;
use super::gpu_types::{DepthFormat, PassConstants, PlainMapHeader};
use super::shaders;
use super::view::LightView;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, Pipeline, attachmentless_pipeline, begin_attachmentless,
    memory_barrier,
};
use ash::vk;
use glam::UVec4;

/// `layers` shadow maps of `width` x `height` in one buffer, layer after layer.
pub struct PlainShadowMap {
    width: u32,
    height: u32,
    layers: u32,
    format: DepthFormat,
    /// The header (`PlainHeader` in shared.glsl): light, size and the depths' address.
    pub header: Buffer,
    /// The layers' texels.
    pub depths: Buffer,
}

impl PlainShadowMap {
    /// `layers` maps of `width` x `height` texels of `format` (one per frame in flight).
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        layers: u32,
        format: DepthFormat,
    ) -> Result<Self> {
        let count = width as u64 * height as u64 * layers.max(1) as u64;
        let bytes = count * format.bytes();
        let limit = ctx.max_addressed_buffer_bytes();
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "shadow map size {width}x{height}"
            )));
        }
        if bytes > limit {
            return Err(Error::DeviceLimit {
                what: "the ordinary shadow maps",
                count,
                element_bytes: format.bytes(),
                needed_bytes: bytes,
                limit_bytes: limit,
            });
        }
        Ok(Self {
            width,
            height,
            layers: layers.max(1),
            format,
            header: Buffer::new(
                ctx,
                "ordinary shadow map header",
                std::mem::size_of::<PlainMapHeader>() as u64,
                BufferUsage::Storage,
            )?,
            depths: Buffer::new(ctx, "ordinary shadow maps", bytes, BufferUsage::Storage)?,
        })
    }
    /// Maps in the buffer.
    pub fn layers(&self) -> u32 {
        self.layers
    }
    /// What each texel holds.
    pub fn format(&self) -> DepthFormat {
        self.format
    }
    /// The device address of the header.
    pub fn header_address(&self) -> u64 {
        self.header.device_address()
    }
    /// Bytes of the maps' texels (the papers' figure for TSM: layers x 4 x pixels).
    pub fn bytes(&self) -> u64 {
        self.depths.size()
    }
}

/// Renders ordinary shadow maps. Immutable after creation.
pub struct PlainShadowPass {
    pipeline: Pipeline,
}

impl PlainShadowPass {
    /// Creates the pipeline (vertex and fragment shader, no attachments).
    pub fn new(ctx: &Context) -> Result<Self> {
        let pipeline = attachmentless_pipeline(
            ctx,
            PUSH_BYTES,
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
        Ok(Self { pipeline })
    }

    /// Renders layer i of `map` with the scene at `times[i]`, seen from `light`.
    ///
    /// # Safety
    /// As [`super::CollectionPass::record`] (for `map` instead of a temporal map).
    ///
    /// Synchronization: waits for earlier shader reads and fragment writes of the map;
    /// leaves its texels written by the fragment stage and visible to shader reads in every
    /// stage. State changed: the bound graphics pipeline, push constants, viewport, scissor.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &PlainShadowMap,
        times: &[f32],
    ) {
        let header = PlainMapHeader {
            light: light.gpu(),
            size: UVec4::new(map.width, map.height, map.layers, map.format as u32),
            depths: map.depths.device_address(),
            reserved: 0,
        };
        memory_barrier(
            device,
            cmd,
            Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW),
            Access::TRANSFER_WRITE,
        );
        unsafe {
            map.header.record_write(device, cmd, &[header]);
            // Empty texels: a NaN depth (and, with ids, no triangle). Depth-only maps keep the
            // signed minimum (see shadow_depth.frag), so their empty value is the largest int.
            let empty = match map.format {
                DepthFormat::DepthOnly => 0x7fff_ffff,
                DepthFormat::DepthAndId => u32::MAX,
            };
            device.cmd_fill_buffer(cmd, map.depths.raw(), 0, vk::WHOLE_SIZE, empty);
        }
        memory_barrier(
            device,
            cmd,
            Access::TRANSFER_WRITE,
            Access::ANY_SHADER_READ.and(Access::FRAGMENT_RW),
        );
        begin_attachmentless(device, cmd, map.width, map.height);
        self.pipeline.bind(device, cmd);
        for (layer, &t) in times.iter().enumerate().take(map.layers as usize) {
            let constants = PassConstants {
                map: map.header_address(),
                first_sample: layer as u32,
                mode: map.format as u32,
                time: t,
                ..PassConstants::default()
            };
            draw_each(device, cmd, &self.pipeline, draws, constants);
        }
        unsafe { device.cmd_end_rendering(cmd) };
        memory_barrier(device, cmd, Access::FRAGMENT_RW, Access::ANY_SHADER_READ);
    }
}
