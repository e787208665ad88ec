//! One frame in flight's own objects: its command buffer, fence and acquire semaphore, its
//! scene geometry (rewritten in place when the animation moves), draw list and temporal
//! shadow map (each map keeps its own static layer), TSM's maps once that method is shown,
//! its timestamps and overlay, and the images of the window's size (G-buffer, lit shares,
//! shaded image) with their descriptor sets. Nothing here is made per frame: the size's
//! objects only on a resize, TSM's on the first switch to it.

use super::allocations::AllocationCounter;
use super::method::ViewMethod;
use super::overlay::{OVERLAY_HEIGHT, OVERLAY_WIDTH};
use super::shade::{OUTPUT_FORMAT, ShadePass};
use crate::render::upload::{SceneGeometry, flatten, scene_draws};
use crate::scene::Scene;
use anyhow::Context as _;
use ash::vk;
use motion_shadows::gpu::{Buffer, BufferUsage, Context, Image, ImageBindings, TimestampQueries};
use motion_shadows::technique::{
    DrawList, EngineTsmBindings, EngineTsmMap, GBuffer, LightingImageOutput, LightingTarget,
    MaskBindings, RangeStorage, TemporalShadowMap, VisibilityMaskPass,
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
    /// The stochastic frame's radiance (RGBA32F), which the shading reads in that frame.
    pub radiance: Image,
    /// The split view's right-hand method's lit shares and its mask's bindings (made with
    /// the size, so that toggling the split allocates no image).
    pub split_lit: Image,
    pub split_mask_bindings: MaskBindings,
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
        let radiance = counter.counted(Image::new(
            ctx,
            "viewer stochastic radiance",
            (width, height, 1),
            vk::Format::R32G32B32A32_SFLOAT,
            vk::ImageUsageFlags::STORAGE,
        )?);
        let split_lit = counter.counted(Image::new(
            ctx,
            "viewer split lit shares",
            (width, height, 1),
            vk::Format::R32_SFLOAT,
            vk::ImageUsageFlags::STORAGE,
        )?);
        let split_mask_bindings = counter.counted(mask.bindings(ctx, size)?);
        Ok(Self {
            size,
            gbuffer,
            lit,
            mask_bindings,
            shade_bindings,
            output,
            radiance,
            split_lit,
            split_mask_bindings,
        })
    }
}

/// The stochastic frame's lighting target of one slot (its size and samples) and the
/// descriptor set that writes it into the radiance image.
pub struct LightingTargets {
    pub target: LightingTarget,
    pub bindings: ImageBindings,
    pub size: (u32, u32),
    pub spp: u32,
}

/// TSM's maps of one slot, drawn `layers` at a time.
pub struct TsmTargets {
    pub map: EngineTsmMap,
    pub bindings: EngineTsmBindings,
}

/// TSM maps drawn per batch (as the offline deferred frame draws them).
pub const TSM_LAYERS_PER_BATCH: u32 = 8;

/// The split view's right-hand method's maps in one slot (made on its first split frame):
/// its own temporal map (the left one may be built for another lookup) and TSM's maps.
pub struct SplitSide {
    pub map: TemporalShadowMap,
    pub tsm: Option<TsmTargets>,
    /// The right-hand method of the slot's last split frame.
    pub last_method: Option<ViewMethod>,
}

/// A submitted frame whose results are still to be read.
pub struct Pending {
    pub frame: u64,
    pub method: ViewMethod,
    /// The stochastic frame (else the deferred one).
    pub stochastic: bool,
    /// The split view's right-hand method.
    pub split: Option<ViewMethod>,
}

impl SplitSide {
    pub fn new(
        ctx: &Context,
        shadow_size: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        Ok(Self {
            map: counter.counted(empty_map(ctx, shadow_size)?),
            tsm: None,
            last_method: None,
        })
    }
}

/// A temporal map with room for one range: its room is reserved before each frame from the
/// host's positions (`super::room`).
fn empty_map(ctx: &Context, shadow_size: (u32, u32)) -> anyhow::Result<TemporalShadowMap> {
    Ok(TemporalShadowMap::with_storage(
        ctx,
        shadow_size.0,
        shadow_size.1,
        1,
        1,
        RangeStorage::Sorted,
    )?)
}

pub struct FrameSlot {
    pub cmd: vk::CommandBuffer,
    /// Signalled when the slot's last frame completed (made signalled).
    pub fence: vk::Fence,
    /// Signalled when the acquired swapchain image may be written.
    pub acquired: vk::Semaphore,
    /// The scene's vertices as this slot last wrote them, and its draws reading them.
    pub geometry: SceneGeometry,
    /// The scene version `geometry` holds.
    pub scene_version: u64,
    pub draws: DrawList,
    draw_capacity: u32,
    pub map: TemporalShadowMap,
    /// Made on the first frame of a TSM method.
    pub tsm: Option<TsmTargets>,
    /// Made on the first split frame.
    pub split: Option<SplitSide>,
    /// Made on the first stochastic frame (again after a resize).
    pub lighting: Option<LightingTargets>,
    pub timestamps: TimestampQueries,
    /// The overlay's codes (`overlay.rs`), written each frame it is shown.
    pub overlay: Buffer,
    pub targets: Option<SizedTargets>,
    /// The method of the slot's last frame (its maps were prepared for it).
    pub last_method: Option<ViewMethod>,
    /// The frame last submitted from this slot, until its results were read.
    pub pending: Option<Pending>,
    /// A screenshot's readback buffer, when this slot's pending frame copies one.
    pub screenshot: Option<(Buffer, (u32, u32))>,
    device: ash::Device,
}

impl FrameSlot {
    pub fn new(
        ctx: &Context,
        pool: vk::CommandPool,
        scene: &Scene,
        shadow_size: (u32, u32),
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<Self> {
        let device = ctx.device().clone();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: `pool` is the caller's, of this device, used from this thread only; the
        // buffer is freed with the pool (the frame loop drops the slots first).
        let cmd = counter
            .counted(unsafe { device.allocate_command_buffers(&alloc) })
            .context("vkAllocateCommandBuffers")?[0];
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: the context's device is alive; the fence is destroyed in Drop (or below on
        // error).
        let fence = counter
            .counted(unsafe { device.create_fence(&signalled, None) })
            .context("vkCreateFence")?;
        // SAFETY: as for the fence.
        let acquired = match counter
            .counted(unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) })
        {
            Ok(s) => s,
            Err(e) => {
                // SAFETY: the fence was just made, is of this device and was never submitted.
                unsafe { device.destroy_fence(fence, None) };
                return Err(e).context("vkCreateSemaphore");
            }
        };
        // The slot owns the fence and semaphore from here on (Drop).
        let make = || -> anyhow::Result<_> {
            let map = empty_map(ctx, shadow_size)?;
            let geometry = SceneGeometry::upload(ctx, scene)?;
            Ok((
                DrawList::new(ctx, geometry.draws.len() as u32)?,
                map,
                TimestampQueries::new(ctx, TIMESTAMPS)?,
                Buffer::new(
                    ctx,
                    "viewer overlay",
                    4 * u64::from(OVERLAY_WIDTH * OVERLAY_HEIGHT),
                    BufferUsage::HostToDevice,
                )?,
                geometry,
            ))
        };
        let (draws, map, timestamps, overlay, geometry) = match make() {
            Ok(v) => v,
            Err(e) => {
                // SAFETY: both were just made on this device and never submitted.
                unsafe {
                    device.destroy_fence(fence, None);
                    device.destroy_semaphore(acquired, None);
                }
                return Err(e);
            }
        };
        counter.note(5);
        Ok(Self {
            draw_capacity: (geometry.draws.len() as u32).max(1),
            cmd,
            fence,
            acquired,
            geometry,
            scene_version: 0,
            draws,
            map,
            tsm: None,
            split: None,
            lighting: None,
            timestamps,
            overlay,
            targets: None,
            last_method: None,
            pending: None,
            screenshot: None,
            device,
        })
    }

    /// Writes `scene`'s vertices (version `version`) into the slot's buffer, in place when
    /// their count is unchanged (else a new buffer, counted), and its draws.
    pub fn update_geometry(
        &mut self,
        ctx: &Context,
        scene: &Scene,
        version: u64,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<()> {
        if self.scene_version == version {
            return Ok(());
        }
        let vertices = flatten(scene);
        let bytes = std::mem::size_of_val(vertices.as_slice()) as u64;
        if bytes == 0 || bytes > self.geometry.vertices.size() {
            self.geometry = counter.counted(SceneGeometry::upload(ctx, scene)?);
        } else {
            self.geometry.vertices.write(&vertices)?;
            self.geometry.draws = scene_draws(scene, &self.geometry.vertices)?;
        }
        let needed = self.geometry.draws.len() as u32;
        if needed > self.draw_capacity {
            self.draws = counter.counted(DrawList::new(ctx, needed)?);
            self.draw_capacity = needed;
        }
        self.scene_version = version;
        Ok(())
    }

    /// Bytes of the slot's shadow maps: the temporal map, TSM's, the split side's.
    pub fn map_bytes(&self) -> u64 {
        let tsm = |t: &Option<TsmTargets>| t.as_ref().map_or(0, |t| t.map.bytes());
        self.map.allocated_bytes()
            + tsm(&self.tsm)
            + self
                .split
                .as_ref()
                .map_or(0, |s| s.map.allocated_bytes() + tsm(&s.tsm))
    }

    /// The stochastic frame's target for `size` and `spp`, made (counted) on first use and
    /// when either changed.
    pub fn lighting_targets(
        &mut self,
        ctx: &Context,
        output: &LightingImageOutput,
        size: (u32, u32),
        spp: u32,
        counter: &mut AllocationCounter,
    ) -> anyhow::Result<()> {
        if self
            .lighting
            .as_ref()
            .is_some_and(|l| l.size == size && l.spp == spp)
        {
            return Ok(());
        }
        self.lighting = None;
        let target = counter.counted(LightingTarget::new(
            ctx,
            size.0,
            size.1,
            spp,
            motion_shadows::technique::MAX_SAMPLES_PER_CHUNK,
        )?);
        let bindings = counter.counted(output.bindings()?);
        self.lighting = Some(LightingTargets {
            target,
            bindings,
            size,
            spp,
        });
        Ok(())
    }
}

impl Drop for FrameSlot {
    /// The caller waited for the device; the command buffer goes with its pool.
    fn drop(&mut self) {
        // SAFETY: the fence and semaphore are this device's, destroyed once; the frame loop
        // drops its slots only after waiting for the device to be idle (or, when its start
        // failed, before any submission), so no submission or acquire uses them.
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

/// TSM's maps in `tsm` for `maps` maps of `shadow_size`, made (counted) on first use or when
/// the batch size changes.
pub fn tsm_targets(
    tsm: &mut Option<TsmTargets>,
    ctx: &Context,
    pass: &motion_shadows::technique::EngineTsmPass,
    shadow_size: (u32, u32),
    maps: u32,
    counter: &mut AllocationCounter,
) -> anyhow::Result<()> {
    let layers = TSM_LAYERS_PER_BATCH.min(maps);
    if tsm.as_ref().is_some_and(|t| t.map.layers() == layers) {
        return Ok(());
    }
    *tsm = None;
    let map = counter.counted(EngineTsmMap::new(
        ctx,
        shadow_size.0,
        shadow_size.1,
        layers,
        motion_shadows::technique::TsmStart::Copy,
    )?);
    let bindings = counter.counted(pass.bindings()?);
    *tsm = Some(TsmTargets { map, bindings });
    Ok(())
}
