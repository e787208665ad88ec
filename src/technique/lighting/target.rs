//! Where the lighting pass renders: the visibility buffer of one chunk of samples, the
//! accumulated radiance, and their readback.

use super::MAX_SAMPLES_PER_CHUNK;
use crate::error::{Error, Result};
use crate::gpu::{Access, Buffer, BufferUsage, Context, memory_barrier};
use crate::technique::gpu_types::{CameraParams, GpuCameraEnd};
use ash::vk;

/// The visibility buffer's size above which a frame's samples are split into more chunks
/// (16 samples of 1024x768 take 96 MiB; at 4096x4096 one chunk holds 2 samples).
const VISIBILITY_BUDGET_BYTES: u64 = 256 << 20;

/// Where the lighting pass renders: the per-sample visibility buffer of one chunk and the
/// accumulated linear radiance (RGBA32F per pixel; alpha: the share of samples that see a
/// moving triangle). One per frame in flight.
pub struct LightingTarget {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) spp: u32,
    pub(super) samples_per_chunk: u32,
    /// The header (`CameraParams`): camera, sampling and this target's buffer addresses.
    pub(crate) header: Buffer,
    /// Per pixel and sample of a chunk: the nearest hit (depth bits << 32 | triangle id).
    pub(crate) visibility: Buffer,
    /// Per pixel: accumulated radiance (rgb) and moving share (a).
    pub(crate) radiance: Buffer,
    /// u32: triangles the lighting pass dropped for an invalid index.
    pub(crate) counters: Buffer,
    readback: Buffer,
    counters_readback: Buffer,
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
        let limit = ctx.max_addressed_buffer_bytes();
        // Each buffer is checked with its own figures, so the error names what does not fit.
        for (what, element_bytes) in [
            ("the radiance buffer (RGBA32F per pixel)", 16),
            ("the visibility buffer (one 8-byte sample per pixel)", 8),
        ] {
            if pixels * element_bytes > limit {
                return Err(Error::DeviceLimit {
                    what,
                    count: pixels,
                    element_bytes,
                    needed_bytes: pixels * element_bytes,
                    limit_bytes: limit,
                });
            }
        }
        // Samples per chunk: as many as fit the budget (large images take several chunks
        // rather than one huge visibility buffer), at least one.
        let budget = limit.min(VISIBILITY_BUDGET_BYTES).max(pixels * 8);
        let fit = (budget / (pixels * 8)).min(MAX_SAMPLES_PER_CHUNK as u64) as u32;
        let samples_per_chunk = spp.min(max_samples_per_chunk).clamp(1, fit);
        Ok(Self {
            width,
            height,
            spp,
            samples_per_chunk,
            header: Buffer::new(
                ctx,
                "lighting target header",
                // Room for a moving camera's pose at t = 1 after the header.
                (std::mem::size_of::<CameraParams>() + std::mem::size_of::<GpuCameraEnd>()) as u64,
                BufferUsage::Storage,
            )?,
            counters: Buffer::new(ctx, "lighting counters", 8, BufferUsage::Storage)?,
            counters_readback: Buffer::new(
                ctx,
                "lighting counters readback",
                8,
                BufferUsage::Readback,
            )?,
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

    pub(super) fn readback(&self) -> &Buffer {
        &self.readback
    }

    pub(super) fn counters_readback(&self) -> &Buffer {
        &self.counters_readback
    }

    /// Samples per pixel the target was made for (every one shares the pixel's average).
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Samples per pixel one geometry pass handles.
    pub fn samples_per_chunk(&self) -> u32 {
        self.samples_per_chunk
    }

    /// Pixels across.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Pixels down.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Records the copy that [`Self::read_rgb`] and [`Self::read_moving_coverage`] read after the submission completes.
    ///
    /// # Safety
    /// `cmd` was allocated from the target's device, is recording, outside any render pass,
    /// after the lighting pass of the frame.
    ///
    /// Synchronization: waits for the compute stage's radiance writes; leaves the copies
    /// visible to host reads once the submission's fence has signalled.
    pub unsafe fn record_readback(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is of the target's device, recording outside any render pass (the
        // contract), on the lighting pass's compute queue, so compute and transfer stages are
        // supported.
        unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_READ) };
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: self.radiance.size(),
        }];
        let counter = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: 8,
        }];
        // SAFETY: the radiance and its readback buffer are the target's own, made with the same
        // size, and the counters' 8 bytes lie within both counter buffers; the radiance writes were
        // made visible to transfer reads just above, and all four buffers live as long as the
        // target (dropping retires them past pending frames).
        unsafe {
            device.cmd_copy_buffer(cmd, self.radiance.raw(), self.readback.raw(), &region);
            device.cmd_copy_buffer(
                cmd,
                self.counters.raw(),
                self.counters_readback.raw(),
                &counter,
            );
        }
        // SAFETY: the same command buffer, outside rendering; host reads are a valid destination
        // once the fence signals.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
    }

    /// Triangles the frame's lighting pass dropped because an index pointed past their draw's
    /// vertex count (read after the submission of [`Self::record_readback`] completed).
    pub fn read_invalid_triangles(&self) -> Result<u32> {
        Ok(self.counters_readback.read::<u32>(2)?[0])
    }

    /// Pixels whose shadow lookups ran so many loop iterations that a device with a loop
    /// limit ([`crate::gpu::DeviceInfo::shader_loop_limit`]) may have cut them short (read
    /// like [`Self::read_invalid_triangles`]). Always 0 on devices without such a limit. When
    /// it is not 0, render again with fewer samples per chunk (each invocation then shades
    /// fewer samples); at one sample per chunk it means the map's lists are too long there
    /// for this device.
    pub fn read_over_budget_pixels(&self) -> Result<u32> {
        Ok(self.counters_readback.read::<u32>(2)?[1])
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
