//! The commands the engine's time-dependent shadow maps record beside their pipelines:
//! rendering into one depth layer, copying the static map into the working layers, and
//! drawing one kind of draw into a map.

use super::map::EngineTsmMap;
use crate::gpu::Pipeline;
use crate::technique::draws::DrawList;
use crate::technique::gpu_types::DRAW_STATIC;
use crate::technique::push_constants::{DrawPush, MapDrawPush};
use ash::vk;

/// Begins dynamic rendering into the depth map `view` (in `DEPTH_ATTACHMENT_OPTIMAL`),
/// cleared to 1 if `clear`, else loaded as it is, stored at the end; viewport and scissor
/// over the map.
///
/// # Safety
/// `cmd` is recording, outside rendering.
pub(super) unsafe fn begin_depth(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    view: vk::ImageView,
    width: u32,
    height: u32,
    clear: bool,
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: vk::Extent2D { width, height },
    };
    let attachment = vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(if clear {
            vk::AttachmentLoadOp::CLEAR
        } else {
            vk::AttachmentLoadOp::LOAD
        })
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .depth_attachment(&attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: width as f32,
        height: height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: `info` (and the attachment it points at) lives through the call; `cmd` is outside
    // rendering (this function's contract) and `view` is a depth view in DEPTH_ATTACHMENT_OPTIMAL
    // of `width` x `height` (the callers' barriers put it there), matching the render area,
    // viewport and scissor set inside the rendering.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// Copies the static map (in `TRANSFER_SRC_OPTIMAL`) into layers `0..layers` of the
/// working map (in `TRANSFER_DST_OPTIMAL`).
///
/// # Safety
/// `cmd` is recording, outside rendering; the maps are in those layouts.
pub(super) unsafe fn copy_static(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &EngineTsmMap,
    layers: u32,
) {
    let layer = |base_array_layer| vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::DEPTH,
        mip_level: 0,
        base_array_layer,
        layer_count: 1,
    };
    let regions: Vec<vk::ImageCopy> = (0..layers)
        .map(|i| vk::ImageCopy {
            src_subresource: layer(0),
            src_offset: vk::Offset3D::default(),
            dst_subresource: layer(i),
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D {
                width: map.width,
                height: map.height,
                depth: 1,
            },
        })
        .collect();
    // SAFETY: the caller's contract: outside rendering, the static map in TRANSFER_SRC_OPTIMAL and
    // the working map in TRANSFER_DST_OPTIMAL; one region per layer below `layers`, which the
    // caller keeps within the working map's layer count (a batch), each the whole map's size in
    // both images.
    unsafe {
        device.cmd_copy_image(
            cmd,
            map.static_map.raw(),
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            map.working.raw(),
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &regions,
        )
    };
}

/// Records the static draws (`moving_at` None) or the moving ones at time `moving_at`,
/// depth-only, inside dynamic rendering with `pipeline` bound (`draw_each` of the collection
/// pass, one kind of draw only). Under a moving light (`light_moves`) nothing stands still in
/// the light's frame: every draw is drawn as moving, at each map's time, and the static map
/// stays empty.
pub(super) fn draw_where(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    draws: &DrawList,
    map: &EngineTsmMap,
    moving_at: Option<f32>,
    light_moves: bool,
) {
    let statics = moving_at.is_none();
    let t = moving_at.unwrap_or(0.0);
    for (i, record) in draws.records().iter().enumerate() {
        let is_static = record.flags() & DRAW_STATIC != 0 && !light_moves;
        if record.triangle_count == 0 || is_static != statics {
            continue;
        }
        let constants = MapDrawPush {
            draw: DrawPush {
                draws: draws.address(),
                draw_index: i as u32,
                draw_count: draws.draw_count(),
            },
            map: map.header_address(),
            time: t,
            flags: 0,
        };
        // SAFETY: draw_where runs inside rendering with `pipeline` bound (its callers in this
        // file), whose layout has MapDrawPush's size as its push range.
        unsafe { pipeline.push(device, cmd, &constants) };
        // SAFETY: inside that rendering with the pipeline bound and pushed; the vertex shader reads
        // only this draw's streams, which the draw list checked.
        unsafe { device.cmd_draw(cmd, 3 * record.triangle_count, 1, 0, 0) };
    }
}
