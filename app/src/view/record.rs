//! One frame's commands, recorded into the slot's command buffer the way a deferred engine
//! records its frame: the draw list's update, the G-buffer, the library's shadow pass
//! (collection and generation) and visibility mask (receivers moving), or TSM's maps and
//! lookups, the viewer's shading (with the overlay), and the blit into the acquired
//! swapchain image (with a copy back for a screenshot).

use super::frame_slot::{FrameSlot, TsmTargets};
use super::shade::{ShadeFrame, ShadePass};
use ash::vk;
use glam::Mat4;
use motion_shadows::gpu::{Access, TimestampQueries, image_barrier, memory_barrier};
use motion_shadows::technique::{
    CollectionPass, DrawList, EngineTsmPass, GBufferCamera, GBufferPass, GenerationPass, LightView,
    LightingImageOutput, LightingPass, LightingView, MaskBindings, MaskInputs, ShadowSource,
    TemporalShadowMap, VisibilityMaskPass,
};

/// The library's passes and the viewer's shading, made once.
pub struct Passes {
    pub gbuffer: GBufferPass,
    pub collection: CollectionPass,
    pub generation: GenerationPass,
    pub mask: VisibilityMaskPass,
    pub shade: ShadePass,
}

/// What the frame shows.
pub struct FrameView<'a> {
    pub light: &'a LightView,
    pub view_proj: Mat4,
    pub eye: glam::Vec3,
    /// The shutter time the G-buffer shows.
    pub camera_time: f32,
    pub moving_receivers: bool,
    /// Still pixels take the plane test (as the offline deferred frame decides).
    pub plane_test_where_still: bool,
    pub exposure: f32,
    /// The overlay's codes and grid size, if shown.
    pub overlay: Option<(u64, (u32, u32))>,
    /// TSM's pass and its number of maps, for TSM methods (else the temporal map's passes).
    pub tsm: Option<(&'a EngineTsmPass, u32)>,
    /// The stochastic frame instead of the deferred one: the lighting pass, its output into
    /// the radiance image, and the camera's samples.
    pub stochastic: Option<(&'a LightingPass, &'a LightingImageOutput, LightingView)>,
    /// The split view: the right half shows this method's deferred frame.
    pub split: Option<SplitFrame<'a>>,
}

/// The split view's right-hand method, drawn with the slot's split side's maps into the split
/// lit shares.
pub struct SplitFrame<'a> {
    pub light: &'a LightView,
    pub plane_test_where_still: bool,
    /// TSM's pass and its number of maps, for TSM methods.
    pub tsm: Option<(&'a EngineTsmPass, u32)>,
}

/// The timestamps' names of the split view's right-hand method's passes start with this.
pub const SPLIT_PASS_PREFIX: &str = "split ";

/// The swapchain image the frame ends in.
pub struct Present {
    pub image: vk::Image,
    /// Copied back into the slot's screenshot buffer too.
    pub screenshot: Option<vk::Buffer>,
}

const COLOR: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

const COLOR_LAYER: vk::ImageSubresourceLayers = vk::ImageSubresourceLayers {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    mip_level: 0,
    base_array_layer: 0,
    layer_count: 1,
};

/// Before the acquired image's first write: the acquire semaphore is waited for at the
/// transfer stage, this barrier's first scope.
const ACQUIRED: Access = Access {
    stages: vk::PipelineStageFlags2::TRANSFER,
    access: vk::AccessFlags2::NONE,
};

/// Records the frame into `slot.cmd` (begun by the caller, ended by it).
///
/// # Safety
/// `slot.cmd` is recording; the slot's previous frame completed (its fence waited for); the
/// slot's sized targets exist at the swapchain image's size; `present.image` was acquired
/// with the semaphore the submission waits for at the transfer stage; the map's room was
/// reserved for the slot's draws (temporal methods).
pub unsafe fn record_frame(
    device: &ash::Device,
    passes: &Passes,
    slot: &mut FrameSlot,
    view: &FrameView<'_>,
    present: &Present,
) -> anyhow::Result<()> {
    let cmd = slot.cmd;
    let Some(targets) = slot.targets.as_mut() else {
        anyhow::bail!("the frame slot has no images of the window's size");
    };
    let ts = &mut slot.timestamps;
    // SAFETY: the caller's contract: `cmd` (the slot's, of `device`) is recording, outside
    // rendering, for the viewer's graphics-and-compute queue (the context's: its timestamps
    // record nothing where that family has none), and the slot's previous frame completed,
    // so its draw list and timestamps are not in use; the draw list's update is recorded
    // before the G-buffer reads it; the slot's buffers and images outlive `cmd`'s execution
    // (the slot replaces them only after its frame completed, and the context retires a
    // dropped object only once the frames that may use it completed).
    unsafe {
        ts.mark(cmd, "start");
        slot.draws
            .record_update(device, cmd, &slot.geometry.draws)?;
        ts.mark(cmd, "draw list");
        let camera = GBufferCamera {
            view_proj: view.view_proj,
            eye: view.eye,
        };
        passes.gbuffer.record(
            device,
            cmd,
            &slot.draws,
            &camera,
            view.camera_time,
            &targets.gbuffer,
        );
        ts.mark(cmd, "g-buffer");
    }
    let mut inputs = targets.gbuffer.mask_inputs(
        targets.lit.layer_view(0),
        view.view_proj.inverse(),
        view.camera_time,
        view.moving_receivers,
    );
    inputs.plane_test_where_still = view.plane_test_where_still;
    let (width, height) = targets.size;
    // SAFETY: as above, and: the passes' descriptor sets (mask, shading, TSM, lighting
    // output) are the slot's own, unused by any pending command buffer (its previous frame
    // completed); each pass follows the one whose output it reads in `cmd` (collection,
    // generation, then the mask, the lighting pass or TSM's; the shading after the global
    // compute barrier), the G-buffer left its images in the layouts `inputs` names; every
    // image barrier names the image's layout at that point or UNDEFINED (contents
    // discarded: the lit shares, radiance and shaded image are rewritten each frame, the
    // swapchain image is acquired), and the blit and copy stay inside the images (the
    // targets, the swapchain image and the screenshot buffer are all of `targets.size`, the
    // caller's contract and `FrameLoop::draw`'s checks).
    unsafe {
        // The lit shares: the last frame's shading read them (contents discarded).
        image_barrier(
            device,
            cmd,
            targets.lit.raw(),
            COLOR,
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
            Access::COMPUTE_RW,
            Access::COMPUTE_RW,
        );
        if let Some((lighting, output, lighting_view)) = &view.stochastic {
            let Some(targets_of_lighting) = slot.lighting.as_mut() else {
                anyhow::bail!("the stochastic frame's target was not made for this slot");
            };
            passes
                .collection
                .record(device, cmd, &slot.draws, view.light, &slot.map, None)?;
            ts.mark(cmd, "collection");
            passes.generation.record(device, cmd, &slot.map);
            ts.mark(cmd, "generation");
            lighting.record(
                device,
                cmd,
                &slot.draws,
                lighting_view,
                ShadowSource::Temporal(&slot.map),
                &targets_of_lighting.target,
                Some(&mut *ts),
            )?;
            slot.map.record_counter_readback(device, cmd);
            // Its counters (the pixels past a loop limit) for the host; the radiance copy
            // comes with them.
            targets_of_lighting.target.record_readback(device, cmd);
            image_barrier(
                device,
                cmd,
                targets.radiance.raw(),
                COLOR,
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::COMPUTE_RW,
                Access::COMPUTE_RW,
            );
            output.record(
                device,
                cmd,
                &mut targets_of_lighting.bindings,
                &targets_of_lighting.target,
                targets.radiance.layer_view(0),
            );
            ts.mark(cmd, "to image");
        } else {
            let left = Shadows {
                light: view.light,
                tsm: view.tsm,
                map: &slot.map,
                tsm_maps: slot.tsm.as_mut(),
                mask_bindings: &mut targets.mask_bindings,
                prefix: "",
            };
            record_shadows(device, cmd, passes, &slot.draws, ts, left, &inputs)?;
            if let Some(split) = &view.split {
                let Some(side) = slot.split.as_mut() else {
                    anyhow::bail!("the split view's maps were not made for this slot");
                };
                // The right-hand method's lit shares: the last frame's shading read them.
                image_barrier(
                    device,
                    cmd,
                    targets.split_lit.raw(),
                    COLOR,
                    (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                    Access::COMPUTE_RW,
                    Access::COMPUTE_RW,
                );
                let mut split_inputs = targets.gbuffer.mask_inputs(
                    targets.split_lit.layer_view(0),
                    view.view_proj.inverse(),
                    view.camera_time,
                    view.moving_receivers,
                );
                split_inputs.plane_test_where_still = split.plane_test_where_still;
                let right = Shadows {
                    light: split.light,
                    tsm: split.tsm,
                    map: &side.map,
                    tsm_maps: side.tsm.as_mut(),
                    mask_bindings: &mut targets.split_mask_bindings,
                    prefix: SPLIT_PASS_PREFIX,
                };
                record_shadows(device, cmd, passes, &slot.draws, ts, right, &split_inputs)?;
            }
        }
        if view.stochastic.is_none() {
            // Its shading binds the radiance image too (not read): in GENERAL.
            image_barrier(
                device,
                cmd,
                targets.radiance.raw(),
                COLOR,
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::COMPUTE_RW,
                Access::COMPUTE_RW,
            );
        }
        memory_barrier(device, cmd, Access::COMPUTE_RW, Access::COMPUTE_RW);
        // The shaded image: the last frame's blit read it (contents discarded).
        image_barrier(
            device,
            cmd,
            targets.output.raw(),
            COLOR,
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
            Access::TRANSFER_READ,
            Access::COMPUTE_RW,
        );
        passes.shade.record(
            device,
            cmd,
            &mut targets.shade_bindings,
            &inputs,
            ShadeFrame {
                light: view.light,
                camera_time: view.camera_time,
                inv_view_proj: view.view_proj.inverse(),
                exposure: view.exposure,
                overlay: view.overlay,
                stochastic: view.stochastic.is_some(),
                split_lit: view.split.as_ref().map(|_| targets.split_lit.layer_view(0)),
                output: targets.output.layer_view(0),
                radiance: targets.radiance.layer_view(0),
            },
        )?;
        ts.mark(cmd, "shade");
        image_barrier(
            device,
            cmd,
            targets.output.raw(),
            COLOR,
            (
                vk::ImageLayout::GENERAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            ),
            Access::COMPUTE_RW,
            Access::TRANSFER_READ,
        );
        image_barrier(
            device,
            cmd,
            present.image,
            COLOR,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            ),
            ACQUIRED,
            Access::TRANSFER_WRITE,
        );
        let corners = [
            vk::Offset3D::default(),
            vk::Offset3D {
                x: width as i32,
                y: height as i32,
                z: 1,
            },
        ];
        // A blit, not a copy: the swapchain's channel order may differ (BGRA); same size,
        // nearest, so every 8-bit value arrives unchanged.
        let region = vk::ImageBlit::default()
            .src_subresource(COLOR_LAYER)
            .src_offsets(corners)
            .dst_subresource(COLOR_LAYER)
            .dst_offsets(corners);
        device.cmd_blit_image(
            cmd,
            targets.output.raw(),
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            present.image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
            vk::Filter::NEAREST,
        );
        let mut last = Access::TRANSFER_WRITE;
        let mut layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        if let Some(buffer) = present.screenshot {
            image_barrier(
                device,
                cmd,
                present.image,
                COLOR,
                (layout, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
                Access::TRANSFER_WRITE,
                Access::TRANSFER_READ,
            );
            let copy = vk::BufferImageCopy {
                buffer_offset: 0,
                buffer_row_length: 0,
                buffer_image_height: 0,
                image_subresource: COLOR_LAYER,
                image_offset: vk::Offset3D::default(),
                image_extent: vk::Extent3D {
                    width,
                    height,
                    depth: 1,
                },
            };
            device.cmd_copy_image_to_buffer(
                cmd,
                present.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                &[copy],
            );
            memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
            last = Access::TRANSFER_READ;
            layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        }
        image_barrier(
            device,
            cmd,
            present.image,
            COLOR,
            (layout, vk::ImageLayout::PRESENT_SRC_KHR),
            last,
            Access::NONE,
        );
        ts.mark(cmd, "present copy");
    }
    Ok(())
}

/// One method's shadow work of a deferred frame: the temporal map's collection, generation
/// and mask, or TSM's maps and lookups, into the lit shares `inputs.output`.
struct Shadows<'a> {
    light: &'a LightView,
    /// TSM's pass and number of maps, for TSM methods.
    tsm: Option<(&'a EngineTsmPass, u32)>,
    map: &'a TemporalShadowMap,
    tsm_maps: Option<&'a mut TsmTargets>,
    mask_bindings: &'a mut MaskBindings,
    /// Put before the timestamps' names.
    prefix: &'static str,
}

/// Records `shadows` into `cmd`.
///
/// # Safety
/// As [`record_frame`]'s: `cmd` is recording, the maps' and bindings' last frame completed,
/// the G-buffer's images are in `inputs`' layouts, `inputs.output` is in GENERAL with
/// earlier accesses ordered before compute, and the temporal map's room was reserved.
unsafe fn record_shadows(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    passes: &Passes,
    draws: &DrawList,
    ts: &mut TimestampQueries,
    shadows: Shadows<'_>,
    inputs: &MaskInputs,
) -> anyhow::Result<()> {
    let named = |pass: &str| format!("{}{pass}", shadows.prefix);
    // SAFETY: the caller's contract, which each pass's needs (a recording command buffer of
    // this device, outside rendering, its descriptor sets and maps unused by pending work,
    // the inputs' images in their layouts) are part of; each pass follows the one whose
    // output it reads.
    unsafe {
        match (shadows.tsm, shadows.tsm_maps) {
            (Some((pass, maps)), Some(tsm)) => {
                pass.record(
                    device,
                    cmd,
                    &mut tsm.bindings,
                    inputs,
                    draws,
                    shadows.light,
                    &tsm.map,
                    maps,
                )?;
                ts.mark(cmd, &named("tsm + mask"));
            }
            (Some(_), None) => anyhow::bail!("TSM's maps were not made for this slot"),
            (None, _) => {
                passes
                    .collection
                    .record(device, cmd, draws, shadows.light, shadows.map, None)?;
                ts.mark(cmd, &named("collection"));
                passes.generation.record(device, cmd, shadows.map);
                ts.mark(cmd, &named("generation"));
                passes
                    .mask
                    .record(device, cmd, shadows.mask_bindings, inputs, shadows.map)?;
                ts.mark(cmd, &named("mask"));
                shadows.map.record_counter_readback(device, cmd);
            }
        }
    }
    Ok(())
}
