//! The steps of [`super::EngineTsmPass::record`], in the order it runs them: the header, the
//! static map when it must be drawn, the bindings, and per batch of maps the working layers
//! started, the moving draws drawn into them, and the mask's dispatch.
//!
//! Each step's safety contract is the part of `record`'s it relies on: `cmd` was allocated
//! from the device the pass and the map were made on, is recording, outside any render pass
//! or dynamic rendering, on a queue with graphics and compute; no other pending command
//! buffer uses the map (unless submitted earlier to the same queue).

use super::TsmStart;
use super::accesses::{Step, step_barrier};
use super::bindings::EngineTsmBindings;
use super::commands::{begin_depth, copy_static, draw_where};
use super::map::{EngineTsmMap, HEADER_BYTES};
use crate::gpu::Pipeline;
use crate::technique::draws::DrawList;
use crate::technique::gpu_types::{DepthFormat, PlainMapHeader};
use crate::technique::mask::{MaskInputs, NormalEncoding, NormalImage, mask_position_flag};
use crate::technique::push_constants::TsmMaskPush;
use crate::technique::view::LightView;
use ash::vk;
use glam::UVec4;

// The mask's flags, shared with glsl/tsm_mask.comp through the generated constants.
use crate::technique::gpu_constants::{
    MASK_HAS_NORMALS as HAS_NORMALS, MASK_NORMALS_UNORM as NORMALS_UNORM,
    TSM_FIRST_BATCH as FIRST_BATCH, TSM_LAST_BATCH as LAST_BATCH,
};

/// One batch of the N maps: maps `first..first + count` of `maps`, drawn into the working
/// map's first `count` layers and tested by one dispatch.
#[derive(Clone, Copy)]
pub(super) struct Batch {
    pub(super) first: u32,
    pub(super) count: u32,
    /// N.
    pub(super) maps: u32,
}

/// Which of the pass's mask pipelines serves `inputs` (moving receivers or not) and a map
/// started as `start`: `moving + 2 * second_lookup`.
pub(super) fn mask_variant(inputs: &MaskInputs, start: TsmStart) -> usize {
    let second_lookup = start == TsmStart::SecondLookup;
    usize::from(inputs.motion.is_some()) + 2 * usize::from(second_lookup)
}

/// The mask's flags that stay the same over the batches: how the normals are encoded and
/// where the receivers' positions come from.
pub(super) fn mask_flags(inputs: &MaskInputs) -> u32 {
    let normal_flags = match inputs.normals {
        Some(NormalImage {
            encoding: NormalEncoding::Unorm,
            ..
        }) => HAS_NORMALS | NORMALS_UNORM,
        Some(_) => HAS_NORMALS,
        None => 0,
    };
    normal_flags | mask_position_flag(inputs)
}

/// Writes the map's header (the light as `shadow_depth.vert` and the mask shader read it, a
/// moving light's pose at t = 1 included) before the shaders below read it.
///
/// # Safety
/// `cmd` is recording, outside any render pass, on a graphics and compute queue; no other
/// pending command buffer reads the map's header; earlier reads of it in `cmd` were ordered
/// before transfer writes (the pass's entry barrier, or the host's).
pub(super) unsafe fn write_header(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &EngineTsmMap,
    light: &LightView,
) {
    let header = PlainMapHeader {
        light: light.gpu(),
        size: UVec4::new(map.width, map.height, 1, DepthFormat::DepthOnly as u32),
        depths: 0,
        ids: 0,
    };
    let mut bytes = bytemuck::bytes_of(&header).to_vec();
    bytes.extend_from_slice(bytemuck::bytes_of(&light.gpu_end()));
    debug_assert_eq!(bytes.len() as u64, HEADER_BYTES);
    // SAFETY: plain data of the header's size (HEADER_BYTES); outside a render pass, after
    // earlier reads (the contract).
    unsafe { map.header.record_write(device, cmd, &bytes) };
    // SAFETY: the same command buffer, outside rendering, on a graphics and compute queue.
    unsafe { step_barrier(device, cmd, map, (Step::HeaderWrite, Step::HeaderReads)) };
}

/// Draws the static draws into the static map, cleared first, with `depth_only`, and leaves
/// it in the layout its next use reads it in (`static_resting_layout` in `map.rs`); under a
/// moving light (`light_moves`) it stays empty ([`draw_where`]).
///
/// # Safety
/// As [`write_header`]; the static map is in no other hands; `depth_only` is the pass's
/// depth-only pipeline; the draws' buffers are as `Draw` requires and `draws` was updated
/// earlier in `cmd` or in a command buffer submitted before it.
pub(super) unsafe fn draw_static_map(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    depth_only: &Pipeline,
    draws: &DrawList,
    map: &EngineTsmMap,
    light_moves: bool,
) {
    // SAFETY: the static map is this map's image, in no other hands (the contract), at rest
    // or discarded: the cleared redraw below replaces its contents.
    unsafe { step_barrier(device, cmd, map, (Step::StaticReads, Step::StaticDraw)) };
    let view = map.static_map.layer_view(0);
    // SAFETY: the caller's contract; the view is in the attachment layout.
    unsafe { begin_depth(device, cmd, view, map.width, map.height, true) };
    // SAFETY: rendering into the static map began just above; the depth-only pipeline is
    // the pass's, made for D32 depth with no colours, the static map's format.
    unsafe { depth_only.bind(device, cmd) };
    draw_where(device, cmd, depth_only, draws, map, None, light_moves);
    // SAFETY: the rendering began above and the static draws are recorded into it.
    unsafe { device.cmd_end_rendering(cmd) };
    // SAFETY: rendering has ended; the static map leaves the attachment layout it was drawn
    // in for its resting layout, where the rest of the frame reads it.
    unsafe { step_barrier(device, cmd, map, (Step::StaticDraw, Step::StaticReads)) };
}

/// Writes the set every dispatch binds: the host's images and the maps. Without a normal or
/// motion image (or, copying, without a second lookup) the depth view stands in (never read:
/// the flag and the variant say so).
///
/// # Safety
/// No command buffer using `bindings` is pending or has it bound; the views of `inputs` are
/// valid, of the map's device, with the layouts [`MaskInputs`] states.
pub(super) unsafe fn write_bindings(
    bindings: &mut EngineTsmBindings,
    inputs: &MaskInputs,
    map: &EngineTsmMap,
) {
    let depth = (inputs.depth, inputs.depth_layout);
    let normals = inputs.normals.map_or(depth, |n| (n.view, n.layout));
    let motion = inputs.motion.map_or(depth, |m| (m.view, m.layout));
    let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    let static_map = if map.start == TsmStart::SecondLookup {
        (map.static_map.layer_view(0), read_only)
    } else {
        depth
    };
    // SAFETY: the caller's contract (the set is not in use; the views are valid).
    unsafe {
        bindings.images.write(&[
            depth,
            normals,
            motion,
            (inputs.output, vk::ImageLayout::GENERAL),
            (map.working_array, read_only),
            static_map,
            inputs.positions.map_or(depth, |p| (p.view, p.layout)),
        ])
    };
}

/// Starts the working map's layers for `batch` once the previous dispatch (or frame) has
/// read them: copies of the static map ([`TsmStart::Copy`]) or, cleared by the rendering
/// that draws into them, nothing ([`TsmStart::SecondLookup`]). Leaves them in the attachment
/// layout.
///
/// # Safety
/// As [`write_header`]; the static map holds the static draws, in its resting layout.
pub(super) unsafe fn start_layers(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &EngineTsmMap,
    batch: Batch,
) {
    // SAFETY: the working map is this map's image, in no other hands; its previous readers
    // (the last dispatch, or an earlier record's) are waited for, and its layers are
    // discarded: the copy or the clearing rendering overwrites every layer used.
    unsafe { step_barrier(device, cmd, map, (Step::LayersRead, Step::LayersStart)) };
    if map.start == TsmStart::Copy {
        // SAFETY: both images are the map's, in the layouts their steps declare (the static
        // map at rest in TRANSFER_SRC_OPTIMAL, the working map in TRANSFER_DST_OPTIMAL).
        unsafe { copy_static(device, cmd, map, batch.count) };
        // SAFETY: the copy is recorded; the working layers move on to the attachment layout
        // the moving draws load.
        unsafe { step_barrier(device, cmd, map, (Step::LayersStart, Step::MovingDraws)) };
    }
}

/// Draws the moving draws (every draw under a moving light, `light_moves`) into each layer of
/// `batch` at its map's time, the centre of its stratum of the shutter, with `depth_only`
/// (the light where it is then: `shadow_depth.vert` reads its pose at t = 1 from the header),
/// and leaves the layers for the mask shader's sampled reads.
///
/// # Safety
/// As [`draw_static_map`]; the batch's layers were started ([`start_layers`]).
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn draw_moving_layers(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    depth_only: &Pipeline,
    draws: &DrawList,
    map: &EngineTsmMap,
    batch: Batch,
    light_moves: bool,
) {
    let Batch { first, maps, .. } = batch;
    let inv_maps = 1.0 / maps as f32;
    let clear = map.start == TsmStart::SecondLookup;
    // SAFETY: outside rendering (the barrier before ended any); the depth-only pipeline is
    // the pass's, alive as long as it.
    unsafe { depth_only.bind(device, cmd) };
    for layer in 0..batch.count {
        let t = ((first + layer) as f32 + 0.5) * inv_maps;
        let view = map.working.layer_view(layer);
        // SAFETY: the caller's contract; the layer is in the attachment layout.
        unsafe { begin_depth(device, cmd, view, map.width, map.height, clear) };
        draw_where(device, cmd, depth_only, draws, map, Some(t), light_moves);
        // SAFETY: this layer's rendering began above and its moving draws are recorded.
        unsafe { device.cmd_end_rendering(cmd) };
    }
    // SAFETY: all the batch's renderings have ended; the working layers leave the
    // attachment layout for the mask shader's sampled reads.
    unsafe { step_barrier(device, cmd, map, (Step::MovingDraws, Step::LayersRead)) };
}

/// Tests every pixel of the host's image against the batch's maps: the first batch writes
/// its count of lit maps, later ones add theirs (after the previous batch's writes), the
/// last scales the sum by 1/N. `flags` are [`mask_flags`].
///
/// # Safety
/// As [`write_header`]; `mask` is the pass's pipeline for [`mask_variant`], made with the
/// layout `bindings` was allocated from; `bindings` was written ([`write_bindings`]) and its
/// views stay alive until `cmd` completes; the batch's layers were drawn
/// ([`draw_moving_layers`]); the host ordered its images' earlier accesses before these
/// reads and writes.
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn dispatch_mask(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    mask: &Pipeline,
    bindings: &EngineTsmBindings,
    inputs: &MaskInputs,
    map: &EngineTsmMap,
    batch: Batch,
    flags: u32,
) {
    let Batch { first, maps, .. } = batch;
    if first > 0 {
        // The previous batch's count, read and rewritten by this one.
        // SAFETY: outside rendering; compute is on this queue.
        unsafe {
            step_barrier(
                device,
                cmd,
                map,
                (Step::Dispatch(inputs), Step::Dispatch(inputs)),
            )
        };
    }
    let flags = flags
        | if first == 0 { FIRST_BATCH } else { 0 }
        | if first + batch.count == maps {
            LAST_BATCH
        } else {
            0
        };
    let constants = TsmMaskPush {
        inv_view_proj: inputs.inv_view_proj,
        light: map.header_address(),
        size: [inputs.size.0, inputs.size.1],
        background_depth: inputs.background_depth,
        flags,
        map_size: [map.width, map.height],
        time: inputs.time,
        maps: maps as f32,
        inv_maps: 1.0 / maps as f32,
        first_map: first,
        batch: batch.count,
        reserved: [0; 3],
    };
    // SAFETY: the mask pipeline is the pass's (its variant for this map's start), alive as
    // long as it; a compute bind outside rendering.
    unsafe { mask.bind(device, cmd) };
    // SAFETY: the set was written before; its views are valid (the caller's contract).
    unsafe {
        device.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            mask.layout(),
            0,
            &[bindings.images.raw()],
            &[],
        );
    }
    // SAFETY: the mask pipeline's layout has TsmMaskPush's size as its push range.
    unsafe { mask.push(device, cmd, &constants) };
    let groups = (inputs.size.0.div_ceil(8), inputs.size.1.div_ceil(8));
    // SAFETY: the mask pipeline and its set are bound with its constants; 8x8 groups cover
    // the host's image, and the shader returns for invocations past its edges.
    unsafe { device.cmd_dispatch(cmd, groups.0, groups.1, 1) };
}
