//! Lighting pass (paper 3.3, McGuire et al. 2010): stochastic rasterization from the camera
//! into a sample-level visibility buffer, then shading and the shadow test per sample.
//!
//! Why a visibility buffer and not MSAA: lavapipe offers at most 4 samples per pixel, and the
//! papers use 8 to 20. Keeping the nearest (distance, triangle) per sample with a 64-bit
//! atomicMin lets one geometry pass serve as many samples as fit in a storage buffer, and
//! shading runs once per visible sample instead of once per covering fragment.

use super::collection::bindings;
use super::coverage::CoverageMap;
use super::geometry::FrameInputs;
use super::gpu_types::{FIXED_TIME, PassConstants, ShadowMode};
use super::plain_shadow::PlainShadowMap;
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, DescriptorKind, DescriptorSet, Pipeline,
    TimestampQueries, attachmentless_pipeline, begin_attachmentless, compute_pipeline,
    memory_barrier,
};
use ash::vk;

/// The most samples one geometry pass handles (bounded further by the device's buffer limit).
pub const MAX_SAMPLES_PER_CHUNK: u32 = 16;

/// Where the lighting pass renders: the per-sample visibility buffer of one chunk and the
/// accumulated linear radiance (RGBA32F per pixel; alpha unused).
pub struct LightingTarget {
    width: u32,
    height: u32,
    spp: u32,
    samples_per_chunk: u32,
    pub visibility: Buffer,
    pub radiance: Buffer,
    readback: Buffer,
}

impl LightingTarget {
    /// A target for `spp` samples per pixel, handling up to `max_samples_per_chunk` (at most
    /// [`MAX_SAMPLES_PER_CHUNK`], and what the device's buffer limit allows) per geometry pass.
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        spp: u32,
        max_samples_per_chunk: u32,
    ) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "image size {width}x{height}"
            )));
        }
        let pixels = width as u64 * height as u64;
        let limit = ctx.max_buffer_bytes();
        let fit = (limit / (pixels * 8)).min(MAX_SAMPLES_PER_CHUNK as u64) as u32;
        if fit == 0 || pixels * 16 > limit {
            return Err(Error::DeviceLimit {
                what: "the visibility buffer (one 8-byte sample per pixel)",
                count: pixels,
                element_bytes: 8,
                needed_bytes: pixels * 8,
                limit_bytes: limit,
            });
        }
        let samples_per_chunk = spp.min(max_samples_per_chunk).clamp(1, fit);
        Ok(Self {
            width,
            height,
            spp,
            samples_per_chunk,
            visibility: Buffer::new(
                ctx,
                "visibility",
                pixels * 8 * samples_per_chunk as u64,
                BufferUsage::Storage,
            )?,
            radiance: Buffer::new(ctx, "radiance", pixels * 16, BufferUsage::Storage)?,
            readback: Buffer::new(ctx, "radiance readback", pixels * 16, BufferUsage::Readback)?,
        })
    }

    /// Samples per pixel the target was made for (every one shares the pixel's average).
    pub fn spp(&self) -> u32 {
        self.spp
    }

    pub fn samples_per_chunk(&self) -> u32 {
        self.samples_per_chunk
    }

    /// Records the copy that [`Self::read_rgb`] and [`Self::read_moving_coverage`] read after the submission completes.
    pub fn record_readback(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_READ);
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: self.radiance.size(),
        }];
        unsafe { device.cmd_copy_buffer(cmd, self.radiance.raw(), self.readback.raw(), &region) };
        memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
    }

    /// Linear radiance, 3 floats per pixel, top row first.
    pub fn read_rgb(&self) -> Result<Vec<f32>> {
        let rgba = self
            .readback
            .read::<f32>((self.width * self.height * 4) as usize)?;
        Ok(rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect())
    }

    /// Per pixel, the share of its samples that see a moving triangle.
    pub fn read_moving_coverage(&self) -> Result<Vec<f32>> {
        let rgba = self
            .readback
            .read::<f32>((self.width * self.height * 4) as usize)?;
        Ok(rgba.chunks_exact(4).map(|p| p[3]).collect())
    }
}

/// What the lighting pass tests shadows against.
#[derive(Clone, Copy)]
pub enum ShadowSource<'a> {
    Temporal(&'a TemporalShadowMap),
    /// Layer 0 of an ordinary shadow map with ids ([`super::DepthFormat::DepthAndId`]), for every
    /// sample.
    Plain(&'a PlainShadowMap),
    /// A temporal shadow map generated with a coverage map, and that map.
    Coverage(&'a TemporalShadowMap, &'a CoverageMap),
    /// Time-dependent shadow maps: one depth-only layer per time stratum (as many layers as
    /// samples per pixel); a sample tests the layer of its stratum.
    TimeDependent(&'a PlainShadowMap),
    None,
}

pub struct LightingPass {
    raster_set: DescriptorSet,
    raster: Pipeline,
    resolve_set: DescriptorSet,
    resolve: Pipeline,
    /// Bound where a shadow source is not used, so every binding is always valid.
    placeholder: Buffer,
}

impl LightingPass {
    pub fn new(ctx: &Context) -> Result<Self> {
        use DescriptorKind::{Storage, Uniform};
        let push = std::mem::size_of::<PassConstants>() as u32;
        let raster_set = DescriptorSet::new(
            ctx,
            &bindings(&[(0, Uniform), (1, Storage), (2, Storage), (3, Storage)]),
        )?;
        let raster = attachmentless_pipeline(
            ctx,
            raster_set.layout(),
            push,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "scene.vert",
                    shaders::SCENE_VERT,
                ),
                (
                    vk::ShaderStageFlags::GEOMETRY,
                    "lighting.geom",
                    shaders::LIGHTING_GEOM,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "lighting.frag",
                    shaders::LIGHTING_FRAG,
                ),
            ],
        )?;
        let resolve_set = DescriptorSet::new(
            ctx,
            &bindings(&[
                (0, Uniform),
                (1, Storage),
                (2, Storage),
                (3, Storage),
                (4, Storage),
                (5, Storage),
                (7, Storage),
                (8, Storage),
                (9, Storage),
                (10, Storage),
            ]),
        )?;
        let resolve = compute_pipeline(
            ctx,
            resolve_set.layout(),
            push,
            "resolve.comp",
            shaders::RESOLVE_COMP,
        )?;
        let placeholder = Buffer::new(ctx, "placeholder", 64, BufferUsage::Storage)?;
        Ok(Self {
            raster_set,
            raster,
            resolve_set,
            resolve,
            placeholder,
        })
    }

    /// Records the whole lighting pass for the target's samples per pixel (as many chunks as the
    /// target needs), leaving the averaged radiance in `target.radiance`. The shadow source
    /// must have been recorded earlier in the same or an earlier submission. With `timestamps`,
    /// marks "lighting raster" and "lighting shade" after each chunk's two halves.
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        inputs: FrameInputs<'_>,
        shadow: ShadowSource<'_>,
        target: &LightingTarget,
        mut timestamps: Option<&mut TimestampQueries>,
    ) {
        self.record_clear(device, cmd, target);
        let mut first = 0;
        while first < target.spp {
            let count = target.samples_per_chunk.min(target.spp - first);
            let samples = Samples {
                first,
                count,
                fixed_time: None,
            };
            self.record_samples(
                device,
                cmd,
                inputs,
                shadow,
                target,
                samples,
                timestamps.as_deref_mut(),
            );
            first += count;
        }
    }

    /// Zeroes the target's radiance, before a frame's first [`Self::record_samples`].
    pub fn record_clear(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        target: &LightingTarget,
    ) {
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW.and(Access::TRANSFER_READ),
            Access::TRANSFER_WRITE,
        );
        unsafe { device.cmd_fill_buffer(cmd, target.radiance.raw(), 0, vk::WHOLE_SIZE, 0) };
        memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_RW);
    }

    /// Renders one chunk of samples (at most the target's samples per chunk) and adds their
    /// share (1/spp each) to the target's radiance.
    #[allow(clippy::too_many_arguments)]
    pub fn record_samples(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        inputs: FrameInputs<'_>,
        shadow: ShadowSource<'_>,
        target: &LightingTarget,
        samples: Samples,
        mut timestamps: Option<&mut TimestampQueries>,
    ) {
        let FrameInputs { frame, geometry } = inputs;
        let p = &self.placeholder;
        let (mode, range_heads, ranges, plain, tsm, coverage, cover_depth) = match shadow {
            ShadowSource::Temporal(map) => (
                ShadowMode::Temporal,
                &map.range_heads,
                &map.ranges,
                p,
                p,
                p,
                p,
            ),
            ShadowSource::Coverage(map, cover) => (
                ShadowMode::Coverage,
                &map.range_heads,
                &map.ranges,
                p,
                p,
                &cover.coverage,
                &cover.cover_depth,
            ),
            ShadowSource::Plain(map) => (ShadowMode::Plain, p, p, &map.depths, p, p, p),
            ShadowSource::TimeDependent(maps) => (ShadowMode::Tsm, p, p, p, &maps.depths, p, p),
            ShadowSource::None => (ShadowMode::None, p, p, p, p, p, p),
        };
        self.raster_set.bind(&[
            frame,
            &geometry.vertices,
            &geometry.triangles,
            &target.visibility,
        ]);
        self.resolve_set.bind(&[
            frame,
            &geometry.vertices,
            &geometry.triangles,
            &target.visibility,
            &target.radiance,
            range_heads,
            plain,
            tsm,
            coverage,
            cover_depth,
        ]);
        let count = samples.count.clamp(1, target.samples_per_chunk);
        let constants = PassConstants {
            first_sample: samples.first,
            sample_count: count,
            mode: mode as u32,
            time: samples.fixed_time.unwrap_or(0.0),
            flags: if samples.fixed_time.is_some() {
                FIXED_TIME
            } else {
                0
            },
            range_address: ranges.device_address(),
            ..PassConstants::default()
        };
        // The previous chunk's resolve read the visibility buffer.
        memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_WRITE);
        unsafe {
            device.cmd_fill_buffer(cmd, target.visibility.raw(), 0, vk::WHOLE_SIZE, u32::MAX)
        };
        memory_barrier(
            device,
            cmd,
            Access::TRANSFER_WRITE,
            Access::FRAGMENT_RW.and(Access::COMPUTE_RW),
        );
        begin_attachmentless(device, cmd, target.width, target.height);
        self.raster.bind(device, cmd, self.raster_set.raw());
        self.raster.push(device, cmd, &constants);
        unsafe {
            device.cmd_draw(cmd, 3 * geometry.triangle_count(), 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
        if let Some(ts) = timestamps.as_deref_mut() {
            ts.mark(cmd, "lighting raster");
        }
        memory_barrier(device, cmd, Access::FRAGMENT_RW, Access::COMPUTE_RW);
        self.resolve.bind(device, cmd, self.resolve_set.raw());
        self.resolve.push(device, cmd, &constants);
        unsafe { device.cmd_dispatch(cmd, target.width.div_ceil(8), target.height.div_ceil(8), 1) };
        if let Some(ts) = timestamps {
            ts.mark(cmd, "lighting shade");
        }
        memory_barrier(
            device,
            cmd,
            Access::COMPUTE_RW,
            Access::COMPUTE_RW.and(Access::TRANSFER_READ),
        );
    }
}

/// Which samples [`LightingPass::record_samples`] renders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Samples {
    pub first: u32,
    pub count: u32,
    /// Every sample at this time instead of its own stratified time (reference slices).
    pub fixed_time: Option<f32>,
}
