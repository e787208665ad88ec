//! One frame in flight's own objects: its command buffer, fence and acquire semaphore, its
//! draw list and temporal shadow map (each map keeps its own static layer), its timestamps,
//! and the images of the window's size (G-buffer, lit shares, shaded image) with their
//! descriptor sets. Nothing here is made per frame: the size's objects only on a resize.

use super::allocations::AllocationCounter;
use super::shade::{OUTPUT_FORMAT, ShadePass};
use anyhow::Context as _;
use ash::vk;
use motion_shadows::gpu::{Buffer, BufferUsage, Context, Image, ImageBindings, TimestampQueries};
use motion_shadows::technique::{
    DrawList, GBuffer, MaskBindings, RangeStorage, TemporalShadowMap, VisibilityMaskPass,
};

/// Timestamps a frame records (one per pass boundary).
const TIMESTAMPS: u32 = 16;

/// The objects of one window size.
pub struct SizedTargets {
    pub size: (u32, u32),
    pub gbuffer: GBuffer,
    /// The mask pass's output: each pixel's lit share of the shutter.
    pub lit: Image,
    pub mask_bindings: MaskBindings,
    pub shade_bindings: ImageBindings,
    /// The shaded 8-bit sRGB image, blitted into the swapchain's.
    pub output: Image,
}

impl SizedTargets {
    pub fn new(
        ctx: &Context,
        size: (u32, u32),
        mask: &VisibilityMaskPass,
        shade: &ShadePass,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        let (width, height) = size;
        let gbuffer = counter.counted(GBuffer::new(ctx, width, height)?);
        let lit = counter.counted(Image::new(
            ctx,
            "viewer lit shares",
            (width, height, 1),
            vk::Format::R32_SFLOAT,
            vk::ImageUsageFlags::STORAGE,
        )?);
        let mask_bindings = counter.counted(mask.bindings(ctx, size)?);
        let shade_bindings = counter.counted(shade.bindings()?);
        let output = counter.counted(Image::new(
            ctx,
            "viewer shaded image",
            (width, height, 1),
            OUTPUT_FORMAT,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
        )?);
        Ok(Self {
            size,
            gbuffer,
            lit,
            mask_bindings,
            shade_bindings,
            output,
        })
    }
}

pub struct FrameSlot {
    pub cmd: vk::CommandBuffer,
    /// Signalled when the slot's last frame completed (made signalled).
    pub fence: vk::Fence,
    /// Signalled when the acquired swapchain image may be written.
    pub acquired: vk::Semaphore,
    pub draws: DrawList,
    pub map: TemporalShadowMap,
    pub timestamps: TimestampQueries,
    pub targets: Option<SizedTargets>,
    /// The frame number last submitted from this slot, until its results were read.
    pub pending: Option<u64>,
    /// A screenshot's readback buffer, when this slot's pending frame copies one.
    pub screenshot: Option<(Buffer, (u32, u32))>,
    device: ash::Device,
}

impl FrameSlot {
    pub fn new(
        ctx: &Context,
        pool: vk::CommandPool,
        draw_count: u32,
        shadow_size: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        let device = ctx.device().clone();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd = counter.counted(unsafe { device.allocate_command_buffers(&alloc) })
            .context("vkAllocateCommandBuffers")?[0];
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        let fence = counter.counted(unsafe { device.create_fence(&signalled, None) })
            .context("vkCreateFence")?;
        let acquired = match counter
            .counted(unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) })
        {
            Ok(s) => s,
            Err(e) => {
                unsafe { device.destroy_fence(fence, None) };
                return Err(e).context("vkCreateSemaphore");
            }
        };
        // The slot owns the fence and semaphore from here on (Drop).
        let make = || -> anyhow::Result<_> {
            // Capacities start at one: the map's room is reserved before each frame from the
            // host's positions (TemporalShadowMap::reserve_for).
            let map = TemporalShadowMap::with_storage(
                ctx,
                shadow_size.0,
                shadow_size.1,
                1,
                1,
                RangeStorage::Sorted,
            )?;
            Ok((
                DrawList::new(ctx, draw_count)?,
                map,
                TimestampQueries::new(ctx, TIMESTAMPS)?,
            ))
        };
        let (draws, map, timestamps) = match make() {
            Ok(v) => v,
            Err(e) => {
                unsafe {
                    device.destroy_fence(fence, None);
                    device.destroy_semaphore(acquired, None);
                }
                return Err(e);
            }
        };
        counter.note(3);
        Ok(Self {
            cmd,
            fence,
            acquired,
            draws,
            map,
            timestamps,
            targets: None,
            pending: None,
            screenshot: None,
            device,
        })
    }
}

impl Drop for FrameSlot {
    /// The caller waited for the device; the command buffer goes with its pool.
    fn drop(&mut self) {
        unsafe {
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_semaphore(self.acquired, None);
        }
    }
}

/// The screenshot readback buffer of `size` (4 bytes a pixel).
pub fn screenshot_buffer(ctx: &Context, size: (u32, u32)) -> anyhow::Result<Buffer> {
    Ok(Buffer::new(
        ctx,
        "viewer screenshot",
        4 * u64::from(size.0) * u64::from(size.1),
        BufferUsage::Readback,
    )?)
}
